//! Opaque greedy quads rasterised in compute, into the 64-bit visibility buffer the far splat
//! writes ([`far`](crate::render::far) states the word: reversed-Z depth bits above the payload, block
//! id in bits 0..16, face in 16..19, AO in 255ths of 3 in 19..27), so that the G-buffer's raster
//! pass can be skipped for the meshed nodes on GPUs with little fixed-function raster
//! throughput (see **Cost** below).
//!
//! # Integration
//!
//! [`Renderer`](crate::render::Renderer) draws its opaque quads this way with
//! `OpaquePath::Compute` (`RendererConfig::opaque`). What it does, and what any other caller
//! must do:
//!
//! 1. **Create**, where `GpuCapabilities::int64_atomics` holds:
//!    `QuadRaster::new(&device, &QuadRasterConfig::for_screen(width, height, 16))`
//!    ([`QuadRaster::new`], [`QuadRasterConfig::for_screen`]). It needs a visibility buffer:
//!    the far splat's ([`FarSplat::visibility`](super::far_splat::FarSplat::visibility)),
//!    which exists only on the splat far path; with another far path the renderer must make
//!    one (`width * height * 8` bytes, `STORAGE`), clear it each frame, bind it to the
//!    lighting pass and set `FRAME_SPLAT`, as the splat path does. On resize nothing is
//!    recreated: the next record makes bind groups for the new buffer (`QuadRaster::cached`
//!    counts them, with the test-support feature).
//! 2. **Each frame**, in encoder order:
//!    - the visibility buffer's clear ([`FarSplat::clear`](super::far_splat::FarSplat::clear)),
//!      and [`QuadRaster::clear_stats`] if the statistics are read;
//!    - per opaque phase (the early phase, and with occlusion culling the late one after the
//!      Hi-Z build), right after that phase's opaque cull record:
//!      [`QuadRaster::record`] with [`QuadRasterInputs`] naming the frame uniforms buffer, that
//!      phase's [`CullOutput`] (`opaque_commands`, or the late
//!      phase's `late_commands`), the quad [`Gigabuffer`], the
//!      visibility buffer and the screen size. Its order against the phase's far splat does
//!      not matter (both only `atomicMax` into the buffer);
//!    - that phase's G-buffer pass without the greedy-quad draws (`commands.draw_page`); the
//!      smooth layer and the raster far draws still draw there;
//!    - the Hi-Z build between the phases already reads the visibility buffer
//!      (`record_build(.., Some(visibility))`), so the early phase's quads occlude in the late
//!      cull with no change;
//!    - lighting resolves the nearer of the G-buffer and the visibility buffer (`FRAME_SPLAT`),
//!      unchanged.
//! 3. **Transparent quads** depth-test against the depth attachment, which no longer holds the
//!    meshed quads: before the transparent pass, write the visibility buffer's depth into it (a
//!    full-screen pass with `frag_depth = max(depth, bits >> 32)`), or test against the buffer
//!    in the transparent fragment shader (the renderer does the latter:
//!    `fs_transparent_over_visibility`).
//! 4. **Statistics** ([`QuadRasterStats`]): [`QuadRaster::read_stats`] after the submit (blocks).
//!
//! # How it works
//!
//! ```text
//!  cull (opaque) ─► CullOutput: per page p, args[p*C ..] + records[p*C ..], counts[p]
//!
//!  QuadRaster::record(encoder, inputs):
//!    clear list counters
//!    qr_page_args   1 thread per page: min(counts[p], C) workgroups, folded < 65535 per axis
//!    qr_quads       per created page, indirect: 1 workgroup per drawn command, 64 quads at a
//!                   time ─► small quads: pixels drawn here, balanced over the workgroup
//!                        ─► big quads:   RasterQuad list + one entry per 16 x 16 screen tile
//!    qr_tile_args   1 thread: tile entries ─► workgroups
//!    qr_tiles       indirect: 1 workgroup per tile entry, 4 pixels per invocation
//! ```
//!
//! **What is drawn.** For every drawn command of every page (`args[p*C + i]`, `i <
//! min(counts[p], C)`) every quad `base_vertex / 4 .. + index_count / 6` of the bound page is
//! rasterised exactly once per record, in the node of `records[first_instance]` (level-0
//! chunk difference, level). A quad's corners are `packed_quad_corner(q, k)` cells; its
//! camera-relative position is `(f32(chunk) * chunk_edge - camera_offset) + corner * 2^level`,
//! as `gbuffer.wgsl`'s `quad_vertex` places it. Each pixel whose centre ray
//! (`render_common`'s `pixel_ray`, whose parameter `t` is the view depth) hits the quad's
//! rectangle writes `atomicMax(visibility[y * W + x], bits(near / t) << 32 | payload)`:
//!
//! - *hit*: the ray runs against the quad's outward normal (back faces draw nothing), meets
//!   its plane at `near < t < 10^30`, and the point lies in the rectangle grown by the
//!   G-buffer's T-junction hair on every side: `eps = t * (1/64 pixel per block of distance) +
//!   1/4096 block` (inclusive edges; neighbours overlap by the hair, so no pinholes where
//!   greedy quads meet at T-junctions, and a pixel centre within the hair past a convex edge
//!   sees the quad, as it does on the raster path);
//! - *AO*: the 4 corner values (`packed_quad_ao`), the triangles `(0, 1, 2), (0, 2, 3)`, or
//!   every corner index + 1 when `ao1 + ao3 > ao0 + ao2` (`mesher::blocky::triangle_indices`,
//!   the raster path's flip), interpolated barycentrically in the quad's plane (what the
//!   raster path's perspective-correct interpolation gives), then `round(ao / 3 * 255)`.
//!
//! [`render_model::quad_raster::reference`] is the CPU twin of every decision, in the same `f32` operations.
//!
//! **Work balance.** A quad's *box* is the pixel-centre bounding box of its projection (the
//! rectangle grown by twice the largest hair it can use, clipped at the near plane, padded by
//! 1/8 pixel). Quads whose box holds at most `LOCAL_MAX_PIXELS` (256) pixel centres are drawn
//! by the workgroup that set them up: a prefix sum over the 64 boxes of a batch, then each
//! invocation takes every 64th pixel of the concatenation (a 6-step binary search finds its
//! quad), so a batch of mixed sizes costs `ceil(sum / 64)` steps per invocation whatever the
//! mix. Larger quads go to the tile list: their `RasterQuad` (32 bytes) and one 8-byte entry
//! per `TILE` x `TILE` screen tile their box touches, written by the whole workgroup; the
//! tiles pass gives each entry a workgroup (4 pixels per invocation). So no invocation tests
//! more than 256 pixels per batch, and a quad covering the whole screen (8,160 tiles at
//! 1920 x 1080) is spread over 8,160 workgroups.
//!
//! **Nothing dropped.** The tile list holds [`QuadRasterConfig::tile_capacity`] entries
//! (default: 16 screens of tiles); a batch takes room for the longest run of its big quads that
//! fits (one compare-and-swap), and the big quads that do not fit are drawn by their own
//! workgroup (counted in [`QuadRasterStats::overflow`]; correct but slow for screen-sized quads:
//! raise the capacity if it is not 0). A big quad touches at least 2 tiles, so the big-quad list
//! (`ceil(tile_capacity / 2)` entries) is never full before the tile list. Counters cannot wrap:
//! the tile counter never passes the capacity. Quad pages not yet created hold no quads, so no
//! command names them.
//!
//! **Cost.** `BENCHMARKS.md` has this pass and the G-buffer raster pass measured side by side
//! on the GPU machine, whose few raster units bound the raster pass by geometry. Per quad, one 8-byte read, the setup (2 corners, 8 matrix-vector products for the box, a
//! near clip), a 6-step workgroup scan per batch of 64 (12 barriers) and a compare-and-swap per
//! batch with big quads; per pixel centre tested, the binary search (6 shared loads) or the
//! tile's bounds, the ray (3 multiply-adds per component), one division for `t`, 2 multiplies
//! and 4 compares for coverage, and on a hit the AO, one division for the depth and one 64-bit
//! `atomicMax`. Tested pixels exceed hits by the box's slack: about 2x for a quad seen
//! obliquely, up to its box/area ratio for long thin diagonal quads, plus tile overhang; the
//! tests print both counts ([`QuadRasterStats::tested_pixels`], [`QuadRasterStats::hits`]).
//! Atomics to one pixel from several quads serialise only where quads overlap on screen
//! (overdraw), as in the far splat. A record is `4 + pages` dispatches, 2 of them of one
//! workgroup. Whether this beats the raster pass depends on the GPU's raster units: the
//! renderer measures both on its device (`OpaquePath::Auto`).
//!
//! **Precision.** All in camera-relative `f32` (see [`render_model::camera`]): no large
//! coordinate is ever an `f32`. A GPU that fuses multiply-adds may decide a pixel centre within
//! about 2^-16 of the magnitudes involved of a (grown) edge or of the near plane differently
//! from the CPU twin (`render_model::quad_raster::PixelSample::ambiguous`), and its depth bits and AO byte may differ by
//! the rounding of those operations; the GPU tests (`tests/gpu_quad_raster.rs`) state and check
//! the bounds against the twin, and `tests/gpu_quad_raster_gbuffer.rs` against the G-buffer
//! raster pass drawing the same quads (depth, face, block and AO per pixel, with a cap on
//! differing pixels).

