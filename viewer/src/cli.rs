//! The viewer's flags (clap) and their parsers: each bad value is refused with a message
//! naming it, before anything runs.

use std::path::PathBuf;

use clap::Parser;
use gpu_backend::render::OpaquePath;
use gpu_backend::render::far::FarRequest;
use render_model::lighting::shadow::ShadowSettings;
use viewer::stream::settings::{FAR_CHOICES, MAX_RADIUS};
use viewer::stream::{MesherMode, StreamSettings};
use voxel_core::{ChunkSize, WorldPos};
use voxel_world::Edit;

use viewer::props::{PropFlag, ScatterFlag, parse_prop, parse_scatter};

use crate::camera_arg::{CameraArg, parse_camera, parse_fov};

/// Shows the built-in procedural terrain (streamed around the camera) or a MagicaVoxel file,
/// in a window or as a PNG; `--flight` measures a scripted flight.
#[derive(Parser, Debug)]
#[command(version, about)]
pub(crate) struct Args {
    /// Render one frame to a PNG even when a display is available.
    #[arg(long, conflicts_with = "window")]
    pub headless: bool,
    /// Open a window even when no display is named in the environment; fail if it cannot.
    #[arg(long)]
    pub window: bool,
    /// Window mode: close after this many presented frames (print what was presented).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub frames: Option<u64>,
    /// Window mode: with --frames, fail when they take longer than this many seconds.
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u64).range(1..))]
    pub frames_timeout: u64,
    /// Window mode: present as fast as possible instead of at the display's refresh rate.
    #[arg(long)]
    pub no_vsync: bool,
    /// Window mode (tests): after the first frame, resize the window to WIDTHxHEIGHT; with
    /// --frames, close only once that size is in use.
    #[arg(long, value_name = "WIDTHxHEIGHT", value_parser = parse_size)]
    pub resize_to: Option<(u32, u32)>,
    /// Window mode: start without the stats overlay (F1 toggles it).
    #[arg(long)]
    pub no_overlay: bool,
    /// Where to write the PNG.
    #[arg(long, default_value = "target/viewer.png")]
    pub out: PathBuf,
    /// Where F12 writes screenshots (window mode).
    #[arg(long, value_name = "DIR", default_value = "target/screenshots")]
    pub screenshot_dir: PathBuf,
    /// Window mode (tests): write a screenshot after this many presented frames, as F12 does.
    #[arg(long, hide = true, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub screenshot_at: Option<u64>,
    /// Image (or window) width in pixels [default: 960, 1920 with --flight].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=8192))]
    pub width: Option<u32>,
    /// Image (or window) height in pixels [default: 540, 1080 with --flight].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=8192))]
    pub height: Option<u32>,
    /// Terrain seed (not with --vox).
    #[arg(long, default_value_t = 1, conflicts_with = "vox")]
    pub seed: i32,
    /// Instead of streaming the terrain, show a fixed square of N x N chunks of 32^3 around
    /// the origin (not with --vox).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(i32).range(1..=64), conflicts_with = "vox")]
    pub chunks: Option<i32>,
    /// Streamed terrain: distance from the camera, in blocks, within which the terrain is
    /// streamed (levels of detail beyond the near ring).
    #[arg(long, value_name = "BLOCKS", default_value_t = 2048, value_parser = parse_radius, allow_hyphen_values = true, conflicts_with_all = ["vox", "chunks"])]
    pub radius: u32,
    /// Streamed terrain: the screen-space error budget, pixels (0 = full detail everywhere).
    #[arg(long, value_name = "PX", default_value_t = 1.0, value_parser = parse_budget, allow_hyphen_values = true, conflicts_with_all = ["vox", "chunks"])]
    pub budget: f32,
    /// Streamed terrain: how blocks are meshed (faces, greedy, smooth, shells: vertical
    /// runs drawn as boxes by the shell pass, or heightmap: each column's top as a box, at
    /// every distance, without far draws).
    #[arg(long, value_name = "MODE", default_value = "greedy", value_parser = parse_mesher, conflicts_with_all = ["vox", "chunks"])]
    pub mesher: MesherMode,
    /// Streamed terrain: far draws of distant nodes (off, auto, splat, sprite, quads3).
    #[arg(long, value_name = "PATH", default_value = "auto", value_parser = parse_far, conflicts_with_all = ["vox", "chunks"])]
    pub far: FarRequest,
    /// Streamed terrain: grass and flowers on grass blocks (`on` or `off`); with `off` they are
    /// neither placed nor stored, and the renderer has no grass pass.
    #[arg(long, value_name = "on|off", default_value = "on", value_parser = parse_on_off, action = clap::ArgAction::Set, conflicts_with_all = ["vox", "chunks"])]
    pub clutter: bool,
    /// Sun shadows and sky visibility (rays through an occupancy grid of the 256 blocks
    /// around the camera, `render_model::lighting::shadow`), GPU and `--cpu` alike.
    #[arg(long, value_name = "on|off", default_value = "off", value_parser = parse_on_off, action = clap::ArgAction::Set)]
    pub shadows: bool,
    /// Streamed terrain: how opaque quads are drawn, `raster` (the G-buffer pass), `compute`
    /// (the compute rasteriser: faster on GPUs with few raster units; needs 64-bit atomics) or
    /// `auto` (both drawn at the first view and the faster kept; raster where the compute path
    /// or GPU timestamps are missing).
    #[arg(long, value_name = "PATH", default_value = "auto", value_parser = parse_opaque, conflicts_with_all = ["vox", "chunks"])]
    pub opaque: OpaquePath,
    /// Streamed terrain: node edge in blocks, 8 or 16 (8 culls finer and streams eight times
    /// as many nodes). Default: 16.
    #[arg(long, value_name = "BLOCKS", value_parser = parse_node_size, conflicts_with_all = ["vox", "chunks"])]
    pub node_size: Option<ChunkSize>,
    /// Streamed terrain: nodes whose cells span at most this many pixels are far-drawn
    /// (0.25 to 64). Default: 2.
    #[arg(long, value_name = "PX", value_parser = parse_far_px, allow_hyphen_values = true, conflicts_with_all = ["vox", "chunks"])]
    pub far_px: Option<f32>,
    /// Streamed terrain: GPU memory for node data, MiB.
    #[arg(long, value_name = "MIB", default_value_t = 1024, value_parser = clap::value_parser!(u64).range(1..=1 << 20), conflicts_with_all = ["vox", "chunks"])]
    pub memory: u64,
    /// Show this MagicaVoxel `.vox` file instead of the built-in terrain.
    #[arg(long)]
    pub vox: Option<PathBuf>,
    /// With --vox: show hidden nodes and hidden layers too.
    #[arg(long, requires = "vox")]
    pub hidden: bool,
    /// Start the camera (headless frame or window) at world position X,Y,Z (voxels, y up),
    /// turned YAW degrees about +y (0 looks along -z, 90 along -x) and PITCH degrees above the
    /// horizon (-90 to 90). Default: a view chosen for the scene.
    #[arg(long, value_name = "X,Y,Z,YAW,PITCH", value_parser = parse_camera, allow_hyphen_values = true)]
    pub camera: Option<CameraArg>,
    /// Vertical field of view in degrees (1 to 179). Default: the scene's view (70 for the
    /// terrain, 60 for .vox files).
    #[arg(long, value_name = "DEG", value_parser = parse_fov, allow_hyphen_values = true)]
    pub fov: Option<f64>,
    /// Render with the CPU reference raycaster even when a GPU is available.
    #[arg(long)]
    pub cpu: bool,
    /// Draw meshes as their quads' edges, to see how the mesher merged faces (the GPU
    /// renderer only; the window toggles it with F3).
    #[arg(long, conflicts_with = "cpu")]
    pub wireframe: bool,
    /// Fly a scripted path over the streamed terrain for this many seconds, headless, and
    /// print frame-time percentiles (CPU, GPU, frame) and nodes streamed per second.
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds, allow_hyphen_values = true, conflicts_with_all = ["window", "vox", "chunks", "cpu", "camera"])]
    pub flight: Option<f64>,
    /// Streamed terrain: place the glTF model FILE with its origin at world X,Y,Z (blocks),
    /// scaled by SCALE (default 1). Repeatable.
    #[arg(long = "prop", value_name = "FILE@X,Y,Z[,SCALE]", value_parser = parse_prop, allow_hyphen_values = true, conflicts_with_all = ["vox", "chunks", "cpu"])]
    pub props: Vec<PropFlag>,
    /// Streamed terrain: place COUNT instances of the glTF model FILE on the terrain surface
    /// within 256 blocks of the origin (a fixed seed: every run alike). Repeatable.
    #[arg(long = "scatter", value_name = "FILE:COUNT", value_parser = parse_scatter, conflicts_with_all = ["vox", "chunks", "cpu"])]
    pub scatters: Vec<ScatterFlag>,
    /// With --flight: also write the figures as JSON to this file.
    #[arg(long, value_name = "FILE", requires = "flight")]
    pub json: Option<PathBuf>,
    /// Streamed terrain: set the block at X,Y,Z to BLOCK (a name: air, grass, dirt, stone,
    /// sand, water, snow; or a palette index) before the first frame. Repeatable; applied
    /// after every --edit-sphere, in the order given.
    #[arg(long = "edit", value_name = "X,Y,Z,BLOCK", value_parser = parse_block_edit, allow_hyphen_values = true, conflicts_with_all = ["vox", "chunks"])]
    pub edits: Vec<Edit>,
    /// Streamed terrain: fill the ball of radius R around X,Y,Z with BLOCK before the first
    /// frame. Repeatable, in the order given.
    #[arg(long = "edit-sphere", value_name = "X,Y,Z,R,BLOCK", value_parser = parse_sphere_edit, allow_hyphen_values = true, conflicts_with_all = ["vox", "chunks"])]
    pub sphere_edits: Vec<Edit>,
    /// Streamed terrain: the world folder: its saved edits are loaded (a new world when the
    /// folder holds none), and the edits made are saved there (headless after the edit
    /// flags, the window on closing and every 30 s).
    #[arg(long, value_name = "DIR", conflicts_with_all = ["vox", "chunks"])]
    pub world: Option<PathBuf>,
    /// With --flight: carve this many spheres of air of radius 4 per second along the path
    /// and report the edit-to-screen latency.
    #[arg(long, value_name = "N", default_value_t = 0.0, value_parser = parse_edit_rate, requires = "flight")]
    pub edits_per_second: f64,
}

