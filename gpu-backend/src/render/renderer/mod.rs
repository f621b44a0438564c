//! [`Renderer`]: resident chunks, camera and lighting in; one frame recorded into one encoder.
//! The frame's order is in [`record`], the draw passes' recording in [`passes`].

mod opaque_choice;
mod passes;
mod record;

pub use opaque_choice::OpaqueChoice;

use std::collections::HashMap;

use wgpu::util::DeviceExt;
use wgpu::{Buffer, BufferUsages, Device, Queue};

use voxel_core::{ChunkSize, MaterialPalette};

use super::error::RenderError;
use super::far::raster::FarRaster;
use super::far::splat::FarSplat;
use super::far::{FarChoice, FarPath, FarRequest};
use super::pipelines::{FullscreenPath, Pipelines};
use render_model::camera::Camera;
use render_model::frame::FrameUniforms;
use render_model::lighting::Lighting;
use render_model::materials::gpu_materials;
use render_model::quad_raster::QuadRasterConfig;

use super::quad_raster::{OpaquePath, QuadRaster};
use super::targets::{FrameImage, RenderTargets, read_output};
use crate::bind::BindGroupCache;
use crate::chunk_table::{GpuTable, MeshedChunkTable, TableError, TableSlot};
use crate::cull::{CullFrame, CullOutput, CullPass};
use crate::device::GpuContext;
use crate::gigabuffer::{ChunkHandle, Gigabuffer, GigabufferConfig};
use crate::timing::GpuTimer;
use render_model::cull::{
    CullConfig, LodAnchor, LodSettings, NodeRecord, SmoothPages, quad_indices,
};
use render_model::resident::{
    ChunkMeshData, ChunkRanges, SmoothFrame, SmoothRanges, chunk_record, mesh_bounds,
};
use voxel_core::formats::DataKind;

/// How a [`Renderer`] is sized.
#[derive(Clone, Debug, PartialEq)]
pub struct RendererConfig {
    /// Output width, pixels.
    pub width: u32,
    /// Output height, pixels.
    pub height: u32,
    /// Edge of every chunk.
    pub chunk_size: ChunkSize,
    /// Gigabuffer budget per kind.
    pub gigabuffer: GigabufferConfig,
    /// Resident chunks at most (the chunk table's capacity).
    pub max_chunks: u32,
    /// How smooth vertex positions map to chunk-local blocks.
    pub smooth: SmoothFrame,
    /// Far draws: which path (see [`far`](crate::render::far)); far draws also need space for
    /// draw blocks in `gigabuffer` and level-of-detail selection ([`Renderer::set_lod`]).
    pub far: FarRequest,
    /// How the full-screen passes run.
    pub fullscreen: FullscreenPath,
    /// How the opaque greedy quads are drawn ([`OpaquePath::Compute`] needs 64-bit atomics
    /// and brings the splat's visibility buffers whatever the far path).
    pub opaque: OpaquePath,
    /// Two-phase occlusion culling against a depth pyramid (see [`crate::hiz`]): the nodes
    /// visible last frame are drawn first, the pyramid built from their depth, then every other
    /// node tested against it.
    pub occlusion: bool,
}

impl RendererConfig {
    /// A configuration for `width x height` and chunks of `size`: 64 MiB of greedy quads,
    /// 16 MiB each of smooth vertices and quads, 4096 chunks. Clutter and draw blocks are not
    /// drawn yet, so they get no space.
    pub fn new(width: u32, height: u32, size: ChunkSize) -> RendererConfig {
        const MIB: u64 = 1 << 20;
        RendererConfig {
            width,
            height,
            chunk_size: size,
            gigabuffer: GigabufferConfig::empty()
                .with_bytes(DataKind::Quads, 64 * MIB)
                .with_bytes(DataKind::SmoothVertices, 16 * MIB)
                .with_bytes(DataKind::SmoothQuads, 16 * MIB)
                .with_max_chunks(4096),
            max_chunks: 4096,
            smooth: SmoothFrame::nocubes(size),
            far: FarRequest::Off,
            fullscreen: FullscreenPath::default(),
            opaque: OpaquePath::default(),
            occlusion: true,
        }
    }

