//! [`Renderer`]: resident chunks, camera and lighting in; one frame recorded into one encoder.
//! The passes' recording is in [`passes`].

mod passes;

use std::collections::{HashMap, HashSet};

use wgpu::util::DeviceExt;
use wgpu::{Buffer, BufferUsages, CommandEncoder, Device, Queue};

use voxel_core::{ChunkSize, MaterialPalette};

use super::camera::RenderCamera;
use super::error::RenderError;
use super::frame::{FrameShape, FrameUniforms};
use super::lighting::LightingParams;
use super::materials::gpu_materials;
use super::pipelines::Pipelines;
use super::residency::{ChunkMeshData, SmoothFrame, SmoothRanges, chunk_record, mesh_bounds};
use super::targets::{FrameImage, RenderTargets, read_output};
use crate::chunk_table::{MeshedChunkTable, TableSlot};
use crate::cull::{CullConfig, CullLayer, CullOutput, CullPass, quad_indices};
use crate::device::GpuContext;
use crate::gigabuffer::{ChunkHandle, DataKind, Gigabuffer, GigabufferConfig};
use crate::timing::{GpuTimer, PassTime};

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
        }
    }
}

/// A resident chunk.
#[derive(Debug)]
struct Resident {
    slot: TableSlot,
    smooth: Option<SmoothRanges>,
}

