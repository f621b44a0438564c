//! The shadow pass: sun shadows and sky visibility per pixel by rays through a camera-centred
//! occupancy grid, the rule of [`render_model::lighting::shadow`] (which states it, why the
//! grid's shell of quads is enough, and why it does not leak at LOD borders).
//!
//! Two compute steps, each timed:
//!
//! | step | timer | shader | what |
//! | ---- | ----- | ------ | ---- |
//! | fill | `shadow grid` | `shadow_fill.wgsl` | clears the grid ([`GRID_CELLS`]^3 bits, 2 MiB), then one workgroup per chunk-table slot and quad page marks the solid cell behind every opaque quad (skirts included), and every voxel of every vertical shell run, of the nodes the cull draws (the same level-of-detail rule, every direction: casters outside the view count); then one bit per 8^3 brick says whether it holds a marked cell (4 KiB) |
//! | trace | `shadow trace` | `shadow_trace.wgsl` | per pixel (8 x 8 per workgroup), the surface the lighting pass shades, its sun ray and 5 sky rays marched through the grid (jumping over the bricks with no marked cell), one [`Visibility`] word out |
//!
//! The lighting pass reads the words (binding 7, `FRAME_SHADOWS` set) and scales the sun term
//! and the hemisphere ambient by them. The grid is filled again whenever the camera, its
//! level-of-detail anchor or the resident set changed ([`ShadowPass::needs_fill`]), for about
//! the cost of a 2 MiB clear and one pass over the quads of the nodes inside it; a still view
//! keeps it.
//!
//! Made with the first frame that switches shadows on ([`Lighting::shadows`]); frames
//! without them record nothing of it, bind a stand-in buffer, and are the image without
//! shadows to the bit.
//!
//! **Bounds.** Only surfaces within [`GRID_CELLS`] / 2 blocks of the eye (per axis) are shadowed,
//! and only casters inside the grid cast; farther surfaces are lit as without shadows. Smooth
//! (NoCubes) layers and far-draw blocks do not mark the grid: they neither cast nor, beyond
//! their quads' shell, receive exact shadows.
//!
//! [`Lighting::shadows`]: render_model::lighting::Lighting::shadows
//! [`Visibility`]: render_model::lighting::shadow::Visibility
//! [`GRID_CELLS`]: render_model::lighting::shadow::GRID_CELLS

use std::cell::Cell;

use wgpu::{
    BindGroupLayout, Buffer, BufferBindingType, BufferUsages, ComputePipeline, Device,
    ShaderStages, TextureSampleType,
};

use render_model::lighting::shadow::GRID_CELLS;
use render_model::lighting::{ShadowFillUniforms, ShadowTraceUniforms};
use voxel_core::formats::DataKind;

use super::frame::{FrameCtx, Recorder};
use super::shared::{
    Shared, bind_layout, buffer_layout_entry, compute_pipeline, texture_layout_entry,
};
use crate::bind::buffer_entry;
use crate::device::alloc::{AllocError, create_buffer};
use crate::shaders::{SHADOW_FILL, SHADOW_TRACE};

/// Slots per row of the fill's folded dispatch (`FILL_ROW` in `shadow_fill.wgsl`).
const FILL_ROW: u32 = 65_535;
/// Bytes of the grid: one bit per cell.
pub const GRID_BYTES: u64 = (GRID_CELLS as u64).pow(3) / 8;
/// Bytes of the grid's brick bits: one bit per 8^3 brick.
const BRICK_BYTES: u64 = GRID_BYTES / 512;

/// The shadow pass (see the [module docs](self)).
#[derive(Debug)]
pub struct ShadowPass {
    device: Device,
    fill_layout: BindGroupLayout,
    fill_pipeline: ComputePipeline,
    /// The fill from the nodes' vertical shell runs.
    shells_fill_pipeline: ComputePipeline,
    /// The brick bits from the filled grid.
    bricks_pipeline: ComputePipeline,
    trace_layout: BindGroupLayout,
    trace_pipeline: ComputePipeline,
    grid: Buffer,
    /// One bit per 8^3 brick of the grid, set when it holds a marked cell.
    bricks: Buffer,
    /// One uniform buffer per quad page (each fill dispatch reads its page's).
    fill_uniforms: Vec<Buffer>,
    trace_uniforms: Buffer,
    /// One `Visibility` word per pixel.
    visibility: Buffer,
    /// The pixels `visibility` holds.
    pixels: u64,
    /// What the grid holds: the fill of these uniforms over the resident set after this many
    /// changes ([`Residency::changes`](crate::residency::Residency::changes)); `None` before
    /// the first fill.
    filled: Cell<Option<(ShadowFillUniforms, u64)>>,
    /// Frames that filled the grid so far.
    fills: Cell<u64>,
}

