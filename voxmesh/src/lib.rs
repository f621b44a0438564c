//! # voxmesh
//!
//! The command-line mesher: a MagicaVoxel `.vox` file (every model of its scene graph, with
//! transforms; hidden nodes and layers left out unless `--hidden`) or the built-in terrain
//! (`terrain:SEED:SIDE`) to a glTF binary (`.glb`, vertex colours from the palette,
//! MagicaVoxel materials as glTF PBR) or an OBJ file.
//!
//! ```text
//! cargo run --release --bin voxmesh -- INPUT -o OUT.glb [--mode faces|greedy|smooth]
//!     [--chunk 16|32|62] [--lod N] [--ao] [--threads N] [--scale S] [--hidden]
//!     [--stats FILE.json]
//! ```
//!
//! The stages, one module each: [`cli`] (arguments) -> [`input`] (load) -> [`mesh`] (surface
//! extraction per chunk, in parallel) -> [`geometry`] (triangles per material) -> [`glb`] or
//! [`obj`] (encoding) -> [`output`] (temporary files renamed into place only when everything
//! is written). [`pbr`] maps MagicaVoxel materials to glTF's, [`progress`] draws the bar,
//! [`run`] ties the stages together.

pub mod cli;
pub mod finite;
pub mod geometry;
pub mod glb;
pub mod input;
pub mod mesh;
pub mod obj;
pub mod output;
pub mod pbr;
pub mod progress;

use std::fmt;
use std::path::PathBuf;
use std::time::Instant;

use mesher::MeshError;
use voxel_scene::vox::VoxError;

use crate::cli::{Args, Output};
use crate::geometry::GeometryOptions;
use crate::output::Outputs;
use crate::progress::Progress;

/// Why a run failed. Nothing has been written when a run fails.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// The `.vox` file could not be read or is malformed.
    Vox {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        source: VoxError,
    },
    /// The input has no visible voxel.
    Empty {
        /// The input as given.
        input: String,
        /// What the loader left out (hidden nodes, ...).
        notes: Vec<String>,
    },
    /// The mesher refused the input.
    Mesh(MeshError),
    /// A saved world (`world:DIR`) that does not load.
    World {
        /// The world folder.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// The output does not fit its format.
    TooLarge(String),
    /// A number of the output is not finite (which one): glTF and OBJ cannot hold it.
    NotFinite(String),
    /// Two of the files named on the command line are the same file.
    SameFile(PathBuf),
    /// The worker threads could not be started.
    Threads(String),
    /// An output file could not be written.
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Vox { path, source } => write!(f, "{}: {source}", path.display()),
            Error::Empty { input, notes } => {
                write!(
                    f,
                    "{input}: nothing to mesh, the scene has no visible voxel"
                )?;
                for note in notes {
                    write!(f, "; {note}")?;
                }
                Ok(())
            }
            Error::Mesh(e) => write!(f, "meshing failed: {e}"),
            Error::World { path, message } => {
                write!(
                    f,
                    "cannot read the saved world {}: {message}",
                    path.display()
                )
            }
            Error::TooLarge(what) => f.write_str(what),
            Error::NotFinite(what) => write!(f, "cannot write a number that is not finite: {what}"),
            Error::SameFile(path) => write!(
                f,
                "{} is named twice (input, output and --stats must be different files)",
                path.display()
            ),
            Error::Threads(why) => write!(f, "cannot start the worker threads: {why}"),
            Error::Write { path, source } => {
                write!(f, "cannot write {}: {source}", path.display())
            }
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Vox { source, .. } => Some(source),
            Error::Mesh(e) => Some(e),
            Error::Write { source, .. } => Some(source),
            _ => None,
        }
    }
}

impl From<MeshError> for Error {
    fn from(e: MeshError) -> Self {
        Error::Mesh(e)
    }
}

/// What a run made; every field also goes to `--stats`.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// Occupied voxels of the input (at full detail).
    pub input_voxels: usize,
    /// Chunks meshed (at the chosen level of detail).
    pub chunks: usize,
    /// Of those, chunks with something to draw.
    pub chunks_with_geometry: usize,
    /// Quads extracted (blocky and smooth).
    pub quads: usize,
    /// Triangles written.
    pub triangles: usize,
    /// Vertices written.
    pub vertices: usize,
    /// Bytes written (the `.glb`, or the `.obj` and `.mtl`).
    pub output_bytes: u64,
    /// Seconds of surface extraction (downsampling for `--lod` included).
    pub meshing_seconds: f64,
    /// Seconds of the whole run.
    pub total_seconds: f64,
    /// What the user should be told about the input.
    pub notes: Vec<String>,
}

impl Summary {
    /// The `--stats` JSON document.
    pub fn to_json(&self, args: &Args) -> serde_json::Value {
        serde_json::json!({
            "input": args.input.to_string(),
            "output": args.output.path().display().to_string(),
            "mode": format!("{:?}", args.mode).to_lowercase(),
            "chunk": args.chunk,
            "lod": args.lod,
            "ao": args.ao,
            "scale": args.scale,
            "threads": rayon::current_num_threads(),
            "input_voxels": self.input_voxels,
            "chunks": self.chunks,
            "chunks_with_geometry": self.chunks_with_geometry,
            "quads": self.quads,
            "triangles": self.triangles,
            "vertices": self.vertices,
            "output_bytes": self.output_bytes,
            "meshing_seconds": self.meshing_seconds,
            "total_seconds": self.total_seconds,
        })
    }
}

/// Runs voxmesh for `args` on `--threads` worker threads, drawing progress on `progress`.
/// Writes the output (and `--stats`) only if every stage succeeds.
pub fn run(args: &Args, progress: &Progress) -> Result<Summary, Error> {
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        pool = pool.num_threads(n as usize);
    }
    let pool = pool.build().map_err(|e| Error::Threads(e.to_string()))?;
    pool.install(|| run_here(args, progress))
}

