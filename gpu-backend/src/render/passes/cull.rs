//! The cull pass on the GPU: near chunks (`MeshedChunkInfo`) to multi-draw-indirect commands.
//! What it decides (frustum, face directions, level of detail, far draws, occlusion), the
//! command layout per page and the CPU reference that makes the same decisions are in
//! [`render_model::cull`]; this module holds the pipelines ([`CullPass`]), the buffers a record
//! writes ([`CullOutput`], [`CullFrame`]) and their reads.
//!
//! **Fallback.** With [`MultiDrawPath::ZeroedCommands`] (no `MULTI_DRAW_INDIRECT_COUNT`) the
//! args buffer is cleared before the dispatch, so every slot past a page's count is a zero
//! command (`instance_count = 0`) and `multi_draw_indexed_indirect(args, p*C*20, C)` draws
//! nothing extra. Order is not deterministic either way: commands of a page come in the order
//! of the atomics (workgroups take their slots with one global `atomicAdd` per page).
//! [`FrameCulls`] holds the renderer's records of a frame.

mod frame_culls;
mod output;

pub use frame_culls::{FrameCullParams, FrameCulls, PreparedFrame};
pub use output::{CullFrame, CullOutput, CullReadback};

use wgpu::{
    BindGroupLayout, BindGroupLayoutEntry, BindingType, Buffer, BufferBindingType, BufferUsages,
    CommandEncoder, ComputePipeline, Device, ShaderStages,
};

use voxel_core::formats::MeshedChunkInfo;

use render_model::cull::{
    CullConfig, CullError, CullLayer, CullLayout, CullParams, CullUniforms, CullView, NodeRecord,
};
use render_model::pages::PageLayout;

use crate::bind::{BindGroupCache, buffer_entry};
use crate::device::{GpuContext, MultiDrawPath};
use crate::residency::GpuTable;
use crate::shaders::{CULL, LIST_ARGS};
use output::OutputFactory;

/// Invocations per workgroup (`CULL_WORKGROUP` in the shader).
const WORKGROUP: u32 = 64;
/// Largest workgroup count of one dispatch dimension (WebGPU's default limit).
const MAX_GROUPS_PER_DIM: u32 = 65_535;
/// Buffer bindings of the cull's bind group (the depth pyramid follows them).
const BINDINGS: u32 = 14;

/// What a record reads besides its view: the chunk table, the node table in the same slots
/// (`None`: no node records, as for chunks uploaded without smooth quads, blocks or skirts),
/// the frame's shared buffers (`None`: the pass's own, for records whose far list and
/// statistics nobody reads), and where its uniforms come from.
#[derive(Clone, Copy, Debug)]
pub struct CullInputs<'a> {
    /// The chunk table.
    pub table: &'a GpuTable<MeshedChunkInfo>,
    /// The node table, slot for slot.
    pub nodes: Option<&'a GpuTable<NodeRecord>>,
    /// The frame's far list and statistics.
    pub frame: Option<&'a CullFrame>,
    /// Occlusion culling's inputs (needed when the record's parameters turn it on).
    pub occlusion: Option<OcclusionInputs<'a>>,
    /// Where the record's uniforms are copied from.
    pub uniforms: UniformSource<'a>,
}

/// The order of a record's commands within each page.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum CullOrder {
    /// In the order of the atomics (opaque layers).
    #[default]
    Any,
    /// Sorted by the depth key of their chunk's box centre, farthest first (blended layers;
    /// `render_model::cull::depth_key` states the rule and its resolution; chunks of one key
    /// in any order, a chunk's face groups in face order). Three dispatches (count, prefix
    /// sums, scatter) after the same copies and clears, plus a clear of the per-key counts;
    /// the CPU work is the same whatever the chunk count. Far-drawn nodes are skipped (the far
    /// draw shades their transparent blocks) and never listed.
    BackToFront,
}