/// What one frame's shadow pass needs besides the frame context.
#[derive(Clone, Copy, Debug)]
pub struct ShadowParams {
    /// The fill's uniforms (`page`, `bound_capacity` set per page by the pass).
    pub fill: ShadowFillUniforms,
    /// [`Residency::changes`](crate::residency::Residency::changes) of the frame.
    pub changes: u64,
    /// The trace's uniforms.
    pub trace: ShadowTraceUniforms,
    /// Whether the grid is cleared and filled this frame: false when it already holds the
    /// fill of the same uniforms over the same resident set ([`ShadowPass::needs_fill`]).
    pub refill: bool,
}

impl ShadowPass {
    /// The pass, with its grid and a visibility buffer for `width x height` pixels.
    pub fn new(
        device: &Device,
        shared: &Shared,
        width: u32,
        height: u32,
    ) -> Result<Self, AllocError> {
        let compute = ShaderStages::COMPUTE;
        let storage = |read_only| BufferBindingType::Storage { read_only };
        let fill_layout = bind_layout(
            device,
            "shadow fill",
            &[
                buffer_layout_entry(0, compute, BufferBindingType::Uniform),
                buffer_layout_entry(1, compute, storage(true)),
                buffer_layout_entry(2, compute, storage(false)),
                buffer_layout_entry(3, compute, storage(true)),
                buffer_layout_entry(4, compute, storage(true)),
                buffer_layout_entry(5, compute, storage(true)),
                buffer_layout_entry(6, compute, storage(false)),
            ],
        );
        let fill_module = SHADOW_FILL.create_module(device);
        let fill_pipeline = compute_pipeline(
            device,
            "shadow fill",
            &fill_module,
            "shadow_fill",
            &[&fill_layout],
        );
        let shells_fill_pipeline = compute_pipeline(
            device,
            "shadow fill shells",
            &fill_module,
            "shadow_fill_shells",
            &[&fill_layout],
        );
        let bricks_pipeline = compute_pipeline(
            device,
            "shadow bricks",
            &fill_module,
            "shadow_bricks",
            &[&fill_layout],
        );
        let trace_layout = bind_layout(
            device,
            "shadow trace",
            &[
                buffer_layout_entry(0, compute, BufferBindingType::Uniform),
                buffer_layout_entry(1, compute, storage(true)),
                texture_layout_entry(2, compute, TextureSampleType::Uint),
                texture_layout_entry(3, compute, TextureSampleType::Depth),
                buffer_layout_entry(4, compute, storage(true)),
                buffer_layout_entry(5, compute, storage(false)),
                buffer_layout_entry(6, compute, storage(true)),
            ],
        );
        let trace_module = SHADOW_TRACE.create_module(device);
        let trace_pipeline = compute_pipeline(
            device,
            "shadow trace",
            &trace_module,
            "shadow_trace",
            &[&shared.frame_layout, &trace_layout],
        );
        let grid = create_buffer(
            device,
            &wgpu::BufferDescriptor {
                label: Some("shadow grid"),
                size: GRID_BYTES,
                usage: BufferUsages::STORAGE | BufferUsages::COPY_DST,
                mapped_at_creation: false,
            },
        )?;
        let bricks = create_buffer(
            device,
            &wgpu::BufferDescriptor {
                label: Some("shadow grid bricks"),
                size: BRICK_BYTES,
                usage: BufferUsages::STORAGE,
                mapped_at_creation: false,
            },
        )?;
        let trace_uniforms = uniform_buffer(
            device,
            "shadow trace uniforms",
            size_of::<ShadowTraceUniforms>(),
        )?;
        let pixels = pixel_count(width, height);
        Ok(ShadowPass {
            device: device.clone(),
            fill_layout,
            fill_pipeline,
            shells_fill_pipeline,
            bricks_pipeline,
            trace_layout,
            trace_pipeline,
            grid,
            bricks,
            fill_uniforms: Vec::new(),
            trace_uniforms,
            visibility: visibility_buffer(device, pixels)?,
            pixels,
            filled: Cell::new(None),
            fills: Cell::new(0),
        })
    }

