//! The G-buffer pass: a phase's opaque surfaces into the G-buffer (`gbuffer.wgsl`): the cull's
//! commands of greedy quads, one multi-draw per quad page (unless the compute rasteriser drew
//! them), then the smooth quads per page pair, then the raster far draws' opaque blocks.
//!
//! **Vertex pulling.** No vertex buffers. A greedy quad (`PackedQuad`, 8 bytes) becomes 4
//! corners in `vs_quad`: the shared quad index buffer gives `vertex_index = 4 * quad + slot`,
//! the cull pass's `base_vertex` puts `quad` in the bound page, and the record at
//! `instance_index` (the command's `first_instance`) holds the chunk. The AO diagonal flip of
//! the mesher (`mesher::blocky::triangle_indices`) is applied by renaming slot `k` to corner
//! `(k + flip) & 3`. Smooth quads (4 indices into the chunk's `BlockVertex`es) are expanded
//! with `vertex_index / 6` = quad and `[0, 1, 2, 0, 2, 3][vertex_index % 6]` = corner, read with
//! FORMATS_WGSL's `smooth_quad_word` / `smooth_quad_corner` in the form the mesher chose.
//!
//! **T-junctions.** Greedy quads of different sizes meet at T-junctions, where the rasterizer
//! can leave pinholes (seen on lavapipe: single sky pixels inside terrain). `vs_quad` grows
//! each opaque quad in its own plane by a hair (1/64 pixel at its distance, at least 1/4096
//! block) so neighbours overlap. The price is a sliver that thin past convex edges, which a
//! pixel centre hits rarely (the image tests skip depth and colour at creases for that reason;
//! a hair of 1/8192 of the distance, 1/10 pixel at 1080p, flipped a few percent of the pixels
//! of far terrain whose blocks are about a pixel wide).
//!
//! **Clears.** The colour targets are never cleared: lighting reads them only where the depth
//! says this frame drew there (depth > 0, nearer than the visibility buffer). A clear is a
//! full-screen fill, slow on GPUs with few raster units (the H100 and H200); only the depth is
//! cleared, by the early phase. On the compute opaque
//! path with no smooth layer and no raster far draws nothing is rasterised: the pass only
//! clears the depth, which stays clear until a pass draws, so it is skipped then.

use std::cell::Cell;

use wgpu::{Device, RenderPipeline};

use super::cull::CullOutput;
use super::far_raster::FarRasterDraw;
use super::frame::{FrameCtx, Phase, Recorder};
use super::shared::{PipelineDesc, Shared, depth_state, pipeline};
use super::targets::{ALBEDO_FORMAT, NORMAL_FORMAT};
use crate::shaders::GBUFFER;

/// The G-buffer pass (see the [module docs](self)).
#[derive(Debug)]
pub struct GbufferPass {
    /// Opaque greedy quads into the G-buffer.
    quads: RenderPipeline,
    /// Smooth quads into the G-buffer.
    smooth: RenderPipeline,
    /// The wireframe view of `quads`: only the quads' edges.
    quads_wire: RenderPipeline,
    /// The wireframe view of `smooth`.
    smooth_wire: RenderPipeline,
    /// The depth attachment holds only the clear value (no G-buffer pass drew since the last
    /// clear), so a phase that draws nothing may skip the pass.
    depth_clear: Cell<bool>,
}

impl GbufferPass {
    /// Compiles the pass's shader and builds its pipelines.
    pub fn new(device: &Device, shared: &Shared) -> GbufferPass {
        let module = GBUFFER.create_module(device);
        let targets = [Some(ALBEDO_FORMAT.into()), Some(NORMAL_FORMAT.into())];
        // Depth written, back faces culled (the wireframe views too: they show what the
        // filled views show).
        let surface = |label, vertex, fragment, group| {
            pipeline(
                device,
                PipelineDesc {
                    label,
                    module: &module,
                    vertex,
                    fragment,
                    groups: [&shared.frame_layout, group],
                    targets: &targets,
                    depth: depth_state(true),
                    cull_back: true,
                },
            )
        };
        GbufferPass {
            quads: surface(
                "quads to gbuffer",
                "vs_quad",
                "fs_gbuffer",
                &shared.quad_layout,
            ),
            smooth: surface(
                "smooth to gbuffer",
                "vs_smooth",
                "fs_gbuffer",
                &shared.smooth_layout,
            ),
            quads_wire: surface(
                "quads to gbuffer, wireframe",
                "vs_quad_wire",
                "fs_gbuffer_wire",
                &shared.quad_layout,
            ),
            smooth_wire: surface(
                "smooth to gbuffer, wireframe",
                "vs_smooth_wire",
                "fs_gbuffer_wire",
                &shared.smooth_layout,
            ),
            depth_clear: Cell::new(false),
        }
    }

