//! The command line: [`Args`] (parsed by clap) and the input and output names it accepts.

use std::path::PathBuf;

use clap::{Parser, ValueEnum};
use voxel_core::ChunkSize;

/// Largest side of the built-in terrain (`terrain:SEED:SIDE`), in block columns: 4096^2
/// columns are about 10^8 voxels, as much as a mesher run should hold in memory.
pub const MAX_TERRAIN_SIDE: u32 = 4096;

/// Meshes a MagicaVoxel .vox file, or the built-in procedural terrain, into a glTF binary
/// (.glb) or Wavefront OBJ file.
#[derive(Parser, Debug, Clone)]
#[command(name = "voxmesh", version, about)]
pub struct Args {
    /// A MagicaVoxel .vox file, world:DIR for a saved world, or terrain:SEED:SIDE for SIDE x SIDE columns of the built-in
    /// terrain.
    #[arg(value_parser = parse_input)]
    pub input: Input,
    /// Where to write the mesh: a .glb file, or .obj (with a .mtl beside it).
    #[arg(short, long, value_parser = parse_output)]
    pub output: Output,
    /// How surfaces are extracted.
    #[arg(long, value_enum, default_value_t = Mode::Greedy)]
    pub mode: Mode,
    /// Chunk edge in voxels (16, 32 or 62).
    #[arg(long, default_value_t = 32, value_parser = parse_chunk)]
    pub chunk: u32,
    /// Level of detail: mesh 2^N-voxel cells (0 = full detail).
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=6))]
    pub lod: u32,
    /// Bake ambient occlusion into the vertex colours.
    #[arg(long)]
    pub ao: bool,
    /// Worker threads (default: one per CPU).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Output units per voxel.
    #[arg(long, default_value_t = 1.0, value_parser = parse_scale)]
    pub scale: f64,
    /// Include hidden nodes and hidden layers of a .vox file.
    #[arg(long)]
    pub hidden: bool,
    /// Write figures of the run (voxels, chunks, quads, triangles, vertices, bytes, meshing
    /// time) to this JSON file.
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
}

impl Args {
    /// The chunk size `--chunk` names (checked when parsed).
    pub fn chunk_size(&self) -> ChunkSize {
        ChunkSize::from_edge(self.chunk).expect("--chunk is checked when parsed")
    }
}

/// What to mesh.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Input {
    /// A MagicaVoxel file.
    Vox(PathBuf),
    /// `terrain:SEED:SIDE`: the built-in terrain over `side x side` columns.
    Terrain {
        /// Generator seed.
        seed: i32,
        /// Columns per side.
        side: u32,
    },
    /// `world:DIR`: the chunks a world saved by `voxel-world` stores (its edited chunks, each
    /// with the base blocks it holds), with the built-in terrain's palette.
    World(PathBuf),
}

impl std::fmt::Display for Input {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Input::Vox(path) => write!(f, "{}", path.display()),
            Input::Terrain { seed, side } => write!(f, "terrain:{seed}:{side}"),
            Input::World(dir) => write!(f, "world:{}", dir.display()),
        }
    }
}

/// Where to write, and in which format.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Output {
    /// glTF binary.
    Glb(PathBuf),
    /// Wavefront OBJ, with its materials in a `.mtl` file of the same name.
    Obj(PathBuf),
}

impl Output {
    /// The output path.
    pub fn path(&self) -> &std::path::Path {
        match self {
            Output::Glb(p) | Output::Obj(p) => p,
        }
    }
}

/// Surface extraction modes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Mode {
    /// One quad per visible voxel face.
    Faces,
    /// Greedy quads: coplanar faces of one colour merged into rectangles.
    Greedy,
    /// NoCubes smoothing: opaque voxels as a smooth surface, see-through ones as greedy quads.
    Smooth,
}

/// `terrain:SEED:SIDE`, `world:DIR`, or else a path.
fn parse_input(text: &str) -> Result<Input, String> {
    if let Some(dir) = text.strip_prefix("world:") {
        if dir.is_empty() {
            return Err(format!("{text:?} names no folder: world:DIR"));
        }
        return Ok(Input::World(PathBuf::from(dir)));
    }
    let Some(rest) = text.strip_prefix("terrain:") else {
        return Ok(Input::Vox(PathBuf::from(text)));
    };
    let (seed, side) = rest
        .split_once(':')
        .ok_or_else(|| format!("{text:?} is not terrain:SEED:SIDE"))?;
    let seed = seed
        .parse::<i32>()
        .map_err(|_| format!("terrain seed {seed:?} is not a 32-bit integer"))?;
    let side = match side.parse::<u32>() {
        Ok(s @ 1..=MAX_TERRAIN_SIDE) => s,
        _ => {
            return Err(format!(
                "terrain side {side:?} is not a whole number from 1 to {MAX_TERRAIN_SIDE}"
            ));
        }
    };
    Ok(Input::Terrain { seed, side })
}