/// One cull record: what it reads ([`CullInputs`]), the view, the layer, the output it writes,
/// what it selects ([`CullParams`]: level of detail, far draws, smooth draws, occlusion) and
/// the order of its commands. [`CullRequest::new`] is the near-field cull of a table of
/// full-detail chunks; set the other fields for more.
#[derive(Clone, Copy, Debug)]
pub struct CullRequest<'a> {
    /// What the record reads besides its view.
    pub inputs: CullInputs<'a>,
    /// The view (eye and frustum planes).
    pub view: &'a CullView,
    /// The quad layer culled.
    pub layer: CullLayer,
    /// Where the commands go.
    pub output: &'a CullOutput,
    /// Level-of-detail selection, far draws, smooth draws, occlusion (see
    /// [`cull::lod`](render_model::cull::lod) for the rule).
    pub params: CullParams,
    /// The order of the commands.
    pub order: CullOrder,
}

impl<'a> CullRequest<'a> {
    /// The cull of `layer` of `table`'s slots `0..slot_bound` for `view` into `output`:
    /// level 0 only, no far draws, no smooth draws, commands in any order.
    pub fn new(
        table: &'a GpuTable<MeshedChunkInfo>,
        view: &'a CullView,
        layer: CullLayer,
        output: &'a CullOutput,
    ) -> CullRequest<'a> {
        CullRequest {
            inputs: CullInputs {
                table,
                nodes: None,
                frame: None,
                occlusion: None,
                uniforms: UniformSource::Own,
            },
            view,
            layer,
            output,
            params: CullParams::default(),
            order: CullOrder::Any,
        }
    }

    /// This request with its commands back to front ([`CullOrder::BackToFront`]).
    pub fn back_to_front(self) -> CullRequest<'a> {
        CullRequest {
            order: CullOrder::BackToFront,
            ..self
        }
    }
}