impl Args {
    /// Every edit of the flags in the order they apply: spheres, then single blocks.
    pub(crate) fn all_edits(&self) -> Vec<Edit> {
        self.sphere_edits
            .iter()
            .chain(&self.edits)
            .copied()
            .collect()
    }

    /// The frame size: the flags, else 960 x 540 (1920 x 1080 for a flight).
    pub(crate) fn size(&self) -> (u32, u32) {
        let (w, h) = if self.flight.is_some() {
            (1920, 1080)
        } else {
            (960, 540)
        };
        (self.width.unwrap_or(w), self.height.unwrap_or(h))
    }

    /// The streamed terrain's settings from the flags.
    pub(crate) fn stream_settings(&self) -> StreamSettings {
        StreamSettings {
            seed: self.seed,
            radius: self.radius,
            budget_px: self.budget,
            mesher: self.mesher,
            far: self.far,
            opaque: self.opaque,
            clutter: self.clutter,
            shadows: self.shadow_settings(),
            memory_bytes: self.memory << 20,
            ..self.node_settings()
        }
    }

    /// The shadows of `--shadows`: the default settings, or none.
    pub(crate) fn shadow_settings(&self) -> ShadowSettings {
        if self.shadows {
            ShadowSettings::default()
        } else {
            ShadowSettings::OFF
        }
    }

