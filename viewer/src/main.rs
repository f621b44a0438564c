//! The viewer's command line: shows the built-in scene (or a `.vox` file).
//!
//! With a display (`DISPLAY` or `WAYLAND_DISPLAY` set) it opens a window (GPU renderer, fly
//! camera, stats overlay; see `viewer::window`); `--window` forces that, and then a failure is
//! an error, while without `--window` a window that cannot be opened falls back to the PNG.
//! `--frames N` closes the window after N presented frames and prints
//! `window: presented N frames WxH on <adapter>`.
//!
//! With no display, or with `--headless`, it renders one frame to a PNG file and prints where
//! it wrote it. The frame comes from the GPU renderer (deferred shading) when a Vulkan adapter
//! exists (lavapipe counts), and from the CPU reference raycaster otherwise or with `--cpu`; it
//! prints which one it used.
//!
//! `--camera X,Y,Z,YAW,PITCH` and `--fov DEG` set the first view (the PNG's, and the window's
//! start; parsed in `camera_arg.rs`); otherwise the scene suggests one. `--vox FILE` shows a
//! MagicaVoxel file instead of the terrain (`--seed` and `--chunks` are then refused),
//! `--hidden` its hidden nodes too.

mod camera_arg;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use camera_arg::{CameraArg, parse_camera, parse_fov};
use clap::Parser;
use gpu_backend::png::encode_png;
use viewer::gpu_view::{GpuViewError, render_scene};
use viewer::lighting::Lighting;
use viewer::reference_raycast::render;
use viewer::scene::vox::{VoxError, VoxOptions, load_vox_file_with};
use viewer::scene::{Scene, camera_looking_at, terrain_scene};
use viewer::window::mode::{Mode, choose_mode, display_present};
use viewer::window::{WindowOptions, run_window};
use voxel_core::ChunkSize;

/// Shows the built-in procedural terrain or a MagicaVoxel file, in a window or as a PNG.
#[derive(Parser, Debug)]
#[command(version, about)]
struct Args {
    /// Render one frame to a PNG even when a display is available.
    #[arg(long, conflicts_with = "window")]
    headless: bool,
    /// Open a window even when no display is named in the environment; fail if it cannot.
    #[arg(long)]
    window: bool,
    /// Window mode: close after this many presented frames (print what was presented).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    frames: Option<u64>,
    /// Window mode: with --frames, fail when they take longer than this many seconds.
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u64).range(1..))]
    frames_timeout: u64,
    /// Window mode: present as fast as possible instead of at the display's refresh rate.
    #[arg(long)]
    no_vsync: bool,
    /// Window mode (tests): after the first frame, resize the window to WIDTHxHEIGHT; with
    /// --frames, close only once that size is in use.
    #[arg(long, value_name = "WIDTHxHEIGHT", value_parser = parse_size)]
    resize_to: Option<(u32, u32)>,
    /// Window mode: start without the stats overlay (F1 toggles it).
    #[arg(long)]
    no_overlay: bool,
    /// Where to write the PNG.
    #[arg(long, default_value = "target/viewer.png")]
    out: PathBuf,
    /// Image (or window) width in pixels.
    #[arg(long, default_value_t = 960, value_parser = clap::value_parser!(u32).range(1..=8192))]
    width: u32,
    /// Image (or window) height in pixels.
    #[arg(long, default_value_t = 540, value_parser = clap::value_parser!(u32).range(1..=8192))]
    height: u32,
    /// Terrain seed (not with --vox).
    #[arg(long, default_value_t = 1, conflicts_with = "vox")]
    seed: i32,
    /// Terrain extent in 32^3 chunks along x and z (not with --vox).
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(i32).range(1..=64), conflicts_with = "vox")]
    chunks: i32,
    /// Show this MagicaVoxel `.vox` file instead of the built-in terrain.
    #[arg(long)]
    vox: Option<PathBuf>,
    /// With --vox: show hidden nodes and hidden layers too.
    #[arg(long, requires = "vox")]
    hidden: bool,
    /// Start the camera (headless frame or window) at world position X,Y,Z (voxels, y up),
    /// turned YAW degrees about +y (0 looks along -z, 90 along -x) and PITCH degrees above the
    /// horizon (-90 to 90). Default: a view chosen for the scene.
    #[arg(long, value_name = "X,Y,Z,YAW,PITCH", value_parser = parse_camera, allow_hyphen_values = true)]
    camera: Option<CameraArg>,
    /// Vertical field of view in degrees (1 to 179). Default: the scene's view (70 for the
    /// terrain, 60 for .vox files).
    #[arg(long, value_name = "DEG", value_parser = parse_fov, allow_hyphen_values = true)]
    fov: Option<f64>,
    /// Render with the CPU reference raycaster even when a GPU is available.
    #[arg(long)]
    cpu: bool,
}