    /// Forgets that the depth holds only its clear value (new targets).
    pub fn targets_changed(&self) {
        self.depth_clear.set(false);
    }

    /// Another pass (the grass) drew into the depth: the next early phase clears it.
    pub fn depth_drawn(&self) {
        self.depth_clear.set(false);
    }

    /// Records `phase`'s G-buffer pass of `commands`, timed as `gbuffer` (`gbuffer late`):
    /// clearing the depth first in the early phase, drawing over it in the late one.
    /// `far` draws the raster far draws' opaque blocks of the phase (their commands are
    /// recorded in the same scope).
    pub fn record(
        &self,
        ctx: &FrameCtx<'_>,
        rec: &mut Recorder<'_, '_>,
        phase: Phase,
        commands: &CullOutput,
        far: Option<FarRasterDraw<'_>>,
    ) {
        let late = phase == Phase::Late;
        let draws = !ctx.quads_in_compute || ctx.residency.has_smooth() || far.is_some();
        if !draws && (late || self.depth_clear.get()) {
            return;
        }
        rec.step(phase.label("gbuffer", "gbuffer late"), false, |rec| {
            let encoder = rec.encoder();
            let far_group = far.as_ref().and_then(|f| f.record_phase_args(encoder));
            let far = far.as_ref().zip(far_group.as_ref());
            self.draw(ctx, encoder, commands, !late, far);
        });
        self.depth_clear.set(!draws);
    }

    /// The render pass: the depth cleared first (`clear_first`) or drawn over.
    fn draw(
        &self,
        ctx: &FrameCtx<'_>,
        encoder: &mut wgpu::CommandEncoder,
        commands: &CullOutput,
        clear_first: bool,
        far: Option<(&FarRasterDraw<'_>, &wgpu::BindGroup)>,
    ) {
        let t = ctx.targets;
        let attachment = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("gbuffer"),
            color_attachments: &[attachment(&t.albedo), attachment(&t.normal)],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &t.depth,
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
        let layout = commands.layout();
        // On the compute opaque path the quads went to the visibility buffer instead.
        if !ctx.quads_in_compute {
            pass.set_pipeline(if ctx.wireframe {
                &self.quads_wire
            } else {
                &self.quads
            });
            pass.set_bind_group(0, ctx.frame_group, &[]);
            pass.set_index_buffer(ctx.shared.quad_indices.slice(..), wgpu::IndexFormat::Uint32);
            for page in 0..layout.page_count {
                let group =
                    ctx.shared
                        .quad_group(ctx.residency, page, commands.records(), ctx.visibility);
                if let Some(group) = group {
                    pass.set_bind_group(1, &group, &[]);
                    commands.draw_page(&mut pass, page);
                }
            }
        }
        if layout.smooth_pairs > 0 && ctx.residency.has_smooth() {
            pass.set_pipeline(if ctx.wireframe {
                &self.smooth_wire
            } else {
                &self.smooth
            });
            pass.set_bind_group(0, ctx.frame_group, &[]);
            for pair in 0..layout.smooth_pairs {
                let group = ctx.shared.smooth_group(
                    ctx.residency,
                    pair,
                    layout.smooth.quad_pages,
                    commands.smooth_records(),
                );
                if let Some(group) = group {
                    pass.set_bind_group(1, &group, &[]);
                    commands.draw_smooth_pair(&mut pass, pair);
                }
            }
        }
        if let Some((far, group)) = far {
            far.draw_opaque(&mut pass, ctx.frame_group, group);
        }
    }
}
