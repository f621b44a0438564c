//! The cull pass on the GPU: pipeline ([`CullPass`]) and per-view output buffers
//! ([`CullOutput`]).

use wgpu::util::DeviceExt;
use wgpu::{
    BindGroupLayout, BindGroupLayoutEntry, BindingType, Buffer, BufferBindingType,
    BufferDescriptor, BufferUsages, CommandEncoder, ComputePipeline, Device, Queue, RenderPass,
    ShaderStages,
};

use voxel_core::formats::{ChunkDrawIndirect, MeshedChunkInfo};

use super::camera::{CullCamera, CullLayer};
use super::layout::{CullConfig, CullError, CullLayout, CullUniforms, DrawIndexedArgs};
use super::order::ORDER_KEYS;
use crate::chunk_table::GpuTable;
use crate::device::{GpuContext, MultiDrawPath};
use crate::gigabuffer::PageLayout;
use crate::readback::{ReadbackError, read_buffer};
use crate::shaders::CULL;

/// Invocations per workgroup (`CULL_WORKGROUP` in the shader).
const WORKGROUP: u32 = 64;
/// Largest workgroup count of one dispatch dimension (WebGPU's default limit).
const MAX_GROUPS_PER_DIM: u32 = 65_535;

/// The cull pipeline for one quad gigabuffer layout (see the [module docs](super)).
#[derive(Debug)]
pub struct CullPass {
    device: Device,
    pipeline: ComputePipeline,
    ordered: OrderedPipelines,
    bind_group_layout: BindGroupLayout,
    layout: CullLayout,
    multi_draw: MultiDrawPath,
    max_binding_bytes: u64,
}

