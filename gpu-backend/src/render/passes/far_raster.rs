//! The raster far draws: sprites ([`FarPath::Sprite`]) and camera-facing cube faces
//! ([`FarPath::CameraQuads`]), drawn into the G-buffer beside the meshed nodes (opaque blocks)
//! and into the HDR target in the transparent pass (transparent blocks), from the same far list
//! and draw blocks as the splat (`far_raster.wgsl` states what each form draws).
//!
//! Per opaque phase: after the cull record, [`FarRaster::record_phase_args`] runs `far_args`
//! (the entries that record appended) and `draw_args_phase` (one non-indexed draw per entry,
//! `first_instance` = its far-list index, in slots `0..n`, `n` in the count word); the G-buffer
//! pass then calls [`FarRaster::draw_opaque`]. Before the transparent pass,
//! [`FarRaster::record_all_args`] lists every entry of the frame and
//! [`FarRaster::draw_transparent`] draws their transparent blocks (blended, depth-tested
//! against everything opaque, far blocks first so nearer transparent quads blend over them).
//!
//! Without a count buffer ([`MultiDrawPath::ZeroedCommands`]) the multi-draw covers every slot
//! of the far list's capacity; the args pass writes the slots past `n` as empty draws.

use wgpu::{
    BindGroup, BindGroupLayout, BindGroupLayoutEntry, BindingType, BlendState, Buffer,
    BufferBindingType, BufferUsages, ColorTargetState, CommandEncoder, ComputePipeline, Device,
    RenderPass, RenderPipeline, ShaderStages,
};

use voxel_core::formats::DataKind;

use super::cull::CullFrame;
use super::frame::FrameCtx;
use super::shared::{PipelineDesc, depth_state, pipeline, pipeline_with_groups};
use super::targets::{ALBEDO_FORMAT, HDR_FORMAT, NORMAL_FORMAT};
use crate::bind::{BindGroupCache, buffer_entry};
use crate::device::alloc::AllocError;
use crate::device::{GpuCapabilities, MultiDrawPath};
use crate::render::far::FarPath;
use crate::shaders::{FAR_ARGS, FAR_DRAW_ARGS, FAR_RASTER, FAR_RASTER_CONSERVATIVE};

/// Bytes of one non-indexed indirect draw.
const DRAW_ARGS_BYTES: u64 = 16;
/// Invocations per workgroup of the args pass (`far_draw_args.wgsl`).
const ARGS_WORKGROUP: u32 = 64;
/// Largest workgroup count of one dispatch dimension.
const MAX_GROUPS: u32 = 65_535;

/// What the far draws bind besides their own buffers.
#[derive(Clone, Copy, Debug)]
pub struct FarRasterInputs<'a> {
    /// The chunk table.
    pub table: &'a Buffer,
    /// The node table.
    pub nodes: &'a Buffer,
    /// The draw-block gigabuffer's page.
    pub blocks: &'a Buffer,
    /// The cull frame (far list, statistics).
    pub frame: &'a CullFrame,
}

/// The raster far draws of one frame: the pass, and what it binds once draw blocks are
/// resident (`inputs` is `None` before).
#[derive(Clone, Copy, Debug)]
pub struct FarRasterDraw<'a> {
    /// The pass.
    pub raster: &'a FarRaster,
    /// What it binds, when there is a draw-block page.
    pub inputs: Option<FarRasterInputs<'a>>,
}

impl<'a> FarRasterDraw<'a> {
    /// The frame's raster far draws with `ctx`'s residency and the frame's far list `frame`.
    pub fn new(raster: &'a FarRaster, ctx: &FrameCtx<'a>, frame: &'a CullFrame) -> Self {
        let residency = ctx.residency;
        let inputs = residency
            .gigabuffer()
            .page(DataKind::DrawBlocks, 0)
            .map(|blocks| FarRasterInputs {
                table: residency.table().buffer(),
                nodes: residency.nodes().buffer(),
                blocks,
                frame,
            });
        FarRasterDraw { raster, inputs }
    }

