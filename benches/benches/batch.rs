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
//!
//! Before the criterion group, the thread counts are also timed interleaved (each round meshes
//! the region once per thread count, in turn; `BATCH_INTERLEAVED_ROUNDS` rounds, 40 by
//! default), and the speedups are printed from the minima and the medians: on a shared
//! machine, load that comes and goes then hits every thread count alike.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use mesher::{BlockClasses, ClutterParams, MeshSettings, SurfaceMode, mesh_chunks};
use voxel_core::{ChunkCoord, ChunkSize};
use voxel_scene::terrain_scene;

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

    let available = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut counts = vec![1, 2];
    if available > 2 {
        counts.push(available);
    }
    let pools: Vec<rayon::ThreadPool> = counts
        .iter()
        .map(|&threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("thread pool")
        })
        .collect();
    let mesh_on = |pool: &rayon::ThreadPool| {
        pool.install(|| black_box(mesh_chunks(&scene.world, &coords, &classes, &settings)))
    };

    let rounds = std::env::var("BATCH_INTERLEAVED_ROUNDS")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(40usize);
    let mut times = vec![Vec::with_capacity(rounds); pools.len()];
    for round in 0..=rounds {
        for (pool, times) in pools.iter().zip(&mut times) {
            let start = Instant::now();
            let meshed = mesh_on(pool);
            let elapsed = start.elapsed();
            drop(meshed);
            if round > 0 {
                times.push(elapsed);
            }
        }
    }
    let spreads: Vec<(f64, f64)> = times
        .into_iter()
        .map(|mut t| {
            t.sort();
            let ms = |d: Option<&Duration>| d.map_or(f64::NAN, |d| d.as_secs_f64() * 1e3);
            (ms(t.first()), ms(t.get(t.len() / 2)))
        })
        .collect();
    let (one_min, one_median) = spreads[0];
    for (&threads, &(min, median)) in counts.iter().zip(&spreads) {
        println!(
            "batch interleaved, {rounds} rounds: {threads} threads {min:.2} / {median:.2} ms \
             (min / median), speedup {:.2}x / {:.2}x",
            one_min / min,
            one_median / median
        );
    }

    let mut group = c.benchmark_group("batch/terrain_8x3x8_32");
    group.throughput(Throughput::Elements(coords.len() as u64));
    group.measurement_time(Duration::from_secs(6));
    group.sample_size(20);
    for (threads, pool) in counts.iter().zip(&pools) {
        group.bench_function(
            BenchmarkId::new("greedy+clutter", format!("{threads} threads")),
            |b| b.iter(|| mesh_on(pool)),
        );
    }
    group.finish();
}

criterion_group!(benches, batch);
criterion_main!(benches);
