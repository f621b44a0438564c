//! Drawing into a host engine's own colour and depth targets.
//!
//! The renderer is deferred: it lights its own G-buffer into its own output. An engine that
//! owns the frame gives [`HostPass::record`] its colour texture and, optionally, its depth
//! texture; the pass records the renderer's frame, then one full-screen pass that writes the
//! renderer's output into the host's colour target where the renderer drew something (sky
//! pixels keep the host's colour) and, with a depth target, the same surface's depth in the
//! host's convention, tested against what the host drew before:
//!
//! ```text
//!  host: draws its scene into colour + depth
//!  HostPass::record(renderer, encoder, &HostTargets { colour, depth })
//!     renderer.record_frame(encoder)           G-buffer, lighting, transparent, tonemap
//!     composite: colour (load) ◄─ output, depth (load, test + write) ◄─ near / depth
//!  host: draws more (UI, effects), submits, presents
//! ```
//!
//! Both cameras must agree: the host sets the renderer's [`Camera`](render_model::Camera)
//! to its own eye, orientation and vertical field of view, and passes its projection so the
//! depths can be converted ([`HostDepth`]). The colour written is the renderer's tonemapped
//! output (linear values from its sRGB view: an sRGB host target stores the same bytes). The
//! depth written is the opaque surface's; a pixel showing only transparent faces over sky
//! keeps the host's colour. The host's targets must be single-sampled and of the renderer's
//! size.

use std::collections::HashMap;
use std::fmt;

use wgpu::{
    BindGroupLayout, CommandEncoder, CompareFunction, Device, RenderPipeline, Texture,
    TextureFormat, TextureUsages,
};

use super::{RenderError, Renderer};
use crate::device::GpuContext;
use crate::device::alloc::{self, AllocError};
use crate::shaders::ShaderSpec;

/// The composite shader (`shaders/host_composite.wgsl`).
pub const HOST_COMPOSITE: ShaderSpec = ShaderSpec {
    capabilities: naga::valid::Capabilities::empty(),
    name: "host_composite",
    body: include_str!("../shaders/host_composite.wgsl"),
};

/// A host's depth target and how it encodes depth.
#[derive(Clone, Copy, Debug)]
pub struct HostDepth<'a> {
    /// The depth texture (a depth format, `RENDER_ATTACHMENT`).
    pub texture: &'a Texture,
    /// The host's column-major projection (right-handed, looking along -z in view space, as
    /// `glam::Mat4::perspective_rh` builds it): the depth of view distance `z` is
    /// `clip.z / clip.w` of `projection * (0, 0, -z, 1)`.
    pub projection: [[f32; 4]; 4],
    /// The host's depth test (`Less` for standard depth, `Greater` for reversed-Z).
    pub compare: CompareFunction,
}

/// The targets of one [`HostPass::record`].
#[derive(Clone, Copy, Debug)]
pub struct HostTargets<'a> {
    /// The colour texture (`RENDER_ATTACHMENT`, a float-readable colour format).
    pub colour: &'a Texture,
    /// The depth target, if the renderer's surfaces are to be depth-tested against the host's.
    pub depth: Option<HostDepth<'a>>,
}

/// Why [`HostPass::record`] refused the targets.
#[derive(Debug)]
#[non_exhaustive]
pub enum HostError {
    /// A target's size differs from the renderer's.
    SizeMismatch {
        /// Which target.
        target: &'static str,
        /// Its size, pixels.
        size: (u32, u32),
        /// The renderer's size.
        renderer: (u32, u32),
    },
    /// A target cannot be drawn to as given: not a render attachment, multisampled, or a
    /// colour texture in a depth format (or the reverse).
    Unusable {
        /// Which target.
        target: &'static str,
        /// Its format.
        format: TextureFormat,
        /// What is wrong.
        reason: &'static str,
    },
    /// The renderer failed to record its frame.
    Render(RenderError),
    /// The device refused the pass's uniform buffer.
    Alloc(AllocError),
}

impl fmt::Display for HostError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HostError::SizeMismatch {
                target,
                size,
                renderer,
            } => write!(
                f,
                "the host's {target} target is {}x{}, the renderer's output {}x{}",
                size.0, size.1, renderer.0, renderer.1
            ),
            HostError::Unusable {
                target,
                format,
                reason,
            } => write!(f, "the host's {target} target ({format:?}) {reason}"),
            HostError::Render(e) => write!(f, "the renderer failed: {e}"),
            HostError::Alloc(e) => write!(f, "the host pass: {e}"),
        }
    }
}

impl std::error::Error for HostError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            HostError::Render(e) => Some(e),
            _ => None,
        }
    }
}

/// The uniforms of the composite shader (`HostDepthUniforms`).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct HostUniforms {
    near: f32,
    a: f32,
    b: f32,
    c: f32,
    d: f32,
    _pad: [f32; 3],
}

/// Pipelines keyed by the host's colour format and depth format and test.
type PipelineKey = (TextureFormat, Option<(TextureFormat, CompareFunction)>);

