//! The shell pass: every resident node's vertical shell runs ([`ShellRun`], SBgl's shell
//! extraction) drawn as boxes synthesised in the vertex shader (`shells.wgsl`), into the same
//! G-buffer as the greedy quads, so the deferred lighting treats them alike.
//!
//! **Where in the frame.** After both opaque phases, beside the grass: the voxel cull's
//! visibility bits then hold this frame's occlusion result for every node, which the shell
//! cull reads. The shells write the G-buffer's depth, which the lighting, the transparent
//! pass and the shadow trace read; they are not in the early phase's depth the Hi-Z pyramid
//! is built from, so they do not occlude other nodes in the late cull (conservative: more is
//! drawn, nothing is missing).
//!
//! **Cull.** A compute dispatch (`shells_cull.wgsl`) visits every chunk table slot and appends
//! one non-indexed indirect draw for each node with runs that the voxel cull would draw: the
//! level-of-detail rule of `lod.wgsl` at the node's level, its mesh box (which holds its runs'
//! boxes) in the frustum, and with occlusion culling its visibility bit. The draws are
//! compacted by an atomic counter and drawn with one `multi_draw_indirect_count` (or, without
//! `MULTI_DRAW_INDIRECT_COUNT`, one `multi_draw_indirect` over a list cleared each frame), as
//! the grass pass does.
//!
//! **Vertex pulling.** No vertex data: 18 vertices per run, on axis `vertex_index / 6` within
//! the run the box face toward the eye (the other is a back face), `first_vertex = 18 * (first
//! run)` in the bound shell page, `first_instance` = the table
//! slot. A face whose side bit is clear is degenerate. The fragment shades with the meshers'
//! per-face ambient occlusion from the node's hiding mask (`far_ao.wgsl`), when the node has
//! one. The shell gigabuffer is bound as one page.
//!
//! Built only when the configuration draws shells ([`RendererConfig::with_shells`]).
//!
//! [`RendererConfig::with_shells`]: crate::render::RendererConfig::with_shells

use wgpu::{
    BindGroupLayout, Buffer, BufferBindingType, BufferUsages, ComputePipeline, Device,
    RenderPipeline, ShaderStages,
};

use render_model::grass::GrassCullUniforms;
use voxel_core::formats::DataKind;
#[cfg(doc)]
use voxel_core::formats::ShellRun;

use super::frame::{FrameCtx, Recorder};
use super::shared::{
    PipelineDesc, Shared, bind_layout, buffer_layout_entry, compute_pipeline, depth_state, pipeline,
};
use super::targets::{ALBEDO_FORMAT, NORMAL_FORMAT};
use crate::bind::buffer_entry;
use crate::device::MultiDrawPath;
use crate::device::alloc::{AllocError, create_buffer};
use crate::shaders::{SHELLS, SHELLS_CULL};

/// Invocations per workgroup of the shell cull (`@workgroup_size` in `shells_cull.wgsl`).
const WORKGROUP: u32 = 64;
/// Bytes of one non-indexed indirect draw.
const DRAW_ARGS_BYTES: u64 = 16;

/// The shell pass (see the [module docs](self)).
#[derive(Debug)]
pub struct ShellPass {
    device: Device,
    cull_layout: BindGroupLayout,
    cull_pipeline: ComputePipeline,
    draw_layout: BindGroupLayout,
    draw_pipeline: RenderPipeline,
    cull_uniforms: Buffer,
    /// One draw per table slot.
    args: Buffer,
    /// Nodes drawn, runs drawn.
    stats: Buffer,
    /// Bound as the visibility bits without occlusion culling, and as the masks without far
    /// blocks.
    zero: Buffer,
    capacity: u32,
    multi_draw: MultiDrawPath,
}

