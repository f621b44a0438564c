//! The viewer's command line: shows the built-in terrain, streamed around the camera (or a
//! fixed square of it with `--chunks`, or a `.vox` file), in a window or as a PNG, or flies a
//! scripted path and measures it (`--flight`).
//!
//! With a display (`DISPLAY` or `WAYLAND_DISPLAY` set) it opens a window (GPU renderer, fly
//! camera, overlay with stats and controls; see `viewer::window`); `--window` forces that, and
//! then a failure is an error, while without `--window` a window that cannot be opened falls
//! back to the PNG. `--frames N` closes the window after N presented frames and prints
//! `window: presented N frames WxH on <adapter>`.
//!
//! With no display, or with `--headless`, it renders one frame to a PNG file and prints where
//! it wrote it. The frame comes from the GPU renderer (deferred shading) when a Vulkan adapter
//! exists (lavapipe counts), and from the CPU reference raycaster otherwise or with `--cpu`; it
//! prints which one it used. A streamed terrain is loaded first (progress on stderr).
//!
//! `--camera X,Y,Z,YAW,PITCH` and `--fov DEG` set the first view (parsed in `camera_arg.rs`);
//! the other flags are in `cli.rs`.

mod camera_arg;
mod cli;

use std::path::Path;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use clap::Parser;
use cli::Args;
use gpu_backend::png::encode_png;
use gpu_backend::{DeviceError, DeviceOptions, GpuContext};
use render_model::antialias::fxaa;
use render_model::camera::Camera;
use render_model::lighting::Lighting;
use viewer::deferred_reference::render_deferred;
use viewer::edits::SharedWorld;
use viewer::flight::{FlightPath, fly_over};
use viewer::gpu_view::{GpuViewError, render_scene};
use viewer::headless::{draw_frame, load};
use viewer::scene::vox::{VoxError, VoxOptions, load_vox_file_with};
use viewer::scene::{
    Scene, Terrain, TerrainBlocks, camera_looking_at, terrain_scene, terrain_view,
};
use viewer::stream::StreamSettings;
use viewer::view::{OPAQUE_TRIAL_FRAMES, StreamedView};
use viewer::window::mode::{Mode, choose_mode, display_present};
use viewer::window::{WindowOptions, WindowSource, run_window};
use voxel_core::{BlockId, ChunkSize, WorldPos};

/// Voxels a `.vox` scene may hold before the viewer refuses it (MagicaVoxel scenes top out
/// far below this; the limit keeps a corrupt or hostile file from exhausting memory).
const MAX_VOX_VOXELS: usize = 64 << 20;

/// How long the first view of a streamed terrain may take to load headless.
const LOAD_TIMEOUT: Duration = Duration::from_secs(1800);

/// Loads a `.vox` file (hidden nodes and layers too with `include_hidden`) and tells the user
/// what was left out.
fn vox_scene(path: &Path, include_hidden: bool) -> Result<Scene, VoxError> {
    let options = VoxOptions {
        include_hidden,
        ..VoxOptions::new(ChunkSize::S32, MAX_VOX_VOXELS)
    };
    let vox = load_vox_file_with(path, &options)?;
    for note in vox.report.notes() {
        eprintln!("viewer: note: {}: {note}", path.display());
    }
    let (lo, hi) = vox.bounds.unwrap_or_default();
    Ok(Scene {
        world: vox.world,
        palette: vox.palette,
        suggested_view: camera_looking_at(lo, hi),
    })
}

/// What the viewer shows.
enum Shown {
    /// A scene held whole (`--vox`, `--chunks`).
    Fixed(Scene),
    /// The streamed terrain and its world (edited by the flags, loaded with `--world`).
    Streamed(StreamSettings, Terrain, SharedWorld),
}

