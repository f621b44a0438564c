//! `voxmesh`: see the library docs (`voxmesh::run`) and `voxmesh --help`.

use std::process::ExitCode;
use std::time::Instant;

use clap::Parser;
use voxmesh::cli::Args;
use voxmesh::progress::Progress;

fn main() -> ExitCode {
    let started = Instant::now();
    let args = Args::parse();
    let progress = Progress::stderr(started);
    match voxmesh::run(&args, &progress) {
        Ok(summary) => {
            for note in &summary.notes {
                eprintln!("voxmesh: note: {note}");
            }
            println!(
                "voxmesh: wrote {} ({} triangles, {} vertices, {} bytes) from {} voxels in {:.2} s (meshing {:.3} s)",
                args.output.path().display(),
                summary.triangles,
                summary.vertices,
                summary.output_bytes,
                summary.input_voxels,
                summary.total_seconds,
                summary.meshing_seconds,
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            progress.finish();
            eprintln!("voxmesh: error: {e}");
            ExitCode::FAILURE
        }
    }
}
