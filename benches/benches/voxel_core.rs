//! Criterion benchmarks of `voxel-core`: chunk storage, neighbourhood gathers, the chunk codec
//! and the packed GPU formats. One group per stage; each benchmark's parameter names its input
//! and output sizes, and each group reports throughput in the unit that stage works in
//! (operations, voxels, padded voxels, rows or fields).
//!
//! ```sh
//! cargo bench -p benches --bench voxel_core                     # everything, about 7 minutes
//! cargo bench -p benches --bench voxel_core -- storage/gather    # one group
//! BENCH_CLOCK=wall cargo bench -p benches --bench voxel_core     # wall-clock time instead
//! ```
//!
//! Times are the benchmarking thread's CPU time ([`benches::cpu_time`]) unless
//! `BENCH_CLOCK=wall`: on the shared 2-core development machine, wall-clock medians move by up
//! to 2x with the load of other processes, CPU-time medians by a few percent.
//!
//! Inputs come from [`benches::inputs`] and are built before any timing starts. There is no
//! peer crate for this stage yet (the peer comparisons belong to the mesher benches).

use std::hint::black_box;
use std::time::Duration;

use benches::cpu_time::{Clock, ThreadCpuTime, clock_from_env};
use benches::inputs::chunks::{
    TERRAIN_CENTRE, describe, distinct_positions, random_chunk, random_ids_from, random_positions,
    stone, terrain_centre, terrain_world_dense, terrain_world_palette, uniform_chunk,
};
use benches::inputs::formats::{
    FORMAT_BATCH, VERTEX_EXTENT, block_vertices, chunk_draw_indirects, chunk_draw_infos,
    clutter_units, draw_blocks, meshed_chunk_infos, packed_quads, unit_normals,
};
use criterion::measurement::Measurement;
use criterion::{BatchSize, BenchmarkGroup, BenchmarkId, Criterion, Throughput};
use voxel_core::formats::{
    BlockVertex, ChunkDrawIndirect, ChunkDrawInfo, ClutterUnit, DrawBlock, MeshedChunkInfo,
    PackedQuad, oct16_decode, oct16_encode, oct32_decode, oct32_encode,
};
use voxel_core::storage::{
    DenseChunk, PaddedChunk, PaletteChunk, VoxelStorage, WorldMap, decode_chunk, encode_chunk,
    gather_neighbourhood,
};
use voxel_core::{BlockId, ChunkSize, LocalPos};

/// The two chunk sizes every storage bench runs at.
const SIZES: [ChunkSize; 2] = [ChunkSize::S32, ChunkSize::S62];
/// Operations per iteration of the per-op storage benches.
const OPS: usize = 4096;
/// Chunks with 16 random ids: the densest 4-bit palette, with no runs.
const RANDOM_IDS: u16 = 16;

/// `"32^3"`.
fn cube(size: ChunkSize) -> String {
    format!("{e}^3", e = size.edge())
}

/// Sum of the ids read at `positions`, so no read can be skipped.
fn get_all<S: VoxelStorage>(chunk: &S, positions: &[LocalPos]) -> u32 {
    positions.iter().fold(0, |acc, &p| {
        acc.wrapping_add(chunk.get(p).map_or(0, |id| u32::from(id.0)))
    })
}

/// Writes `ids[i]` at `positions[i]`; returns the sum of the replaced ids.
fn set_all<S: VoxelStorage>(chunk: &mut S, positions: &[LocalPos], ids: &[BlockId]) -> u32 {
    positions.iter().zip(ids).fold(0, |acc, (&p, &id)| {
        acc.wrapping_add(chunk.set(p, id).map_or(0, |old| u32::from(old.0)))
    })
}

/// `storage/get_set`: random single-voxel reads and writes on the terrain chunk, per op.
/// Writes use ids of the chunk's own palette, so the palette chunk never changes width.
fn get_set<M: Measurement>(c: &mut Criterion<M>) {
    let mut group = c.benchmark_group("storage/get_set");
    group.throughput(Throughput::Elements(OPS as u64));
    for size in SIZES {
        let dense = terrain_centre(size);
        let palette = PaletteChunk::from_dense(&dense);
        eprintln!("{}", describe("terrain", &dense));
        let positions = random_positions(size, OPS, 11);
        let ids = random_ids_from(palette.palette(), OPS, 12);
        let label = format!("terrain {}, {OPS} random ops", cube(size));

        group.bench_function(BenchmarkId::new("get/dense", &label), |b| {
            b.iter(|| get_all(black_box(&dense), &positions))
        });
        group.bench_function(BenchmarkId::new("get/palette", &label), |b| {
            b.iter(|| get_all(black_box(&palette), &positions))
        });
        let mut chunk = dense.clone();
        group.bench_function(BenchmarkId::new("set/dense", &label), |b| {
            b.iter(|| set_all(black_box(&mut chunk), &positions, &ids))
        });
        let mut chunk = palette.clone();
        group.bench_function(BenchmarkId::new("set/palette", &label), |b| {
            b.iter(|| set_all(black_box(&mut chunk), &positions, &ids))
        });
    }
    group.finish();
}