    /// The defaults with `--node-size` and `--far-px` applied.
    fn node_settings(&self) -> StreamSettings {
        let defaults = StreamSettings::default();
        StreamSettings {
            chunk: self.node_size.unwrap_or(defaults.chunk),
            far_cell_px: self.far_px.unwrap_or(defaults.far_cell_px),
            ..defaults
        }
    }
}

/// `count` comma-separated integers of `text`, for `what`.
fn integers(text: &str, count: usize, what: &str) -> Result<Vec<i64>, String> {
    let parts: Vec<&str> = text.split(',').collect();
    if parts.len() != count {
        return Err(format!("{text:?} is not {what}"));
    }
    parts
        .iter()
        .map(|p| {
            p.trim()
                .parse::<i64>()
                .map_err(|_| format!("{p:?} in {text:?} is not an integer ({what})"))
        })
        .collect()
}

/// A block coordinate in the i32 range.
fn coordinate(v: i64, text: &str) -> Result<i32, String> {
    i32::try_from(v).map_err(|_| format!("{v} in {text:?} is past the i32 block range"))
}

/// `X,Y,Z,BLOCK`: a single-block edit.
fn parse_block_edit(text: &str) -> Result<Edit, String> {
    let (coords, block) = text
        .rsplit_once(',')
        .ok_or_else(|| format!("{text:?} is not X,Y,Z,BLOCK"))?;
    let v = integers(coords, 3, "X,Y,Z,BLOCK")?;
    let pos = WorldPos::new(
        coordinate(v[0], text)?,
        coordinate(v[1], text)?,
        coordinate(v[2], text)?,
    );
    let id = viewer::edits::parse_block(block)?;
    Ok(Edit::Block { pos, id })
}