/// What two-phase occlusion culling reads and writes: a bit per table slot (visible in the last
/// late phase; `ceil(capacity / 32)` words, zeroed at creation) and the depth pyramid of the
/// early phase ([`DepthPyramid::texture_view`](super::hiz::DepthPyramid::texture_view)).
#[derive(Clone, Copy, Debug)]
pub struct OcclusionInputs<'a> {
    /// The visibility bits.
    pub visible: &'a Buffer,
    /// The depth pyramid, all mips.
    pub pyramid: &'a wgpu::TextureView,
}

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
    /// Zeroed node records for records without a node table.
    no_nodes: Buffer,
    /// The frame buffers of records without a frame.
    own_frame: CullFrame,
    /// Bound when a record has no occlusion inputs.
    no_visible: Buffer,
    no_pyramid: wgpu::TextureView,
    /// The records' bind groups, made once per set of buffers.
    bind_cache: BindGroupCache,
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
                storage(7, true),
                storage(8, false),
                storage(9, false),
                storage(10, false),
                storage(11, false),
                storage(12, false),
                storage(13, false),
                super::hiz::DepthPyramid::layout_entry(14, ShaderStages::COMPUTE),
                storage(15, false),
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
        let list_args_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("transparent list dispatch"),
            entries: &[storage(0, false), storage(1, false), storage(2, true)],
        });
        let list_args = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("transparent list dispatch"),
            layout: Some(
                &device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some("transparent list dispatch"),
                    bind_group_layouts: &[Some(&list_args_layout)],
                    immediate_size: 0,
                }),
            ),
            module: &LIST_ARGS.create_module(device),
            entry_point: Some("transparent_args"),
            compilation_options: Default::default(),
            cache: None,
        });
        let ordered = OrderedPipelines {
            count: pipeline_for("cull_count"),
            prefix: pipeline_for("order_prefix"),
            scatter: pipeline_for("cull_scatter"),
            list_args,
            list_args_layout,
        };
        let max_binding_bytes = ctx.capabilities.max_page_bytes();
        let factory = OutputFactory {
            device,
            layout,
            multi_draw: ctx.capabilities.multi_draw,
            max_binding_bytes,
        };
        let own_frame = factory.frame("unread")?;
        let node_bytes = u64::from(config.table_capacity.max(1)) * size_of::<NodeRecord>() as u64;
        if node_bytes > max_binding_bytes {
            return Err(CullError::OutputTooLarge {
                buffer: "node records",
                bytes: node_bytes,
                max_bytes: max_binding_bytes,
            });
        }
        let no_nodes = crate::device::alloc::create_buffer(
            device,
            &wgpu::BufferDescriptor {
                label: Some("cull: no node records"),
                size: node_bytes,
                usage: BufferUsages::STORAGE,
                mapped_at_creation: false,
            },
        )?;
        let no_visible = crate::device::alloc::create_buffer(
            device,
            &wgpu::BufferDescriptor {
                label: Some("cull: no visibility bits"),
                size: 16,
                usage: BufferUsages::STORAGE,
                mapped_at_creation: false,
            },
        )?;
        let no_pyramid = crate::device::alloc::create_texture(
            device,
            &wgpu::TextureDescriptor {
                label: Some("cull: no depth pyramid"),
                size: wgpu::Extent3d {
                    width: 1,
                    height: 1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::R32Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
        )?
        .create_view(&Default::default());
        Ok(CullPass {
            device: device.clone(),
            pipeline,
            ordered,
            bind_group_layout,
            layout,
            multi_draw: ctx.capabilities.multi_draw,
            max_binding_bytes,
            no_nodes,
            own_frame,
            no_visible,
            no_pyramid,
            bind_cache: BindGroupCache::default(),
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

    fn factory(&self) -> OutputFactory<'_> {
        OutputFactory {
            device: &self.device,
            layout: self.layout,
            multi_draw: self.multi_draw,
            max_binding_bytes: self.max_binding_bytes,
        }
    }

    /// Buffers for one view's commands: `total_commands` args (20 B) and records (16 B), the
    /// per-page counts, the smooth draws per page pair, and the uniforms. One output per (view,
    /// layer) whose commands must live at the same time; an output may also be recorded again
    /// once its draws are recorded.
    pub fn create_output(&self, label: &str) -> Result<CullOutput, CullError> {
        self.factory().output(label)
    }

    /// The buffers a frame's records share: the far list (`far_capacity` entries) and the
    /// statistics.
    pub fn create_frame(&self, label: &str) -> Result<CullFrame, CullError> {
        self.factory().frame(label)
    }

    /// Records the cull `request` into `encoder`: its copies and clears, then its dispatches
    /// in a compute pass of their own. Commands come in any order, or back to front with
    /// [`CullOrder::BackToFront`].
    ///
    /// In encoder order: the uniforms are copied in (so several records of one output in one
    /// encoder each see their own view), the counts cleared, with
    /// [`MultiDrawPath::ZeroedCommands`] the args cleared too, then the dispatches. Flush the
    /// table before submitting (its writes land before the submission).
    pub fn record(
        &self,
        encoder: &mut CommandEncoder,
        request: &CullRequest<'_>,
    ) -> Result<(), CullError> {
        let prepared = self.prepare(encoder, request)?;
        if let Some(prepared) = &prepared {
            let label = match request.order {
                CullOrder::Any => "cull",
                CullOrder::BackToFront => "ordered cull",
            };
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes: None,
            });
            self.dispatch(&mut pass, prepared);
        }
        Ok(())
    }

    /// The first half of [`record`](Self::record): the request's copies and clears, recorded
    /// into `encoder`; [`dispatch`](Self::dispatch) records the rest into any later compute
    /// pass of the same encoder (several records can share one pass; see
    /// [`PassChain`](crate::pass_chain::PassChain)). `None`: nothing to dispatch (no slots).
    pub fn prepare(
        &self,
        encoder: &mut CommandEncoder,
        request: &CullRequest<'_>,
    ) -> Result<Option<PreparedCull>, CullError> {
        let Some((bind_group, groups)) = self.prepare_record(encoder, request)? else {
            return Ok(None);
        };
        let ordered = match request.order {
            CullOrder::Any => None,
            CullOrder::BackToFront => {
                encoder.clear_buffer(&request.output.order_counts, 0, None);
                let frame = request.inputs.frame.unwrap_or(&self.own_frame);
                let from_list = request.params.from_list.then(|| {
                    let args_group = self.bind_cache.get(
                        &self.device,
                        "transparent list dispatch",
                        &self.ordered.list_args_layout,
                        &[
                            buffer_entry(0, &frame.stats),
                            buffer_entry(1, &frame.list_args),
                            buffer_entry(2, &frame.transparent_list),
                        ],
                    );
                    (args_group, frame.list_args.clone())
                });
                Some(OrderedDispatch { from_list })
            }
        };
        Ok(Some(PreparedCull {
            bind_group,
            groups,
            ordered,
        }))
    }

    /// Records a prepared record's dispatches into `pass`.
    pub fn dispatch(&self, pass: &mut wgpu::ComputePass<'_>, prepared: &PreparedCull) {
        let Some(ordered) = &prepared.ordered else {
            pass.set_bind_group(0, &prepared.bind_group, &[]);
            pass.set_pipeline(&self.pipeline);
            dispatch_slots(pass, prepared.groups);
            return;
        };
        if let Some((args_group, _)) = &ordered.from_list {
            pass.set_pipeline(&self.ordered.list_args);
            pass.set_bind_group(0, args_group, &[]);
            pass.dispatch_workgroups(1, 1, 1);
        }
        pass.set_bind_group(0, &prepared.bind_group, &[]);
        let dispatch = |pass: &mut wgpu::ComputePass<'_>| match &ordered.from_list {
            Some((_, list_args)) => pass.dispatch_workgroups_indirect(list_args, 0),
            None => dispatch_slots(pass, prepared.groups),
        };
        pass.set_pipeline(&self.ordered.count);
        dispatch(pass);
        pass.set_pipeline(&self.ordered.prefix);
        pass.dispatch_workgroups(self.layout.page_count, 1, 1);
        pass.set_pipeline(&self.ordered.scatter);
        dispatch(pass);
    }

    /// The uniforms `request` copies in: what a caller writes into its own staging buffer for
    /// [`UniformSource::Staged`] (`request.inputs.uniforms` is not read).
    pub fn uniforms(&self, request: &CullRequest<'_>) -> CullUniforms {
        CullUniforms::new(
            &self.layout,
            request.view,
            request.layer,
            request.inputs.table.slot_bound(),
            &request.params,
        )
    }

    /// The copies and clears every record starts with, and the bind group; `None` when the
    /// table has no slots (nothing to dispatch).
    fn prepare_record(
        &self,
        encoder: &mut CommandEncoder,
        request: &CullRequest<'_>,
    ) -> Result<Option<(wgpu::BindGroup, u32)>, CullError> {
        let (inputs, output, params) = (&request.inputs, request.output, &request.params);
        if output.layout != self.layout || output.multi_draw != self.multi_draw {
            return Err(CullError::OutputMismatch);
        }
        let table = inputs.table;
        if inputs
            .nodes
            .is_some_and(|n| n.capacity() < table.slot_bound())
        {
            return Err(CullError::OutputMismatch);
        }
        if inputs.nodes.is_none() && u64::from(table.slot_bound()) * 64 > self.no_nodes.size() {
            return Err(CullError::OutputMismatch);
        }
        if params.occlusion.is_some() && inputs.occlusion.is_none() {
            return Err(CullError::OcclusionInputsMissing);
        }
        let slot_bound = table.slot_bound();
        let size = size_of::<CullUniforms>() as u64;
        match inputs.uniforms {
            UniformSource::Own => {
                let uniforms = self.uniforms(request);
                let staging = crate::device::alloc::create_buffer_init(
                    &self.device,
                    &wgpu::util::BufferInitDescriptor {
                        label: Some("cull uniforms staging"),
                        contents: bytemuck::bytes_of(&uniforms),
                        usage: BufferUsages::COPY_SRC,
                    },
                )?;
                encoder.copy_buffer_to_buffer(&staging, 0, &output.uniforms, 0, size);
            }
            UniformSource::Staged { buffer, offset } => {
                let fits = buffer.usage().contains(BufferUsages::COPY_SRC)
                    && offset.is_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT)
                    && offset
                        .checked_add(size)
                        .is_some_and(|end| end <= buffer.size());
                if !fits {
                    return Err(CullError::StagedUniformsUnusable {
                        offset,
                        buffer_size: buffer.size(),
                    });
                }
                encoder.copy_buffer_to_buffer(buffer, offset, &output.uniforms, 0, size);
            }
        }
        encoder.clear_buffer(&output.counts, 0, None);
        encoder.clear_buffer(&output.smooth_counts, 0, None);
        if self.multi_draw == MultiDrawPath::ZeroedCommands {
            encoder.clear_buffer(&output.args, 0, None);
            encoder.clear_buffer(&output.smooth_args, 0, None);
        }
        let frame = inputs.frame.unwrap_or(&self.own_frame);
        if inputs.frame.is_none() {
            frame.clear(encoder);
        }
        let groups = slot_bound.div_ceil(WORKGROUP);
        if groups == 0 {
            return Ok(None);
        }
        let nodes = inputs.nodes.map_or(&self.no_nodes, |n| n.buffer());
        let (visible, pyramid) = inputs
            .occlusion
            .map_or((&self.no_visible, &self.no_pyramid), |o| {
                (o.visible, o.pyramid)
            });
        let buffers: [&Buffer; BINDINGS as usize] = [
            &output.uniforms,
            table.buffer(),
            &output.args,
            &output.records,
            &output.counts,
            &output.order_counts,
            &output.order_cursors,
            nodes,
            &frame.far_list,
            &output.smooth_args,
            &output.smooth_records,
            &output.smooth_counts,
            &frame.stats,
            visible,
        ];
        let mut entries: Vec<wgpu::BindGroupEntry<'_>> = buffers
            .iter()
            .enumerate()
            .map(|(binding, buffer)| wgpu::BindGroupEntry {
                binding: binding as u32,
                resource: buffer.as_entire_binding(),
            })
            .collect();
        entries.push(wgpu::BindGroupEntry {
            binding: BINDINGS,
            resource: wgpu::BindingResource::TextureView(pyramid),
        });
        entries.push(buffer_entry(BINDINGS + 1, &frame.transparent_list));
        let bind_group =
            self.bind_cache
                .get(&self.device, "cull", &self.bind_group_layout, &entries);
        Ok(Some((bind_group, groups)))
    }
}