/// The composite pass into host targets (see the [module docs](self)); one per device, its
/// pipelines made on first use for each combination of target formats.
#[derive(Debug)]
pub struct HostPass {
    layout: BindGroupLayout,
    uniforms: wgpu::Buffer,
    pipelines: HashMap<PipelineKey, RenderPipeline>,
}

impl HostPass {
    /// The pass on the context's device (the renderer's, i.e. the host's).
    pub fn new(ctx: &GpuContext) -> Result<HostPass, HostError> {
        let device = &ctx.device;
        let texture = |binding, sample_type| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Texture {
                sample_type,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("host composite"),
            entries: &[
                texture(0, wgpu::TextureSampleType::Float { filterable: false }),
                texture(1, wgpu::TextureSampleType::Depth),
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
            ],
        });
        let uniforms = alloc::create_buffer(
            device,
            &wgpu::BufferDescriptor {
                label: Some("host composite uniforms"),
                size: size_of::<HostUniforms>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            },
        )
        .map_err(HostError::Alloc)?;
        Ok(HostPass {
            layout,
            uniforms,
            pipelines: HashMap::new(),
        })
    }

    /// Records `renderer`'s frame into `encoder`, then draws its output into `targets`
    /// (loading what the host drew there). Submit the encoder afterwards, as with
    /// [`Renderer::record_frame`], before the next `record` (the pass's uniforms are written
    /// through the queue).
    pub fn record(
        &mut self,
        ctx: &GpuContext,
        renderer: &mut Renderer,
        encoder: &mut CommandEncoder,
        targets: &HostTargets<'_>,
    ) -> Result<(), HostError> {
        let size = (renderer.targets().width, renderer.targets().height);
        check_target("colour", targets.colour, size, false)?;
        if let Some(depth) = &targets.depth {
            check_target("depth", depth.texture, size, true)?;
        }
        renderer.record_frame(encoder).map_err(HostError::Render)?;

        let p = targets.depth.map_or([[0.0; 4]; 4], |d| d.projection);
        let uniforms = HostUniforms {
            near: renderer.camera().near as f32,
            a: p[2][2],
            b: p[3][2],
            c: p[2][3],
            d: p[3][3],
            _pad: [0.0; 3],
        };
        let key: PipelineKey = (
            targets.colour.format(),
            targets.depth.map(|d| (d.texture.format(), d.compare)),
        );
        let device = &ctx.device;
        let layout = &self.layout;
        let pipeline = self
            .pipelines
            .entry(key)
            .or_insert_with(|| make_pipeline(device, layout, key));
        let rt = renderer.targets();
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("host composite"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&rt.output),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&rt.depth),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: self.uniforms.as_entire_binding(),
                },
            ],
        });
        ctx.queue
            .write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&uniforms));
        let colour_view = targets.colour.create_view(&Default::default());
        let depth_view = targets
            .depth
            .map(|d| d.texture.create_view(&Default::default()));
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("host composite"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &colour_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: depth_view.as_ref().map(|view| {
                wgpu::RenderPassDepthStencilAttachment {
                    view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }
            }),
            ..Default::default()
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.draw(0..3, 0..1);
        Ok(())
    }
}

/// `texture` is a single-sampled render attachment of `size`, a depth format exactly when
/// `depth`.
fn check_target(
    target: &'static str,
    texture: &Texture,
    size: (u32, u32),
    depth: bool,
) -> Result<(), HostError> {
    let format = texture.format();
    let unusable = |reason| {
        Err(HostError::Unusable {
            target,
            format,
            reason,
        })
    };
    if !texture.usage().contains(TextureUsages::RENDER_ATTACHMENT) {
        return unusable("lacks RENDER_ATTACHMENT usage");
    }
    if texture.sample_count() != 1 {
        return unusable("is multisampled");
    }
    if format.is_depth_stencil_format() != depth {
        return unusable(if depth {
            "is not a depth format"
        } else {
            "is a depth format"
        });
    }
    let has = (texture.width(), texture.height());
    if has != size {
        return Err(HostError::SizeMismatch {
            target,
            size: has,
            renderer: size,
        });
    }
    Ok(())
}

/// The composite pipeline for one combination of host formats.
fn make_pipeline(device: &Device, layout: &BindGroupLayout, key: PipelineKey) -> RenderPipeline {
    let (colour, depth) = key;
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("host composite"),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    let module = HOST_COMPOSITE.create_module(device);
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("host composite"),
        layout: Some(&pipeline_layout),
        vertex: wgpu::VertexState {
            module: &module,
            entry_point: Some("vs_host"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: depth.map(|(format, compare)| wgpu::DepthStencilState {
            format,
            depth_write_enabled: Some(true),
            depth_compare: Some(compare),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module: &module,
            entry_point: Some(if depth.is_some() {
                "fs_host_depth"
            } else {
                "fs_host_colour"
            }),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: colour,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_composite_shader_validates() {
        crate::shaders::validate(HOST_COMPOSITE.name, &HOST_COMPOSITE.source())
            .unwrap_or_else(|e| panic!("{e}"));
    }

    #[test]
    fn uniforms_match_the_wgsl_struct() {
        assert_eq!(size_of::<HostUniforms>(), 32);
    }
}