impl CullPass {
    /// The pass for the quad gigabuffer `quads` (`gigabuffer.layout(DataKind::Quads)`), sized by
    /// `config`. Reads `ctx.capabilities.multi_draw` to decide whether commands past the
    /// count must be zeroed.
    pub fn new(
        ctx: &GpuContext,
        quads: &PageLayout,
        config: &CullConfig,
    ) -> Result<CullPass, CullError> {
        let layout = CullLayout::new(quads, config)?;
        let device = &ctx.device;
        let storage = |binding: u32, read_only: bool| BindGroupLayoutEntry {
            binding,
            visibility: ShaderStages::COMPUTE,
            ty: BindingType::Buffer {
                ty: BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("cull"),
            entries: &[
                BindGroupLayoutEntry {
                    binding: 0,
                    visibility: ShaderStages::COMPUTE,
                    ty: BindingType::Buffer {
                        ty: BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: wgpu::BufferSize::new(size_of::<CullUniforms>() as u64),
                    },
                    count: None,
                },
                storage(1, true),
                storage(2, false),
                storage(3, false),
                storage(4, false),
                storage(5, false),
                storage(6, false),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("cull"),
            bind_group_layouts: &[Some(&bind_group_layout)],
            immediate_size: 0,
        });
        let module = CULL.create_module(device);
        let pipeline_for = |entry_point: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry_point),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry_point),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let pipeline = pipeline_for("cull");
        let ordered = OrderedPipelines {
            count: pipeline_for("cull_count"),
            prefix: pipeline_for("order_prefix"),
            scatter: pipeline_for("cull_scatter"),
        };
        Ok(CullPass {
            device: device.clone(),
            pipeline,
            ordered,
            bind_group_layout,
            layout,
            multi_draw: ctx.capabilities.multi_draw,
            max_binding_bytes: ctx.capabilities.max_page_bytes(),
        })
    }

    /// The sizes this pass works with.
    pub fn layout(&self) -> &CullLayout {
        &self.layout
    }

    /// The draw path the outputs are prepared for.
    pub fn multi_draw(&self) -> MultiDrawPath {
        self.multi_draw
    }

    /// Buffers for one view's commands: `total_commands` args (20 B) and records (32 B), the
    /// per-page counts and the uniforms. One output per (view, layer) whose commands must live
    /// at the same time; an output may also be recorded again once its draws are recorded.
    pub fn create_output(&self, label: &str) -> Result<CullOutput, CullError> {
        let total = self.layout.total_commands();
        let check = |buffer: &'static str, bytes: u64| {
            if bytes > self.max_binding_bytes {
                Err(CullError::OutputTooLarge {
                    buffer,
                    bytes,
                    max_bytes: self.max_binding_bytes,
                })
            } else {
                Ok(bytes)
            }
        };
        let args_bytes = check("args", total * size_of::<DrawIndexedArgs>() as u64)?;
        let records_bytes = check("records", total * size_of::<ChunkDrawIndirect>() as u64)?;
        let order_bytes = check(
            "order counts",
            u64::from(self.layout.page_count) * u64::from(ORDER_KEYS) * 4,
        )?;
        let buffer = |suffix: &str, size: u64, usage: BufferUsages| {
            self.device.create_buffer(&BufferDescriptor {
                label: Some(&format!("{label} cull {suffix}")),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let readable = BufferUsages::STORAGE | BufferUsages::COPY_SRC | BufferUsages::COPY_DST;
        Ok(CullOutput {
            args: buffer("args", args_bytes, readable | BufferUsages::INDIRECT),
            records: buffer("records", records_bytes, readable),
            counts: buffer(
                "counts",
                u64::from(self.layout.page_count + 1) * 4,
                readable | BufferUsages::INDIRECT,
            ),
            uniforms: buffer(
                "uniforms",
                size_of::<CullUniforms>() as u64,
                BufferUsages::UNIFORM | BufferUsages::COPY_DST,
            ),
            order_counts: buffer("order counts", order_bytes, readable),
            order_cursors: buffer("order cursors", order_bytes, BufferUsages::STORAGE),
            layout: self.layout,
            multi_draw: self.multi_draw,
        })
    }

    /// Records the cull of `layer` of `table`'s slots `0..slot_bound` for `camera` into
    /// `encoder`, writing `output`; commands come in any order.
    ///
    /// In encoder order: the uniforms are copied in (so several records of one output in one
    /// encoder each see their own camera), the counts cleared, with
    /// [`MultiDrawPath::ZeroedCommands`] the args cleared too, then one dispatch. Flush the
    /// table before submitting (its writes land before the submission).
    pub fn record(
        &self,
        encoder: &mut CommandEncoder,
        table: &GpuTable<MeshedChunkInfo>,
        camera: &CullCamera,
        layer: CullLayer,
        output: &CullOutput,
    ) -> Result<(), CullError> {
        let Some((bind_group, groups)) = self.prepare(encoder, table, camera, layer, output)?
        else {
            return Ok(());
        };
        let mut pass = cull_pass(encoder, "cull", &bind_group);
        pass.set_pipeline(&self.pipeline);
        dispatch_slots(&mut pass, groups);
        Ok(())
    }

    /// Like [`record`](Self::record), but each page's commands come back to front: sorted by
    /// the depth key of their chunk's box centre, farthest first (see [`depth_key`] for the
    /// rule and its resolution; chunks of one key in any order, a chunk's face groups in face
    /// order). For blended layers. Three dispatches (count, prefix sums, scatter) after the
    /// same copies and clears as `record`, plus a clear of the per-key counts; the CPU work is
    /// the same whatever the chunk count.
    ///
    /// [`depth_key`]: super::depth_key
    pub fn record_ordered(
        &self,
        encoder: &mut CommandEncoder,
        table: &GpuTable<MeshedChunkInfo>,
        camera: &CullCamera,
        layer: CullLayer,
        output: &CullOutput,
    ) -> Result<(), CullError> {
        let Some((bind_group, groups)) = self.prepare(encoder, table, camera, layer, output)?
        else {
            return Ok(());
        };
        encoder.clear_buffer(&output.order_counts, 0, None);
        let mut pass = cull_pass(encoder, "ordered cull", &bind_group);
        pass.set_pipeline(&self.ordered.count);
        dispatch_slots(&mut pass, groups);
        pass.set_pipeline(&self.ordered.prefix);
        pass.dispatch_workgroups(self.layout.page_count, 1, 1);
        pass.set_pipeline(&self.ordered.scatter);
        dispatch_slots(&mut pass, groups);
        Ok(())
    }

    /// The copies and clears every record starts with, and the bind group; `None` when the
    /// table has no slots (nothing to dispatch).
    fn prepare(
        &self,
        encoder: &mut CommandEncoder,
        table: &GpuTable<MeshedChunkInfo>,
        camera: &CullCamera,
        layer: CullLayer,
        output: &CullOutput,
    ) -> Result<Option<(wgpu::BindGroup, u32)>, CullError> {
        if output.layout != self.layout || output.multi_draw != self.multi_draw {
            return Err(CullError::OutputMismatch);
        }
        let slot_bound = table.slot_bound();
        let uniforms = CullUniforms::new(&self.layout, camera, layer, slot_bound);
        let staging = self
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("cull uniforms staging"),
                contents: bytemuck::bytes_of(&uniforms),
                usage: BufferUsages::COPY_SRC,
            });
        encoder.copy_buffer_to_buffer(&staging, 0, &output.uniforms, 0, None);
        encoder.clear_buffer(&output.counts, 0, None);
        if self.multi_draw == MultiDrawPath::ZeroedCommands {
            encoder.clear_buffer(&output.args, 0, None);
        }
        let groups = slot_bound.div_ceil(WORKGROUP);
        if groups == 0 {
            return Ok(None);
        }
        let buffers = [
            &output.uniforms,
            table.buffer(),
            &output.args,
            &output.records,
            &output.counts,
            &output.order_counts,
            &output.order_cursors,
        ];
        let entries: Vec<wgpu::BindGroupEntry<'_>> = buffers
            .iter()
            .enumerate()
            .map(|(binding, buffer)| wgpu::BindGroupEntry {
                binding: binding as u32,
                resource: buffer.as_entire_binding(),
            })
            .collect();
        let bind_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("cull"),
            layout: &self.bind_group_layout,
            entries: &entries,
        });
        Ok(Some((bind_group, groups)))
    }
}

