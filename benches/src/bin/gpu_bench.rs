//! The GPU benchmark: the mesher's terrain made resident in growing amounts and drawn by the
//! deferred renderer, with GPU time per pass, resident bytes and CPU frame time per scene
//! (see `benches::gpu_bench`). Prints a Markdown table; `--out FILE` also writes it there.
//!
//! ```sh
//! cargo run --release -p benches --bin gpu_bench -- --side 4096 --chunk 8
//! ```

use std::process::ExitCode;
use std::time::Instant;

use benches::gpu_bench::{BenchConfig, markdown_table, run};
use benches::gpu_scene::MeshedTerrain;
use clap::Parser;
use gpu_backend::{DeviceOptions, GpuContext};
use voxel_core::ChunkSize;

/// Command-line options.
#[derive(Parser, Debug)]
#[command(about = "GPU benchmark: terrain from the mesher, drawn by the deferred renderer")]
struct Args {
    /// Block columns per side of the terrain square.
    #[arg(long, default_value_t = 4096)]
    side: u32,
    /// Chunk edge (8, 16, 32 or 62).
    #[arg(long, default_value_t = 8)]
    chunk: u32,
    /// Resident chunk counts to measure, ascending; "all" is the whole terrain.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "10000,50000,100000,200000,400000,all"
    )]
    scenes: Vec<String>,
    /// Output width, pixels.
    #[arg(long, default_value_t = 1920)]
    width: u32,
    /// Output height, pixels.
    #[arg(long, default_value_t = 1080)]
    height: u32,
    /// Timed frames per scene.
    #[arg(long, default_value_t = 20)]
    frames: usize,
    /// Terrain seed.
    #[arg(long, default_value_t = 1)]
    seed: i32,
    /// Also write the table (and the setup lines) to this file.
    #[arg(long)]
    out: Option<std::path::PathBuf>,
    /// Write the last scene's image to this PNG.
    #[arg(long)]
    png: Option<std::path::PathBuf>,
}

fn main() -> ExitCode {
    match bench(&Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("gpu_bench: {e}");
            ExitCode::FAILURE
        }
    }
}

fn bench(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
    let size = ChunkSize::from_edge(args.chunk)?;
    let ctx = GpuContext::new_headless(&DeviceOptions::default())?;
    eprintln!("adapter: {}", ctx.capabilities.adapter);
    let started = Instant::now();
    let terrain = MeshedTerrain::generate(args.side, size, args.seed)?;
    let total = terrain.meshes.len();
    let mut scene_chunks = Vec::new();
    for s in &args.scenes {
        let n = if s == "all" {
            total
        } else {
            s.parse::<usize>()
                .map_err(|e| format!("scene size {s:?}: {e}"))?
        };
        scene_chunks.push(n.min(total));
    }
    scene_chunks.dedup();
    let mut lines = vec![
        format!("adapter: {}", ctx.capabilities.adapter),
        format!(
            "terrain: {}² columns, {}³ chunks, {} chunks meshed, {} non-empty, {} quads; \
             generated in {:.2} s, meshed in {:.2} s ({} threads), {:.1} s in all",
            terrain.side,
            size.edge(),
            terrain.chunks_meshed,
            total,
            terrain.quad_count(total),
            terrain.generate_seconds,
            terrain.mesh_seconds,
            rayon::current_num_threads(),
            started.elapsed().as_secs_f64()
        ),
        format!(
            "frames: {} x {}, {} timed per scene; times are medians",
            args.width, args.height, args.frames
        ),
    ];
    for line in &lines {
        eprintln!("{line}");
    }
    let config = BenchConfig {
        scene_chunks,
        width: args.width,
        height: args.height,
        frames: args.frames,
    };
    let (reports, image) = run(&ctx, &terrain, &config)?;
    let table = markdown_table(&reports);
    println!("{table}");
    lines.push(String::new());
    lines.push(table);
    if let Some(path) = &args.out {
        std::fs::write(path, lines.join("\n"))?;
    }
    if let Some(path) = &args.png {
        std::fs::write(
            path,
            viewer::reference_raycast::encode_png(image.width, image.height, &image.rgba)?,
        )?;
        eprintln!("image: {}", path.display());
    }
    Ok(())
}