impl ShellPass {
    /// The pass for a chunk table of `capacity` slots, drawing its compacted draws the
    /// `multi_draw` way.
    pub fn new(
        device: &Device,
        shared: &Shared,
        capacity: u32,
        multi_draw: MultiDrawPath,
    ) -> Result<ShellPass, AllocError> {
        let storage = |read_only| BufferBindingType::Storage { read_only };
        let compute = ShaderStages::COMPUTE;
        let cull_layout = bind_layout(
            device,
            "shell cull",
            &[
                buffer_layout_entry(0, compute, BufferBindingType::Uniform),
                buffer_layout_entry(1, compute, storage(true)),
                buffer_layout_entry(2, compute, storage(true)),
                buffer_layout_entry(3, compute, storage(false)),
                buffer_layout_entry(4, compute, storage(true)),
                buffer_layout_entry(5, compute, storage(false)),
            ],
        );
        let cull_module = SHELLS_CULL.create_module(device);
        let cull_pipeline = compute_pipeline(
            device,
            "shell cull",
            &cull_module,
            "shells_cull",
            &[&cull_layout],
        );
        let both = ShaderStages::VERTEX | ShaderStages::FRAGMENT;
        let draw_layout = bind_layout(
            device,
            "shells",
            &[
                buffer_layout_entry(0, both, storage(true)),
                buffer_layout_entry(1, both, storage(true)),
                buffer_layout_entry(2, both, storage(true)),
                buffer_layout_entry(3, both, storage(true)),
            ],
        );
        let module = SHELLS.create_module(device);
        let targets = [Some(ALBEDO_FORMAT.into()), Some(NORMAL_FORMAT.into())];
        let draw_pipeline = pipeline(
            device,
            PipelineDesc {
                label: "shells to gbuffer",
                module: &module,
                vertex: "vs_shell",
                fragment: "fs_shell",
                groups: [&shared.frame_layout, &draw_layout],
                targets: &targets,
                depth: depth_state(true),
                cull_back: true,
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
        Ok(ShellPass {
            device: device.clone(),
            cull_layout,
            cull_pipeline,
            draw_layout,
            draw_pipeline,
            cull_uniforms: buffer(
                "shell cull uniforms",
                size_of::<GrassCullUniforms>() as u64,
                BufferUsages::UNIFORM | copy_dst,
            )?,
            args: buffer(
                "shell draws",
                u64::from(capacity.max(1)) * DRAW_ARGS_BYTES,
                BufferUsages::STORAGE | BufferUsages::INDIRECT | copy_dst,
            )?,
            stats: buffer(
                "shell stats",
                16,
                BufferUsages::STORAGE | BufferUsages::INDIRECT | BufferUsages::COPY_SRC | copy_dst,
            )?,
            zero: buffer("shell zero words", 16, BufferUsages::STORAGE)?,
            capacity,
            multi_draw,
        })
    }

    /// The statistics buffer: `[nodes drawn, runs drawn, 0, 0]` as `u32`s, cleared by
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
        self.args.size() + self.stats.size() + self.cull_uniforms.size() + self.zero.size()
    }

    /// Records the shell cull and draw, timed as `shells`, with the cull uniforms the grass
    /// cull uses (`cull`: the same selection, frustum and occlusion flags). `visible` is the
    /// voxel cull's visibility bits when `cull` turns occlusion on. Nothing is recorded while
    /// no shell page exists.
    pub fn record(
        &self,
        ctx: &FrameCtx<'_>,
        rec: &mut Recorder<'_, '_>,
        cull: &GrassCullUniforms,
        visible: Option<&Buffer>,
    ) {
        let gigabuffer = ctx.residency.gigabuffer();
        let Some(shells) = gigabuffer.page(DataKind::Shells, 0) else {
            return;
        };
        let slots = cull.slot_bound.min(self.capacity);
        if slots == 0 {
            return;
        }
        ctx.queue
            .write_buffer(&self.cull_uniforms, 0, bytemuck::bytes_of(cull));
        let table = ctx.residency.table().buffer();
        let nodes = ctx.residency.nodes().buffer();
        let masks = gigabuffer
            .page(DataKind::DrawBlocks, 0)
            .unwrap_or(&self.zero);
        let cache = &ctx.shared.bind_cache;
        let cull_group = cache.get(
            &self.device,
            "shell cull",
            &self.cull_layout,
            &[
                buffer_entry(0, &self.cull_uniforms),
                buffer_entry(1, table),
                buffer_entry(2, nodes),
                buffer_entry(3, &self.args),
                buffer_entry(4, visible.unwrap_or(&self.zero)),
                buffer_entry(5, &self.stats),
            ],
        );
        let draw_group = cache.get(
            &self.device,
            "shells",
            &self.draw_layout,
            &[
                buffer_entry(0, shells),
                buffer_entry(1, table),
                buffer_entry(2, nodes),
                buffer_entry(3, masks),
            ],
        );
        rec.step("shells", false, |rec| {
            let pass = rec.compute();
            pass.set_pipeline(&self.cull_pipeline);
            pass.set_bind_group(0, &cull_group, &[]);
            pass.dispatch_workgroups(slots.div_ceil(WORKGROUP), 1, 1);
            let mut pass = ctx.targets.begin_gbuffer_overlay(rec.encoder(), "shells");
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