/// The streamed terrain's world: loaded from `--world` (a new one when the folder holds
/// none; chunks that did not load are named), with the edit flags applied, and saved back
/// there when they changed anything.
fn open_world(args: &Args, settings: &StreamSettings) -> Result<SharedWorld, String> {
    let top = settings.top_level();
    let world = match &args.world {
        Some(dir) => {
            let (world, report) = SharedWorld::open_or_new(dir, settings.seed, settings.chunk, top)
                .map_err(|e| format!("world {}: {e}", dir.display()))?;
            match report {
                Some(report) => {
                    eprintln!(
                        "viewer: world {}: {} edited chunks loaded from {} regions",
                        dir.display(),
                        report.chunks,
                        report.regions
                    );
                    for (path, fault) in &report.faults {
                        eprintln!(
                            "viewer: warning: {}: {fault}; that chunk is not loaded",
                            path.display()
                        );
                    }
                }
                None => eprintln!(
                    "viewer: world {}: new (nothing saved there yet)",
                    dir.display()
                ),
            }
            world
        }
        None => SharedWorld::new(settings.seed, settings.chunk, top).map_err(|e| e.to_string())?,
    };
    let edits = args.all_edits();
    if !edits.is_empty() {
        let dirty = world.apply(&edits).map_err(|e| e.to_string())?;
        eprintln!(
            "viewer: {} edits changed {} chunks",
            edits.len(),
            dirty.changed().count()
        );
        if let Some(dir) = &args.world {
            let chunks = world
                .save(dir)
                .map_err(|e| format!("saving the world to {}: {e}", dir.display()))?;
            eprintln!(
                "viewer: world {}: saved {chunks} region files",
                dir.display()
            );
        }
    }
    Ok(world)
}

fn main() -> ExitCode {
    let args = Args::parse();
    if let Some(seconds) = args.flight {
        return flight(&args, seconds);
    }
    let mode = choose_mode(args.headless, args.window, display_present());
    let started = Instant::now();
    let shown = match (&args.vox, args.chunks) {
        (Some(path), _) => match vox_scene(path, args.hidden) {
            Ok(scene) => Shown::Fixed(scene),
            Err(e) => {
                eprintln!("viewer: {}: {e}", path.display());
                return ExitCode::FAILURE;
            }
        },
        (None, Some(n)) => Shown::Fixed(terrain_scene(args.seed, ChunkSize::S32, n, 2, n)),
        (None, None) => {
            let settings = match with_props(&args, args.stream_settings()) {
                Ok(s) => s,
                Err(e) => {
                    eprintln!("viewer: {e}");
                    return ExitCode::FAILURE;
                }
            };
            if let Err(e) = settings.clone().validate() {
                eprintln!("viewer: {e}");
                return ExitCode::FAILURE;
            }
            let world = match open_world(&args, &settings) {
                Ok(world) => world,
                Err(e) => {
                    eprintln!("viewer: {e}");
                    return ExitCode::FAILURE;
                }
            };
            Shown::Streamed(
                settings,
                Terrain::new(args.seed, TerrainBlocks::palette().1),
                world,
            )
        }
    };
    let generated = started.elapsed();
    // --camera and --fov replace the scene's first view, for the PNG and the window alike.
    let suggested = match &shown {
        Shown::Fixed(scene) => scene.suggested_view,
        Shown::Streamed(_, terrain, _) => terrain_view(terrain),
    };
    let fov_y = args.fov.unwrap_or(suggested.fov_y);
    let view = match args.camera {
        Some(camera) => camera.camera(fov_y),
        None => Camera { fov_y, ..suggested },
    };
    let (width, height) = args.size();
    if let Mode::Window { forced } = mode {
        let options = WindowOptions {
            frames: args.frames,
            frames_deadline: Duration::from_secs(args.frames_timeout),
            vsync: !args.no_vsync,
            resize_to: args.resize_to,
            overlay: !args.no_overlay,
            screenshot_dir: args.screenshot_dir.clone(),
            screenshot_at: args.screenshot_at,
            wireframe: args.wireframe,
            ..WindowOptions::new(width, height)
        };
        let source = match &shown {
            Shown::Fixed(scene) => WindowSource::Fixed(scene),
            Shown::Streamed(settings, _, world) => WindowSource::Streamed {
                settings: settings.clone(),
                world: world.clone(),
                world_dir: args.world.clone(),
            },
        };
        match run_window(source, view, options) {
            Ok(report) => {
                println!("window: {report}");
                return ExitCode::SUCCESS;
            }
            Err(e) if forced => {
                eprintln!("viewer: window: {e}");
                return ExitCode::FAILURE;
            }
            Err(e) => eprintln!("viewer: no window ({e}); rendering to a PNG instead"),
        }
    }
    let started = Instant::now();
    let frame = match &shown {
        Shown::Fixed(scene) => fixed_frame(&args, scene, &view, generated),
        Shown::Streamed(settings, terrain, world) => {
            streamed_frame(&args, settings, terrain, world, &view)
        }
    };
    let Some((rgba, what)) = frame else {
        return ExitCode::FAILURE;
    };
    let what = format!("{what} in {:.0?}", started.elapsed());
    write_png(&args.out, width, height, &rgba, &what)
}