/// `X,Y,Z,R,BLOCK`: a sphere edit (its size is checked when it is applied).
fn parse_sphere_edit(text: &str) -> Result<Edit, String> {
    let (coords, block) = text
        .rsplit_once(',')
        .ok_or_else(|| format!("{text:?} is not X,Y,Z,R,BLOCK"))?;
    let v = integers(coords, 4, "X,Y,Z,R,BLOCK")?;
    let centre = WorldPos::new(
        coordinate(v[0], text)?,
        coordinate(v[1], text)?,
        coordinate(v[2], text)?,
    );
    let radius = u32::try_from(v[3])
        .map_err(|_| format!("the radius {} in {text:?} is not from 0 to 2^32 - 1", v[3]))?;
    let id = viewer::edits::parse_block(block)?;
    Ok(Edit::Sphere { centre, radius, id })
}

/// Edits per second: finite, from 0 to 100000.
fn parse_edit_rate(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(r) if r.is_finite() && (0.0..=100_000.0).contains(&r) => Ok(r),
        _ => Err(format!(
            "{text:?} is not a number of edits per second from 0 to 100000"
        )),
    }
}

/// `WIDTHxHEIGHT`, each 1 to 8192.
pub(crate) fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let parse = |part: &str| match part.trim().parse::<u32>() {
        Ok(v @ 1..=8192) => Ok(v),
        _ => Err(format!("{part:?} is not a size from 1 to 8192")),
    };
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("{text:?} is not WIDTHxHEIGHT"))?;
    Ok((parse(w)?, parse(h)?))
}

/// Blocks from 16 to [`MAX_RADIUS`].
fn parse_radius(text: &str) -> Result<u32, String> {
    match text.trim().parse::<u32>() {
        Ok(r) if (16..=MAX_RADIUS).contains(&r) => Ok(r),
        _ => Err(format!(
            "{text:?} is not a radius from 16 to {MAX_RADIUS} blocks"
        )),
    }
}

