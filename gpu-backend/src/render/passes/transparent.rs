//! The transparent pass (`transparent.wgsl`): the raster far draws' transparent blocks (they
//! are behind every meshed node), then the transparent greedy quads of the ordered cull's
//! commands, one multi-draw per quad page, lit forward with the deferred lighting model and
//! blended into the HDR target over the lit opaque image (depth-tested, not written). The
//! order (chunks back to front, faces within a chunk unsorted) and its artefacts are
//! `render_model::transparent`'s; the colour of a layer (depth tint of volumes, Fresnel sky
//! reflection, sun highlight) is `render_model::lighting::surface`'s, premultiplied, so the
//! blend is `src + dst * (1 - src.a)`.
//!
//! The G-buffer depth is the pass's depth attachment, read-only, and is bound as a texture
//! too (group 2): a volume (water) is tinted by the distance from its surface to the opaque
//! surface behind, for the raster far draws' transparent blocks as for the quads.
//!
//! | group | bindings                                            |
//! | ----- | --------------------------------------------------- |
//! | 0     | the frame (`Shared::frame_layout`)                  |
//! | 1     | the quad page (`Shared::quad_layout`)               |
//! | 2     | 0 the opaque depth (the depth attachment, read-only) |
//!
//! Transparent quads are not grown like opaque ones (see the G-buffer pass): an overlap would
//! be blended twice. Splatted far blocks and compute-rasterised quads are not in the depth
//! attachment, so `fs_transparent_over_visibility` also hides the quads behind the opaque
//! visibility buffer.

use wgpu::{BindGroup, BindGroupLayout, BlendState, ColorTargetState, Device, RenderPipeline};

use super::cull::CullOutput;
use super::far_raster::FarRasterDraw;
use super::frame::{FrameCtx, Recorder};
use super::shared::{PipelineDesc, Shared, depth_state, pipeline_with_groups};
use super::targets::HDR_FORMAT;
use crate::shaders::TRANSPARENT;

/// The transparent pass (see the [module docs](self)).
#[derive(Debug)]
pub struct TransparentPass {
    depth_layout: BindGroupLayout,
    pipeline: RenderPipeline,
}

impl TransparentPass {
    /// Compiles the pass's shader and builds its pipeline.
    pub fn new(device: &Device, shared: &Shared) -> TransparentPass {
        let module = TRANSPARENT.create_module(device);
        let depth_layout = shared.opaque_depth_layout.clone();
        let pipeline = pipeline_with_groups(
            device,
            PipelineDesc {
                label: "transparent quads",
                module: &module,
                vertex: "vs_quad_transparent",
                fragment: "fs_transparent_over_visibility",
                groups: [&shared.frame_layout, &shared.quad_layout],
                targets: &[Some(ColorTargetState {
                    format: HDR_FORMAT,
                    // transparent_colour is premultiplied (lighting::surface).
                    blend: Some(BlendState::PREMULTIPLIED_ALPHA_BLENDING),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
                depth: depth_state(false),
                cull_back: true,
            },
            &[&depth_layout],
        );
        TransparentPass {
            depth_layout,
            pipeline,
        }
    }

    /// Records the pass, timed as `transparent`: the ordered cull's `commands`, and the raster
    /// far draws' transparent blocks (`far`, with the bind group their commands were recorded
    /// with) first.
    pub fn record(
        &self,
        ctx: &FrameCtx<'_>,
        rec: &mut Recorder<'_, '_>,
        commands: &CullOutput,
        far: Option<(&FarRasterDraw<'_>, &BindGroup)>,
    ) {
        let t = ctx.targets;
        let depth_group = ctx.shared.bind_cache.get(
            ctx.device,
            "transparent depth",
            &self.depth_layout,
            &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&t.depth),
            }],
        );
        rec.step("transparent", false, |rec| {
            let mut pass = t.begin_hdr_over_depth(rec.encoder(), "transparent");
            if let Some((far, group)) = far {
                far.draw_transparent(&mut pass, ctx.frame_group, group, &depth_group);
            }
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, ctx.frame_group, &[]);
            pass.set_bind_group(2, &depth_group, &[]);
            pass.set_index_buffer(ctx.shared.quad_indices.slice(..), wgpu::IndexFormat::Uint32);
            for page in 0..commands.layout().page_count {
                let group =
                    ctx.shared
                        .quad_group(ctx.residency, page, commands.records(), ctx.visibility);
                if let Some(group) = group {
                    pass.set_bind_group(1, &group, &[]);
                    commands.draw_page(&mut pass, page);
                }
            }
        });
    }
}
