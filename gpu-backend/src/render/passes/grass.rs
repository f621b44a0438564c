//! The grass pass: every resident chunk's clutter units drawn as two crossed quads each
//! (`grass.wgsl`), into the same G-buffer as the voxels, after the opaque phases, so the
//! deferred lighting lights them. The geometry, the wind and the fade by the error budget are
//! [`render_model::grass`]'s rules.
//!
//! **Cull.** A compute dispatch (`grass_cull.wgsl`) visits every chunk table slot and appends
//! one non-indexed indirect draw for each slot whose chunk the voxel cull draws (a level-0
//! chunk selected by the same level-of-detail rule, in the frustum, and with occlusion culling
//! visible in this frame's late phase by its visibility bit) and that is no closer to fading
//! out than its tallest blade allows. The draws are compacted (an atomic counter, the first
//! word of the statistics): with `MULTI_DRAW_INDIRECT_COUNT` one `multi_draw_indirect_count`
//! reads that count on the GPU, so the draw (and wgpu's validation of it) covers the drawn
//! chunks only, not the table's capacity; without it the draw list is cleared each frame and
//! one `multi_draw_indirect` over the used slots draws the compacted list and zeroed rest.
//! Either way the CPU work per frame does not grow with the chunk count.
//! The occlusion bit is the chunk's mesh box's: a blade standing above an occluded mesh by
//! less than a block is culled with it.
//!
//! **Vertex pulling.** No vertex or index buffers: 12 vertices per unit, `first_vertex = 12 *
//! (first unit)` in the bound clutter page, `first_instance` = the chunk table slot, whose
//! record gives the chunk. The clutter gigabuffer is bound as one page.
//!
//! Built only when the configuration draws clutter ([`RendererConfig::with_clutter`]).
//!
//! [`RendererConfig::with_clutter`]: crate::render::RendererConfig::with_clutter

use wgpu::{
    BindGroupLayout, Buffer, BufferBindingType, BufferUsages, ComputePipeline, Device,
    RenderPipeline, ShaderStages,
};

use render_model::grass::{GrassCullUniforms, GrassUniforms};
use voxel_core::formats::DataKind;

use super::frame::{FrameCtx, Recorder};
use super::shared::{
    PipelineDesc, Shared, bind_layout, buffer_layout_entry, compute_pipeline, depth_state, pipeline,
};
use super::targets::{ALBEDO_FORMAT, NORMAL_FORMAT};
use crate::bind::buffer_entry;
use crate::device::MultiDrawPath;
use crate::device::alloc::{AllocError, create_buffer};
use crate::shaders::{GRASS, GRASS_CULL};

/// Invocations per workgroup of the grass cull (`@workgroup_size` in `grass_cull.wgsl`).
const WORKGROUP: u32 = 64;
/// Bytes of one non-indexed indirect draw.
const DRAW_ARGS_BYTES: u64 = 16;

/// The grass pass (see the [module docs](self)).
#[derive(Debug)]
pub struct GrassPass {
    device: Device,
    cull_layout: BindGroupLayout,
    cull_pipeline: ComputePipeline,
    draw_layout: BindGroupLayout,
    draw_pipeline: RenderPipeline,
    cull_uniforms: Buffer,
    draw_uniforms: Buffer,
    /// One draw per table slot.
    args: Buffer,
    /// Chunks drawn, units drawn (before the per-blade fade).
    stats: Buffer,
    /// Bound as the visibility bits without occlusion culling.
    no_visible: Buffer,
    capacity: u32,
    /// How the compacted draws are drawn.
    multi_draw: MultiDrawPath,
}

/// What one frame's grass pass draws with.
#[derive(Clone, Copy, Debug)]
pub struct GrassParams {
    /// The cull's uniforms.
    pub cull: GrassCullUniforms,
    /// The draw's uniforms.
    pub draw: GrassUniforms,
}