    /// [`FarRaster::record_phase_args`] and the draws' bind group; `None` (nothing recorded)
    /// without draw blocks.
    pub fn record_phase_args(&self, encoder: &mut CommandEncoder) -> Option<BindGroup> {
        let inputs = self.inputs.as_ref()?;
        self.raster.record_phase_args(encoder, inputs);
        Some(self.raster.bind_group(inputs))
    }

    /// [`FarRaster::record_all_args`] and the draws' bind group; `None` (nothing recorded)
    /// without draw blocks.
    pub fn record_all_args(&self, encoder: &mut CommandEncoder) -> Option<BindGroup> {
        let inputs = self.inputs.as_ref()?;
        self.raster.record_all_args(encoder, inputs);
        Some(self.raster.bind_group(inputs))
    }

    /// [`FarRaster::draw_opaque`].
    pub fn draw_opaque(
        &self,
        pass: &mut RenderPass<'_>,
        frame_group: &BindGroup,
        group: &BindGroup,
    ) {
        self.raster.draw_opaque(pass, frame_group, group);
    }

    /// [`FarRaster::draw_transparent`].
    pub fn draw_transparent(
        &self,
        pass: &mut RenderPass<'_>,
        frame_group: &BindGroup,
        group: &BindGroup,
        opaque_depth: &BindGroup,
    ) {
        self.raster
            .draw_transparent(pass, frame_group, group, opaque_depth);
    }
}

/// The raster far draws' pipelines and indirect commands.
#[derive(Debug)]
pub struct FarRaster {
    device: Device,
    path: FarPath,
    multi_draw: MultiDrawPath,
    /// Whether the sprite's G-buffer shader keeps the early depth test (conservative depth).
    conservative: bool,
    vertices_per_block: u32,
    draw_layout: BindGroupLayout,
    opaque: RenderPipeline,
    transparent: RenderPipeline,
    range_layout: BindGroupLayout,
    range_pipeline: ComputePipeline,
    args_layout: BindGroupLayout,
    args_phase: ComputePipeline,
    args_all: ComputePipeline,
    range: Buffer,
    args: Buffer,
    count: Buffer,
    capacity: u32,
    bind_cache: BindGroupCache,
}

fn storage(binding: u32, visibility: ShaderStages, read_only: bool) -> BindGroupLayoutEntry {
    BindGroupLayoutEntry {
        binding,
        visibility,
        ty: BindingType::Buffer {
            ty: BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn compute(
    device: &Device,
    label: &str,
    layout: &BindGroupLayout,
    module: &wgpu::ShaderModule,
    entry: &str,
    constants: &[(&str, f64)],
) -> ComputePipeline {
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &[Some(layout)],
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: Some(&pipeline_layout),
        module,
        entry_point: Some(entry),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants,
            ..Default::default()
        },
        cache: None,
    })
}

