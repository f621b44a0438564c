//! Recording the renderer's passes: bind groups, the G-buffer pass (opaque quads from the cull
//! pass's commands, then smooth chunks), the transparent pass and the two full-screen passes.

use std::collections::HashMap;

use wgpu::util::DeviceExt;
use wgpu::{BindGroup, Buffer, BufferUsages, CommandEncoder};

use super::Renderer;
use crate::cull::{CullCamera, in_frustum, relative_box};
use crate::gigabuffer::DataKind;
use crate::render::frame::SmoothDraw;

impl Renderer {
    pub(super) fn frame_group(&self) -> BindGroup {
        self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame"),
            layout: &self.pipelines.frame_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: self.frame_uniforms.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: self.materials.as_entire_binding(),
                },
            ],
        })
    }

    /// Group 1 of the quad pipelines: quad page `page` and `records`.
    fn quad_group(&self, page: u32, records: &Buffer) -> Option<BindGroup> {
        let quads = self.gigabuffer.page(DataKind::Quads, page)?;
        Some(self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("quads"),
            layout: &self.pipelines.quad_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: quads.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: records.as_entire_binding(),
                },
            ],
        }))
    }

    pub(super) fn record_gbuffer(
        &self,
        encoder: &mut CommandEncoder,
        frame_group: &BindGroup,
        camera: &CullCamera,
    ) {
        let clear = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let smooth = self.smooth_batches(camera);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("gbuffer"),
            color_attachments: &[clear(&self.targets.albedo), clear(&self.targets.normal)],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.targets.depth,
                // Reversed-Z: 0 is infinitely far.
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipelines.quad_gbuffer);
        pass.set_bind_group(0, frame_group, &[]);
        pass.set_index_buffer(self.quad_indices.slice(..), wgpu::IndexFormat::Uint32);
        for page in 0..self.cull.layout().page_count {
            if let Some(group) = self.quad_group(page, self.opaque_commands.records()) {
                pass.set_bind_group(1, &group, &[]);
                self.opaque_commands.draw_page(&mut pass, page);
            }
        }
        if !smooth.is_empty() {
            pass.set_pipeline(&self.pipelines.smooth_gbuffer);
            pass.set_bind_group(0, frame_group, &[]);
            for (group, draws) in &smooth {
                pass.set_bind_group(1, group, &[]);
                for (i, draw) in draws {
                    pass.draw(0..6 * draw.quad_count, *i..*i + 1);
                }
            }
        }
    }

    /// The smooth draws of the resident chunks, grouped by the pages they read.
    /// Smooth chunks are culled here, on the CPU, by their boxes against the frustum (the cull
    /// pass reads only the quad layers); there are few of them.
    fn smooth_batches(&self, camera: &CullCamera) -> Vec<(BindGroup, Vec<(u32, SmoothDraw)>)> {
        let edge = self.config.chunk_size.edge();
        let vertices = self
            .gigabuffer
            .layout(DataKind::SmoothVertices)
            .page_capacity;
        let quads = self.gigabuffer.layout(DataKind::SmoothQuads).page_capacity;
        let eye_chunk = self.camera.chunk;
        let mut by_pages: HashMap<(u32, u32), Vec<SmoothDraw>> = HashMap::new();
        for resident in self.smooth_chunks.iter().filter_map(|h| self.chunks.get(h)) {
            let (Some(smooth), Some(info)) = (resident.smooth, self.table.get(resident.slot))
            else {
                continue;
            };
            let (centre, extent) = relative_box(info, camera, edge);
            if !in_frustum(&camera.planes, centre, extent) {
                continue;
            }
            let (Some(vp), Some(qp)) = (
                smooth.vertices.offset.checked_div(vertices),
                smooth.quads.offset.checked_div(quads),
            ) else {
                continue;
            };
            by_pages.entry((vp, qp)).or_default().push(SmoothDraw {
                chunk: [
                    info.chunk[0].wrapping_sub(eye_chunk.x),
                    info.chunk[1].wrapping_sub(eye_chunk.y),
                    info.chunk[2].wrapping_sub(eye_chunk.z),
                ],
                vertex_offset: smooth.vertices.offset % vertices,
                quad_offset: smooth.quads.offset % quads,
                quad_count: smooth.quad_count,
                quad_form: smooth.form as u32,
                pad: 0,
            });
        }
        let mut batches = Vec::new();
        for ((vp, qp), draws) in by_pages {
            let (Some(vertex_page), Some(quad_page)) = (
                self.gigabuffer.page(DataKind::SmoothVertices, vp),
                self.gigabuffer.page(DataKind::SmoothQuads, qp),
            ) else {
                continue;
            };
            let records = self
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("smooth draws"),
                    contents: bytemuck::cast_slice(&draws),
                    usage: BufferUsages::STORAGE,
                });
            let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("smooth"),
                layout: &self.pipelines.smooth_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: vertex_page.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: quad_page.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: records.as_entire_binding(),
                    },
                ],
            });
            batches.push((group, (0u32..).zip(draws).collect()));
        }
        batches
    }

    /// The transparent pass: the ordered cull's commands, one multi-draw per quad page,
    /// blended into the HDR target over the lit opaque image (depth-tested, not written).
    pub(super) fn record_transparent(&self, encoder: &mut CommandEncoder, frame_group: &BindGroup) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("transparent"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.targets.hdr,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.targets.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipelines.quad_transparent);
        pass.set_bind_group(0, frame_group, &[]);
        pass.set_index_buffer(self.quad_indices.slice(..), wgpu::IndexFormat::Uint32);
        let commands = &self.transparent_commands;
        for page in 0..self.cull.layout().page_count {
            if let Some(group) = self.quad_group(page, commands.records()) {
                pass.set_bind_group(1, &group, &[]);
                commands.draw_page(&mut pass, page);
            }
        }
    }

    /// The lighting pass (`tonemap = false`: G-buffer to HDR) or the tonemap pass (HDR to the
    /// output).
    pub(super) fn record_fullscreen(
        &self,
        encoder: &mut CommandEncoder,
        frame_group: &BindGroup,
        tonemap: bool,
    ) {
        let t = &self.targets;
        let texture = |binding, view| wgpu::BindGroupEntry {
            binding,
            resource: wgpu::BindingResource::TextureView(view),
        };
        let (pipeline, layout, entries, target) = if tonemap {
            (
                &self.pipelines.tonemap,
                &self.pipelines.hdr_read_layout,
                vec![texture(3, &t.hdr)],
                &t.output,
            )
        } else {
            (
                &self.pipelines.lighting,
                &self.pipelines.gbuffer_read_layout,
                vec![
                    texture(0, &t.albedo),
                    texture(1, &t.normal),
                    texture(2, &t.depth),
                ],
                &t.hdr,
            )
        };
        let group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(if tonemap { "hdr read" } else { "gbuffer read" }),
            layout,
            entries: &entries,
        });
        let mut pass = crate::fullscreen::fullscreen_pass(
            encoder,
            if tonemap { "tonemap" } else { "lighting" },
            target,
        );
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, frame_group, &[]);
        pass.set_bind_group(1, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}