impl GrassPass {
    /// The pass for a chunk table of `capacity` slots, drawing its compacted draws the
    /// `multi_draw` way.
    pub fn new(
        device: &Device,
        shared: &Shared,
        capacity: u32,
        multi_draw: MultiDrawPath,
    ) -> Result<GrassPass, AllocError> {
        let storage = |read_only| BufferBindingType::Storage { read_only };
        let compute = ShaderStages::COMPUTE;
        let cull_layout = bind_layout(
            device,
            "grass cull",
            &[
                buffer_layout_entry(0, compute, BufferBindingType::Uniform),
                buffer_layout_entry(1, compute, storage(true)),
                buffer_layout_entry(2, compute, storage(false)),
                buffer_layout_entry(3, compute, storage(true)),
                buffer_layout_entry(4, compute, storage(false)),
            ],
        );
        let cull_module = GRASS_CULL.create_module(device);
        let cull_pipeline = compute_pipeline(
            device,
            "grass cull",
            &cull_module,
            "grass_cull",
            &[&cull_layout],
        );
        let vertex = ShaderStages::VERTEX;
        let draw_layout = bind_layout(
            device,
            "grass",
            &[
                buffer_layout_entry(0, vertex, storage(true)),
                buffer_layout_entry(1, vertex, storage(true)),
                buffer_layout_entry(2, vertex, BufferBindingType::Uniform),
            ],
        );
        let module = GRASS.create_module(device);
        let targets = [Some(ALBEDO_FORMAT.into()), Some(NORMAL_FORMAT.into())];
        // Blades are seen from both sides: no face culling.
        let draw_pipeline = pipeline(
            device,
            PipelineDesc {
                label: "grass to gbuffer",
                module: &module,
                vertex: "vs_grass",
                fragment: "fs_grass",
                groups: [&shared.frame_layout, &draw_layout],
                targets: &targets,
                depth: depth_state(true),
                cull_back: false,
            },
        );
        let buffer = |label, size: u64, usage| {
            create_buffer(
                device,
                &wgpu::BufferDescriptor {
                    label: Some(label),
                    size,
                    usage,
                    mapped_at_creation: false,
                },
            )
        };
        let copy_dst = BufferUsages::COPY_DST;
        Ok(GrassPass {
            device: device.clone(),
            cull_layout,
            cull_pipeline,
            draw_layout,
            draw_pipeline,
            cull_uniforms: buffer(
                "grass cull uniforms",
                size_of::<GrassCullUniforms>() as u64,
                BufferUsages::UNIFORM | copy_dst,
            )?,
            draw_uniforms: buffer(
                "grass uniforms",
                size_of::<GrassUniforms>() as u64,
                BufferUsages::UNIFORM | copy_dst,
            )?,
            args: buffer(
                "grass draws",
                u64::from(capacity.max(1)) * DRAW_ARGS_BYTES,
                BufferUsages::STORAGE | BufferUsages::INDIRECT | copy_dst,
            )?,
            stats: buffer(
                "grass stats",
                16,
                BufferUsages::STORAGE | BufferUsages::INDIRECT | BufferUsages::COPY_SRC | copy_dst,
            )?,
            no_visible: buffer("grass no visibility bits", 16, BufferUsages::STORAGE)?,
            capacity,
            multi_draw,
        })
    }

    /// The statistics buffer: `[chunks drawn, units drawn, 0, 0]` as `u32`s, cleared by
    /// [`clear`](Self::clear).
    pub fn stats(&self) -> &Buffer {
        &self.stats
    }

    /// Clears the statistics, whose first word is the draw count (a frame's first commands),
    /// and without `MULTI_DRAW_INDIRECT_COUNT` the draw list.
    pub fn clear(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.clear_buffer(&self.stats, 0, None);
        if self.multi_draw == MultiDrawPath::ZeroedCommands {
            encoder.clear_buffer(&self.args, 0, None);
        }
    }

    /// GPU bytes the pass holds.
    pub fn resident_bytes(&self) -> u64 {
        self.args.size() + self.stats.size() + self.cull_uniforms.size() + self.draw_uniforms.size()
    }

    /// Records the grass cull and draw, timed as `grass`. `visible` is the voxel cull's
    /// visibility bits when `params` turns occlusion on. Nothing is recorded while no clutter
    /// page exists.
    pub fn record(
        &self,
        ctx: &FrameCtx<'_>,
        rec: &mut Recorder<'_, '_>,
        params: &GrassParams,
        visible: Option<&Buffer>,
    ) {
        let Some(clutter) = ctx.residency.gigabuffer().page(DataKind::Clutter, 0) else {
            return;
        };
        let slots = params.cull.slot_bound.min(self.capacity);
        if slots == 0 {
            return;
        }
        ctx.queue
            .write_buffer(&self.cull_uniforms, 0, bytemuck::bytes_of(&params.cull));
        ctx.queue
            .write_buffer(&self.draw_uniforms, 0, bytemuck::bytes_of(&params.draw));
        let table = ctx.residency.table().buffer();
        let cache = &ctx.shared.bind_cache;
        let cull_group = cache.get(
            &self.device,
            "grass cull",
            &self.cull_layout,
            &[
                buffer_entry(0, &self.cull_uniforms),
                buffer_entry(1, table),
                buffer_entry(2, &self.args),
                buffer_entry(3, visible.unwrap_or(&self.no_visible)),
                buffer_entry(4, &self.stats),
            ],
        );
        let draw_group = cache.get(
            &self.device,
            "grass",
            &self.draw_layout,
            &[
                buffer_entry(0, clutter),
                buffer_entry(1, table),
                buffer_entry(2, &self.draw_uniforms),
            ],
        );
        rec.step("grass", false, |rec| {
            let pass = rec.compute();
            pass.set_pipeline(&self.cull_pipeline);
            pass.set_bind_group(0, &cull_group, &[]);
            pass.dispatch_workgroups(slots.div_ceil(WORKGROUP), 1, 1);
            let mut pass = ctx.targets.begin_gbuffer_overlay(rec.encoder(), "grass");
            pass.set_pipeline(&self.draw_pipeline);
            pass.set_bind_group(0, ctx.frame_group, &[]);
            pass.set_bind_group(1, &draw_group, &[]);
            match self.multi_draw {
                MultiDrawPath::IndirectCount => {
                    pass.multi_draw_indirect_count(&self.args, 0, &self.stats, 0, slots)
                }
                MultiDrawPath::ZeroedCommands => pass.multi_draw_indirect(&self.args, 0, slots),
            }
        });
    }
}