/// The fixed scene's frame: GPU, or the CPU raycaster without a GPU (or with `--cpu`).
fn fixed_frame(
    args: &Args,
    scene: &Scene,
    view: &Camera,
    generated: Duration,
) -> Option<(Vec<u8>, String)> {
    let (width, height) = args.size();
    let lighting = Lighting {
        shadows: args.shadow_settings(),
        ..Lighting::default()
    };
    let gpu = if args.cpu {
        Err("--cpu given".to_owned())
    } else {
        match render_scene(scene, view, &lighting, (width, height), args.wireframe) {
            Ok(frame) => Ok(frame),
            Err(GpuViewError::Device(e)) if e.is_no_adapter() && args.wireframe => {
                eprintln!("viewer: --wireframe needs the GPU renderer: {e}");
                return None;
            }
            Err(GpuViewError::Device(e)) if e.is_no_adapter() => Err(e.to_string()),
            Err(e) => {
                eprintln!("viewer: GPU renderer: {e}");
                return None;
            }
        }
    };
    let chunks = format!("{} chunks generated in {generated:.0?}", scene.world.len());
    Some(match gpu {
        Ok(frame) => (
            frame.rgba,
            format!(
                "{chunks}, {width}x{height} rendered with the GPU renderer on {}, {} chunks; \
                 passes: {}",
                frame.adapter,
                frame.chunks,
                passes_text(&frame.timings)
            ),
        ),
        Err(why) => {
            let block_at = |p| scene.world.get_block(p);
            let image = render_deferred(
                &block_at,
                &scene.palette,
                view,
                &lighting,
                width,
                height,
                400.0,
            );
            (
                fxaa(&image.rgba, width, height),
                format!(
                    "{chunks}, {width}x{height} rendered with the CPU reference raycast; no GPU: {why}"
                ),
            )
        }
    })
}

/// How far the CPU reference traces the terrain, blocks.
const CPU_TERRAIN_DISTANCE: f64 = 400.0;

