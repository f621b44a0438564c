//! The GPU benchmark (binary `gpu_bench`): the viewer's terrain at every level of detail made
//! resident, then drawn by the [`Renderer`] for each requested setting (error budget, far path,
//! far threshold, full-screen path), each for a number of frames with GPU timestamps per pass.
//!
//! Per setting it reports the median GPU time of each pass and in total, the median CPU time to
//! record and submit a frame, what the last frame drew (nodes per level and representation,
//! quads, far blocks, culled nodes), and the image error against the full-detail frame (level 0
//! only, every node meshed) when that is rendered; per scene, the resident bytes by kind.
//!
//! Each setting gets three untimed frames first (the first uploads, and the driver settles).

pub mod features;
pub mod geometry;
mod image_error;
pub mod props;
mod report;

use std::time::Instant;

use gpu_backend::GpuContext;
use gpu_backend::render::far::{FarChoice, FarRequest};
use gpu_backend::render::{
    FrameImage, FullscreenPath, OpaquePath, RenderError, Renderer, RendererConfig,
};
use gpu_backend::residency::GigabufferConfig;
use mesher::lod::NodeMesh;
use render_model::camera::Camera;
use render_model::cull::{LodParams, LodSettings, lod};
use render_model::lighting::Lighting;
use render_model::resident::ChunkMeshData;
use voxel_core::formats::DataKind;
use voxel_core::{ChunkCoord, WorldPos};

use crate::cpu_time::thread_cpu_now;
use crate::gpu_scene::LodTerrain;

pub use image_error::{ImageError, OFF_THRESHOLD, image_error};
pub use report::{
    BenchReport, DrawnCounts, ImageErrorReport, PassMedian, QuadRasterCounts, RunReport,
    SceneSummary, markdown, median, pass_medians,
};

/// Untimed frames before each setting's timed ones.
const WARM_UP_FRAMES: usize = 3;

/// What to measure.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchConfig {
    /// Output width, pixels.
    pub width: u32,
    /// Output height, pixels.
    pub height: u32,
    /// Timed frames per setting.
    pub frames: usize,
    /// Error budgets to measure, pixels.
    pub budgets: Vec<f32>,
    /// Also render full detail (level 0 only, meshes only): its time, and the reference of
    /// every image error.
    pub reference: bool,
    /// Far paths to measure (one renderer each).
    pub far: Vec<FarRequest>,
    /// Far thresholds to measure, pixels.
    pub far_cell_px: Vec<f32>,
    /// Full-screen paths to measure.
    pub fullscreen: Vec<FullscreenPath>,
    /// Two-phase occlusion culling settings to measure (one renderer each, per far path).
    pub occlusion: Vec<bool>,
    /// Opaque quad paths to measure (one renderer each, per far path and occlusion setting).
    pub opaque: Vec<OpaquePath>,
    /// The light of every run (with `Lighting::shadows` on, the shadow pass's steps are
    /// timed as `shadow grid` and `shadow trace`).
    pub lighting: Lighting,
}

/// Why the benchmark stopped.
#[derive(Debug)]
pub enum BenchError {
    /// The renderer refused the configuration or an upload.
    Render(RenderError),
    /// A setting is invalid.
    BadConfig(String),
}

impl std::fmt::Display for BenchError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BenchError::Render(e) => write!(f, "renderer: {e}"),
            BenchError::BadConfig(why) => write!(f, "configuration: {why}"),
        }
    }
}

impl std::error::Error for BenchError {}

impl From<RenderError> for BenchError {
    fn from(e: RenderError) -> Self {
        BenchError::Render(e)
    }
}

/// The camera every run is drawn from: 16 blocks above the highest hills at the terrain's
/// centre, looking out over it (yaw 40 degrees, 12 degrees down, 70-degree vertical field of
/// view), so the far terrain fills the top of the image up to the horizon.
pub fn bench_camera() -> Camera {
    Camera::new(
        WorldPos::new(0, 48, 0),
        glam::DVec3::splat(0.5),
        40f64.to_radians(),
        -12f64.to_radians(),
        70f64.to_radians(),
    )
}

/// The selection inputs of each error budget in `budgets` seen from `camera` on a screen
/// `height` pixels tall, anchored at the camera with no hysteresis (as the benchmark's fixed
/// view needs), levels `0..=top_level`.
pub fn budget_params(
    camera: &Camera,
    budgets: &[f32],
    top_level: u32,
    height: u32,
    size: voxel_core::ChunkSize,
) -> Vec<LodParams> {
    let eye = camera.eye(size);
    budgets
        .iter()
        .map(|&budget_px| LodParams {
            anchor_chunk: [eye.chunk.x, eye.chunk.y, eye.chunk.z],
            top_level,
            anchor_offset: eye.offset,
            budget_px,
            focal_px: lod::focal_px(camera.fov_y, height),
            hysteresis: 0.0,
            chunk_edge: size.edge() as f32,
            pad: 0,
        })
        .collect()
}

