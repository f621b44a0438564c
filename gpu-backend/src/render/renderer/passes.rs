//! Recording the renderer's passes: bind groups, the G-buffer pass (opaque quads from the cull
//! pass's commands, then smooth chunks), the transparent pass and the two full-screen passes.

use wgpu::{BindGroup, Buffer, CommandEncoder};

use super::Renderer;
use crate::bind::buffer_entry;
use crate::cull::CullOutput;
use crate::pass_chain::PassChain;
use crate::render::pipelines::FullscreenPipelines;
use voxel_core::formats::DataKind;

impl Renderer {
    pub(super) fn frame_group(&self) -> BindGroup {
        self.bind_cache.get(
            &self.device,
            "frame",
            &self.pipelines.frame_layout,
            &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: self.frame_uniforms.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: self.materials.as_entire_binding(),
                },
            ],
        )
    }

    /// Group 1 of the quad pipelines: quad page `page`, `records`, and the opaque visibility
    /// buffer the transparent quads test against (a stand-in without one).
    fn quad_group(&self, page: u32, records: &Buffer) -> Option<BindGroup> {
        let quads = self.gigabuffer.page(DataKind::Quads, page)?;
        let visibility = self
            .splat
            .as_ref()
            .map_or(&self.no_visibility, |s| s.visibility());
        Some(self.bind_cache.get(
            &self.device,
            "quads",
            &self.pipelines.quad_layout,
            &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: quads.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: records.as_entire_binding(),
                },
                buffer_entry(9, visibility),
            ],
        ))
    }

    /// Group 1 of the smooth pipeline: smooth pair `pair`'s pages and `commands`' smooth
    /// records.
    fn smooth_group(&self, pair: u32, commands: &CullOutput) -> Option<BindGroup> {
        let quad_pages = self.cull.layout().smooth.quad_pages.max(1);
        let vertices = self
            .gigabuffer
            .page(DataKind::SmoothVertices, pair / quad_pages)?;
        let quads = self
            .gigabuffer
            .page(DataKind::SmoothQuads, pair % quad_pages)?;
        Some(self.bind_cache.get(
            &self.device,
            "smooth",
            &self.pipelines.smooth_layout,
            &[
                buffer_entry(2, vertices),
                buffer_entry(3, quads),
                buffer_entry(4, commands.smooth_records()),
            ],
        ))
    }

    /// The G-buffer pass of `commands` (opaque quads per page, then smooth quads per page
    /// pair, then the raster far draws' opaque blocks when `far_group` is given): clearing
    /// the depth first, or drawing over it.
    pub(super) fn record_gbuffer(
        &self,
        encoder: &mut CommandEncoder,
        frame_group: &BindGroup,
        commands: &CullOutput,
        clear_first: bool,
        far_group: Option<&BindGroup>,
    ) {
        // The colour targets are never cleared: lighting reads them only where the depth
        // says this frame drew there (depth > 0, nearer than the visibility buffer). A clear
        // is a full-screen fill, which costs ~0.6 ms on GPUs with few raster units (the H100),
        // a third of the frame budget; only the depth is cleared.
        let colour_load = wgpu::LoadOp::Load;
        let attachment = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: colour_load,
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("gbuffer"),
            color_attachments: &[
                attachment(&self.targets.albedo),
                attachment(&self.targets.normal),
            ],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.targets.depth,
                // Reversed-Z: 0 is infinitely far.
                depth_ops: Some(wgpu::Operations {
                    load: if clear_first {
                        wgpu::LoadOp::Clear(0.0)
                    } else {
                        wgpu::LoadOp::Load
                    },
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        // On the compute opaque path the quads went to the visibility buffer instead.
        if !self.quads_in_compute() {
            pass.set_pipeline(if self.wireframe {
                &self.pipelines.quad_gbuffer_wire
            } else {
                &self.pipelines.quad_gbuffer
            });
            pass.set_bind_group(0, frame_group, &[]);
            pass.set_index_buffer(self.quad_indices.slice(..), wgpu::IndexFormat::Uint32);
            for page in 0..self.cull.layout().page_count {
                if let Some(group) = self.quad_group(page, commands.records()) {
                    pass.set_bind_group(1, &group, &[]);
                    commands.draw_page(&mut pass, page);
                }
            }
        }
        let pairs = self.cull.layout().smooth_pairs;
        if pairs > 0 && self.has_smooth() {
            pass.set_pipeline(if self.wireframe {
                &self.pipelines.smooth_gbuffer_wire
            } else {
                &self.pipelines.smooth_gbuffer
            });
            pass.set_bind_group(0, frame_group, &[]);
            for pair in 0..pairs {
                if let Some(group) = self.smooth_group(pair, commands) {
                    pass.set_bind_group(1, &group, &[]);
                    commands.draw_smooth_pair(&mut pass, pair);
                }
            }
        }
        if let (Some(raster), Some(group)) = (&self.far_raster, far_group) {
            raster.draw_opaque(&mut pass, frame_group, group);
        }
    }

    /// The transparent pass: the raster far draws' transparent blocks when `far_group` is
    /// given (they are behind every meshed node), then the ordered cull's commands, one
    /// multi-draw per quad page, blended into the HDR target over the lit opaque image
    /// (depth-tested, not written).
    pub(super) fn record_transparent(
        &self,
        encoder: &mut CommandEncoder,
        frame_group: &BindGroup,
        far_group: Option<&BindGroup>,
    ) {
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
        if let (Some(raster), Some(group)) = (&self.far_raster, far_group) {
            raster.draw_transparent(&mut pass, frame_group, group);
        }
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

    /// Whether the full-screen passes are compute dispatches (else fragment passes).
    pub(super) fn fullscreen_in_compute(&self) -> bool {
        matches!(
            self.pipelines.fullscreen,
            FullscreenPipelines::Compute { .. }
        )
    }

    /// The lighting pass (`tonemap = false`: G-buffer and far visibility to HDR) or the
    /// tonemap pass (HDR to the output): a fragment pass, or a dispatch in the chain's
    /// compute pass.
    pub(super) fn record_fullscreen(
        &self,
        chain: &mut PassChain<'_>,
        frame_group: &BindGroup,
        tonemap: bool,
    ) {
        let t = &self.targets;
        let texture = |binding, view| wgpu::BindGroupEntry {
            binding,
            resource: wgpu::BindingResource::TextureView(view),
        };
        let compute = self.fullscreen_in_compute();
        let (visibility, transparent) = match &self.splat {
            Some(splat) => (splat.visibility(), splat.transparent()),
            None => (&self.no_visibility, &self.no_visibility),
        };
        let (layout, mut entries) = if tonemap {
            (&self.pipelines.hdr_read_layout, vec![texture(3, &t.hdr)])
        } else {
            (
                &self.pipelines.gbuffer_read_layout,
                vec![
                    texture(0, &t.albedo),
                    texture(1, &t.normal),
                    texture(2, &t.depth),
                    buffer_entry(4, visibility),
                    buffer_entry(5, transparent),
                ],
            )
        };
        if compute {
            entries.push(if tonemap {
                texture(7, &t.output_storage)
            } else {
                texture(6, &t.hdr)
            });
        }
        let group = self.bind_cache.get(
            &self.device,
            if tonemap { "hdr read" } else { "gbuffer read" },
            layout,
            &entries,
        );
        let label = if tonemap { "tonemap" } else { "lighting" };
        match &self.pipelines.fullscreen {
            FullscreenPipelines::Fragment {
                lighting,
                tonemap: tone,
            } => {
                let target = if tonemap { &t.output } else { &t.hdr };
                let mut pass = crate::fullscreen::fullscreen_pass(chain.encoder(), label, target);
                pass.set_pipeline(if tonemap { tone } else { lighting });
                pass.set_bind_group(0, frame_group, &[]);
                pass.set_bind_group(1, &group, &[]);
                pass.draw(0..3, 0..1);
            }
            FullscreenPipelines::Compute {
                lighting,
                tonemap: tone,
            } => {
                let pass = chain.compute();
                pass.set_pipeline(if tonemap { tone } else { lighting });
                pass.set_bind_group(0, frame_group, &[]);
                pass.set_bind_group(1, &group, &[]);
                pass.dispatch_workgroups(t.width.div_ceil(8), t.height.div_ceil(8), 1);
            }
        }
    }
}