/// The streamed terrain's frame: loaded around `view` on the GPU, or the CPU raycaster over
/// the terrain's function without a GPU (or with `--cpu`).
fn streamed_frame(
    args: &Args,
    settings: &StreamSettings,
    terrain: &Terrain,
    world: &SharedWorld,
    view: &Camera,
) -> Option<(Vec<u8>, String)> {
    let (width, height) = args.size();
    let no_gpu = if args.cpu {
        Some("--cpu given".to_owned())
    } else {
        match GpuContext::new_headless(&DeviceOptions::default()) {
            Ok(ctx) => {
                return streamed_gpu_frame(
                    &ctx,
                    settings,
                    world,
                    view,
                    (width, height),
                    args.wireframe,
                );
            }
            Err(e) if e.is_no_adapter() && args.wireframe => {
                eprintln!("viewer: --wireframe needs the GPU renderer: {e}");
                return None;
            }
            Err(e) if e.is_no_adapter() => Some(e.to_string()),
            Err(e) => {
                eprintln!("viewer: GPU renderer: {}", DeviceError::to_string(&e));
                return None;
            }
        }
    };
    let why = no_gpu.unwrap_or_default();
    let top = voxel_scene::TERRAIN_TOP;
    // The edits over the terrain's function: an edited chunk's blocks, else the function's.
    let edited = world.read();
    let block_at = |p: WorldPos| {
        if let Some(id) = edited.edited_block(p) {
            id
        } else if (0..=top).contains(&p.y) {
            terrain.block_at(p.x, p.y, p.z)
        } else {
            BlockId::AIR
        }
    };
    let (palette, _) = TerrainBlocks::palette();
    // The CPU traces CPU_TERRAIN_DISTANCE blocks; its haze ends the world there, as the GPU's
    // ends it at the streamed radius.
    let lighting = Lighting {
        haze_distance: CPU_TERRAIN_DISTANCE as f32,
        shadows: settings.shadows,
        ..Lighting::default()
    };
    let image = render_deferred(
        &block_at,
        &palette,
        view,
        &lighting,
        width,
        height,
        CPU_TERRAIN_DISTANCE,
    );
    Some((
        fxaa(&image.rgba, width, height),
        format!(
            "the terrain's function, {width}x{height} rendered with the CPU reference raycast \
             ({CPU_TERRAIN_DISTANCE} blocks, hazed there); no GPU: {why}"
        ),
    ))
}

/// Loads the streamed view around `view` (progress on stderr) and renders one frame.
fn streamed_gpu_frame(
    ctx: &GpuContext,
    settings: &StreamSettings,
    world: &SharedWorld,
    view: &Camera,
    (width, height): (u32, u32),
    wireframe: bool,
) -> Option<(Vec<u8>, String)> {
    let camera = *view;
    let loaded = Instant::now();
    let result = StreamedView::with_world(ctx, settings, width, height, world.clone()).and_then(
        |mut streamed| {
            load(&mut streamed, &camera, LOAD_TIMEOUT, |status| {
                eprintln!("viewer: {}", status.progress_line());
            })?;
            let load_time = loaded.elapsed();
            if let Some(choice) = streamed.choose_opaque_path(OPAQUE_TRIAL_FRAMES)? {
                eprintln!("viewer: opaque path (auto): {choice}");
            }
            streamed.renderer_mut().set_wireframe(wireframe);
            let passes = draw_frame(ctx, &mut streamed)?;
            let image = streamed
                .renderer()
                .read_image()
                .map_err(viewer::stream::StreamError::Renderer)?;
            let status = streamed.streamer().status();
            Ok((
                image.rgba,
                passes,
                status,
                load_time,
                streamed.streamer().far_choice().clone(),
            ))
        },
    );
    match result {
        Ok((rgba, passes, status, load_time, far)) => Some((
            rgba,
            format!(
                "terrain streamed to a radius of {} blocks ({} nodes, {:.1} MiB, loaded in \
                 {load_time:.1?}), {width}x{height} rendered with the GPU renderer on {} (far \
                 draws {far}); passes: {}",
                settings.radius,
                status.drawn_nodes,
                status.node_bytes as f64 / f64::from(1u32 << 20),
                ctx.capabilities.adapter,
                passes_text(&passes)
            ),
        )),
        Err(e) => {
            eprintln!("viewer: streamed terrain: {e}");
            None
        }
    }
}

/// Per-pass times as `label 1.23 ms, ...`.
fn passes_text(passes: &[gpu_backend::PassTime]) -> String {
    let parts: Vec<String> = passes
        .iter()
        .map(|t| format!("{} {:.2} ms", t.label, t.nanoseconds as f64 / 1e6))
        .collect();
    parts.join(", ")
}