/// The selection inputs the benchmark's frames fade grass by: `params` (one per budget), and
/// with the full-detail `reference` its fade budget too
/// ([`DEFAULT_BUDGET_PX`](render_model::grass::DEFAULT_BUDGET_PX): level-of-detail selection
/// is off there).
pub fn grass_params(params: &[LodParams], reference: bool) -> Vec<LodParams> {
    let mut out = params.to_vec();
    if reference && let Some(first) = params.first() {
        out.push(LodParams {
            budget_px: render_model::grass::DEFAULT_BUDGET_PX,
            ..*first
        });
    }
    out
}

/// True when some frame of `params` ([`grass_params`]) can draw the grass of level-0 chunk
/// `coord`: the viewer's placement rule
/// ([`chunk_may_draw_grass`](render_model::grass::chunk_may_draw_grass)), with no hysteresis
/// (the fixed camera is the anchor). The benchmark places clutter on these chunks only.
pub fn may_draw_grass(params: &[LodParams], coord: ChunkCoord) -> bool {
    params
        .iter()
        .any(|p| render_model::grass::chunk_may_draw_grass(p, [coord.x, coord.y, coord.z]))
}

/// True when some budget of `params` selects node `coord` of `level`.
pub fn selected_by_any(params: &[LodParams], level: u32, coord: ChunkCoord) -> bool {
    params
        .iter()
        .any(|p| lod::selected(p, [coord.x, coord.y, coord.z], level))
}

/// The renderer for `terrain` and far path `far` (occlusion culling on): room for every node's
/// quads and draw blocks (1/16 slack for allocator fragmentation) and its node count.
pub fn renderer_for(
    ctx: &GpuContext,
    terrain: &LodTerrain,
    width: u32,
    height: u32,
    far: FarRequest,
) -> Result<Renderer, RenderError> {
    renderer_with(ctx, terrain, (width, height), far, true, OpaquePath::Raster)
}

/// [`renderer_for`] with occlusion culling `occlusion` and opaque quads drawn by `opaque`.
pub fn renderer_with(
    ctx: &GpuContext,
    terrain: &LodTerrain,
    (width, height): (u32, u32),
    far: FarRequest,
    occlusion: bool,
    opaque: OpaquePath,
) -> Result<Renderer, RenderError> {
    let slack = |n: u64| n + n / 16 + 4096;
    let nodes = terrain.nodes().count().max(1) as u32;
    let mut config = RendererConfig::new(width, height, terrain.size);
    config.gigabuffer = GigabufferConfig::empty()
        .with_bytes(DataKind::Quads, slack(terrain.quad_count()) * 8)
        .with_max_chunks(nodes);
    config.max_chunks = nodes;
    config.occlusion = occlusion;
    config.opaque = opaque;
    // Nodes without far-draw data (heightmap cubes) have nothing for a far path to draw.
    let config = match far {
        FarRequest::Off => config,
        _ if terrain.draw_block_words() == 0 => config,
        far => config.with_far(far, slack(terrain.draw_block_words()) * 4),
    };
    // The grass pass, when the terrain carries clutter (`--clutter`).
    let clutter = terrain.clutter_count();
    let config = if clutter > 0 {
        config.with_clutter(slack(clutter) * 20)
    } else {
        config
    };
    // The shell pass, when the nodes are meshed as vertical shells or heightmap cubes
    // (`--geometry shells` or `heightmap`).
    let runs = terrain.shell_count();
    let config = if runs > 0 {
        config.with_shells(slack(runs) * 8)
    } else {
        config
    };
    Renderer::new(ctx, &config, &terrain.palette)
}

/// Uploads every node of `terrain`; returns the CPU milliseconds it took.
pub fn upload_terrain(renderer: &mut Renderer, terrain: &LodTerrain) -> Result<f64, RenderError> {
    upload_terrain_where(renderer, terrain, |_| true)
}

/// Uploads the nodes of `terrain` that `keep` accepts; returns the CPU milliseconds it took.
pub fn upload_terrain_where(
    renderer: &mut Renderer,
    terrain: &LodTerrain,
    keep: impl Fn(&NodeMesh) -> bool,
) -> Result<f64, RenderError> {
    let started = Instant::now();
    for node in terrain.nodes().filter(|n| keep(n)) {
        renderer.upload_chunk(&ChunkMeshData {
            coord: node.coord,
            lod: node.level,
            layers: node.layers(),
        })?;
    }
    Ok(started.elapsed().as_secs_f64() * 1e3)
}

