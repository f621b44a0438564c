//! The speed-against-accuracy report (`docs/tradeoff.md`), measured afresh on every run.
//!
//! `cargo run --release -p benches --bin tradeoff_report -- --out docs` runs every measurement
//! below and writes `docs/tradeoff.md` and its plots (`docs/tradeoff/*.svg`). One job per file:
//!
//! | module | job |
//! | --- | --- |
//! | [`cpu`] | CPU meshing time per chunk (median of N runs), quads, triangles and bytes for every mesher mode and chunk size on the `.vox` samples and the procedural terrain |
//! | [`geometry`] | distance from SurfaceNets meshes to analytic sphere and torus surfaces against grid resolution; the extra error of unorm16 positions and 8+8 / 16+16 octahedral normals |
//! | [`image`] | the budget sweep (image error, GPU time, bytes) read from a `gpu_bench --json` file |
//! | [`node_geometry`] | greedy quads against vertical shells on the same terrain (bytes, instances, GPU time, image difference), read from `gpu_bench --geometry --json` files |
//! | [`features`] | each image feature's GPU cost against its effect on the picture, read from a `gpu_bench --features --json` file |
//! | [`lavapipe`] | the same sweep measured in this run on the machine's own Vulkan adapter (lavapipe on a CPU-only machine) over a small terrain, marked with the adapter |
//! | [`extremes`] | the same view rendered by the CPU reference raycaster at the origin and at 2^30 offsets, pixel difference |
//! | [`recommend`] | the defaults the report recommends, chosen from the figures by stated rules |
//! | [`plot`] | the SVG plots (`plotters`, SVG backend only) |
//! | [`markdown`] | the markdown page |
//!
//! [`measure`] runs every measurement of a [`Config`]; [`write_report`] writes the page and
//! its plots. The smoke test (`benches/tests/tradeoff_report.rs`) runs both on tiny inputs.

pub mod cpu;
pub mod extremes;
pub mod features;
pub mod geometry;
pub mod image;
pub mod lavapipe;
pub mod markdown;
pub mod node_geometry;
pub mod plot;
pub mod recommend;

use std::path::{Path, PathBuf};

use voxel_core::ChunkSize;

/// What to measure, and how much.
#[derive(Clone, Debug)]
pub struct Config {
    /// `.vox` models to mesh (each at every chunk size).
    pub vox_files: Vec<PathBuf>,
    /// Side, in block columns, of the procedural terrain (0 leaves the terrain out).
    pub terrain_side: u32,
    /// Seed of the procedural terrain.
    pub terrain_seed: i32,
    /// Chunk sizes to mesh at.
    pub chunk_sizes: Vec<ChunkSize>,
    /// Timed runs per (input, mode, size); the median is reported.
    pub runs: usize,
    /// Sphere radii (and torus minor radii), in voxels, for the geometry section.
    pub radii: Vec<f32>,
    /// Random unit normals for the octahedral encoding error.
    pub normal_samples: usize,
    /// The `gpu_bench --json` file with the budget sweep, if any.
    pub gpu_json: Option<PathBuf>,
    /// The `gpu_bench --features --json` file with the image features' table, if any.
    pub features_json: Option<PathBuf>,
    /// `gpu_bench --geometry --json` files (one per opaque path), if any.
    pub geometry_json: Vec<PathBuf>,
    /// Side in columns of the terrain the local-adapter sweep draws (0: no local sweep).
    pub local_gpu_side: u32,
    /// Width and height of the local-adapter sweep's frames, pixels.
    pub local_gpu_size: (u32, u32),
    /// Width and height of the extremes view, in pixels.
    pub view_size: (u32, u32),
    /// One line describing the machine the CPU figures come from.
    pub machine: String,
}

