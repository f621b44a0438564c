//! The GPU benchmark (binary `gpu_bench`): the mesher's terrain made resident in growing
//! amounts (the nearest `n` chunks of one meshed terrain, so each scene is a square of the same
//! world), each drawn for a number of frames by the [`Renderer`] with GPU timestamps per pass.
//!
//! Per scene it reports: resident chunks and quads, gigabuffer bytes per quad and per chunk
//! (with the per-chunk overhead of the chunk table and the cull's command slots stated
//! separately), the median GPU time of each pass, and the median CPU time to record and
//! submit a frame (the CPU cost the renderer adds per frame, which must not grow with the
//! chunk count).
//!
//! The uploads of a scene are flushed by one frame, and three more warm up, before the timed
//! frames start.

mod report;

use std::time::Instant;

use gpu_backend::GpuContext;
use gpu_backend::gigabuffer::{ChunkLayersData, DataKind, GigabufferConfig};
use gpu_backend::render::RenderError;
use gpu_backend::render::{
    ChunkMeshData, FrameImage, LightingParams, RenderCamera, Renderer, RendererConfig,
};
use mesher::blocky::BlockyLayer;
use voxel_core::WorldPos;
use voxel_core::formats::{ChunkDrawIndirect, MeshedChunkInfo};

use crate::gpu_scene::MeshedTerrain;

pub use report::{PassMedian, SceneReport, markdown_table};

/// Untimed frames after each scene's upload frame.
const WARM_UP_FRAMES: usize = 3;

/// What to measure.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchConfig {
    /// Resident chunk counts to measure, ascending; counts above the terrain's chunk count are
    /// measured at the whole terrain.
    pub scene_chunks: Vec<usize>,
    /// Output width, pixels.
    pub width: u32,
    /// Output height, pixels.
    pub height: u32,
    /// Timed frames per scene (after the untimed upload and warm-up frames).
    pub frames: usize,
}

/// Why the benchmark stopped.
#[derive(Debug)]
pub enum BenchError {
    /// The renderer refused the configuration or an upload.
    Render(RenderError),
    /// The scene list is empty or not ascending.
    BadScenes(String),
}

impl std::fmt::Display for BenchError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BenchError::Render(e) => write!(f, "renderer: {e}"),
            BenchError::BadScenes(why) => write!(f, "scene list: {why}"),
        }
    }
}

impl std::error::Error for BenchError {}

impl From<RenderError> for BenchError {
    fn from(e: RenderError) -> Self {
        BenchError::Render(e)
    }
}

/// The camera every scene is drawn from: 16 blocks above the highest hills at the terrain's
/// centre, looking out over it (yaw 40 degrees, 12 degrees down, 70-degree vertical field of
/// view), so the far terrain fills the top of the image up to the horizon.
pub fn bench_camera(terrain: &MeshedTerrain) -> RenderCamera {
    RenderCamera::from_world(
        WorldPos::new(0, 48, 0),
        [0.5; 3],
        terrain.size,
        40f64.to_radians(),
        -12f64.to_radians(),
        70f64.to_radians(),
    )
}

/// A renderer with room for every chunk of `terrain`: its quads (both layers, with 1/16 slack
/// for allocator fragmentation) and its chunk count.
pub fn renderer_for(
    ctx: &GpuContext,
    terrain: &MeshedTerrain,
    width: u32,
    height: u32,
) -> Result<Renderer, RenderError> {
    let quads = terrain.quad_count(terrain.meshes.len());
    let quad_bytes = (quads + quads / 16 + 4096) * 8;
    let chunks = terrain.meshes.len().max(1) as u32;
    let mut config = RendererConfig::new(width, height, terrain.size);
    config.gigabuffer = GigabufferConfig::empty()
        .with_bytes(DataKind::Quads, quad_bytes)
        .with_max_chunks(chunks);
    config.max_chunks = chunks;
    Renderer::new(ctx, &config, &terrain.palette)
}

/// Runs the benchmark: for each scene size, uploads the chunks it adds, flushes them with one
/// frame, then times `config.frames` frames. Returns the reports and the last frame's image.
pub fn run(
    ctx: &GpuContext,
    terrain: &MeshedTerrain,
    config: &BenchConfig,
) -> Result<(Vec<SceneReport>, FrameImage), BenchError> {
    if config.scene_chunks.is_empty() || !config.scene_chunks.is_sorted() {
        return Err(BenchError::BadScenes(format!(
            "{:?} must be non-empty and ascending",
            config.scene_chunks
        )));
    }
    let mut renderer = renderer_for(ctx, terrain, config.width, config.height)?;
    renderer.set_camera(&bench_camera(terrain));
    renderer.set_lighting(&LightingParams::default());
    let mut resident = 0usize;
    let mut reports = Vec::new();
    for &wanted in &config.scene_chunks {
        let target = wanted.min(terrain.meshes.len());
        let started = Instant::now();
        for mesh in &terrain.meshes[resident..target] {
            let opaque = mesh.blocky.layer(BlockyLayer::Opaque);
            let transparent = mesh.blocky.layer(BlockyLayer::Transparent);
            let layers = ChunkLayersData {
                opaque_quads: faces(opaque),
                transparent_quads: faces(transparent),
                ..Default::default()
            };
            renderer.upload_chunk(&ChunkMeshData {
                coord: mesh.coord,
                lod: 0,
                layers,
            })?;
        }
        let upload_cpu = started.elapsed();
        resident = target;
        // One frame flushes the uploads (staging copies); a few more let the driver finish
        // compiling pipelines and settle its memory (the first scene's first frames are
        // several times slower on an H200).
        let started = Instant::now();
        renderer.render()?;
        let flush_frame = started.elapsed();
        for _ in 0..WARM_UP_FRAMES {
            renderer.render()?;
        }
        let mut passes: Vec<Vec<(String, u64)>> = Vec::new();
        let mut cpu_frame_ns = Vec::new();
        for _ in 0..config.frames {
            let started = Instant::now();
            let mut encoder = ctx.device.create_command_encoder(&Default::default());
            renderer.record_frame(&mut encoder)?;
            ctx.queue.submit([encoder.finish()]);
            cpu_frame_ns.push(started.elapsed().as_nanos() as u64);
            let times = renderer.collect_timings()?;
            passes.push(
                times
                    .into_iter()
                    .map(|t| (t.label, t.nanoseconds))
                    .collect(),
            );
        }
        let usage = renderer.gigabuffer().resident();
        let quad_bytes = usage.kinds.get(DataKind::Quads).used_bytes;
        let quads = terrain.quad_count(resident);
        reports.push(SceneReport {
            chunks: resident,
            quads,
            covered_side: terrain.covered_side(resident),
            quad_bytes,
            table_bytes_per_chunk: size_of::<MeshedChunkInfo>() as u64,
            // The cull's exact default: six command slots per table slot, each a 20-byte
            // DrawIndexedIndirect plus a 32-byte record.
            command_bytes_per_chunk: 6 * (20 + size_of::<ChunkDrawIndirect>() as u64),
            upload_cpu_ms: upload_cpu.as_secs_f64() * 1e3,
            flush_frame_ms: flush_frame.as_secs_f64() * 1e3,
            passes: report::pass_medians(&passes),
            cpu_frame_us: report::median(&mut cpu_frame_ns) as f64 / 1e3,
        });
    }
    Ok((reports, renderer.read_image()?))
}

/// A quad layer's six face groups.
fn faces(layer: &mesher::QuadLayer) -> [&[voxel_core::formats::PackedQuad]; 6] {
    voxel_core::FaceDirection::ALL.map(|face| layer.face(face))
}