fn run_here(args: &Args, progress: &Progress) -> Result<Summary, Error> {
    run_within(args, progress, glb::MAX_GLB_BYTES)
}

/// [`run`]'s stages on the current pool, with `.glb` outputs limited to `glb_limit` bytes
/// (the format's limit; the tests use smaller ones).
fn run_within(args: &Args, progress: &Progress, glb_limit: u64) -> Result<Summary, Error> {
    let started = Instant::now();
    check_distinct(args)?;
    let size = args.chunk_size();
    let scene = input::load(&args.input, size, args.hidden)?;
    if scene.voxel_count == 0 {
        return Err(Error::Empty {
            input: args.input.to_string(),
            notes: scene.notes,
        });
    }

    let meshing = Instant::now();
    let classes = mesh::classes_for(&scene.palette, args.mode);
    let world = mesh::downsample(scene.world, &classes, args.lod)?;
    progress.stage("meshing", world.len() as u64);
    let chunks = mesh::mesh_world(&world, &classes, args.mode, args.ao, &|| progress.step())?;
    let meshing_seconds = meshing.elapsed().as_secs_f64();
    if let Output::Glb(_) = &args.output {
        glb::check_fits(&chunks, glb_limit)?;
    }

    progress.stage("triangles", chunks.len() as u64);
    let options = GeometryOptions {
        edge: size.edge(),
        cell: args.scale * f64::from(1u32 << args.lod),
        ambient_occlusion: args.ao,
    };
    let geometry = geometry::build(&chunks, &scene.materials, &options, &|| progress.step());
    finite::check(&geometry)?;

    progress.stage("writing", 1);
    let mut outputs = Outputs::new();
    let output_bytes = match &args.output {
        Output::Glb(path) => {
            let bytes = glb::to_glb(&geometry)?;
            if bytes.len() as u64 > glb_limit {
                return Err(Error::TooLarge(format!(
                    "the mesh needs {} bytes, more than the limit of {glb_limit}",
                    bytes.len()
                )));
            }
            outputs.write(path, &bytes)?
        }
        Output::Obj(path) => {
            let mtl_path = path.with_extension("mtl");
            let mtl_name = mtl_path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            let (obj, mtl) = obj::write_obj(&geometry, &mtl_name);
            outputs.write(&mtl_path, mtl.as_bytes())? + outputs.write(path, obj.as_bytes())?
        }
    };
    let summary = Summary {
        input_voxels: scene.voxel_count,
        chunks: world.len(),
        chunks_with_geometry: chunks.len(),
        quads: geometry.quads,
        triangles: geometry.triangle_count(),
        vertices: geometry.vertex_count(),
        output_bytes,
        meshing_seconds,
        total_seconds: started.elapsed().as_secs_f64(),
        notes: scene.notes,
    };
    if let Some(path) = &args.stats {
        let json =
            serde_json::to_string_pretty(&summary.to_json(args)).expect("a JSON value serialises");
        outputs.write(path, json.as_bytes())?;
    }
    outputs.commit()?;
    progress.step();
    progress.finish();
    Ok(summary)
}

/// Refuses command lines that name one file twice (e.g. `--stats` over the input).
fn check_distinct(args: &Args) -> Result<(), Error> {
    let mut paths: Vec<PathBuf> = vec![args.output.path().to_path_buf()];
    if let Output::Obj(p) = &args.output {
        paths.push(p.with_extension("mtl"));
    }
    if let cli::Input::Vox(p) = &args.input {
        paths.push(p.clone());
    }
    paths.extend(args.stats.clone());
    // Compare canonical paths where the file exists (a link or `./` names the same file).
    let canonical: Vec<PathBuf> = paths
        .iter()
        .map(|p| std::fs::canonicalize(p).unwrap_or_else(|_| p.clone()))
        .collect();
    for (i, a) in canonical.iter().enumerate() {
        if canonical[..i].contains(a) {
            return Err(Error::SameFile(paths[i].clone()));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    /// A `.glb` that cannot fit is refused on the meshed chunks, before the triangles are
    /// built: the run never reaches its "triangles" stage and writes nothing.
    ///
    /// The fault it catches: the size checked only on the finished `.glb` (as `to_glb` does),
    /// after the whole mesh is built. Planted (the early check removed), this test failed:
    /// the run built the triangles and only the finished file's size refused it ("the mesh
    /// needs 749896 bytes, more than the limit of 374948").
    #[test]
    fn a_glb_too_large_is_refused_before_the_triangles_are_built() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("t.glb");
        let args =
            Args::try_parse_from(["voxmesh", "terrain:3:48", "-o", out.to_str().unwrap()]).unwrap();
        // How much this run needs: its own .glb, written with no limit.
        let roomy = Progress::new(
            Instant::now(),
            std::time::Duration::MAX,
            Box::new(indicatif::ProgressDrawTarget::hidden),
        );
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let summary = pool
            .install(|| run_within(&args, &roomy, glb::MAX_GLB_BYTES))
            .unwrap();
        std::fs::remove_file(&out).unwrap();
        let progress = Progress::new(
            Instant::now(),
            std::time::Duration::MAX,
            Box::new(indicatif::ProgressDrawTarget::hidden),
        );
        let limit = summary.output_bytes / 2;
        let err = pool
            .install(|| run_within(&args, &progress, limit))
            .unwrap_err();
        assert!(
            matches!(&err, Error::TooLarge(why) if why.contains("at least")),
            "{err}"
        );
        assert_eq!(progress.stages(), ["meshing"], "{err}");
        assert!(!out.exists());
    }
}
