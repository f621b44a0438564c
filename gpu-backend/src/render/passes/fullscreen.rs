//! What the full-screen passes share (lighting, tonemap, present blit): how they run
//! ([`FullscreenPath`]), their pipeline of either kind ([`FullscreenPipeline`]), and the render
//! pass of one colour target they draw a single covering triangle into.

use wgpu::{BindGroup, BindGroupLayout, Device, ShaderModule, ShaderStages, TextureFormat};

use super::frame::Recorder;
use super::shared::{PipelineDesc, compute_pipeline, pipeline};

/// How the full-screen passes (lighting, tonemap) run: the same per-pixel function either way.
/// On compute-heavy GPUs (the H100 rasterises through a few units) compute is faster; see
/// BENCHMARKS.md for the measured pair.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FullscreenPath {
    /// A full-screen triangle per pass.
    Fragment,
    /// 8 x 8-pixel workgroups writing storage textures.
    #[default]
    Compute,
}

impl FullscreenPath {
    /// The shader stages that read a full-screen pass's bindings on this path.
    pub fn stages(self) -> ShaderStages {
        match self {
            FullscreenPath::Fragment => ShaderStages::FRAGMENT,
            FullscreenPath::Compute => ShaderStages::COMPUTE,
        }
    }
}

/// One full-screen pass's pipeline on one [`FullscreenPath`].
#[derive(Debug)]
pub enum FullscreenPipeline {
    /// A fragment pipeline drawing `vs_fullscreen`'s triangle.
    Fragment(wgpu::RenderPipeline),
    /// A compute pipeline of 8 x 8-pixel workgroups.
    Compute(wgpu::ComputePipeline),
}

impl FullscreenPipeline {
    /// The pipeline of `module`'s entry points `(fragment, compute)` on `path`, binding
    /// `groups`; the fragment form writes one target of `format`.
    pub fn new(
        device: &Device,
        path: FullscreenPath,
        label: &str,
        module: &ShaderModule,
        (fragment, compute): (&str, &str),
        groups: [&BindGroupLayout; 2],
        format: TextureFormat,
    ) -> FullscreenPipeline {
        match path {
            FullscreenPath::Fragment => FullscreenPipeline::Fragment(pipeline(
                device,
                PipelineDesc {
                    label,
                    module,
                    vertex: "vs_fullscreen",
                    fragment,
                    groups,
                    targets: &[Some(format.into())],
                    depth: None,
                    cull_back: false,
                },
            )),
            FullscreenPath::Compute => FullscreenPipeline::Compute(compute_pipeline(
                device, label, module, compute, &groups,
            )),
        }
    }

    /// The path this pipeline runs on.
    pub fn path(&self) -> FullscreenPath {
        match self {
            FullscreenPipeline::Fragment(_) => FullscreenPath::Fragment,
            FullscreenPipeline::Compute(_) => FullscreenPath::Compute,
        }
    }

    /// Records the pass over a `size` screen: a render pass into `target` (fragment), or a
    /// dispatch into the recorder's open compute pass (compute; the shader writes its storage
    /// texture itself).
    pub fn record(
        &self,
        rec: &mut Recorder<'_, '_>,
        label: &str,
        target: &wgpu::TextureView,
        groups: [&BindGroup; 2],
        (width, height): (u32, u32),
    ) {
        match self {
            FullscreenPipeline::Fragment(pipeline) => {
                let mut pass = fullscreen_pass(rec.encoder(), label, target);
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, groups[0], &[]);
                pass.set_bind_group(1, groups[1], &[]);
                pass.draw(0..3, 0..1);
            }
            FullscreenPipeline::Compute(pipeline) => {
                let pass = rec.compute();
                pass.set_pipeline(pipeline);
                pass.set_bind_group(0, groups[0], &[]);
                pass.set_bind_group(1, groups[1], &[]);
                pass.dispatch_workgroups(width.div_ceil(8), height.div_ceil(8), 1);
            }
        }
    }
}

/// Begins a pass labelled `label` that draws into `target` alone: cleared to black first,
/// stored, no depth, no timestamps. Draw `0..3` with a full-screen-triangle vertex shader.
pub(crate) fn fullscreen_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    target: &wgpu::TextureView,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: target,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}