/// Medians of the CPU time to record and submit one frame.
struct CpuFrame {
    /// Wall-clock microseconds (includes time slices given to other processes).
    wall_us: f64,
    /// Microseconds of the calling thread's CPU time (`CLOCK_THREAD_CPUTIME_ID`).
    thread_us: f64,
    /// The part of `thread_us` spent in `CommandEncoder::finish` (wgpu-core turning the
    /// recorded passes into driver commands).
    finish_thread_us: f64,
    /// The part of `thread_us` spent in `Queue::submit` (wgpu's validation and the driver).
    submit_thread_us: f64,
}

/// One setting measured: warm-up, timed frames, the last frame's counts and image.
fn measure(
    ctx: &GpuContext,
    renderer: &mut Renderer,
    frames: usize,
) -> Result<(Vec<PassMedian>, CpuFrame, DrawnCounts, FrameImage), BenchError> {
    for _ in 0..WARM_UP_FRAMES {
        renderer.render()?;
    }
    let mut passes: Vec<Vec<(String, u64)>> = Vec::new();
    let mut cpu_frame_ns = Vec::new();
    let mut cpu_thread_ns = Vec::new();
    let mut finish_thread_ns = Vec::new();
    let mut submit_thread_ns = Vec::new();
    let fills_before = renderer.shadow_grid_fills();
    for _ in 0..frames {
        let started = Instant::now();
        let thread_started = thread_cpu_now();
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        renderer.record_frame(&mut encoder)?;
        let finish_started = thread_cpu_now();
        let commands = encoder.finish();
        let submit_started = thread_cpu_now();
        ctx.queue.submit([commands]);
        let thread_now = thread_cpu_now();
        cpu_thread_ns.push(thread_now.saturating_sub(thread_started).as_nanos() as u64);
        finish_thread_ns.push(submit_started.saturating_sub(finish_started).as_nanos() as u64);
        submit_thread_ns.push(thread_now.saturating_sub(submit_started).as_nanos() as u64);
        cpu_frame_ns.push(started.elapsed().as_nanos() as u64);
        let times = renderer.collect_timings()?;
        passes.push(
            times
                .into_iter()
                .map(|t| (t.label, t.nanoseconds))
                .collect(),
        );
    }
    if renderer.shadow_grid_fills() > 0 {
        // The still camera keeps the grid; the log says so, for a reader of the grid's time.
        eprintln!(
            "shadow grid filled in {} of {frames} timed frames",
            renderer.shadow_grid_fills() - fills_before
        );
    }
    // One more frame with the rasteriser's counters cleared first, so they count one frame.
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    renderer.clear_quad_raster_stats(&mut encoder);
    renderer.record_frame(&mut encoder)?;
    ctx.queue.submit([encoder.finish()]);
    renderer.collect_timings()?;
    let quad_raster = renderer
        .read_quad_raster_stats()?
        .map(|s| QuadRasterCounts {
            quads: s.quads,
            visible: s.visible,
            local_pixels: s.local_pixels,
            big: s.big,
            tile_pixels: s.tile_pixels,
            hits: s.hits,
            tiles: s.tiles,
        });
    let (cull, splat) = renderer.read_frame_stats()?;
    let (grass_chunks, grass_units) = renderer.grass_stats()?.unwrap_or((0, 0));
    let mut per_level = cull.per_level.to_vec();
    while per_level.last() == Some(&0) {
        per_level.pop();
    }
    let drawn = DrawnCounts {
        selected: cull.selected,
        selected_per_level: per_level,
        frustum_culled: cull.frustum_culled,
        occluded: cull.occluded,
        mesh_nodes: cull.mesh_nodes,
        far_nodes: cull.far_nodes,
        mesh_quads: cull.mesh_quads,
        transparent_quads: cull.transparent_quads,
        smooth_quads: cull.smooth_quads,
        far_blocks: cull.far_blocks,
        splat_pixels: splat.pixels,
        splat_skipped: splat.skipped,
        quad_raster,
        grass_chunks,
        grass_units,
    };
    let image = renderer.read_image()?;
    Ok((
        pass_medians(&passes),
        CpuFrame {
            wall_us: median(&mut cpu_frame_ns) as f64 / 1e3,
            thread_us: median(&mut cpu_thread_ns) as f64 / 1e3,
            finish_thread_us: median(&mut finish_thread_ns) as f64 / 1e3,
            submit_thread_us: median(&mut submit_thread_ns) as f64 / 1e3,
        },
        drawn,
        image,
    ))
}

/// The images a run kept: the full-detail reference and the last setting's frame.
#[derive(Debug)]
pub struct BenchImages {
    /// The full-detail frame, when rendered.
    pub reference: Option<FrameImage>,
    /// The last measured frame.
    pub last: Option<FrameImage>,
}

