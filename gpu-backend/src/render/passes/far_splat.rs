//! The compute splat of far-drawn nodes (see [`far`](crate::render::far) for the format and
//! the bounds): its pipelines, its visibility buffers, and recording one splat per cull record.
//!
//! Per frame: [`FarSplat::clear`] empties both visibility buffers and the range; after each cull
//! record that appended to the far list, [`FarSplat::record`] runs `far_args` (one thread: the
//! new entries' range and workgroup counts) and `splat` (indirect, one workgroup per entry), so
//! the entries of every record are splatted exactly once.

use wgpu::{
    BindGroup, BindGroupLayout, BindGroupLayoutEntry, BindingType, Buffer, BufferBindingType,
    BufferUsages, CommandEncoder, ComputePipeline, Device, ShaderStages,
};

use voxel_core::formats::DataKind;

use super::cull::CullFrame;
use super::frame::{FrameCtx, Phase, Recorder};
use crate::bind::{BindGroupCache, buffer_entry};
use crate::device::alloc::AllocError;
use crate::shaders::{FAR_ARGS, FAR_SPLAT};

/// Invocations per workgroup of `splat` (`SPLAT_WORKGROUP`).
pub const SPLAT_WORKGROUP: u32 = 64;
/// The statistics word counting the pixels the splat tested (`STAT_SPLAT_PIXELS`).
pub const STAT_SPLAT_PIXELS: usize = 11;
/// The statistics word counting blocks skipped (near plane, or too many pixels).
pub const STAT_SPLAT_SKIPPED: usize = 12;

/// What the splat counted in a frame (words of the cull frame's statistics).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SplatStats {
    /// Pixel centres tested against a block.
    pub pixels: u32,
    /// Blocks skipped: reaching the near plane or covering more than 32 x 32 pixels.
    pub skipped: u32,
}

impl SplatStats {
    /// The counters from the statistics words.
    pub fn from_words(words: &[u32]) -> SplatStats {
        SplatStats {
            pixels: words.get(STAT_SPLAT_PIXELS).copied().unwrap_or(0),
            skipped: words.get(STAT_SPLAT_SKIPPED).copied().unwrap_or(0),
        }
    }
}

/// What a splat binds besides its own buffers.
#[derive(Clone, Copy, Debug)]
pub struct SplatInputs<'a> {
    /// The frame uniforms.
    pub frame_uniforms: &'a Buffer,
    /// The chunk table.
    pub table: &'a Buffer,
    /// The node table.
    pub nodes: &'a Buffer,
    /// The draw-block gigabuffer's page.
    pub blocks: &'a Buffer,
    /// The cull frame (far list, statistics).
    pub frame: &'a CullFrame,
}

/// The splat's pipelines and buffers for one output size.
#[derive(Debug)]
pub struct FarSplat {
    device: Device,
    frame_layout: BindGroupLayout,
    layout: BindGroupLayout,
    args_layout: BindGroupLayout,
    splat: ComputePipeline,
    args: ComputePipeline,
    visibility: Buffer,
    transparent: Buffer,
    range: Buffer,
    width: u32,
    height: u32,
    bind_cache: BindGroupCache,
}

