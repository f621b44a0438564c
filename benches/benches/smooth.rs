//! Smooth meshers against `fast-surface-nets` 0.2, same inputs, same run, one thread.
//!
//! One criterion group per input (`surface_nets/<input>`) with `ours_f32`, `ours_i8`,
//! `fsn_f32` and `fsn_i8` (the peer with the `Sd8` sample type of its own benchmark, fed the
//! same `i8` values as ours). Ours writes the packed `SmoothMesh` (16-byte `BlockVertex`es and
//! 6-byte compact quads on these inputs, or `u16` / `u32` quads where a mesh needs them; the
//! report line names the form); the peer writes `f32` positions and normals and `u32` triangle
//! indices. Both
//! reuse their output buffers, as in the peer's benchmark. The counts and bytes per quad of
//! every input are printed before the timings, with an interleaved timing of the 4 variants
//! (min and median of 200 rounds), which a shared, noisy machine disturbs far less than the
//! sequential criterion measurements. `nocubes/terrain62` times NoCubes on the 62^3
//! terrain chunk (no peer): the smooth surface and the cube faces' greedy quads; its report
//! line gives the bytes per smooth quad and per quad of both. Criterion times are the benchmarking thread's CPU time
//! ([`benches::cpu_time`]) unless `BENCH_CLOCK=wall`; the interleaved timing always uses the
//! thread CPU time.
//!
//! `cargo bench -p benches --bench smooth`

use std::hint::black_box;
use std::time::Duration;

use benches::cpu_time::{Clock, ThreadCpuTime, clock_from_env};
use benches::smooth_inputs::{
    DensityGrid, nocubes_chunk, nocubes_palette, sine_34, sphere_34, terrain_62, to_i8,
};
use criterion::Criterion;
use criterion::measurement::Measurement;
use fast_surface_nets::ndshape::ConstShape3u32;
use fast_surface_nets::{SignedDistance, SurfaceNetsBuffer, surface_nets};
use mesher::BlockClasses;
use mesher::blocky::BlockyMesh;
use mesher::smooth::{GridShape, NoCubes, SmoothMesh, SmoothQuads, SurfaceNets};
use voxel_core::BlockId;

/// The peer's own `i8` sample type (its `bench/src/bench.rs`): `q / 127`.
#[derive(Clone, Copy)]
struct Sd8(i8);

impl From<Sd8> for f32 {
    fn from(d: Sd8) -> f32 {
        f32::from(d.0) * (1.0 / 127.0)
    }
}

impl SignedDistance for Sd8 {
    fn is_negative(self) -> bool {
        self.0 < 0
    }
}

/// The form of a mesh's quads and its bytes per quad, for the report lines.
fn quad_form(mesh: &SmoothMesh) -> String {
    let quads = mesh.quads();
    let form = match quads {
        SmoothQuads::Compact(_) => "compact",
        SmoothQuads::U16(_) => "u16",
        SmoothQuads::U32(_) => "u32",
    };
    format!("{form} quads, {} B each", quads.quad_bytes())
}

