//! `tradeoff_report`: regenerates `docs/tradeoff.md` and its plots from measurements made in
//! this run (see `benches::report`).
//!
//! ```sh
//! cargo run --release -p benches --bin tradeoff_report -- --out docs \
//!     --gpu-json docs/data/gpu_bench_h100_budgets.json \
//!     --features-json docs/data/gpu_bench_features.json \
//!     --geometry-json docs/data/gpu_bench_geometry.json \
//!     --geometry-json docs/data/gpu_bench_geometry_raster.json
//! ```

use std::path::PathBuf;
use std::process::ExitCode;

use benches::report::{Config, measure, write_report};
use clap::Parser;

/// Measures meshing speed, surface and format error, reads the GPU budget sweep and renders
/// at far offsets; writes OUT/tradeoff.md and OUT/tradeoff/*.svg.
#[derive(Parser, Debug)]
#[command(version, about)]
struct Args {
    /// Folder to write `tradeoff.md` and `tradeoff/*.svg` into.
    #[arg(long, default_value = "docs")]
    out: PathBuf,
    /// A `gpu_bench --json` file with the budget sweep (the image section says so when absent).
    #[arg(long)]
    gpu_json: Option<PathBuf>,
    /// A `gpu_bench --features --json` file with the image features' table (the section says
    /// so when absent).
    #[arg(long)]
    features_json: Option<PathBuf>,
    /// `gpu_bench --geometry --json` files (repeatable: one per opaque path) with the node
    /// geometry tables (the section says so when absent).
    #[arg(long)]
    geometry_json: Vec<PathBuf>,
    /// Folder of the `.vox` sample models.
    #[arg(long, default_value = "../shared/data/vox")]
    vox_dir: PathBuf,
    /// Timed runs per input, mode and chunk size (the median is reported).
    #[arg(long, default_value_t = 7)]
    runs: usize,
    /// Side of the procedural terrain, in block columns.
    #[arg(long, default_value_t = 256)]
    terrain_side: u32,
    /// Side in columns of the small terrain whose budget sweep is measured on this machine's
    /// Vulkan adapter (lavapipe without a GPU); 0 skips it.
    #[arg(long, default_value_t = 256)]
    local_gpu_side: u32,
    /// Words describing the machine the CPU figures come from (defaults to its thread count).
    #[arg(long)]
    machine: Option<String>,
}

fn main() -> ExitCode {
    let args = Args::parse();
    let mut config = match Config::full(&args.vox_dir) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("tradeoff_report: {}: {e}", args.vox_dir.display());
            return ExitCode::FAILURE;
        }
    };
    config.gpu_json = args.gpu_json;
    config.features_json = args.features_json;
    config.geometry_json = args.geometry_json;
    config.runs = args.runs.max(1);
    config.terrain_side = args.terrain_side;
    config.local_gpu_side = args.local_gpu_side;
    if let Some(m) = args.machine {
        config.machine = m;
    }
    let result = measure(&config, &|step| eprintln!("tradeoff_report: {step}"))
        .and_then(|m| write_report(&m, &args.out));
    match result {
        Ok(_) => {
            println!("{}", args.out.join("tradeoff.md").display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("tradeoff_report: {e}");
            ExitCode::FAILURE
        }
    }
}