/// The ordered cull's three pipelines (entry points of `cull.wgsl`).
#[derive(Debug)]
struct OrderedPipelines {
    count: ComputePipeline,
    prefix: ComputePipeline,
    scatter: ComputePipeline,
}

/// A compute pass with the cull's bind group set.
fn cull_pass<'e>(
    encoder: &'e mut CommandEncoder,
    label: &str,
    bind_group: &wgpu::BindGroup,
) -> wgpu::ComputePass<'e> {
    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
        label: Some(label),
        timestamp_writes: None,
    });
    pass.set_bind_group(0, bind_group, &[]);
    pass
}

/// Dispatches `groups` workgroups of slots, folded into two dimensions past the per-dimension
/// limit (the shader linearises them).
fn dispatch_slots(pass: &mut wgpu::ComputePass<'_>, groups: u32) {
    let x = groups.min(MAX_GROUPS_PER_DIM);
    let y = groups.div_ceil(x);
    pass.dispatch_workgroups(x, y, 1);
}

/// One view's cull results on the GPU (see the [module docs](super) for the layout).
#[derive(Debug)]
pub struct CullOutput {
    args: Buffer,
    records: Buffer,
    counts: Buffer,
    uniforms: Buffer,
    order_counts: Buffer,
    order_cursors: Buffer,
    layout: CullLayout,
    multi_draw: MultiDrawPath,
}

impl CullOutput {
    /// Tightly packed [`DrawIndexedArgs`], one range of `commands_per_page` per page: the
    /// indirect buffer of the draws.
    pub fn args(&self) -> &Buffer {
        &self.args
    }

    /// The [`ChunkDrawIndirect`] of every command, at the same index as its args: the vertex
    /// shader reads `records[instance_index]` (`first_instance` is the command index).
    pub fn records(&self) -> &Buffer {
        &self.records
    }