/// Creates `path`'s folder if needed.
fn create_parent(path: &Path) -> Result<(), String> {
    match path.parent().filter(|d| !d.as_os_str().is_empty()) {
        Some(dir) => std::fs::create_dir_all(dir)
            .map_err(|e| format!("could not create {}: {e}", dir.display())),
        None => Ok(()),
    }
}

/// Writes the PNG and says what it holds and where it went.
fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8], what: &str) -> ExitCode {
    let png = match encode_png(width, height, rgba) {
        Ok(bytes) => bytes,
        Err(e) => {
            eprintln!("viewer: could not encode the PNG: {e}");
            return ExitCode::FAILURE;
        }
    };
    if let Err(e) = create_parent(path) {
        eprintln!("viewer: {e}");
        return ExitCode::FAILURE;
    }
    if let Err(e) = std::fs::write(path, png) {
        eprintln!("viewer: could not write {}: {e}", path.display());
        return ExitCode::FAILURE;
    }
    let shown = std::fs::canonicalize(path).unwrap_or(path.to_owned());
    println!("viewer: {what}");
    println!("viewer: wrote {}", shown.display());
    ExitCode::SUCCESS
}

/// `--flight SECONDS`: flies the scripted path headless on the GPU and prints (and with
/// `--json`, writes) the figures.
/// `settings` with the props of `--prop` and `--scatter` loaded and placed (scattered ones
/// on the terrain of `--seed`, within 256 blocks of the origin).
fn with_props(
    args: &Args,
    mut settings: StreamSettings,
) -> Result<StreamSettings, viewer::props::PropSceneError> {
    if args.props.is_empty() && args.scatters.is_empty() {
        return Ok(settings);
    }
    let terrain = Terrain::new(args.seed, TerrainBlocks::palette().1);
    let scene = viewer::props::prop_scene(&args.props, &args.scatters, &terrain, 256.0)?;
    eprintln!(
        "viewer: {} prop instances of {} models",
        scene.placements.len(),
        scene.models.len()
    );
    settings.props = Some(std::sync::Arc::new(scene));
    Ok(settings)
}

fn flight(args: &Args, seconds: f64) -> ExitCode {
    let ctx = match GpuContext::new_headless(&DeviceOptions::default()) {
        Ok(ctx) => ctx,
        Err(e) => {
            eprintln!("viewer: --flight needs a GPU: {e}");
            return ExitCode::FAILURE;
        }
    };
    let settings = match with_props(args, args.stream_settings()) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("viewer: {e}");
            return ExitCode::FAILURE;
        }
    };
    let world = match open_world(args, &settings) {
        Ok(world) => world,
        Err(e) => {
            eprintln!("viewer: {e}");
            return ExitCode::FAILURE;
        }
    };
    let terrain = Terrain::new(args.seed, TerrainBlocks::palette().1);
    // Above the highest hills at the origin, so the climb starts clear of the ground.
    let height = f64::from(terrain.height(0, 0).max(terrain.sea_level) + 24);
    let path = FlightPath::over_origin(height);
    let report = match fly_over(
        &ctx,
        &settings,
        world,
        &path,
        seconds,
        args.size(),
        args.edits_per_second,
        |status| {
            eprintln!("viewer: {}", status.progress_line());
        },
    ) {
        Ok(report) => report,
        Err(e) => {
            eprintln!("viewer: flight: {e}");
            return ExitCode::FAILURE;
        }
    };
    for line in report.lines() {
        println!("{line}");
    }
    if let Some(path) = &args.json {
        let json = match serde_json::to_string_pretty(&report) {
            Ok(json) => json,
            Err(e) => {
                eprintln!("viewer: could not write the flight as JSON: {e}");
                return ExitCode::FAILURE;
            }
        };
        if let Err(e) = create_parent(path).and_then(|()| {
            std::fs::write(path, json + "\n")
                .map_err(|e| format!("could not write {}: {e}", path.display()))
        }) {
            eprintln!("viewer: {e}");
            return ExitCode::FAILURE;
        }
        println!("flight: wrote {}", path.display());
    }
    ExitCode::SUCCESS
}