    /// Makes the visibility buffer fit `width x height` pixels (a new one when the size
    /// changed).
    pub fn fit(&mut self, width: u32, height: u32) -> Result<(), AllocError> {
        let pixels = pixel_count(width, height);
        if pixels != self.pixels {
            self.visibility = visibility_buffer(&self.device, pixels)?;
            self.pixels = pixels;
        }
        Ok(())
    }

    /// Makes a fill uniform buffer for each of `pages` quad pages.
    pub fn fit_pages(&mut self, pages: u32) -> Result<(), AllocError> {
        while self.fill_uniforms.len() < pages as usize {
            let b = uniform_buffer(
                &self.device,
                "shadow fill uniforms",
                size_of::<ShadowFillUniforms>(),
            )?;
            self.fill_uniforms.push(b);
        }
        Ok(())
    }

    /// The per-pixel `Visibility` words of the last frame (row-major), which the lighting
    /// pass reads.
    pub fn visibility(&self) -> &Buffer {
        &self.visibility
    }

    /// GPU bytes the pass holds.
    pub fn resident_bytes(&self) -> u64 {
        self.grid.size() + self.bricks.size() + self.visibility.size()
    }

    /// Whether the grid must be filled again for `fill` over a resident set after `changes`
    /// uploads and frees. The grid depends on nothing else (the level-of-detail rule from the
    /// camera, the camera's block, the table and the quads), so a still camera over an
    /// unchanged resident set keeps its grid and skips both the clear and the fill.
    pub fn needs_fill(&self, fill: &ShadowFillUniforms, changes: u64) -> bool {
        self.filled.get() != Some((*fill, changes))
    }

    /// Frames recorded so far that cleared and filled the grid (the others kept it).
    pub fn fills(&self) -> u64 {
        self.fills.get()
    }

    /// Clears the grid (a frame's first commands, when [`ShadowParams::refill`] is set).
    pub fn clear(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.clear_buffer(&self.grid, 0, None);
    }