    /// This configuration with far draws `far` and `draw_block_bytes` of draw-block space.
    pub fn with_far(mut self, far: FarRequest, draw_block_bytes: u64) -> RendererConfig {
        self.far = far;
        self.gigabuffer = self
            .gigabuffer
            .with_bytes(DataKind::DrawBlocks, draw_block_bytes);
        self
    }
}

/// A resident chunk.
#[derive(Debug)]
struct Resident {
    slot: TableSlot,
    level: u32,
    smooth: Option<SmoothRanges>,
}

/// What two-phase occlusion culling keeps between frames.
#[derive(Debug)]
struct Occlusion {
    late_commands: CullOutput,
    pyramid: crate::hiz::DepthPyramid,
    visible: Buffer,
}

impl Occlusion {
    fn new(
        device: &Device,
        cull: &CullPass,
        capacity: u32,
        width: u32,
        height: u32,
    ) -> Result<Occlusion, RenderError> {
        Ok(Occlusion {
            late_commands: cull.create_output("opaque late")?,
            pyramid: crate::hiz::DepthPyramid::new(device, width, height)
                .map_err(RenderError::Hiz)?,
            visible: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("visibility bits"),
                size: u64::from(capacity.div_ceil(32).max(1)) * 4,
                usage: BufferUsages::STORAGE,
                mapped_at_creation: false,
            }),
        })
    }
}

/// The deferred voxel renderer (see the [module docs](super) for a frame's passes).
#[derive(Debug)]
pub struct Renderer {
    device: Device,
    queue: Queue,
    config: RendererConfig,
    gigabuffer: Gigabuffer,
    table: MeshedChunkTable,
    /// Per table slot, what the chunk record does not hold (same slots as `table`).
    nodes: GpuTable<NodeRecord>,
    chunks: HashMap<ChunkHandle, Resident>,
    /// Resident chunks per level of detail (the top level is the highest with any).
    per_level: [u32; 16],
    /// Resident chunks with a smooth layer.
    smooth_chunks: u32,
    /// The depth attachment holds only the clear value (no G-buffer pass drew since the last
    /// clear), so a frame that draws nothing into the G-buffer may skip the pass.
    depth_clear: bool,
    /// The wireframe view: meshes are drawn as their quads' edges (see
    /// [`Renderer::set_wireframe`]).
    wireframe: bool,
    /// The opaque path drawing now: `Raster` or `Compute` (the latter only with
    /// `quad_raster`).
    opaque: OpaquePath,
    cull: CullPass,
    cull_frame: CullFrame,
    opaque_commands: CullOutput,
    transparent_commands: CullOutput,
    /// Occlusion culling: the late phase's commands, the depth pyramid, the visibility bits.
    occlusion: Option<Occlusion>,
    /// Level-of-detail selection; `None` draws level 0 only (full detail).
    lod: Option<LodSettings>,
    anchor: LodAnchor,
    pipelines: Pipelines,
    /// The frame's bind groups, made once per set of resources.
    bind_cache: BindGroupCache,
    /// The far path in use and why.
    far_choice: FarChoice,
    /// The compute splat's visibility buffers and pipelines: when the splat is the far path,
    /// or the opaque quads are rasterised in compute (which draws into them).
    splat: Option<FarSplat>,
    /// The compute rasteriser of opaque quads ([`OpaquePath::Compute`]).
    quad_raster: Option<QuadRaster>,
    /// The raster far draws, when the far path is a raster one.
    far_raster: Option<FarRaster>,
    /// Read by the full-screen passes when there is no splat.
    no_visibility: Buffer,
    targets: RenderTargets,
    quad_indices: Buffer,
    materials: Buffer,
    material_count: u32,
    frame_uniforms: Buffer,
    timer: GpuTimer,
    /// The device's largest storage binding (the visibility buffers' limit).
    gigabuffer_max_page: u64,
    camera: Camera,
    lighting: Lighting,
}