/// Runs `routine` on a fresh clone of `input` per iteration, timing only the routine (the
/// clone and the drop are outside the timing; 64 inputs per timed batch).
fn on_clones<M: Measurement, T: Clone, O>(
    group: &mut BenchmarkGroup<'_, M>,
    id: BenchmarkId,
    input: &T,
    mut routine: impl FnMut(&mut T) -> O,
) {
    group.bench_function(id, |b| {
        b.iter_batched_ref(|| input.clone(), &mut routine, BatchSize::NumIterations(64))
    });
}

/// `storage/fill`: filling a terrain chunk with one id (dense: rewrite every voxel and mask;
/// palette: drop the buffers and become uniform).
fn fill<M: Measurement>(c: &mut Criterion<M>) {
    let mut group = c.benchmark_group("storage/fill");
    let id = stone();
    for size in SIZES {
        group.throughput(Throughput::Elements(size.volume() as u64));
        let dense = terrain_centre(size);
        let palette = PaletteChunk::from_dense(&dense);
        let label = format!("terrain {s} -> uniform {s}", s = cube(size));
        on_clones(
            &mut group,
            BenchmarkId::new("dense", &label),
            &dense,
            |chunk| chunk.fill(black_box(id)),
        );
        on_clones(
            &mut group,
            BenchmarkId::new("palette", &label),
            &palette,
            |chunk| chunk.fill(black_box(id)),
        );
    }
    group.finish();
}

/// The dense chunks of the compress / decompress / codec benches: terrain at both sizes and a
/// 32^3 chunk of 16 random ids.
fn palette_inputs() -> Vec<(String, DenseChunk)> {
    let mut inputs: Vec<(String, DenseChunk)> = SIZES
        .iter()
        .map(|&size| (format!("terrain {}", cube(size)), terrain_centre(size)))
        .collect();
    let random = random_chunk(ChunkSize::S32, RANDOM_IDS, 21);
    eprintln!("{}", describe("random", &random));
    inputs.push((format!("random {RANDOM_IDS} ids 32^3"), random));
    inputs
}

/// `storage/palette_compress` (`PaletteChunk::from_dense`) and `storage/palette_decompress`
/// (`DenseChunk::from_palette`), per voxel.
fn palette_convert<M: Measurement>(c: &mut Criterion<M>) {
    let inputs = palette_inputs();
    let mut group = c.benchmark_group("storage/palette_compress");
    for (name, dense) in &inputs {
        group.throughput(Throughput::Elements(dense.size().volume() as u64));
        let bits = PaletteChunk::from_dense(dense).bits_per_voxel();
        let label = format!("{name} dense -> {bits} bits/voxel");
        group.bench_function(BenchmarkId::from_parameter(label), |b| {
            b.iter(|| PaletteChunk::from_dense(black_box(dense)))
        });
    }
    group.finish();

    let mut group = c.benchmark_group("storage/palette_decompress");
    for (name, dense) in &inputs {
        group.throughput(Throughput::Elements(dense.size().volume() as u64));
        let palette = PaletteChunk::from_dense(dense);
        let label = format!("{name} {} bits/voxel -> dense", palette.bits_per_voxel());
        group.bench_function(BenchmarkId::from_parameter(label), |b| {
            b.iter(|| DenseChunk::from_palette(black_box(&palette)))
        });
    }
    group.finish();
}

/// One gather bench: `world` around the terrain centre into a reused padded buffer.
fn bench_gather<M: Measurement, C: VoxelStorage>(
    group: &mut BenchmarkGroup<'_, M>,
    id: BenchmarkId,
    world: &WorldMap<C>,
) {
    let mut padded = PaddedChunk::new(world.size());
    group.bench_function(id, |b| {
        b.iter(|| {
            gather_neighbourhood(black_box(world), TERRAIN_CENTRE, &mut padded);
            black_box(&mut padded);
        })
    });
}