/// The deferred voxel renderer (see the [module docs](super) for a frame's passes).
#[derive(Debug)]
pub struct Renderer {
    device: Device,
    queue: Queue,
    config: RendererConfig,
    gigabuffer: Gigabuffer,
    table: MeshedChunkTable,
    chunks: HashMap<ChunkHandle, Resident>,
    /// The resident chunks with a smooth layer (drawn one by one; the others only through
    /// the cull's commands, so a frame's CPU work does not grow with them).
    smooth_chunks: HashSet<ChunkHandle>,
    cull: CullPass,
    opaque_commands: CullOutput,
    transparent_commands: CullOutput,
    pipelines: Pipelines,
    targets: RenderTargets,
    quad_indices: Buffer,
    materials: Buffer,
    material_count: u32,
    frame_uniforms: Buffer,
    timer: GpuTimer,
    camera: RenderCamera,
    lighting: LightingParams,
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
        let cull = CullPass::new(
            ctx,
            gigabuffer.layout(DataKind::Quads),
            &CullConfig::new(config.chunk_size, config.max_chunks),
        )?;
        let opaque_commands = cull.create_output("opaque")?;
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
            chunks: HashMap::new(),
            smooth_chunks: HashSet::new(),
            cull,
            opaque_commands,
            transparent_commands,
            pipelines: Pipelines::new(device),
            targets,
            quad_indices,
            materials,
            material_count,
            frame_uniforms,
            timer: GpuTimer::new(ctx, 16),
            camera: RenderCamera::from_world(
                voxel_core::WorldPos::new(edge / 2, edge / 2, edge / 2),
                [0.5; 3],
                config.chunk_size,
                0.0,
                0.0,
                1.0,
            ),
            lighting: LightingParams::default(),
            config: config.clone(),
        })
    }

    /// Replaces the material palette.
    pub fn set_palette(&mut self, palette: &MaterialPalette) {
        (self.materials, self.material_count) = material_buffer(&self.device, palette);
    }

    /// Sets the camera of the next frames.
    pub fn set_camera(&mut self, camera: &RenderCamera) {
        self.camera = *camera;
    }

    /// The current camera.
    pub fn camera(&self) -> &RenderCamera {
        &self.camera
    }

    /// Sets the light of the next frames.
    pub fn set_lighting(&mut self, lighting: &LightingParams) {
        self.lighting = *lighting;
    }

    /// Changes the output size (recreates the targets).
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), RenderError> {
        self.targets = RenderTargets::new(&self.device, width, height)?;
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
        let bounds = mesh_bounds(&mesh.layers, self.config.smooth);
        let uploaded = self.gigabuffer.upload(&mesh.layers)?;
        let record = chunk_record(mesh.coord, bounds, &uploaded.ranges)
            .map_err(RenderError::from)
            .and_then(|record| self.table.insert(record).map_err(RenderError::from));
        let slot = match record {
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
        if smooth.is_some() {
            self.smooth_chunks.insert(uploaded.handle);
        }
        self.chunks
            .insert(uploaded.handle, Resident { slot, smooth });
        Ok(uploaded.handle)
    }

    /// Frees a resident chunk: its space and table slot. A stale or foreign handle is an
    /// error and frees nothing.
    pub fn free_chunk(&mut self, handle: ChunkHandle) -> Result<(), RenderError> {
        let resident = self
            .chunks
            .remove(&handle)
            .ok_or(RenderError::UnknownChunk(handle))?;
        self.smooth_chunks.remove(&handle);
        self.table.remove(resident.slot)?;
        self.gigabuffer.free(handle)?;
        Ok(())
    }

    /// Records a whole frame into `encoder`: pending uploads, the cull, the G-buffer pass
    /// (opaque quads, then smooth quads), lighting, the transparent pass and the tonemap, each
    /// timed by the renderer's [`GpuTimer`], then the timer's resolve. Submit the encoder (on
    /// the CPU timing path the timer submits parts of it itself), then call
    /// [`collect_timings`](Self::collect_timings) if wanted.
    pub fn record_frame(&mut self, encoder: &mut CommandEncoder) -> Result<(), RenderError> {
        let (width, height) = (self.targets.width, self.targets.height);
        self.gigabuffer.flush(encoder);
        self.table.flush(&self.queue);
        let shape = FrameShape {
            width,
            height,
            chunk_edge: self.config.chunk_size.edge(),
            material_count: self.material_count,
            smooth_extent: self.config.smooth.extent,
            smooth_origin: self.config.smooth.origin,
        };
        let uniforms = FrameUniforms::new(&self.camera, &self.lighting, &shape);
        self.queue
            .write_buffer(&self.frame_uniforms, 0, bytemuck::bytes_of(&uniforms));
        let frame_group = self.frame_group();
        let cull_camera = self.camera.cull_camera(width, height);

        let scope = self.timer.begin(encoder, "cull");
        self.cull.record(
            encoder,
            &self.table,
            &cull_camera,
            CullLayer::Opaque,
            &self.opaque_commands,
        )?;
        self.timer.end(encoder, scope);

        // The transparent layer, back to front (see `render::transparent`).
        let scope = self.timer.begin(encoder, "cull transparent");
        self.cull.record_ordered(
            encoder,
            &self.table,
            &cull_camera,
            CullLayer::Transparent,
            &self.transparent_commands,
        )?;
        self.timer.end(encoder, scope);

        let scope = self.timer.begin(encoder, "gbuffer");
        self.record_gbuffer(encoder, &frame_group, &cull_camera);
        self.timer.end(encoder, scope);

        let scope = self.timer.begin(encoder, "lighting");
        self.record_fullscreen(encoder, &frame_group, false);
        self.timer.end(encoder, scope);

        let scope = self.timer.begin(encoder, "transparent");
        self.record_transparent(encoder, &frame_group);
        self.timer.end(encoder, scope);

        let scope = self.timer.begin(encoder, "tonemap");
        self.record_fullscreen(encoder, &frame_group, true);
        self.timer.end(encoder, scope);
        self.timer.resolve(encoder);
        Ok(())
    }

    /// Records and submits one frame, waits for it, and returns its per-pass times.
    pub fn render(&mut self) -> Result<Vec<PassTime>, RenderError> {
        let mut encoder = self.device.create_command_encoder(&Default::default());
        self.record_frame(&mut encoder)?;
        self.queue.submit([encoder.finish()]);
        self.collect_timings()
    }

    /// The last submitted frame's per-pass times (waits for the GPU).
    pub fn collect_timings(&mut self) -> Result<Vec<PassTime>, RenderError> {
        self.timer.collect().map_err(RenderError::Timer)
    }

    /// Reads the last frame's output and depth back (blocks).
    pub fn read_image(&self) -> Result<FrameImage, RenderError> {
        read_output(&self.device, &self.queue, &self.targets)
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