/// A finite budget from 0 to 1024 pixels.
fn parse_budget(text: &str) -> Result<f32, String> {
    match text.trim().parse::<f32>() {
        Ok(b) if (0.0..=1024.0).contains(&b) => Ok(b),
        _ => Err(format!(
            "{text:?} is not an error budget from 0 to 1024 pixels"
        )),
    }
}

/// 8 or 16 blocks.
fn parse_node_size(text: &str) -> Result<ChunkSize, String> {
    match text.trim() {
        "8" => Ok(ChunkSize::S8),
        "16" => Ok(ChunkSize::S16),
        _ => Err(format!("{text:?} is not a node size (8 or 16 blocks)")),
    }
}

/// A far threshold from 0.25 to 64 pixels.
fn parse_far_px(text: &str) -> Result<f32, String> {
    match text.trim().parse::<f32>() {
        Ok(px) if (0.25..=64.0).contains(&px) => Ok(px),
        _ => Err(format!(
            "{text:?} is not a far threshold from 0.25 to 64 pixels"
        )),
    }
}

/// `faces`, `greedy`, `smooth`, `shells` or `heightmap`.
fn parse_mesher(text: &str) -> Result<MesherMode, String> {
    MesherMode::ALL
        .into_iter()
        .find(|m| m.name() == text)
        .ok_or_else(|| {
            format!("{text:?} is not a mesher mode (faces, greedy, smooth, shells, heightmap)")
        })
}

/// One of [`FAR_CHOICES`].
fn parse_far(text: &str) -> Result<FarRequest, String> {
    FAR_CHOICES
        .iter()
        .find(|(name, _)| *name == text)
        .map(|&(_, far)| far)
        .ok_or_else(|| {
            let names: Vec<&str> = FAR_CHOICES.iter().map(|(n, _)| *n).collect();
            format!("{text:?} is not a far-draw path ({})", names.join(", "))
        })
}

/// `raster`, `compute` or `auto`.
fn parse_opaque(text: &str) -> Result<OpaquePath, String> {
    match text {
        "raster" => Ok(OpaquePath::Raster),
        "compute" => Ok(OpaquePath::Compute),
        "auto" => Ok(OpaquePath::Auto),
        _ => Err(format!(
            "{text:?} is not an opaque path (auto, raster, compute)"
        )),
    }
}

/// Seconds, more than 0 and at most an hour.
fn parse_on_off(text: &str) -> Result<bool, String> {
    match text {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err(format!("{text:?} is neither on nor off")),
    }
}

