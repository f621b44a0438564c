//! The prop draw (`props.wgsl`): one `draw_indexed_indirect` per batch from the batch records
//! the prop cull filled, into the G-buffer over the voxels' depth, and the blended (`BLEND`)
//! batches after the lighting, into the lit colour, back to front
//! ([`render_model::props::blend_order`]; see [`crate::render::props`] for the colour and alpha
//! rules). Vertex buffers hold the models' `PropVertex`es; the instance index is the batch's
//! `first_instance + k`, the `k`-th entry of its visible range naming the instance slot.

use wgpu::{BindGroup, BindGroupLayout, Device, RenderPipeline, ShaderStages};

use render_model::props::{PropEye, blend_order};

use super::frame::{FrameCtx, Recorder};
use super::shared::{bind_layout, buffer_layout_entry, depth_state};
use super::targets::{ALBEDO_FORMAT, HDR_FORMAT, NORMAL_FORMAT};
use crate::render::props::GpuProps;
use crate::shaders::PROPS;

/// The prop draw's pipelines: into the G-buffer and blended into the lit colour, each with
/// back faces culled and with both faces (double-sided materials).
#[derive(Debug)]
pub struct PropsPass {
    layout: BindGroupLayout,
    single: RenderPipeline,
    double: RenderPipeline,
    blend_single: RenderPipeline,
    blend_double: RenderPipeline,
}

const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 3] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2];

impl PropsPass {
    /// Compiles the shader and builds the pipelines; `frame_layout` is the renderer's group 0,
    /// `material_layout` the props' group 2.
    pub fn new(
        device: &Device,
        frame_layout: &BindGroupLayout,
        material_layout: &BindGroupLayout,
    ) -> PropsPass {
        use wgpu::BufferBindingType as B;
        let v = ShaderStages::VERTEX;
        let layout = bind_layout(
            device,
            "prop instances",
            &[
                buffer_layout_entry(0, v, B::Uniform),
                buffer_layout_entry(1, v, B::Storage { read_only: true }),
                buffer_layout_entry(2, v, B::Storage { read_only: true }),
            ],
        );
        let module = PROPS.create_module(device);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("props"),
            bind_group_layouts: &[Some(frame_layout), Some(&layout), Some(material_layout)],
            immediate_size: 0,
        });
        let gbuffer = [Some(ALBEDO_FORMAT.into()), Some(NORMAL_FORMAT.into())];
        // fs_prop_blend's colour is premultiplied.
        let blended = [Some(wgpu::ColorTargetState {
            format: HDR_FORMAT,
            blend: Some(wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING),
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let make = |cull_mode, blend: bool| {
            let (label, fragment, targets, write): (_, _, &[Option<wgpu::ColorTargetState>], _) =
                if blend {
                    ("blended props", "fs_prop_blend", &blended, false)
                } else {
                    ("props to gbuffer", "fs_prop", &gbuffer, true)
                };
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_prop"),
                    compilation_options: Default::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: 32,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &VERTEX_ATTRIBUTES,
                    })],
                },
                primitive: wgpu::PrimitiveState {
                    front_face: wgpu::FrontFace::Ccw,
                    cull_mode,
                    ..Default::default()
                },
                depth_stencil: depth_state(write),
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fragment),
                    compilation_options: Default::default(),
                    targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        PropsPass {
            single: make(Some(wgpu::Face::Back), false),
            double: make(None, false),
            blend_single: make(Some(wgpu::Face::Back), true),
            blend_double: make(None, true),
            layout,
        }
    }

    /// The instance bind group (group 1) of `props`' buffers, `None` before any exist.
    fn instance_group(&self, ctx: &FrameCtx<'_>, props: &GpuProps) -> Option<BindGroup> {
        let buffers = props.buffers()?;
        Some(ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("prop instances"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buffers.uniforms.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: buffers.instances.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: buffers.visible.as_entire_binding(),
                },
            ],
        }))
    }

    /// Records the blended batches of `props` seen from `eye`, back to front, into the lit
    /// colour over the opaque depth (read, not written), timed as `blended props`; nothing
    /// when no blended batch shows an instance.
    pub fn record_blend(
        &self,
        ctx: &FrameCtx<'_>,
        rec: &mut Recorder<'_, '_>,
        props: &GpuProps,
        eye: &PropEye,
    ) {
        let registry = props.registry();
        let order = blend_order(
            registry.batch_records(),
            registry.instance_records(),
            eye,
            |m| props.is_blended(m),
        );
        let (Some(buffers), Some(group)) = (props.buffers(), self.instance_group(ctx, props))
        else {
            return;
        };
        if order.is_empty() {
            return;
        }
        let t = ctx.targets;
        rec.step("blended props", false, |rec| {
            let mut pass = t.begin_hdr_over_depth(rec.encoder(), "blended props");
            pass.set_bind_group(0, ctx.frame_group, &[]);
            pass.set_bind_group(1, &group, &[]);
            for b in order {
                let batch = &registry.batch_records()[b as usize];
                let Some((model, draw)) = props.batch_draw(batch.material) else {
                    continue;
                };
                let pipeline = if draw.double_sided {
                    &self.blend_double
                } else {
                    &self.blend_single
                };
                pass.set_pipeline(pipeline);
                pass.set_bind_group(2, &draw.group, &[]);
                pass.set_vertex_buffer(0, model.vertices.slice(..));
                pass.set_index_buffer(model.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed_indirect(&buffers.batches, 48 * u64::from(b));
            }
        });
    }

    /// Records the draw of every batch of `props` (after its cull) but the blended ones,
    /// timed as `props`.
    pub fn record(&self, ctx: &FrameCtx<'_>, rec: &mut Recorder<'_, '_>, props: &GpuProps) {
        let (Some(buffers), Some(group)) = (props.buffers(), self.instance_group(ctx, props))
        else {
            return;
        };
        rec.step("props", false, |rec| {
            let mut pass = ctx.targets.begin_gbuffer_overlay(rec.encoder(), "props");
            pass.set_bind_group(0, ctx.frame_group, &[]);
            pass.set_bind_group(1, &group, &[]);
            for (b, batch) in props.registry().batch_records().iter().enumerate() {
                if batch.visible_count == 0 {
                    continue;
                }
                let Some((model, draw)) = props.batch_draw(batch.material) else {
                    continue;
                };
                if draw.blend {
                    continue;
                }
                pass.set_pipeline(if draw.double_sided {
                    &self.double
                } else {
                    &self.single
                });
                pass.set_bind_group(2, &draw.group, &[]);
                pass.set_vertex_buffer(0, model.vertices.slice(..));
                pass.set_index_buffer(model.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed_indirect(&buffers.batches, 48 * b as u64);
            }
        });
    }
}