impl Config {
    /// The full report's settings: every sample model in `vox_dir`, a 256 x 256-column terrain,
    /// chunk sizes 16, 32 and 62, 7 runs.
    pub fn full(vox_dir: &Path) -> std::io::Result<Config> {
        let mut vox_files: Vec<PathBuf> = std::fs::read_dir(vox_dir)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("vox")))
            .collect();
        vox_files.sort();
        Ok(Config {
            vox_files,
            terrain_side: 256,
            terrain_seed: 7,
            chunk_sizes: vec![ChunkSize::S16, ChunkSize::S32, ChunkSize::S62],
            runs: 7,
            radii: vec![2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0],
            normal_samples: 200_000,
            gpu_json: None,
            features_json: None,
            geometry_json: Vec::new(),
            local_gpu_side: 256,
            local_gpu_size: (320, 180),
            view_size: (192, 128),
            machine: default_machine(),
        })
    }

    /// Tiny settings for the smoke test: a 32 x 32-column terrain, 16^3 chunks, one run.
    pub fn tiny() -> Config {
        Config {
            vox_files: Vec::new(),
            terrain_side: 32,
            terrain_seed: 7,
            chunk_sizes: vec![ChunkSize::S16],
            runs: 1,
            radii: vec![3.0, 5.0],
            normal_samples: 2_000,
            gpu_json: None,
            features_json: None,
            geometry_json: Vec::new(),
            local_gpu_side: 0,
            local_gpu_size: (64, 36),
            view_size: (32, 24),
            machine: default_machine(),
        }
    }
}

/// The machine line when none is given: the number of hardware threads.
pub fn default_machine() -> String {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    format!("{threads} hardware threads; meshing timed on one thread")
}

/// Every figure of one run.
#[derive(Clone, Debug)]
pub struct Measurements {
    /// The settings they were made with.
    pub config: Config,
    /// CPU meshing figures.
    pub cpu: Vec<cpu::CpuRow>,
    /// SurfaceNets distance to the analytic surface.
    pub geometry: Vec<geometry::SurfaceRow>,
    /// Quantization error of positions and normals.
    pub quantization: geometry::Quantization,
    /// The budget sweep, when a GPU file was given.
    pub image: Option<image::BudgetSweep>,
    /// The node geometry tables, with the files they were read from.
    pub node_geometry: Vec<(PathBuf, crate::gpu_bench::geometry::GeometryReport)>,
    /// The image features' table, when its GPU file was given.
    pub features: Option<crate::gpu_bench::features::FeatureReport>,
    /// The sweep measured in this run on the local adapter: `None` when not asked for,
    /// `Some(None)` when the machine has no Vulkan adapter.
    pub local_image: Option<Option<image::BudgetSweep>>,
    /// Origin against far-offset renders.
    pub extremes: Vec<extremes::ExtremeRow>,
}

/// An error of the report: a file that could not be read or written, or bad input.
#[derive(Debug)]
pub struct ReportError(pub String);

impl std::fmt::Display for ReportError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ReportError {}

/// Runs every measurement of `config` (`progress` is told each step's name).
pub fn measure(config: &Config, progress: &dyn Fn(&str)) -> Result<Measurements, ReportError> {
    progress("CPU meshing");
    let cpu = cpu::measure(config, progress)?;
    progress("geometry");
    let geometry = geometry::surface_error(&config.radii)?;
    let quantization = geometry::quantization(&config.radii, config.normal_samples)?;
    progress("image");
    let image = match &config.gpu_json {
        Some(path) => Some(image::load(path)?),
        None => None,
    };
    let node_geometry = config
        .geometry_json
        .iter()
        .map(|p| node_geometry::load(p).map(|r| (p.clone(), r)))
        .collect::<Result<Vec<_>, _>>()?;
    let features = match &config.features_json {
        Some(path) => Some(features::load(path)?),
        None => None,
    };
    let local_image = if config.local_gpu_side > 0 {
        progress("local GPU budget sweep");
        Some(lavapipe::measure(
            config.local_gpu_side,
            config.local_gpu_size,
            config.runs.min(5),
        )?)
    } else {
        None
    };
    progress("extremes");
    let extremes = extremes::measure(config.terrain_seed, config.view_size);
    Ok(Measurements {
        config: config.clone(),
        cpu,
        geometry,
        quantization,
        image,
        node_geometry,
        features,
        local_image,
        extremes,
    })
}

/// Writes `out/tradeoff.md` and its plots under `out/tradeoff/`; returns the markdown.
pub fn write_report(m: &Measurements, out: &Path) -> Result<String, ReportError> {
    let io = |what: &Path, e: std::io::Error| ReportError(format!("{}: {e}", what.display()));
    let plots_dir = out.join(plot::PLOT_DIR);
    std::fs::create_dir_all(&plots_dir).map_err(|e| io(&plots_dir, e))?;
    let plots = plot::draw_all(m, &plots_dir)?;
    let text = markdown::render(m, &plots);
    let page = out.join("tradeoff.md");
    std::fs::write(&page, &text).map_err(|e| io(&page, e))?;
    Ok(text)
}