/// `storage/gather`: `gather_neighbourhood` of the terrain centre with all 26 neighbours
/// stored, per padded voxel written.
fn gather<M: Measurement>(c: &mut Criterion<M>) {
    let mut group = c.benchmark_group("storage/gather");
    for size in SIZES {
        let p = size.padded_edge();
        group.throughput(Throughput::Elements((p * p * p) as u64));
        let label = format!("27 x {} -> {p}^3 padded", cube(size));
        bench_gather(
            &mut group,
            BenchmarkId::new("dense", &label),
            &terrain_world_dense(size),
        );
        bench_gather(
            &mut group,
            BenchmarkId::new("palette", &label),
            &terrain_world_palette(size),
        );
    }
    group.finish();
}

/// Xor of every row mask of `chunk`.
fn all_masks<S: VoxelStorage>(chunk: &S) -> u64 {
    let e = chunk.size().edge();
    let mut acc = 0;
    for z in 0..e {
        for y in 0..e {
            acc ^= chunk.column_mask(y, z).unwrap_or(0);
        }
    }
    acc
}

/// `storage/occupancy`: the cost of keeping masks on writes (dense writes that flip a voxel
/// between air and solid, against writes that do not), and of reading every row mask
/// (stored in a dense chunk, derived from the packed indices in a palette chunk).
fn occupancy<M: Measurement>(c: &mut Criterion<M>) {
    let mut group = c.benchmark_group("storage/occupancy");
    for size in SIZES {
        let dense = terrain_centre(size);
        // Distinct positions, so every write of the first pass flips and the second pass
        // restores the chunk.
        let positions = distinct_positions(size, OPS, 31);
        let original: Vec<BlockId> = positions.iter().map(|&p| dense.get(p).unwrap()).collect();
        let (flip, same): (Vec<BlockId>, Vec<BlockId>) = original
            .iter()
            .map(|&id| match id {
                BlockId::AIR => (stone(), BlockId::AIR),
                // Stone is 3 and sand 4: both solid terrain ids.
                id if id == stone() => (BlockId::AIR, BlockId(id.0 + 1)),
                _ => (BlockId::AIR, stone()),
            })
            .unzip();
        group.throughput(Throughput::Elements(2 * OPS as u64));
        let label = format!("terrain {}, {} distinct writes", cube(size), 2 * OPS);
        for (name, first) in [("set_flip/dense", &flip), ("set_no_flip/dense", &same)] {
            let mut chunk = dense.clone();
            group.bench_function(BenchmarkId::new(name, &label), |b| {
                b.iter(|| {
                    let chunk = black_box(&mut chunk);
                    set_all(chunk, &positions, first) ^ set_all(chunk, &positions, &original)
                })
            });
        }

        let rows = size.columns();
        group.throughput(Throughput::Elements(rows as u64));
        let palette = PaletteChunk::from_dense(&dense);
        let label = format!("terrain {} -> {rows} row masks", cube(size));
        group.bench_function(BenchmarkId::new("masks/dense", &label), |b| {
            b.iter(|| all_masks(black_box(&dense)))
        });
        group.bench_function(BenchmarkId::new("masks/palette", &label), |b| {
            b.iter(|| all_masks(black_box(&palette)))
        });
    }
    group.finish();
}

/// `codec`: `encode_chunk` into a reused buffer and `decode_chunk` from bytes, per voxel.
fn codec<M: Measurement>(c: &mut Criterion<M>) {
    let mut group = c.benchmark_group("codec");
    let mut inputs = palette_inputs();
    inputs.push(("uniform 32^3".to_owned(), uniform_chunk(ChunkSize::S32)));
    for (name, dense) in &inputs {
        let chunk = PaletteChunk::from_dense(dense);
        let mut bytes = Vec::new();
        encode_chunk(&chunk, &mut bytes);
        let len = bytes.len();
        group.throughput(Throughput::Elements(dense.size().volume() as u64));
        let mut out = Vec::with_capacity(len);
        group.bench_function(
            BenchmarkId::new("encode", format!("{name} -> {len} B")),
            |b| {
                b.iter(|| {
                    out.clear();
                    encode_chunk(black_box(&chunk), &mut out);
                    out.len()
                })
            },
        );
        group.bench_function(
            BenchmarkId::new("decode", format!("{len} B -> {name}")),
            |b| b.iter(|| decode_chunk(black_box(&bytes))),
        );
    }
    group.finish();
}

/// `"4096 x 8 B"`: the packed side of a format bench.
fn packed_label<T>() -> String {
    format!("{FORMAT_BATCH} x {} B", size_of::<T>())
}

/// Encodes every field of `fields` into a reused buffer.
fn bench_encode<M: Measurement, F, T>(
    group: &mut BenchmarkGroup<'_, M>,
    name: &str,
    fields: &[F],
    encode: impl Fn(&F) -> T,
) {
    let mut out: Vec<T> = Vec::with_capacity(fields.len());
    let id = BenchmarkId::new(format!("encode/{name}"), packed_label::<T>());
    group.bench_function(id, |b| {
        b.iter(|| {
            out.clear();
            out.extend(black_box(fields).iter().map(&encode));
            black_box(&mut out);
        })
    });
}