    /// `u32` per page (commands wanted; the draw count is `min(count, commands_per_page)`),
    /// then the malformed-layer count: the count buffer of the draws.
    pub fn counts(&self) -> &Buffer {
        &self.counts
    }

    /// The sizes of this output.
    pub fn layout(&self) -> &CullLayout {
        &self.layout
    }

    /// Byte offset of page `page`'s commands in [`args`](Self::args).
    pub fn args_offset(&self, page: u32) -> u64 {
        self.layout.page_commands(page).start * size_of::<DrawIndexedArgs>() as u64
    }

    /// Byte offset of page `page`'s count in [`counts`](Self::counts).
    pub fn count_offset(&self, page: u32) -> u64 {
        u64::from(page) * 4
    }

    /// Records the draw of page `page`'s commands into `pass`, whose pipeline, index buffer
    /// (see [`quad_indices`](super::quad_indices)) and bind groups (with page `page` of the
    /// quad gigabuffer and [`records`](Self::records)) are set: one
    /// `multi_draw_indexed_indirect_count` with [`MultiDrawPath::IndirectCount`], one
    /// `multi_draw_indexed_indirect` over the whole (zero-padded) range otherwise. Needs
    /// `INDIRECT_FIRST_INSTANCE` (the commands' `first_instance` is not 0).
    pub fn draw_page(&self, pass: &mut RenderPass<'_>, page: u32) {
        let max = self.layout.commands_per_page;
        match self.multi_draw {
            MultiDrawPath::IndirectCount => pass.multi_draw_indexed_indirect_count(
                &self.args,
                self.args_offset(page),
                &self.counts,
                self.count_offset(page),
                max,
            ),
            MultiDrawPath::ZeroedCommands => {
                pass.multi_draw_indexed_indirect(&self.args, self.args_offset(page), max)
            }
        }
    }

    /// Reads everything back (tests, debugging). Blocks until the GPU is done.
    pub fn read(&self, device: &Device, queue: &Queue) -> Result<CullReadback, ReadbackError> {
        let counts: Vec<u32> = cast(read_buffer(
            device,
            queue,
            &self.counts,
            0,
            self.counts.size(),
        )?)?;
        let args: Vec<DrawIndexedArgs> =
            cast(read_buffer(device, queue, &self.args, 0, self.args.size())?)?;
        let records: Vec<ChunkDrawIndirect> = cast(read_buffer(
            device,
            queue,
            &self.records,
            0,
            self.records.size(),
        )?)?;
        let per_page = self.layout.commands_per_page as usize;
        let pages = self.layout.page_count as usize;
        Ok(CullReadback {
            wanted: counts[..pages].to_vec(),
            malformed: counts[pages],
            args: args.chunks(per_page).map(<[_]>::to_vec).collect(),
            records: records.chunks(per_page).map(<[_]>::to_vec).collect(),
        })
    }
}

fn cast<T: bytemuck::Pod>(bytes: Vec<u8>) -> Result<Vec<T>, ReadbackError> {
    bytemuck::try_cast_slice(&bytes)
        .map(<[T]>::to_vec)
        .map_err(|e| ReadbackError(format!("cannot cast {} bytes: {e}", bytes.len())))
}

/// A [`CullOutput`] read back.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CullReadback {
    /// Per page, the commands the cull wanted (`counts[page]`).
    pub wanted: Vec<u32>,
    /// Malformed chunk layers skipped.
    pub malformed: u32,
    /// Per page, every command slot's args (the whole range, used or not).
    pub args: Vec<Vec<DrawIndexedArgs>>,
    /// Per page, every command slot's record.
    pub records: Vec<Vec<ChunkDrawIndirect>>,
}

impl CullReadback {
    /// Commands of page `page` that were written: `min(wanted, commands_per_page)`.
    pub fn written(&self, page: usize) -> usize {
        (self.wanted[page] as usize).min(self.args[page].len())
    }
}