mod cache;
mod error;
mod pipelines;

pub use error::QuadRasterError;

use std::sync::Mutex;

use wgpu::{BindGroup, Buffer, BufferUsages, CommandEncoder, Device, Features, Queue};

use cache::{Cache, Maker};

use super::cull::CullOutput;
use super::frame::{FrameCtx, Phase, Recorder};
use crate::readback::{ReadbackError, read_buffer};
use crate::residency::Gigabuffer;
use pipelines::{Layouts, Pipelines};
use render_model::frame::FrameUniforms;
use render_model::quad_raster::QuadRasterStats;
use render_model::quad_raster::{
    FIRST_STAT_WORD, MAX_GROUPS, MAX_SCREEN_EDGE, PageArgs, QuadRasterConfig, STATE_WORDS,
};

/// What a record reads and writes besides the rasteriser's own buffers.
#[derive(Clone, Copy, Debug)]
pub struct QuadRasterInputs<'a> {
    /// The frame uniforms ([`FrameUniforms`]: camera-relative view-projection, camera offset,
    /// chunk edge, the scaled camera basis, near, width, height), a `UNIFORM` buffer.
    pub frame_uniforms: &'a Buffer,
    /// The opaque layer's cull output, recorded earlier in the same encoder.
    pub commands: &'a CullOutput,
    /// The gigabuffer whose quad pages the commands name.
    pub quads: &'a Gigabuffer,
    /// The visibility buffer: `width * height` 64-bit words, row-major, `STORAGE`.
    pub visibility: &'a Buffer,
    /// The screen's width: the frame uniforms' `width`.
    pub width: u32,
    /// The screen's height: the frame uniforms' `height`.
    pub height: u32,
}