/// Decodes every value of `packed` into a reused buffer.
fn bench_decode<M: Measurement, T: Copy, F>(
    group: &mut BenchmarkGroup<'_, M>,
    name: &str,
    packed: &[T],
    decode: impl Fn(T) -> F,
) {
    let mut out: Vec<F> = Vec::with_capacity(packed.len());
    let id = BenchmarkId::new(format!("decode/{name}"), packed_label::<T>());
    group.bench_function(id, |b| {
        b.iter(|| {
            out.clear();
            out.extend(black_box(packed).iter().map(|&p| decode(p)));
            black_box(&mut out);
        })
    });
}

/// Encode and decode benches of one format over `fields`.
fn bench_format<M: Measurement, F, T: Copy, D>(
    group: &mut BenchmarkGroup<'_, M>,
    name: &str,
    fields: &[F],
    encode: impl Fn(&F) -> T,
    decode: impl Fn(T) -> D,
) {
    bench_encode(group, name, fields, &encode);
    let packed: Vec<T> = fields.iter().map(&encode).collect();
    bench_decode(group, name, &packed, decode);
}

/// `formats/pack`: encode and decode throughput of each packed GPU format and of the
/// octahedral normal codes, over [`FORMAT_BATCH`] precomputed values, per value.
fn formats_pack<M: Measurement>(c: &mut Criterion<M>) {
    const VALID: &str = "bench inputs are valid";
    let n = FORMAT_BATCH;
    let mut group = c.benchmark_group("formats/pack");
    group.throughput(Throughput::Elements(n as u64));
    let g = &mut group;
    bench_format(
        g,
        "DrawBlock",
        &draw_blocks(n, 41),
        |f| DrawBlock::encode(f).expect(VALID),
        DrawBlock::decode,
    );
    bench_format(
        g,
        "PackedQuad",
        &packed_quads(n, 42),
        |f| PackedQuad::encode(f).expect(VALID),
        |p| p.decode().expect(VALID),
    );
    bench_format(
        g,
        "BlockVertex",
        &block_vertices(n, 43),
        |f| BlockVertex::encode(f, VERTEX_EXTENT).expect(VALID),
        |p| p.decode(VERTEX_EXTENT),
    );
    bench_format(
        g,
        "ClutterUnit",
        &clutter_units(n, 44),
        |f| ClutterUnit::encode(f, VERTEX_EXTENT).expect(VALID),
        |p| p.decode(VERTEX_EXTENT),
    );
    bench_format(
        g,
        "ChunkDrawInfo",
        &chunk_draw_infos(n, 45),
        |f| ChunkDrawInfo::encode(f).expect(VALID),
        |p| p.decode().expect(VALID),
    );
    bench_format(
        g,
        "MeshedChunkInfo",
        &meshed_chunk_infos(n, 46),
        |f| MeshedChunkInfo::encode(f).expect(VALID),
        |p| p.decode().expect(VALID),
    );
    bench_format(
        g,
        "ChunkDrawIndirect",
        &chunk_draw_indirects(n, 47),
        ChunkDrawIndirect::encode,
        ChunkDrawIndirect::decode,
    );
    let normals = unit_normals(n, 48);
    bench_format(
        g,
        "oct16",
        &normals,
        |&v| oct16_encode(v).expect(VALID),
        oct16_decode,
    );
    bench_format(
        g,
        "oct32",
        &normals,
        |&v| oct32_encode(v).expect(VALID),
        oct32_decode,
    );
    group.finish();
}

/// Every group of this target, in order.
fn all<M: Measurement>(c: &mut Criterion<M>) {
    get_set(c);
    fill(c);
    palette_convert(c);
    gather(c);
    occupancy(c);
    codec(c);
    formats_pack(c);
}

/// Sized so the whole run takes about 7 minutes on 2 cores; 100 samples per bench keep the
/// median stable when other processes share the machine.
fn config<M: Measurement>(c: Criterion<M>) -> Criterion<M> {
    c.warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4))
        .sample_size(100)
        .configure_from_args()
}

fn main() {
    match clock_from_env() {
        Clock::ThreadCpu => {
            let mut c = config(Criterion::default().with_measurement(ThreadCpuTime::default()));
            all(&mut c);
            c.final_summary();
        }
        Clock::Wall => {
            let mut c = config(Criterion::default());
            all(&mut c);
            c.final_summary();
        }
    }
}