fn storage(binding: u32, read_only: bool) -> BindGroupLayoutEntry {
    BindGroupLayoutEntry {
        binding,
        visibility: ShaderStages::COMPUTE,
        ty: BindingType::Buffer {
            ty: BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn pipeline(
    device: &Device,
    label: &str,
    layouts: &[&BindGroupLayout],
    module: &wgpu::ShaderModule,
    entry: &str,
) -> ComputePipeline {
    let layouts: Vec<Option<&BindGroupLayout>> = layouts.iter().map(|l| Some(*l)).collect();
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &layouts,
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: Some(&layout),
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    })
}

impl FarSplat {
    /// The splat for `width x height` pixels on `device`, which must have the 64-bit atomics
    /// (`GpuCapabilities::int64_atomics`; the caller checks). The visibility buffers take 8
    /// bytes per pixel each, refused with [`SplatError::TooLarge`] past `max_bytes`
    /// (the device's storage binding limit).
    pub fn new(
        device: &Device,
        width: u32,
        height: u32,
        max_bytes: u64,
    ) -> Result<FarSplat, SplatError> {
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("splat frame"),
            entries: &[BindGroupLayoutEntry {
                binding: 0,
                visibility: ShaderStages::COMPUTE,
                ty: BindingType::Buffer {
                    ty: BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("splat"),
            entries: &[
                storage(0, true),
                storage(1, true),
                storage(2, true),
                storage(3, true),
                storage(4, false),
                storage(5, false),
                storage(6, true),
                storage(7, false),
            ],
        });
        let args_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("far args"),
            entries: &[storage(0, false), storage(1, false), storage(2, true)],
        });
        let splat_module = FAR_SPLAT.create_module(device);
        let args_module = FAR_ARGS.create_module(device);
        let splat = pipeline(
            device,
            "splat",
            &[&frame_layout, &layout],
            &splat_module,
            "splat",
        );
        let args = pipeline(
            device,
            "far args",
            &[&args_layout],
            &args_module,
            "far_args",
        );
        let (visibility, transparent) = visibility_buffers(device, width, height, max_bytes)?;
        let range = crate::device::alloc::create_buffer(
            device,
            &wgpu::BufferDescriptor {
                label: Some("splat range"),
                size: 32,
                usage: BufferUsages::STORAGE | BufferUsages::INDIRECT | BufferUsages::COPY_DST,
                mapped_at_creation: false,
            },
        )?;
        Ok(FarSplat {
            device: device.clone(),
            frame_layout,
            layout,
            args_layout,
            splat,
            args,
            visibility,
            transparent,
            range,
            width,
            height,
            bind_cache: BindGroupCache::default(),
        })
    }

    /// Resizes the visibility buffers.
    pub fn resize(&mut self, width: u32, height: u32, max_bytes: u64) -> Result<(), SplatError> {
        (self.visibility, self.transparent) =
            visibility_buffers(&self.device, width, height, max_bytes)?;
        (self.width, self.height) = (width, height);
        Ok(())
    }

    /// The opaque visibility buffer (`width * height` 64-bit words).
    pub fn visibility(&self) -> &Buffer {
        &self.visibility
    }

    /// The transparent visibility buffer.
    pub fn transparent(&self) -> &Buffer {
        &self.transparent
    }

    /// Empties both visibility buffers and the entry range: once per frame, before the first
    /// [`record`](Self::record).
    pub fn clear(&self, encoder: &mut CommandEncoder) {
        encoder.clear_buffer(&self.visibility, 0, None);
        encoder.clear_buffer(&self.transparent, 0, None);
        encoder.clear_buffer(&self.range, 0, None);
    }

    /// Splats the far-list entries appended since the last record of the frame: one compute
    /// pass of [`record_in`](Self::record_in).
    pub fn record(&self, encoder: &mut CommandEncoder, inputs: &SplatInputs<'_>) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("splat"),
            timestamp_writes: None,
        });
        self.record_in(&mut pass, inputs);
    }

    /// [`record`](Self::record) into an open compute pass: the dispatch that sizes the splat
    /// from the far list's count, then the splat.
    pub fn record_in(&self, pass: &mut wgpu::ComputePass<'_>, inputs: &SplatInputs<'_>) {
        let args_group = self.bind_cache.get(
            &self.device,
            "far args",
            &self.args_layout,
            &[
                buffer_entry(0, inputs.frame.stats()),
                buffer_entry(1, &self.range),
                buffer_entry(2, inputs.frame.far_list()),
            ],
        );
        let frame_group = self.bind_cache.get(
            &self.device,
            "splat frame",
            &self.frame_layout,
            &[buffer_entry(0, inputs.frame_uniforms)],
        );
        let group = self.splat_group(inputs);
        pass.set_pipeline(&self.args);
        pass.set_bind_group(0, &args_group, &[]);
        pass.dispatch_workgroups(1, 1, 1);
        pass.set_pipeline(&self.splat);
        pass.set_bind_group(0, &frame_group, &[]);
        pass.set_bind_group(1, &group, &[]);
        pass.dispatch_workgroups_indirect(&self.range, 0);
    }

    /// Records the splat of the far nodes `phase`'s cull listed in `frame` in the renderer's
    /// frame, timed as `far splat` (`far splat late`); nothing before draw blocks are resident.
    pub fn record_phase(
        &self,
        ctx: &FrameCtx<'_>,
        rec: &mut Recorder<'_, '_>,
        phase: Phase,
        frame: &CullFrame,
    ) {
        let residency = ctx.residency;
        let Some(blocks) = residency.gigabuffer().page(DataKind::DrawBlocks, 0) else {
            return;
        };
        let inputs = SplatInputs {
            frame_uniforms: &ctx.shared.frame_uniforms,
            table: residency.table().buffer(),
            nodes: residency.nodes().buffer(),
            blocks,
            frame,
        };
        rec.step(phase.label("far splat", "far splat late"), true, |rec| {
            self.record_in(rec.compute(), &inputs);
        });
    }

    fn splat_group(&self, inputs: &SplatInputs<'_>) -> BindGroup {
        let buffers = [
            inputs.table,
            inputs.nodes,
            inputs.frame.far_list(),
            inputs.blocks,
            &self.visibility,
            &self.transparent,
            &self.range,
            inputs.frame.stats(),
        ];
        let entries: Vec<wgpu::BindGroupEntry<'_>> = buffers
            .iter()
            .enumerate()
            .map(|(binding, buffer)| wgpu::BindGroupEntry {
                binding: binding as u32,
                resource: buffer.as_entire_binding(),
            })
            .collect();
        self.bind_cache
            .get(&self.device, "splat", &self.layout, &entries)
    }
}