/// A path ending in `.glb` or `.obj` (any case).
fn parse_output(text: &str) -> Result<Output, String> {
    let path = PathBuf::from(text);
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match extension.as_deref() {
        Some("glb") => Ok(Output::Glb(path)),
        Some("obj") => Ok(Output::Obj(path)),
        _ => Err(format!("{text:?} must end in .glb or .obj")),
    }
}

fn parse_chunk(text: &str) -> Result<u32, String> {
    match text.parse::<u32>() {
        Ok(edge @ (16 | 32 | 62)) => Ok(edge),
        _ => Err(format!("{text:?} is not a chunk edge of 16, 32 or 62")),
    }
}

fn parse_scale(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(s) if s.is_finite() && s > 0.0 && s <= 1e6 => Ok(s),
        _ => Err(format!(
            "{text:?} is not a scale above 0 and at most 1000000"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(args: &[&str]) -> Result<Args, String> {
        Args::try_parse_from(std::iter::once("voxmesh").chain(args.iter().copied()))
            .map_err(|e| e.to_string())
    }

    #[test]
    fn every_option_parses() {
        let a = parse(&[
            "terrain:-3:100",
            "-o",
            "x.OBJ",
            "--mode",
            "smooth",
            "--chunk",
            "62",
            "--lod",
            "2",
            "--ao",
            "--threads",
            "3",
            "--scale",
            "0.25",
            "--hidden",
            "--stats",
            "s.json",
        ])
        .unwrap();
        assert_eq!(
            a.input,
            Input::Terrain {
                seed: -3,
                side: 100
            }
        );
        assert_eq!(a.output, Output::Obj("x.OBJ".into()));
        assert_eq!((a.mode, a.chunk, a.lod, a.ao), (Mode::Smooth, 62, 2, true));
        assert_eq!((a.threads, a.scale, a.hidden), (Some(3), 0.25, true));
        assert_eq!(a.stats, Some("s.json".into()));
        assert_eq!(a.chunk_size(), ChunkSize::S62);
        let d = parse(&["m.vox", "-o", "m.glb"]).unwrap();
        assert_eq!(d.input, Input::Vox("m.vox".into()));
        assert_eq!(
            (d.mode, d.chunk, d.lod, d.ao, d.scale),
            (Mode::Greedy, 32, 0, false, 1.0)
        );
    }

    #[test]
    fn bad_values_are_refused_with_the_value_named() {
        for (args, named) in [
            (&["m.vox", "-o", "m.gltf"][..], "must end in .glb or .obj"),
            (&["m.vox", "-o", "m"][..], "must end in .glb or .obj"),
            (
                &["m.vox", "-o", "m.glb", "--chunk", "8"][..],
                "16, 32 or 62",
            ),
            (
                &["m.vox", "-o", "m.glb", "--scale", "0"][..],
                "\"0\" is not a scale",
            ),
            (
                &["m.vox", "-o", "m.glb", "--scale", "nan"][..],
                "\"nan\" is not a scale",
            ),
            (&["m.vox", "-o", "m.glb", "--lod", "7"][..], "7"),
            (&["m.vox", "-o", "m.glb", "--threads", "0"][..], "0"),
            (&["m.vox", "-o", "m.glb", "--mode", "cubes"][..], "cubes"),
            (&["terrain:1", "-o", "m.glb"][..], "terrain:SEED:SIDE"),
            (&["terrain:x:5", "-o", "m.glb"][..], "seed \"x\""),
            (&["terrain:1:0", "-o", "m.glb"][..], "side \"0\""),
            (&["terrain:1:5000", "-o", "m.glb"][..], "side \"5000\""),
            (&["m.vox"][..], "--output"),
        ] {
            let err = parse(args).expect_err(&format!("{args:?} accepted"));
            assert!(err.contains(named), "{args:?}: {err}");
        }
    }
}