fn parse_seconds(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(s) if s > 0.0 && s <= 3600.0 => Ok(s),
        _ => Err(format!(
            "{text:?} is not a flight time from 0 to 3600 seconds"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn on_off_flags_take_their_value() {
        let args = Args::try_parse_from(["viewer", "--clutter", "off", "--shadows", "on"]).unwrap();
        assert!(!args.clutter && args.shadows);
        let args = Args::try_parse_from(["viewer"]).unwrap();
        assert!(
            args.clutter && !args.shadows,
            "defaults: grass on, shadows off"
        );
        assert!(Args::try_parse_from(["viewer", "--shadows", "maybe"]).is_err());
    }

    #[test]
    fn edits_parse_and_bad_ones_are_refused_by_name() {
        let stone = viewer::edits::parse_block("stone").unwrap();
        assert_eq!(
            parse_block_edit("1,-2,3,stone"),
            Ok(Edit::Block {
                pos: WorldPos::new(1, -2, 3),
                id: stone
            })
        );
        assert_eq!(
            parse_sphere_edit("0, 40, -7, 4, air"),
            Ok(Edit::Sphere {
                centre: WorldPos::new(0, 40, -7),
                radius: 4,
                id: voxel_core::BlockId::AIR
            })
        );
        for (bad, why) in [
            ("1,2,stone", "not X,Y,Z,BLOCK"),
            ("1,2,x,stone", "not an integer"),
            ("1,2,3,lava", "unknown block"),
            ("3000000000,0,0,air", "i32 block range"),
        ] {
            let e = parse_block_edit(bad).unwrap_err();
            assert!(e.contains(why), "{bad}: {e}");
        }
        let e = parse_sphere_edit("0,0,0,-1,air").unwrap_err();
        assert!(e.contains("radius"), "{e}");
        assert!(parse_edit_rate("1000").is_ok());
        assert!(parse_edit_rate("NaN").is_err());
        assert!(parse_edit_rate("-1").is_err());
    }

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
        for extra in [
            &["--seed", "3"][..],
            &["--chunks", "2"][..],
            &["--radius", "300"][..],
            &["--mesher", "smooth"][..],
        ] {
            let mut args = vec!["--vox", "model.vox"];
            args.extend_from_slice(extra);
            let err = parse(&args).expect_err("conflict");
            assert!(err.contains(extra[0]) && err.contains("--vox"), "{err}");
        }
        assert!(parse(&["--vox", "model.vox"]).is_ok());
        assert!(parse(&["--seed", "3", "--chunks", "2"]).is_ok());
        assert!(parse(&["--hidden"]).unwrap_err().contains("--vox"));
        assert!(parse(&["--chunks", "2", "--budget", "2"]).is_err());
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

    #[test]
    fn streaming_flags_parse_and_bad_values_are_named() {
        let a = parse(&[
            "--radius",
            "512",
            "--budget",
            "2.5",
            "--mesher",
            "faces",
            "--far",
            "sprite",
            "--memory",
            "64",
            "--opaque",
            "compute",
            "--node-size",
            "8",
            "--far-px",
            "1.5",
        ])
        .unwrap();
        let s = a.stream_settings();
        assert_eq!(s.opaque, OpaquePath::Compute);
        assert_eq!(
            parse(&[]).unwrap().stream_settings().opaque,
            OpaquePath::Auto
        );
        assert_eq!(
            (s.radius, s.budget_px, s.mesher),
            (512, 2.5, MesherMode::Faces)
        );
        assert_eq!(s.memory_bytes, 64 << 20);
        assert_eq!((s.chunk, s.far_cell_px), (ChunkSize::S8, 1.5));
        let defaults = parse(&[]).unwrap().stream_settings();
        assert_eq!(
            (defaults.chunk, defaults.far_cell_px),
            (
                StreamSettings::default().chunk,
                StreamSettings::default().far_cell_px
            )
        );
        assert_eq!(a.size(), (960, 540));
        for (bad, named) in [
            (&["--radius", "8"][..], "radius"),
            (&["--radius", "x"][..], "radius"),
            (&["--budget", "-1"][..], "error budget"),
            (&["--budget", "NaN"][..], "error budget"),
            (&["--mesher", "marching"][..], "mesher mode"),
            (&["--opaque", "fragment"][..], "opaque path"),
            (&["--far", "rays"][..], "far-draw path"),
            (&["--flight", "0"][..], "flight time"),
            (&["--clutter", "maybe"][..], "neither on nor off"),
            (&["--flight", "inf"][..], "flight time"),
            (&["--memory", "0"][..], "--memory"),
            (&["--node-size", "32"][..], "node size"),
            (&["--far-px", "0"][..], "far threshold"),
            (&["--far-px", "NaN"][..], "far threshold"),
        ] {
            let err = parse(bad).expect_err(bad[0]);
            assert!(err.contains(named), "{bad:?}: {err}");
        }
    }

    #[test]
    fn a_flight_is_headless_at_1080p_unless_told() {
        let a = parse(&["--flight", "2"]).unwrap();
        assert_eq!(a.size(), (1920, 1080));
        let a = parse(&["--flight", "2", "--width", "64", "--height", "36"]).unwrap();
        assert_eq!(a.size(), (64, 36));
        assert!(parse(&["--flight", "2", "--window"]).is_err());
        assert!(
            parse(&["--json", "x.json"])
                .unwrap_err()
                .contains("--flight")
        );
    }
}