fn bench_input<M: Measurement, const D: u32>(c: &mut Criterion<M>, name: &str, grid: &DensityGrid) {
    assert_eq!(grid.dims, [D; 3]);
    type Shape<const D: u32> = ConstShape3u32<D, D, D>;
    let shape = GridShape::new(grid.dims).expect("a valid grid");
    let f = &grid.samples;
    let q = to_i8(f);
    let sd8: Vec<Sd8> = q.iter().map(|&v| Sd8(v)).collect();
    let max = [D - 1; 3];

    let mut mesher = SurfaceNets::new();
    let mut ours = SmoothMesh::new();
    let mut peer = SurfaceNetsBuffer::default();
    mesher
        .mesh_f32(f, shape, BlockId(1), &mut ours)
        .expect("finite");
    surface_nets(f, &Shape::<D> {}, [0; 3], max, &mut peer);
    println!(
        "{name}: {D}^3 samples; ours f32 {} vertices, {} quads ({}), {} B, {:.2} B/quad; \
         fast-surface-nets {} vertices, {} triangles ({} quads)",
        ours.vertices().len(),
        ours.quad_count(),
        quad_form(&ours),
        ours.byte_len(),
        ours.bytes_per_quad(),
        peer.positions.len(),
        peer.indices.len() / 3,
        peer.indices.len() / 6,
    );
    mesher
        .mesh_i8(&q, shape, BlockId(1), &mut ours)
        .expect("finite");
    surface_nets(&sd8, &Shape::<D> {}, [0; 3], max, &mut peer);
    println!(
        "{name}: i8: ours {} vertices, {} quads ({}), {:.2} B/quad; \
         fast-surface-nets {} vertices, {} quads",
        ours.vertices().len(),
        ours.quad_count(),
        quad_form(&ours),
        ours.bytes_per_quad(),
        peer.positions.len(),
        peer.indices.len() / 6,
    );

    // Interleaved timing (thread CPU time): the 4 variants in turn, 5 calls each, 200 rounds.
    // On a shared machine, load that comes and goes hits all 4 alike here, while criterion
    // below times them one after the other; the minimum is the least disturbed round.
    let clock = ThreadCpuTime::default();
    let mut times: [Vec<f64>; 4] = Default::default();
    for _ in 0..200 {
        for (v, t) in times.iter_mut().enumerate() {
            let start = clock.start();
            for _ in 0..5 {
                match v {
                    0 => mesher
                        .mesh_f32(f, shape, BlockId(1), &mut ours)
                        .expect("finite"),
                    1 => mesher
                        .mesh_i8(&q, shape, BlockId(1), &mut ours)
                        .expect("finite"),
                    2 => surface_nets(f, &Shape::<D> {}, [0; 3], max, &mut peer),
                    _ => surface_nets(&sd8, &Shape::<D> {}, [0; 3], max, &mut peer),
                }
            }
            t.push(clock.end(start).as_secs_f64() * 1e6 / 5.0);
        }
    }
    let [of, oi, pf, pi] = times.map(|mut t| {
        t.sort_by(f64::total_cmp);
        (t[0], t[t.len() / 2])
    });
    println!(
        "{name}: interleaved (min / median us): ours_f32 {:.1} / {:.1}, ours_i8 {:.1} / {:.1}, \
         fsn_f32 {:.1} / {:.1}, fsn_i8 {:.1} / {:.1}; fsn_f32 / ours_f32 {:.2}x / {:.2}x, \
         fsn_i8 / ours_i8 {:.2}x / {:.2}x",
        of.0,
        of.1,
        oi.0,
        oi.1,
        pf.0,
        pf.1,
        pi.0,
        pi.1,
        pf.0 / of.0,
        pf.1 / of.1,
        pi.0 / oi.0,
        pi.1 / oi.1,
    );

    let mut group = c.benchmark_group(format!("surface_nets/{name}"));
    group.bench_function("ours_f32", |b| {
        b.iter(|| {
            mesher
                .mesh_f32(black_box(f), shape, BlockId(1), &mut ours)
                .expect("finite");
            black_box(ours.quad_count())
        })
    });
    group.bench_function("ours_i8", |b| {
        b.iter(|| {
            mesher
                .mesh_i8(black_box(&q), shape, BlockId(1), &mut ours)
                .expect("finite");
            black_box(ours.quad_count())
        })
    });
    group.bench_function("fsn_f32", |b| {
        b.iter(|| {
            surface_nets(black_box(f), &Shape::<D> {}, [0; 3], max, &mut peer);
            black_box(peer.indices.len())
        })
    });
    group.bench_function("fsn_i8", |b| {
        b.iter(|| {
            surface_nets(black_box(&sd8), &Shape::<D> {}, [0; 3], max, &mut peer);
            black_box(peer.indices.len())
        })
    });
    group.finish();
}

fn surface_nets_benches<M: Measurement>(c: &mut Criterion<M>) {
    bench_input::<M, 34>(c, "sphere34", &sphere_34());
    bench_input::<M, 34>(c, "sine34", &sine_34());
    bench_input::<M, 64>(c, "terrain62", &terrain_62());
    let empty = DensityGrid {
        dims: [34; 3],
        samples: vec![1.0; 34 * 34 * 34],
    };
    bench_input::<M, 34>(c, "empty34", &empty);
}

fn nocubes_benches<M: Measurement>(c: &mut Criterion<M>) {
    let chunk = nocubes_chunk();
    let classes = BlockClasses::from_palette(&nocubes_palette());
    let mut mesher = NoCubes::new();
    let (mut smooth, mut cubes) = (SmoothMesh::new(), BlockyMesh::new());
    let stats = mesher
        .mesh(&chunk, &classes, &mut smooth, &mut cubes)
        .expect("known ids");
    let cube_bytes = 8 * cubes.opaque.len();
    println!(
        "nocubes terrain62: {stats:?}; smooth: {} vertices, {} quads ({}), {:.2} B/smooth quad; \
         cubes: {} greedy quads, {cube_bytes} B; all: {:.2} B/quad",
        smooth.vertices().len(),
        smooth.quad_count(),
        quad_form(&smooth),
        smooth.bytes_per_quad(),
        cubes.opaque.len(),
        (smooth.byte_len() + cube_bytes) as f64 / (smooth.quad_count() + cubes.opaque.len()) as f64,
    );
    let mut group = c.benchmark_group("nocubes/terrain62");
    group.bench_function("ours", |b| {
        b.iter(|| {
            mesher
                .mesh(black_box(&chunk), &classes, &mut smooth, &mut cubes)
                .expect("known ids");
            black_box(smooth.quad_count() + cubes.opaque.len())
        })
    });
    group.finish();
}

/// Criterion's defaults shortened (0.5 s warm-up, 3 s of 50 samples per bench); the
/// command-line options override these.
fn config<M: Measurement>(c: Criterion<M>) -> Criterion<M> {
    c.warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3))
        .sample_size(50)
        .configure_from_args()
}

fn main() {
    match clock_from_env() {
        Clock::ThreadCpu => {
            let mut c = config(Criterion::default().with_measurement(ThreadCpuTime::default()));
            surface_nets_benches(&mut c);
            nocubes_benches(&mut c);
            c.final_summary();
        }
        Clock::Wall => {
            let mut c = config(Criterion::default());
            surface_nets_benches(&mut c);
            nocubes_benches(&mut c);
            c.final_summary();
        }
    }
}