/// The compute rasteriser of opaque greedy quads (see the [module docs](super)).
#[derive(Debug)]
pub struct QuadRaster {
    device: Device,
    config: QuadRasterConfig,
    layouts: Layouts,
    pipelines: Pipelines,
    state: Buffer,
    tile_dispatch: Buffer,
    lists: BindGroup,
    stride: u64,
    cache: Mutex<Cache>,
}

impl QuadRaster {
    /// The rasteriser's pipelines and lists on `device`, which must have been created with
    /// `SHADER_INT64` and `SHADER_INT64_ATOMIC_MIN_MAX` (`GpuCapabilities::int64_atomics`).
    /// The lists take [`QuadRasterConfig::tile_bytes`] + [`QuadRasterConfig::big_bytes`].
    pub fn new(device: &Device, config: &QuadRasterConfig) -> Result<QuadRaster, QuadRasterError> {
        let needed = Features::SHADER_INT64 | Features::SHADER_INT64_ATOMIC_MIN_MAX;
        if !device.features().contains(needed) {
            return Err(QuadRasterError::MissingInt64Atomics);
        }
        let limits = device.limits();
        let max_bytes = limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size);
        for (list, bytes) in [
            ("tile", config.tile_bytes()),
            ("big-quad", config.big_bytes()),
        ] {
            if bytes == 0 || bytes > max_bytes {
                return Err(QuadRasterError::BadCapacity {
                    list,
                    bytes,
                    max_bytes,
                });
            }
        }
        let layouts = Layouts::new(device);
        let pipelines = Pipelines::new(device, &layouts);
        let buffer = |label, size, usage| {
            crate::device::alloc::create_buffer(
                device,
                &wgpu::BufferDescriptor {
                    label: Some(label),
                    size,
                    usage,
                    mapped_at_creation: false,
                },
            )
        };
        let storage = BufferUsages::STORAGE;
        let state = buffer(
            "quad raster state",
            u64::from(STATE_WORDS) * 4,
            storage | BufferUsages::COPY_DST | BufferUsages::COPY_SRC,
        )?;
        let bigs = buffer("quad raster big quads", config.big_bytes(), storage)?;
        let tiles = buffer("quad raster tiles", config.tile_bytes(), storage)?;
        let tile_dispatch = buffer(
            "quad raster tile dispatch",
            16,
            storage | BufferUsages::INDIRECT,
        )?;
        let lists = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("quad raster lists"),
            layout: &layouts.lists,
            entries: &[
                crate::bind::buffer_entry(0, &state),
                crate::bind::buffer_entry(1, &bigs),
                crate::bind::buffer_entry(2, &tiles),
            ],
        });
        let align = u64::from(limits.min_storage_buffer_offset_alignment.max(1));
        let stride = (size_of::<PageArgs>() as u64).div_ceil(align) * align;
        Ok(QuadRaster {
            device: device.clone(),
            config: *config,
            layouts,
            pipelines,
            state,
            tile_dispatch,
            lists,
            stride,
            cache: Mutex::new(Cache::default()),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &QuadRasterConfig {
        &self.config
    }

    /// The state words (`render_model::quad_raster::StateWord`): list counters and statistics.
    pub fn state(&self) -> &Buffer {
        &self.state
    }

    /// Cached bind groups: (frame pairs, cull outputs), each at most 4 (tests of the cache).
    #[cfg(feature = "test-support")]
    pub fn cached(&self) -> (usize, usize) {
        self.cache.lock().unwrap_or_else(|e| e.into_inner()).sizes()
    }

    /// Records the rasterisation of every drawn command of `inputs.commands` into
    /// `inputs.visibility` (which the caller clears once per frame, like the far splat's): one
    /// compute pass of [`record_in`](Self::record_in).
    pub fn record(
        &self,
        encoder: &mut CommandEncoder,
        inputs: &QuadRasterInputs<'_>,
    ) -> Result<(), QuadRasterError> {
        self.check(inputs)?;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("quad raster"),
            timestamp_writes: None,
        });
        self.record_checked(&mut pass, inputs)
    }

    /// [`record`](Self::record) into an open compute pass (of a
    /// [`PassChain`](crate::pass_chain::PassChain), say): `qr_page_args` (the pages' dispatches
    /// from the cull's counts; it also zeroes the list counters), `qr_quads` once per created
    /// quad page (indirect: one workgroup per drawn command), `qr_tile_args`, `qr_tiles`
    /// (indirect: one workgroup per tile entry). Record it after the cull that wrote the
    /// commands, in the same or an earlier-submitted encoder. CPU cost: a few checks, two cache
    /// lookups (bind groups are made on first use of a buffer, counted by `cached` with the
    /// test-support feature), and `4 + pages` dispatches.
    pub fn record_in(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        inputs: &QuadRasterInputs<'_>,
    ) -> Result<(), QuadRasterError> {
        self.check(inputs)?;
        self.record_checked(pass, inputs)
    }

    /// Records `phase`'s rasterisation of `commands` into `visibility` in the renderer's frame,
    /// timed as `quad raster` (`quad raster late`).
    pub fn record_phase(
        &self,
        ctx: &FrameCtx<'_>,
        rec: &mut Recorder<'_, '_>,
        phase: Phase,
        commands: &CullOutput,
        visibility: &Buffer,
    ) -> Result<(), QuadRasterError> {
        let (width, height) = ctx.size();
        let inputs = QuadRasterInputs {
            frame_uniforms: &ctx.shared.frame_uniforms,
            commands,
            quads: ctx.residency.gigabuffer(),
            visibility,
            width,
            height,
        };
        let label = phase.label("quad raster", "quad raster late");
        rec.step(label, true, |rec| self.record_in(rec.compute(), &inputs))
    }

    /// [`record_in`](Self::record_in) after its checks.
    fn record_checked(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        inputs: &QuadRasterInputs<'_>,
    ) -> Result<(), QuadRasterError> {
        let maker = Maker {
            device: &self.device,
            layouts: &self.layouts,
            state: &self.state,
            tile_dispatch: &self.tile_dispatch,
            tile_capacity: self.config.tile_capacity,
            stride: self.stride,
        };
        let mut cache = self.cache.lock().unwrap_or_else(|e| e.into_inner());
        let frame = cache
            .frame(&maker, inputs.frame_uniforms, inputs.visibility)
            .group
            .clone();
        let output = cache.output(&maker, inputs.commands, inputs.quads)?;
        let page_count = inputs.commands.layout().page_count;
        pass.set_pipeline(&self.pipelines.page_args);
        pass.set_bind_group(0, &output.args_group, &[]);
        pass.dispatch_workgroups(page_count.div_ceil(64), 1, 1);
        pass.set_pipeline(&self.pipelines.quads);
        pass.set_bind_group(0, &frame, &[]);
        pass.set_bind_group(1, &self.lists, &[]);
        for (page, slot) in output.pages.iter().enumerate() {
            // Pages not created yet hold no quads, so no command names them.
            if let Some((_, group)) = slot {
                pass.set_bind_group(2, group, &[]);
                pass.dispatch_workgroups_indirect(&output.page_args, page as u64 * self.stride);
            }
        }
        pass.set_pipeline(&self.pipelines.tile_args);
        pass.set_bind_group(0, &output.args_group, &[]);
        pass.dispatch_workgroups(1, 1, 1);
        pass.set_pipeline(&self.pipelines.tiles);
        pass.set_bind_group(0, &frame, &[]);
        pass.set_bind_group(1, &self.lists, &[]);
        pass.dispatch_workgroups_indirect(&self.tile_dispatch, 0);
        Ok(())
    }

    fn check(&self, inputs: &QuadRasterInputs<'_>) -> Result<(), QuadRasterError> {
        let (width, height) = (inputs.width, inputs.height);
        if width == 0 || height == 0 || width > MAX_SCREEN_EDGE || height > MAX_SCREEN_EDGE {
            return Err(QuadRasterError::BadScreen { width, height });
        }
        let uniforms = inputs.frame_uniforms;
        if !uniforms.usage().contains(BufferUsages::UNIFORM)
            || uniforms.size() < size_of::<FrameUniforms>() as u64
        {
            return Err(QuadRasterError::BufferUnusable {
                buffer: "frame uniforms",
                needs: "UNIFORM usage and at least 224 bytes",
            });
        }
        let visibility = inputs.visibility;
        if !visibility.usage().contains(BufferUsages::STORAGE) {
            return Err(QuadRasterError::BufferUnusable {
                buffer: "visibility",
                needs: "STORAGE usage",
            });
        }
        let needed = u64::from(width) * u64::from(height) * 8;
        if visibility.size() < needed {
            return Err(QuadRasterError::VisibilityTooSmall {
                bytes: visibility.size(),
                needed,
            });
        }
        let commands_per_page = inputs.commands.layout().commands_per_page;
        if u64::from(commands_per_page) > u64::from(MAX_GROUPS) * u64::from(MAX_GROUPS) {
            return Err(QuadRasterError::TooManyCommands { commands_per_page });
        }
        Ok(())
    }

    /// Clears the statistics words (once per frame, or whenever the counts should restart).
    pub fn clear_stats(&self, encoder: &mut CommandEncoder) {
        let first = u64::from(FIRST_STAT_WORD) * 4;
        encoder.clear_buffer(&self.state, first, None);
    }

    /// Reads the counters back (tests, benchmarks). Blocks until the GPU is done.
    pub fn read_stats(
        &self,
        device: &Device,
        queue: &Queue,
    ) -> Result<QuadRasterStats, ReadbackError> {
        let bytes = read_buffer(device, queue, &self.state, 0, self.state.size())?;
        Ok(QuadRasterStats::from_words(&bytemuck::pod_collect_to_vec(
            &bytes,
        )))
    }
}