/// Runs the benchmark over `terrain` (already generated): per far path a renderer with every
/// node resident, then each setting. `scene` is filled with the resident figures.
pub fn run(
    ctx: &GpuContext,
    terrain: &LodTerrain,
    config: &BenchConfig,
    scene: &mut SceneSummary,
) -> Result<(Vec<RunReport>, BenchImages, Vec<FarChoice>), BenchError> {
    if config.far.is_empty()
        || config.fullscreen.is_empty()
        || config.occlusion.is_empty()
        || config.opaque.is_empty()
    {
        return Err(BenchError::BadConfig(
            "at least one far path, full-screen path, occlusion setting and opaque path".to_owned(),
        ));
    }
    let camera = bench_camera();
    let mut runs = Vec::new();
    let mut images = BenchImages {
        reference: None,
        last: None,
    };
    let mut choices = Vec::new();
    let settings = config.far.iter().flat_map(|&far| {
        config.occlusion.iter().flat_map(move |&occlusion| {
            config
                .opaque
                .iter()
                .map(move |&opaque| (far, occlusion, opaque))
        })
    });
    let top_level = terrain.levels.len().saturating_sub(1) as u32;
    let params = budget_params(
        &camera,
        &config.budgets,
        top_level,
        config.height,
        terrain.size,
    );
    for (index, (far, occlusion, opaque)) in settings.enumerate() {
        let size = (config.width, config.height);
        if config.reference && index == 0 {
            // Full detail in a renderer of its own holding level 0 only, freed before the
            // budgets' runs: their frames then cost what the view's own resident set costs.
            let mut renderer = renderer_with(ctx, terrain, size, far, occlusion, opaque)?;
            renderer.set_camera(&camera);
            renderer
                .set_lighting(&config.lighting)
                .map_err(|e| BenchError::BadConfig(e.to_string()))?;
            upload_terrain_where(&mut renderer, terrain, |n| n.level == 0)?;
            renderer.set_lod(None)?;
            for &fullscreen in &config.fullscreen {
                renderer.set_fullscreen_path(fullscreen);
                let (passes, cpu, drawn, image) = measure(ctx, &mut renderer, config.frames)?;
                runs.push(RunReport {
                    budget_px: None,
                    far: "Off".to_owned(),
                    far_cell_px: 0.0,
                    fullscreen: format!("{fullscreen:?}"),
                    occlusion,
                    opaque: format!("{opaque:?}"),
                    gpu_total_us: passes.iter().map(|p| p.micros).sum(),
                    passes,
                    cpu_frame_us: cpu.wall_us,
                    cpu_thread_us: cpu.thread_us,
                    cpu_finish_us: cpu.finish_thread_us,
                    cpu_submit_us: cpu.submit_thread_us,
                    drawn,
                    image_error: None,
                });
                images.reference.get_or_insert(image);
            }
        }
        let mut renderer = renderer_with(ctx, terrain, size, far, occlusion, opaque)?;
        let far_choice = renderer.far_choice().clone();
        eprintln!("far draws: {far_choice}");
        choices.push(far_choice.clone());
        renderer.set_camera(&camera);
        renderer
            .set_lighting(&config.lighting)
            .map_err(|e| BenchError::BadConfig(e.to_string()))?;
        scene.upload_ms = upload_terrain_where(&mut renderer, terrain, |n| {
            selected_by_any(&params, n.level, n.coord)
        })?;
        scene.resident_bytes = renderer
            .resident_bytes()
            .into_iter()
            .map(|(k, v)| (k.to_owned(), v))
            .collect();
        for &fullscreen in &config.fullscreen {
            renderer.set_fullscreen_path(fullscreen);
            let fullscreen_name = format!("{fullscreen:?}");
            for &budget in &config.budgets {
                for &far_cell_px in &config.far_cell_px {
                    renderer.set_lod(Some(LodSettings {
                        budget_px: budget,
                        far_cell_px,
                        ..LodSettings::default()
                    }))?;
                    let (passes, cpu, drawn, image) = measure(ctx, &mut renderer, config.frames)?;
                    let error = images
                        .reference
                        .as_ref()
                        .and_then(|r| image_error(&image.rgba, &r.rgba))
                        .map(ImageErrorReport::from);
                    runs.push(RunReport {
                        budget_px: Some(budget),
                        far: format!("{:?}", far_choice.path),
                        far_cell_px,
                        fullscreen: fullscreen_name.clone(),
                        occlusion,
                        opaque: format!("{opaque:?}"),
                        gpu_total_us: passes.iter().map(|p| p.micros).sum(),
                        passes,
                        cpu_frame_us: cpu.wall_us,
                        cpu_thread_us: cpu.thread_us,
                        cpu_finish_us: cpu.finish_thread_us,
                        cpu_submit_us: cpu.submit_thread_us,
                        drawn,
                        image_error: error,
                    });
                    images.last = Some(image);
                }
            }
        }
    }
    Ok((runs, images, choices))
}