impl Renderer {
    /// A renderer on `ctx` drawing `palette`'s materials. Needs `INDIRECT_FIRST_INSTANCE`
    /// (the cull pass's commands name their record through `first_instance`).
    pub fn new(
        ctx: &GpuContext,
        config: &RendererConfig,
        palette: &MaterialPalette,
    ) -> Result<Renderer, RenderError> {
        if !ctx.capabilities.indirect_first_instance {
            return Err(RenderError::MissingFeature("INDIRECT_FIRST_INSTANCE"));
        }
        let device = &ctx.device;
        let targets = RenderTargets::new(device, config.width, config.height)?;
        let gigabuffer = Gigabuffer::new(device, &ctx.capabilities, &config.gigabuffer)?;
        let table = MeshedChunkTable::new(
            device,
            config.max_chunks,
            ctx.capabilities.max_storage_buffer_binding_size,
        )?;
        let nodes = GpuTable::new(
            device,
            config.max_chunks,
            ctx.capabilities.max_storage_buffer_binding_size,
        )?;
        let cull_config = CullConfig {
            smooth: Some(SmoothPages::of(
                gigabuffer.layout(DataKind::SmoothVertices),
                gigabuffer.layout(DataKind::SmoothQuads),
            )),
            ..CullConfig::new(config.chunk_size, config.max_chunks)
        };
        let cull = CullPass::new(ctx, gigabuffer.layout(DataKind::Quads), &cull_config)?;
        let cull_frame = cull.create_frame("renderer")?;
        let far_choice = config
            .far
            .resolve(&ctx.capabilities)
            .map_err(RenderError::FarDrawsUnavailable)?;
        if far_choice.path != FarPath::Off {
            let blocks = gigabuffer.layout(DataKind::DrawBlocks);
            if blocks.page_count != 1 {
                return Err(RenderError::FarDrawsUnavailable(format!(
                    "the far draws bind the draw-block gigabuffer as one page; {} bytes of \
                     draw blocks make {} pages of at most {} bytes",
                    config.gigabuffer.bytes.get(DataKind::DrawBlocks),
                    blocks.page_count,
                    ctx.capabilities.max_page_bytes()
                )));
            }
        }
        let compute_opaque = match config.opaque {
            OpaquePath::Raster => false,
            OpaquePath::Compute if !ctx.capabilities.int64_atomics => {
                return Err(RenderError::MissingFeature(
                    "SHADER_INT64_ATOMIC_MIN_MAX (the compute opaque path)",
                ));
            }
            OpaquePath::Compute => true,
            OpaquePath::Auto => ctx.capabilities.int64_atomics,
        };
        let splat = if far_choice.path == FarPath::Splat || compute_opaque {
            Some(FarSplat::new(
                device,
                config.width,
                config.height,
                ctx.capabilities.max_page_bytes(),
            )?)
        } else {
            None
        };
        let quad_raster = if compute_opaque {
            Some(QuadRaster::new(
                device,
                &QuadRasterConfig::for_screen(config.width, config.height, 16),
            )?)
        } else {
            None
        };
        let pipelines = Pipelines::new(device, config.fullscreen);
        let far_raster = far_choice.path.is_raster().then(|| {
            FarRaster::new(
                device,
                &ctx.capabilities,
                far_choice.path,
                cull.layout().far_capacity,
                &pipelines.frame_layout,
            )
        });
        let no_visibility = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("no far visibility"),
            size: 16,
            usage: BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let opaque_commands = cull.create_output("opaque")?;
        let occlusion = if config.occlusion {
            Some(Occlusion::new(
                device,
                &cull,
                config.max_chunks,
                config.width,
                config.height,
            )?)
        } else {
            None
        };
        let transparent_commands = cull.create_output("transparent")?;
        let indices = quad_indices(cull.layout().max_quads_per_draw);
        let quad_indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("quad indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: BufferUsages::INDEX,
        });
        let (materials, material_count) = material_buffer(device, palette);
        let frame_uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("frame uniforms"),
            size: size_of::<FrameUniforms>() as u64,
            usage: BufferUsages::UNIFORM | BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let edge = config.chunk_size.edge() as i32;
        Ok(Renderer {
            device: device.clone(),
            queue: ctx.queue.clone(),
            gigabuffer,
            table,
            nodes,
            chunks: HashMap::new(),
            per_level: [0; 16],
            smooth_chunks: 0,
            depth_clear: false,
            wireframe: false,
            opaque: if config.opaque == OpaquePath::Compute {
                OpaquePath::Compute
            } else {
                OpaquePath::Raster
            },
            cull,
            cull_frame,
            opaque_commands,
            transparent_commands,
            occlusion,
            lod: None,
            anchor: LodAnchor {
                chunk: voxel_core::ChunkCoord::new(0, 0, 0),
                offset: [0.0; 3],
            },
            pipelines,
            bind_cache: BindGroupCache::default(),
            far_choice,
            splat,
            quad_raster,
            far_raster,
            no_visibility,
            targets,
            quad_indices,
            materials,
            material_count,
            frame_uniforms,
            timer: GpuTimer::new(ctx, 16),
            gigabuffer_max_page: ctx.capabilities.max_page_bytes(),
            camera: Camera::new(
                voxel_core::WorldPos::new(edge / 2, edge / 2, edge / 2),
                glam::DVec3::splat(0.5),
                0.0,
                0.0,
                1.0,
            ),
            lighting: Lighting::default(),
            config: config.clone(),
        })
    }

    /// Replaces the material palette.
    pub fn set_palette(&mut self, palette: &MaterialPalette) {
        (self.materials, self.material_count) = material_buffer(&self.device, palette);
    }

    /// Sets the camera of the next frames. The level-of-detail anchor follows it with the
    /// selection's hysteresis (see [`cull::lod`](crate::cull::lod)); a caller that streams
    /// chunks in sets the anchor itself with [`set_lod_anchor`](Self::set_lod_anchor) after this.
    pub fn set_camera(&mut self, camera: &Camera) {
        self.camera = *camera;
        let eye = camera.eye(self.config.chunk_size);
        let hysteresis = self.lod.map_or(0.0, |l| l.hysteresis);
        self.anchor = self.anchor.follow(
            eye.chunk,
            eye.offset,
            self.config.chunk_size.edge(),
            hysteresis,
        );
    }

    /// Turns level-of-detail selection on with `settings` (see
    /// [`cull::lod`](crate::cull::lod)), or off with `None`: then only level-0 chunks are drawn
    /// (full detail). Refuses a non-finite or negative setting.
    pub fn set_lod(&mut self, settings: Option<LodSettings>) -> Result<(), RenderError> {
        self.lod = settings.map(LodSettings::validate).transpose()?;
        Ok(())
    }

    /// The level-of-detail settings in use.
    pub fn lod(&self) -> Option<LodSettings> {
        self.lod
    }

    /// Moves the level-of-detail anchor (where distances are measured from): a streaming
    /// caller moves it only once the chunks the new selection needs are resident.
    pub fn set_lod_anchor(&mut self, anchor: LodAnchor) {
        self.anchor = anchor;
    }

    /// The level-of-detail anchor.
    pub fn lod_anchor(&self) -> LodAnchor {
        self.anchor
    }

    /// The current camera.
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// Sets the light of the next frames.
    pub fn set_lighting(&mut self, lighting: &Lighting) {
        self.lighting = *lighting;
    }

    /// Turns the wireframe view on or off: meshed quads (greedy and smooth) are drawn as
    /// their edges, about a pixel wide, lit as usual, with the sky or the far field behind.
    /// It shows how the mesher merged faces. Far-drawn blocks are drawn as usual (a block
    /// there covers about a pixel). On the compute opaque path the meshes go through the
    /// G-buffer pass while the view is on.
    pub fn set_wireframe(&mut self, on: bool) {
        self.wireframe = on;
    }

    /// Whether the wireframe view is on.
    pub fn wireframe(&self) -> bool {
        self.wireframe
    }

    /// Whether the opaque quads of this frame go through the compute rasteriser (the compute
    /// opaque path, outside the wireframe view).
    pub(super) fn quads_in_compute(&self) -> bool {
        self.opaque == OpaquePath::Compute && self.quad_raster.is_some() && !self.wireframe
    }

    /// The opaque path drawing now: `Raster` or `Compute` (`Auto` only picks between them).
    pub fn opaque_path(&self) -> OpaquePath {
        self.opaque
    }

    /// Draws the opaque quads of the next frames with `path`. `Compute` needs a renderer made
    /// with [`RendererConfig::opaque`] `Compute`, or `Auto` on a device with 64-bit atomic
    /// min/max; `Auto` is not a path to draw with (see
    /// [`measure_opaque_paths`](Self::measure_opaque_paths)).
    pub fn set_opaque_path(&mut self, path: OpaquePath) -> Result<(), RenderError> {
        match path {
            OpaquePath::Auto => Err(RenderError::OpaquePathUnavailable(
                "Auto picks a path; name Raster or Compute",
            )),
            OpaquePath::Compute if self.quad_raster.is_none() => {
                Err(RenderError::OpaquePathUnavailable(
                    "the compute rasteriser was not built (make the renderer with opaque \
                     Compute, or Auto on a device with 64-bit atomic min/max)",
                ))
            }
            _ => {
                self.opaque = path;
                Ok(())
            }
        }
    }

    /// The far path in use and why it was chosen.
    pub fn far_choice(&self) -> &FarChoice {
        &self.far_choice
    }

    /// Changes how the full-screen passes run (rebuilds the pipelines when it changes).
    pub fn set_fullscreen_path(&mut self, path: FullscreenPath) {
        if path != self.config.fullscreen {
            self.config.fullscreen = path;
            self.pipelines = Pipelines::new(&self.device, path);
        }
    }

    /// How the full-screen passes run.
    pub fn fullscreen_path(&self) -> FullscreenPath {
        self.config.fullscreen
    }

    /// Changes the output size (recreates the targets).
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), RenderError> {
        if let Some(splat) = &mut self.splat {
            let max = self.gigabuffer_max_page;
            splat.resize(width, height, max)?;
        }
        self.targets = RenderTargets::new(&self.device, width, height)?;
        self.depth_clear = false;
        if let Some(occlusion) = &mut self.occlusion {
            occlusion.pyramid = crate::hiz::DepthPyramid::new(&self.device, width, height)
                .map_err(RenderError::Hiz)?;
        }
        self.config.width = width;
        self.config.height = height;
        Ok(())
    }

    /// The output and G-buffer textures.
    pub fn targets(&self) -> &RenderTargets {
        &self.targets
    }

    /// The gigabuffer (memory use, layouts).
    pub fn gigabuffer(&self) -> &Gigabuffer {
        &self.gigabuffer
    }

    /// Resident chunks.
    pub fn chunk_count(&self) -> usize {
        self.chunks.len()
    }

    /// GPU bytes the renderer holds, by kind: the gigabuffer's used bytes per data kind, the
    /// chunk and node tables, the cull's outputs and far list, the far visibility buffers.
    /// (Render targets are not counted: they depend on the output size only.)
    pub fn resident_bytes(&self) -> Vec<(&'static str, u64)> {
        let used = self.gigabuffer.resident();
        let mut out: Vec<(&'static str, u64)> = DataKind::ALL
            .iter()
            .map(|&kind| (kind.name(), used.kinds.get(kind).used_bytes))
            .collect();
        out.push(("chunk table", self.table.buffer().size()));
        out.push(("node table", self.nodes.buffer().size()));
        let late = self
            .occlusion
            .as_ref()
            .map_or(0, |o| o.late_commands.byte_size() + o.visible.size());
        out.push((
            "cull outputs",
            self.opaque_commands.byte_size() + self.transparent_commands.byte_size() + late,
        ));
        out.push(("far list", self.cull_frame.far_list().size()));
        if let Some(splat) = &self.splat {
            out.push((
                "far visibility buffers",
                splat.visibility().size() + splat.transparent().size(),
            ));
        }
        out
    }

    /// True when a resident chunk has a smooth layer.
    fn has_smooth(&self) -> bool {
        self.smooth_chunks > 0
    }

    /// Smooth quads of the resident chunks.
    pub fn smooth_quad_count(&self) -> u64 {
        self.chunks
            .values()
            .filter_map(|r| r.smooth)
            .map(|s| u64::from(s.quad_count))
            .sum()
    }

    /// Uploads a chunk's mesh (its bytes reach the GPU with the next recorded frame) and
    /// returns its handle. On error nothing stays allocated.
    pub fn upload_chunk(&mut self, mesh: &ChunkMeshData<'_>) -> Result<ChunkHandle, RenderError> {
        if mesh.lod > voxel_core::formats::MeshedChunkInfo::MAX_LOD {
            return Err(RenderError::BadLevel(mesh.lod));
        }
        self.check_far_data(&mesh.layers)?;
        let bounds = mesh_bounds(&mesh.layers, self.config.smooth);
        let uploaded = self.gigabuffer.upload(&mesh.layers)?;
        let slot = match self.insert_records(mesh, bounds, &uploaded.ranges) {
            Ok(slot) => slot,
            Err(e) => {
                // The upload succeeded; give its space back before reporting.
                self.gigabuffer.free(uploaded.handle)?;
                return Err(e);
            }
        };
        let ranges = uploaded.ranges;
        let smooth = (ranges.smooth_quad_count > 0).then_some(SmoothRanges {
            vertices: ranges.smooth_vertices,
            quads: ranges.smooth_quads,
            quad_count: ranges.smooth_quad_count,
            form: ranges.smooth_quad_form,
        });
        self.per_level[mesh.lod as usize] += 1;
        self.smooth_chunks += u32::from(smooth.is_some());
        self.chunks.insert(
            uploaded.handle,
            Resident {
                slot,
                level: mesh.lod,
                smooth,
            },
        );
        Ok(uploaded.handle)
    }

    /// The chunk and node records of an uploaded chunk, in the same slot of both tables.
    fn insert_records(
        &mut self,
        mesh: &ChunkMeshData<'_>,
        bounds: Option<([f32; 3], [f32; 3])>,
        ranges: &ChunkRanges,
    ) -> Result<TableSlot, RenderError> {
        let record = chunk_record(mesh.coord, mesh.lod, bounds, ranges)?;
        let node = NodeRecord::new(ranges)?;
        let slot = self.table.insert(record)?;
        match self.nodes.insert(node) {
            // Both tables hand out the lowest free slot and change together, so they agree.
            Ok(node_slot) if node_slot == slot => Ok(slot),
            Ok(node_slot) => {
                self.nodes.remove(node_slot)?;
                self.table.remove(slot)?;
                Err(RenderError::Table(TableError::VacantSlot(node_slot)))
            }
            Err(e) => {
                self.table.remove(slot)?;
                Err(e.into())
            }
        }
    }

    /// Far-draw data must come whole: blocks with the hiding mask of the chunk's padded
    /// neighbourhood, in chunks a `DrawBlock` can address.
    fn check_far_data(
        &self,
        layers: &voxel_core::formats::ChunkLayersData<'_>,
    ) -> Result<(), RenderError> {
        let blocks = layers.draw_blocks.len()
            + layers
                .draw_block_skirts
                .iter()
                .map(|s| s.len())
                .sum::<usize>();
        if blocks == 0 && layers.hiding_mask.is_empty() && layers.transparent_mask.is_empty() {
            return Ok(());
        }
        let edge = self.config.chunk_size.edge();
        if edge > voxel_core::formats::DrawBlock::MAX_POSITION + 1 {
            return Err(RenderError::BadFarData(format!(
                "chunks of edge {edge} have draw blocks, but a DrawBlock addresses 16^3: far \
                 draws need chunks of at most 16^3"
            )));
        }
        let p = (edge + 2) as usize;
        let words = (p * p * p).div_ceil(32);
        if layers.hiding_mask.len() != words {
            return Err(RenderError::BadFarData(format!(
                "{blocks} draw blocks come with a hiding mask of {} words; chunks of edge \
                 {edge} need {words} (mesher::surface_blocks::hiding_mask)",
                layers.hiding_mask.len()
            )));
        }
        if !layers.transparent_mask.is_empty() && layers.transparent_mask.len() != words {
            return Err(RenderError::BadFarData(format!(
                "a transparent mask of {} words; chunks of edge {edge} need {words} or none \
                 (mesher::surface_blocks::transparent_mask)",
                layers.transparent_mask.len()
            )));
        }
        Ok(())
    }

    /// Sends the pending uploads (gigabuffer copies, chunk and node records) to the GPU now,
    /// in a submission of their own, without drawing: for a renderer that streams chunks in
    /// while nothing of it is shown (a recorded frame starts with the same flush).
    pub fn flush_uploads(&mut self) {
        let mut encoder = self.device.create_command_encoder(&Default::default());
        self.gigabuffer.flush(&mut encoder);
        self.table.flush(&self.queue);
        self.nodes.flush(&self.queue);
        self.queue.submit([encoder.finish()]);
    }

    /// Frees a resident chunk: its space and table slot. A stale or foreign handle is an
    /// error and frees nothing.
    pub fn free_chunk(&mut self, handle: ChunkHandle) -> Result<(), RenderError> {
        let resident = self
            .chunks
            .remove(&handle)
            .ok_or(RenderError::UnknownChunk(handle))?;
        self.per_level[resident.level as usize] -= 1;
        self.smooth_chunks -= u32::from(resident.smooth.is_some());
        self.table.remove(resident.slot)?;
        self.nodes.remove(resident.slot)?;
        self.gigabuffer.free(handle)?;
        Ok(())
    }

    /// Reads the last frame's output and depth back (blocks).
    ///
    /// The depth is the frame's: where a far draw was splatted nearer than the rasterised
    /// depth, the splat's.
    pub fn read_image(&self) -> Result<FrameImage, RenderError> {
        let mut image = read_output(&self.device, &self.queue, &self.targets)?;
        if let Some(splat) = &self.splat {
            let words: Vec<[u32; 2]> = bytemuck::pod_collect_to_vec(&crate::readback::read_buffer(
                &self.device,
                &self.queue,
                splat.visibility(),
                0,
                splat.visibility().size(),
            )?);
            for (depth, word) in image.depth.iter_mut().zip(words) {
                *depth = depth.max(f32::from_bits(word[1]));
            }
        }
        Ok(image)
    }
}

/// The palette as a storage buffer, and its entry count.
fn material_buffer(device: &Device, palette: &MaterialPalette) -> (Buffer, u32) {
    let materials = gpu_materials(palette);
    let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("materials"),
        contents: bytemuck::cast_slice(&materials),
        usage: BufferUsages::STORAGE,
    });
    (buffer, materials.len() as u32)
}