/// A visibility buffer larger than one storage binding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct VisibilityTooLarge {
    /// Screen width, pixels.
    pub width: u32,
    /// Screen height, pixels.
    pub height: u32,
    /// Bytes the buffer takes.
    pub bytes: u64,
    /// The device's storage binding limit.
    pub max_bytes: u64,
}

impl std::fmt::Display for VisibilityTooLarge {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let VisibilityTooLarge {
            width,
            height,
            bytes,
            max_bytes,
        } = self;
        write!(
            f,
            "a {width}x{height} visibility buffer takes {bytes} bytes, above the device's \
             storage binding limit of {max_bytes}"
        )
    }
}

impl std::error::Error for VisibilityTooLarge {}

/// Why the splat's buffers could not be made.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SplatError {
    /// A visibility buffer would be larger than one storage binding.
    TooLarge(VisibilityTooLarge),
    /// The device refused a buffer.
    Alloc(AllocError),
}

impl std::fmt::Display for SplatError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SplatError::TooLarge(e) => write!(f, "{e}"),
            SplatError::Alloc(e) => write!(f, "far splat: {e}"),
        }
    }
}

impl std::error::Error for SplatError {}

impl From<AllocError> for SplatError {
    fn from(e: AllocError) -> Self {
        SplatError::Alloc(e)
    }
}

fn visibility_buffers(
    device: &Device,
    width: u32,
    height: u32,
    max_bytes: u64,
) -> Result<(Buffer, Buffer), SplatError> {
    let bytes = u64::from(width) * u64::from(height) * 8;
    if bytes > max_bytes {
        return Err(SplatError::TooLarge(VisibilityTooLarge {
            width,
            height,
            bytes,
            max_bytes,
        }));
    }
    let buffer = |label| {
        crate::device::alloc::create_buffer(
            device,
            &wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage: BufferUsages::STORAGE | BufferUsages::COPY_DST | BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            },
        )
    };
    Ok((
        buffer("far visibility")?,
        buffer("far transparent visibility")?,
    ))
}