    /// Records the fill (timed `shadow grid`) and the trace (timed `shadow trace`), after
    /// every opaque draw and before lighting. [`fit_pages`](Self::fit_pages) must have made
    /// a uniform buffer per quad page.
    pub fn record(&self, ctx: &FrameCtx<'_>, rec: &mut Recorder<'_, '_>, params: &ShadowParams) {
        let gigabuffer = ctx.residency.gigabuffer();
        let layout = gigabuffer.layout(DataKind::Quads);
        let table = ctx.residency.table().buffer();
        let cache = &ctx.shared.bind_cache;
        let slots = params.fill.slot_bound;
        let nodes = ctx.residency.nodes().buffer();
        let shells = gigabuffer.page(DataKind::Shells, 0);
        let dummy = &ctx.shared.no_visibility;
        let mut fills = Vec::new();
        for (page, uniforms) in (0..layout.page_count).zip(&self.fill_uniforms) {
            let Some(quads) = gigabuffer.page(DataKind::Quads, page) else {
                continue;
            };
            let bound_capacity = if page + 1 == layout.page_count {
                layout.last_page_capacity
            } else {
                layout.page_capacity
            };
            let fill = ShadowFillUniforms {
                page,
                page_capacity: layout.page_capacity,
                bound_capacity,
                ..params.fill
            };
            ctx.queue
                .write_buffer(uniforms, 0, bytemuck::bytes_of(&fill));
            fills.push(cache.get(
                &self.device,
                "shadow fill",
                &self.fill_layout,
                &[
                    buffer_entry(0, uniforms),
                    buffer_entry(1, table),
                    buffer_entry(2, &self.grid),
                    buffer_entry(3, quads),
                    buffer_entry(4, nodes),
                    buffer_entry(5, shells.unwrap_or(dummy)),
                    buffer_entry(6, &self.bricks),
                ],
            ));
        }
        // The runs' fill reads the first page's uniforms (the page fields are unused there).
        let shell_fill = match (shells, self.fill_uniforms.first()) {
            (Some(shells), Some(uniforms)) => {
                if fills.is_empty() {
                    let fill = ShadowFillUniforms {
                        page: 0,
                        page_capacity: layout.page_capacity.max(1),
                        bound_capacity: 0,
                        ..params.fill
                    };
                    ctx.queue
                        .write_buffer(uniforms, 0, bytemuck::bytes_of(&fill));
                }
                let quads = gigabuffer.page(DataKind::Quads, 0).unwrap_or(dummy);
                Some(cache.get(
                    &self.device,
                    "shadow fill shells",
                    &self.fill_layout,
                    &[
                        buffer_entry(0, uniforms),
                        buffer_entry(1, table),
                        buffer_entry(2, &self.grid),
                        buffer_entry(3, quads),
                        buffer_entry(4, nodes),
                        buffer_entry(5, shells),
                        buffer_entry(6, &self.bricks),
                    ],
                ))
            }
            _ => None,
        };
        if params.refill {
            // Recorded now, after the frame's clear: the grid holds this fill from here on.
            self.filled.set(Some((params.fill, params.changes)));
            self.fills.set(self.fills.get() + 1);
        }
        rec.step("shadow grid", true, |rec| {
            if slots == 0 || !params.refill {
                return;
            }
            let pass = rec.compute();
            pass.set_pipeline(&self.fill_pipeline);
            for group in &fills {
                pass.set_bind_group(0, group, &[]);
                pass.dispatch_workgroups(slots.min(FILL_ROW), slots.div_ceil(FILL_ROW), 1);
            }
            if let Some(group) = &shell_fill {
                pass.set_pipeline(&self.shells_fill_pipeline);
                pass.set_bind_group(0, group, &[]);
                pass.dispatch_workgroups(slots.min(FILL_ROW), slots.div_ceil(FILL_ROW), 1);
            }
            // The brick bits of what the fills marked (any layout-compatible group binds the
            // grid and the bits): the trace jumps the bricks they call empty, so they follow
            // every fill. Without a fill the grid is clear, and a stale bit can only call a
            // brick marked, which costs the trace its cell steps, never a wrong answer.
            if let Some(group) = fills.first().or(shell_fill.as_ref()) {
                // One workgroup per word (32 bricks).
                let words = (BRICK_BYTES / 4) as u32;
                pass.set_pipeline(&self.bricks_pipeline);
                pass.set_bind_group(0, group, &[]);
                pass.dispatch_workgroups(words, 1, 1);
            }
        });
        ctx.queue
            .write_buffer(&self.trace_uniforms, 0, bytemuck::bytes_of(&params.trace));
        let t = ctx.targets;
        let texture = |binding, view| wgpu::BindGroupEntry {
            binding,
            resource: wgpu::BindingResource::TextureView(view),
        };
        let trace = cache.get(
            &self.device,
            "shadow trace",
            &self.trace_layout,
            &[
                buffer_entry(0, &self.trace_uniforms),
                buffer_entry(1, &self.grid),
                texture(2, &t.normal),
                texture(3, &t.depth),
                buffer_entry(4, ctx.visibility.unwrap_or(&ctx.shared.no_visibility)),
                buffer_entry(5, &self.visibility),
                buffer_entry(6, &self.bricks),
            ],
        );
        let (width, height) = ctx.size();
        rec.step("shadow trace", true, |rec| {
            let pass = rec.compute();
            pass.set_pipeline(&self.trace_pipeline);
            pass.set_bind_group(0, ctx.frame_group, &[]);
            pass.set_bind_group(1, &trace, &[]);
            pass.dispatch_workgroups(width.div_ceil(8), height.div_ceil(8), 1);
        });
    }
}

fn pixel_count(width: u32, height: u32) -> u64 {
    u64::from(width.max(1)) * u64::from(height.max(1))
}

fn uniform_buffer(device: &Device, label: &str, size: usize) -> Result<Buffer, AllocError> {
    create_buffer(
        device,
        &wgpu::BufferDescriptor {
            label: Some(label),
            size: size as u64,
            usage: BufferUsages::UNIFORM | BufferUsages::COPY_DST,
            mapped_at_creation: false,
        },
    )
}

fn visibility_buffer(device: &Device, pixels: u64) -> Result<Buffer, AllocError> {
    create_buffer(
        device,
        &wgpu::BufferDescriptor {
            label: Some("shadow visibility"),
            size: pixels * 4,
            usage: BufferUsages::STORAGE | BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        },
    )
}
