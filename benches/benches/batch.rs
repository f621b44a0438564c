//! Batch meshing of a terrain region on 1, 2 and all available threads (rayon), wall-clock time.
//!
//! ```sh
//! cargo bench -p benches --bench batch
//! ```
//!
//! The input is the viewer's terrain (seed 7) over 8 x 2 x 8 chunks of 32^3, plus the empty
//! chunk layer above it, meshed with greedy quads, AO and clutter. Unlike the per-chunk benches
//! this one measures wall-clock time: the point is how much faster the region is done with
//! more threads, which a per-thread CPU clock cannot see.

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use mesher::{BlockClasses, ClutterParams, MeshSettings, SurfaceMode, mesh_chunks};
use viewer::scene::terrain_scene;
use voxel_core::{ChunkCoord, ChunkSize};

fn batch(c: &mut Criterion) {
    let scene = terrain_scene(7, ChunkSize::S32, 8, 2, 8);
    let classes = BlockClasses::from_palette(&scene.palette);
    let coords: Vec<ChunkCoord> = (-4..4)
        .flat_map(|z| (0..3).flat_map(move |y| (-4..4).map(move |x| ChunkCoord::new(x, y, z))))
        .collect();
    let settings = MeshSettings {
        surface: SurfaceMode::Greedy,
        clutter: Some(ClutterParams::new(1.0, 7).expect("1.0 is a valid density")),
    };
    let meshes = mesh_chunks(&scene.world, &coords, &classes, &settings).expect("terrain meshes");
    let quads: usize = meshes.iter().map(|m| m.blocky.len()).sum();
    let bytes: usize = meshes.iter().map(|m| m.byte_len()).sum();
    eprintln!(
        "batch input: {} chunks of 32^3 ({} stored), {quads} quads, {bytes} bytes of packed layers",
        coords.len(),
        scene.world.len()
    );

    let mut group = c.benchmark_group("batch/terrain_8x3x8_32");
    group.throughput(Throughput::Elements(coords.len() as u64));
    group.measurement_time(Duration::from_secs(6));
    group.sample_size(20);
    let available = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut counts = vec![1, 2];
    if available > 2 {
        counts.push(available);
    }
    for threads in counts {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool");
        group.bench_function(
            BenchmarkId::new("greedy+clutter", format!("{threads} threads")),
            |b| {
                b.iter(|| {
                    pool.install(|| {
                        black_box(mesh_chunks(&scene.world, &coords, &classes, &settings))
                    })
                });
            },
        );
    }
    group.finish();
}

criterion_group!(benches, batch);
criterion_main!(benches);