/// Voxels a `.vox` scene may hold before the viewer refuses it (MagicaVoxel scenes top out
/// far below this; the limit keeps a corrupt or hostile file from exhausting memory).
const MAX_VOX_VOXELS: usize = 64 << 20;

/// Loads a `.vox` file (hidden nodes and layers too with `include_hidden`) and tells the user
/// what was left out.
fn vox_scene(path: &std::path::Path, include_hidden: bool) -> Result<Scene, VoxError> {
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

/// `WIDTHxHEIGHT`, each 1 to 8192.
fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let parse = |part: &str| match part.trim().parse::<u32>() {
        Ok(v @ 1..=8192) => Ok(v),
        _ => Err(format!("{part:?} is not a size from 1 to 8192")),
    };
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("{text:?} is not WIDTHxHEIGHT"))?;
    Ok((parse(w)?, parse(h)?))
}

fn main() -> ExitCode {
    let args = Args::parse();
    let mode = choose_mode(args.headless, args.window, display_present());

    let started = Instant::now();
    let mut scene = match &args.vox {
        None => terrain_scene(args.seed, ChunkSize::S32, args.chunks, 2, args.chunks),
        Some(path) => match vox_scene(path, args.hidden) {
            Ok(scene) => scene,
            Err(e) => {
                eprintln!("viewer: {}: {e}", path.display());
                return ExitCode::FAILURE;
            }
        },
    };
    let generated = started.elapsed();
    // --camera and --fov replace the scene's first view, for the PNG and the window alike.
    let fov_y = args.fov.unwrap_or(scene.suggested_view.fov_y);
    scene.suggested_view = match args.camera {
        Some(camera) => camera.camera(fov_y),
        None => viewer::camera::Camera {
            fov_y,
            ..scene.suggested_view
        },
    };
    if let Mode::Window { forced } = mode {
        let options = WindowOptions {
            frames: args.frames,
            frames_deadline: Duration::from_secs(args.frames_timeout),
            vsync: !args.no_vsync,
            resize_to: args.resize_to,
            overlay: !args.no_overlay,
            ..WindowOptions::new(args.width, args.height)
        };
        match run_window(&scene, options) {
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
    headless(&args, &scene, generated)
}

/// Renders one frame of `scene` to the PNG at `args.out` and says where it went.
fn headless(args: &Args, scene: &Scene, generated: Duration) -> ExitCode {
    let started = Instant::now();
    let lighting = Lighting::default();
    // The CPU reference stands in only where there is no GPU at all (or --cpu); any other
    // GPU failure (a scene the device cannot hold, a refused upload) is the run's error.
    let gpu = if args.cpu {
        Err("--cpu given".to_owned())
    } else {
        match render_scene(
            scene,
            &scene.suggested_view,
            &lighting,
            args.width,
            args.height,
        ) {
            Ok(frame) => Ok(frame),
            Err(GpuViewError::Device(e)) if e.is_no_adapter() => Err(e.to_string()),
            Err(e) => {
                eprintln!("viewer: GPU renderer: {e}");
                return ExitCode::FAILURE;
            }
        }
    };
    let (rgba, renderer_used) = match gpu {
        Ok(frame) => {
            let passes: Vec<String> = frame
                .timings
                .iter()
                .map(|t| format!("{} {:.2} ms", t.label, t.nanoseconds as f64 / 1e6))
                .collect();
            let used = format!(
                "GPU renderer on {}, {} chunks; passes: {}",
                frame.adapter,
                frame.chunks,
                passes.join(", ")
            );
            (frame.rgba, used)
        }
        Err(why) => {
            let block_at = |p| scene.world.get_block(p);
            let image = render(
                &block_at,
                &scene.palette,
                &scene.suggested_view,
                &lighting,
                args.width,
                args.height,
                400.0,
            );
            (image.rgba, format!("CPU reference raycast; no GPU: {why}"))
        }
    };
    let rendered = started.elapsed();

    let png = match encode_png(args.width, args.height, &rgba) {
        Ok(bytes) => bytes,
        Err(e) => {
            eprintln!("viewer: could not encode the PNG: {e}");
            return ExitCode::FAILURE;
        }
    };
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty())
        && let Err(e) = std::fs::create_dir_all(dir)
    {
        eprintln!("viewer: could not create {}: {e}", dir.display());
        return ExitCode::FAILURE;
    }
    if let Err(e) = std::fs::write(&args.out, png) {
        eprintln!("viewer: could not write {}: {e}", args.out.display());
        return ExitCode::FAILURE;
    }
    let shown = std::fs::canonicalize(&args.out).unwrap_or(args.out.clone());
    println!(
        "viewer: {} chunks generated in {:.0?}, {}x{} rendered in {:.0?} with the {}",
        scene.world.len(),
        generated,
        args.width,
        args.height,
        rendered,
        renderer_used
    );
    println!("viewer: wrote {}", shown.display());
    ExitCode::SUCCESS
}

#[cfg(test)]
mod tests {
    use super::{Args, Parser, parse_size};

    #[test]
    fn sizes_parse_and_bad_ones_are_refused() {
        assert_eq!(parse_size("200x120"), Ok((200, 120)));
        assert_eq!(parse_size("8X9"), Ok((8, 9)));
        for bad in ["200", "0x10", "10x0", "9000x10", "ax1", "-1x2", ""] {
            assert!(parse_size(bad).is_err(), "{bad:?} accepted");
        }
    }

    fn parse(args: &[&str]) -> Result<Args, String> {
        Args::try_parse_from(std::iter::once("viewer").chain(args.iter().copied()))
            .map_err(|e| e.to_string())
    }

    #[test]
    fn terrain_options_with_vox_are_an_error() {
        for extra in [&["--seed", "3"][..], &["--chunks", "2"][..]] {
            let mut args = vec!["--vox", "model.vox"];
            args.extend_from_slice(extra);
            let err = parse(&args).expect_err("conflict");
            assert!(err.contains(extra[0]) && err.contains("--vox"), "{err}");
        }
        assert!(parse(&["--vox", "model.vox"]).is_ok());
        assert!(parse(&["--seed", "3", "--chunks", "2"]).is_ok());
        assert!(parse(&["--hidden"]).unwrap_err().contains("--vox"));
    }

    #[test]
    fn camera_and_fov_reach_the_arguments() {
        let a = parse(&["--camera", "-10.5,40,3,90,-30", "--fov", "45"]).unwrap();
        let camera = a.camera.unwrap();
        assert_eq!(camera.yaw_degrees, 90.0);
        assert_eq!(a.fov, Some(45f64.to_radians()));
        for bad in [&["--camera", "1,2,3"][..], &["--fov", "-5"][..]] {
            assert!(parse(bad).is_err(), "{bad:?}");
        }
    }
}