impl FarRaster {
    /// The raster far draws of `path` (sprite or camera quads) for a far list of `capacity`
    /// entries, drawing with `frame_layout` as group 0 (the renderer's frame uniforms and
    /// materials).
    ///
    /// # Panics
    ///
    /// If `path` is not a raster path (a caller bug: the renderer builds this for those only).
    pub fn new(
        device: &Device,
        capabilities: &GpuCapabilities,
        path: FarPath,
        capacity: u32,
        frame_layout: &BindGroupLayout,
        opaque_depth_layout: &BindGroupLayout,
    ) -> Result<FarRaster, AllocError> {
        let vertices_per_block = match path {
            FarPath::Sprite => 6,
            FarPath::CameraQuads => 18,
            FarPath::Off | FarPath::Splat => panic!("{path:?} is not a raster far path"),
        };
        let drawn = ShaderStages::VERTEX | ShaderStages::FRAGMENT;
        let draw_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("far raster"),
            entries: &[
                storage(5, drawn, true),
                storage(6, drawn, true),
                storage(7, drawn, true),
                storage(8, drawn, true),
            ],
        });
        let conservative = path == FarPath::Sprite && capabilities.early_depth_test;
        let module = if conservative {
            FAR_RASTER_CONSERVATIVE.create_module(device)
        } else {
            FAR_RASTER.create_module(device)
        };
        let (vs, fs, vs_transparent, fs_transparent) = match path {
            FarPath::Sprite => (
                "vs_sprite",
                if conservative {
                    "fs_sprite_conservative"
                } else {
                    "fs_sprite"
                },
                "vs_sprite_transparent",
                "fs_sprite_transparent",
            ),
            _ => (
                "vs_cube",
                "fs_gbuffer",
                "vs_cube_transparent",
                "fs_transparent",
            ),
        };
        let gbuffer_targets = [Some(ALBEDO_FORMAT.into()), Some(NORMAL_FORMAT.into())];
        let opaque = pipeline(
            device,
            PipelineDesc {
                label: "far blocks to gbuffer",
                module: &module,
                vertex: vs,
                fragment: fs,
                groups: [frame_layout, &draw_layout],
                targets: &gbuffer_targets,
                depth: depth_state(true),
                // Sprites face the camera; cube faces are chosen facing it.
                cull_back: false,
            },
        );
        let transparent = pipeline_with_groups(
            device,
            PipelineDesc {
                label: "transparent far blocks",
                module: &module,
                vertex: vs_transparent,
                fragment: fs_transparent,
                groups: [frame_layout, &draw_layout],
                targets: &[Some(ColorTargetState {
                    format: HDR_FORMAT,
                    // transparent_colour is premultiplied (lighting::surface).
                    blend: Some(BlendState::PREMULTIPLIED_ALPHA_BLENDING),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
                depth: depth_state(false),
                cull_back: false,
            },
            &[opaque_depth_layout],
        );
        let compute_only = ShaderStages::COMPUTE;
        let range_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("far raster range"),
            entries: &[
                storage(0, compute_only, false),
                storage(1, compute_only, false),
                storage(2, compute_only, true),
            ],
        });
        let range_module = FAR_ARGS.create_module(device);
        let range_pipeline = compute(
            device,
            "far raster range",
            &range_layout,
            &range_module,
            "far_args",
            &[],
        );
        let args_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("far draw args"),
            entries: &[
                storage(0, compute_only, true),
                storage(1, compute_only, true),
                storage(2, compute_only, true),
                storage(3, compute_only, false),
                storage(4, compute_only, false),
            ],
        });
        let args_module = FAR_DRAW_ARGS.create_module(device);
        let constants = [("VERTICES_PER_BLOCK", f64::from(vertices_per_block))];
        let args_phase = compute(
            device,
            "far draw args",
            &args_layout,
            &args_module,
            "draw_args_phase",
            &constants,
        );
        let args_all = compute(
            device,
            "far draw args (all)",
            &args_layout,
            &args_module,
            "draw_args_all",
            &constants,
        );
        let capacity = capacity.max(1);
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
        let indirect = BufferUsages::STORAGE | BufferUsages::INDIRECT | BufferUsages::COPY_DST;
        Ok(FarRaster {
            device: device.clone(),
            path,
            multi_draw: capabilities.multi_draw,
            conservative,
            vertices_per_block,
            draw_layout,
            opaque,
            transparent,
            range_layout,
            range_pipeline,
            args_layout,
            args_phase,
            args_all,
            range: buffer("far raster range", 32, indirect)?,
            args: buffer(
                "far draw args",
                u64::from(capacity) * DRAW_ARGS_BYTES,
                indirect,
            )?,
            count: buffer("far draw count", 16, indirect)?,
            capacity,
            bind_cache: BindGroupCache::default(),
        })
    }

    /// The path drawn.
    pub fn path(&self) -> FarPath {
        self.path
    }

    /// Whether sprites keep the early depth test (conservative depth).
    pub fn conservative_depth(&self) -> bool {
        self.conservative
    }

    /// Vertices drawn per block: 6 (sprite) or 18 (camera quads).
    pub fn vertices_per_block(&self) -> u32 {
        self.vertices_per_block
    }

    /// Empties the entry range: once per frame, before the first phase.
    pub fn clear(&self, encoder: &mut CommandEncoder) {
        encoder.clear_buffer(&self.range, 0, None);
    }

    /// The draws of the far-list entries appended since the last call of the frame.
    pub fn record_phase_args(&self, encoder: &mut CommandEncoder, inputs: &FarRasterInputs<'_>) {
        self.record_args(encoder, inputs, false);
    }

    /// The draws of every far-list entry of the frame (for the transparent pass; after the
    /// last phase's [`record_phase_args`](Self::record_phase_args)).
    pub fn record_all_args(&self, encoder: &mut CommandEncoder, inputs: &FarRasterInputs<'_>) {
        self.record_args(encoder, inputs, true);
    }

    fn record_args(&self, encoder: &mut CommandEncoder, inputs: &FarRasterInputs<'_>, all: bool) {
        let range_group = self.bind_cache.get(
            &self.device,
            "far raster range",
            &self.range_layout,
            &[
                buffer_entry(0, inputs.frame.stats()),
                buffer_entry(1, &self.range),
                buffer_entry(2, inputs.frame.far_list()),
            ],
        );
        let args_group = self.bind_cache.get(
            &self.device,
            "far draw args",
            &self.args_layout,
            &[
                buffer_entry(0, &self.range),
                buffer_entry(1, inputs.frame.far_list()),
                buffer_entry(2, inputs.nodes),
                buffer_entry(3, &self.args),
                buffer_entry(4, &self.count),
            ],
        );
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("far draw args"),
            timestamp_writes: None,
        });
        // The phase's range (the "all" pass reads only its end, which the last phase set).
        if !all {
            pass.set_pipeline(&self.range_pipeline);
            pass.set_bind_group(0, &range_group, &[]);
            pass.dispatch_workgroups(1, 1, 1);
        }
        let groups = self.capacity.div_ceil(ARGS_WORKGROUP);
        pass.set_pipeline(if all {
            &self.args_all
        } else {
            &self.args_phase
        });
        pass.set_bind_group(0, &args_group, &[]);
        pass.dispatch_workgroups(groups.min(MAX_GROUPS), groups.div_ceil(MAX_GROUPS), 1);
    }

    /// Group 1 of the draws.
    pub fn bind_group(&self, inputs: &FarRasterInputs<'_>) -> BindGroup {
        self.bind_cache.get(
            &self.device,
            "far raster",
            &self.draw_layout,
            &[
                buffer_entry(5, inputs.table),
                buffer_entry(6, inputs.nodes),
                buffer_entry(7, inputs.frame.far_list()),
                buffer_entry(8, inputs.blocks),
            ],
        )
    }

    /// Draws the opaque blocks of the listed entries into a G-buffer pass.
    pub fn draw_opaque(
        &self,
        pass: &mut RenderPass<'_>,
        frame_group: &BindGroup,
        group: &BindGroup,
    ) {
        self.draw(pass, &self.opaque, frame_group, group);
    }

    /// Draws the transparent blocks of the listed entries into the transparent pass, tinted by
    /// the opaque depth behind them (`opaque_depth`, of `Shared::opaque_depth_layout`).
    pub fn draw_transparent(
        &self,
        pass: &mut RenderPass<'_>,
        frame_group: &BindGroup,
        group: &BindGroup,
        opaque_depth: &BindGroup,
    ) {
        pass.set_bind_group(2, opaque_depth, &[]);
        self.draw(pass, &self.transparent, frame_group, group);
    }

    fn draw(
        &self,
        pass: &mut RenderPass<'_>,
        pipeline: &RenderPipeline,
        frame_group: &BindGroup,
        group: &BindGroup,
    ) {
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, frame_group, &[]);
        pass.set_bind_group(1, group, &[]);
        match self.multi_draw {
            MultiDrawPath::IndirectCount => {
                pass.multi_draw_indirect_count(&self.args, 0, &self.count, 0, self.capacity)
            }
            MultiDrawPath::ZeroedCommands => pass.multi_draw_indirect(&self.args, 0, self.capacity),
        }
    }
}