/// The ordered cull's three pipelines (entry points of `cull.wgsl`), and the one that sizes
/// its dispatches over the transparent list (`list_args.wgsl`).
#[derive(Debug)]
struct OrderedPipelines {
    count: ComputePipeline,
    prefix: ComputePipeline,
    scatter: ComputePipeline,
    list_args: ComputePipeline,
    list_args_layout: BindGroupLayout,
}

/// Where a prepared record's uniforms are copied from.
#[derive(Clone, Copy, Debug)]
pub enum UniformSource<'a> {
    /// A staging buffer made for the record (one buffer creation per record).
    Own,
    /// [`CullPass::uniforms`]' bytes, already at `offset` of `buffer` (`COPY_SRC` usage,
    /// `offset` a multiple of 4): one staging buffer for several records' uniforms and the
    /// caller's own, since each buffer creation costs the CPU more than the copies.
    Staged {
        /// The staging buffer.
        buffer: &'a Buffer,
        /// Where the record's uniforms start.
        offset: u64,
    },
}

/// A cull record whose copies and clears are in the encoder and whose dispatches are not yet
/// recorded ([`CullPass::prepare`]; recorded by [`CullPass::dispatch`]).
#[derive(Debug)]
pub struct PreparedCull {
    bind_group: wgpu::BindGroup,
    /// Workgroups over the table's slots.
    groups: u32,
    /// `Some` for the back-to-front record.
    ordered: Option<OrderedDispatch>,
}

/// What the ordered record dispatches besides the slots.
#[derive(Debug)]
struct OrderedDispatch {
    /// Over the transparent list instead of every slot: the group and buffer of the indirect
    /// dispatch that sizes it.
    from_list: Option<(wgpu::BindGroup, Buffer)>,
}

/// Dispatches `groups` workgroups of slots, folded into two dimensions past the per-dimension
/// limit (the shader linearises them).
fn dispatch_slots(pass: &mut wgpu::ComputePass<'_>, groups: u32) {
    let x = groups.min(MAX_GROUPS_PER_DIM);
    let y = groups.div_ceil(x);
    pass.dispatch_workgroups(x, y, 1);
}
