//! Parity inputs: thousands of random values per format, drawn fresh from a printed seed, plus
//! the edge values (all zero, every field at its maximum, sentinels, extreme floats).
//!
//! Formats where every bit pattern decodes get raw random bytes; the others get random bits
//! with the invalid patterns (reserved bits, face 6 and 7, kinds above 2, ...) mapped to valid
//! ones, so every input is something `encode` can produce.

use voxel_core::BlockId;
use voxel_core::formats::{
    BlockVertex, ChunkDrawIndirect, ChunkDrawInfo, ClutterUnit, DrawBlock, FaceLayerRange,
    LayerRange, MeshedChunkInfo, PackedQuad, ShellRun, ShellRunFields,
};

use crate::common::Rng;

/// Random values per format.
pub(crate) const RANDOM: usize = 4096;

/// Random bit patterns, all valid.
fn raw<T: bytemuck::Pod>(rng: &mut Rng, edges: Vec<T>) -> Vec<T> {
    let mut v = edges;
    v.extend(rng.bytes::<T>(RANDOM));
    v
}

/// All-zero and all-one bit patterns.
fn zero_and_ones<T: bytemuck::Pod>() -> Vec<T> {
    let mut ones = T::zeroed();
    bytemuck::bytes_of_mut(&mut ones).fill(0xff);
    vec![T::zeroed(), ones]
}

pub(crate) fn draw_blocks(rng: &mut Rng) -> Vec<DrawBlock> {
    raw(rng, zero_and_ones())
}

pub(crate) fn block_vertices(rng: &mut Rng) -> Vec<BlockVertex> {
    let mut edges = zero_and_ones::<BlockVertex>();
    // Normal codes at the square's corners and axes, including the most negative code.
    for normal in [
        0x0000, 0x007f, 0x7f00, 0x7f7f, 0x8080, 0x8181, 0x807f, 0x0081, 0xff7f,
    ] {
        edges.push(BlockVertex {
            position: [0, 32768, 65535],
            normal,
            uv: [65535, 1],
            block: 65535,
            extra: 1,
        });
    }
    raw(rng, edges)
}

pub(crate) fn clutter_units(rng: &mut Rng) -> Vec<ClutterUnit> {
    raw(rng, zero_and_ones())
}

pub(crate) fn chunk_draw_indirects(rng: &mut Rng) -> Vec<ChunkDrawIndirect> {
    raw(rng, zero_and_ones())
}

pub(crate) fn packed_quads(rng: &mut Rng) -> Vec<PackedQuad> {
    // Every face with all-zero and all-maximum fields.
    let mut v: Vec<PackedQuad> = (0..6)
        .flat_map(|face| {
            [
                PackedQuad {
                    position_size: 0,
                    face_ao_block: face,
                },
                PackedQuad {
                    position_size: (1 << 30) - 1,
                    face_ao_block: (((1 << 27) - 1) & !7) | face,
                },
            ]
        })
        .collect();
    v.extend((0..RANDOM).map(|_| PackedQuad {
        position_size: rng.next_u32() & ((1 << 30) - 1),
        face_ao_block: (rng.next_u32() & ((1 << 27) - 1) & !7) | rng.below(6),
    }));
    v
}

/// A random i32, often an extreme one.
fn coordinate(rng: &mut Rng) -> i32 {
    match rng.below(8) {
        0 => i32::MIN,
        1 => i32::MAX,
        2 => -1,
        _ => rng.next_u32() as i32,
    }
}

/// -1 (the sentinel) or a random non-negative i32.
fn sentinel(rng: &mut Rng) -> i32 {
    match rng.below(4) {
        0 => -1,
        1 => i32::MAX,
        _ => (rng.next_u32() >> 1) as i32,
    }
}

/// Valid shell runs: random fields, plus the extremes (a run at the origin, one filling a
/// 64-voxel column, one ending at the top of the chunk, one 64 voxels wide).
pub(crate) fn shell_runs(rng: &mut Rng) -> Vec<ShellRun> {
    let run = |position: [u32; 3], height, width, block: u16, sides, feet| {
        ShellRun::encode(&ShellRunFields {
            position,
            height,
            width,
            block: BlockId(block),
            sides,
            feet,
        })
        .expect("valid fields")
    };
    let mut v = vec![
        run([0, 0, 0], 1, 1, 0, 1, 0),
        run(
            [63, 0, 63],
            64,
            1,
            u16::MAX,
            ShellRun::ALL_SIDES,
            ShellRun::ALL_FEET,
        ),
        run([5, 63, 7], 1, 1, 9, 0b10_0000, 0b1000),
        run([0, 4, 2], 3, 64, 9, ShellRun::ALL_SIDES, 0b0101),
    ];
    for _ in 0..2000 {
        let y = rng.below(64);
        let position = [rng.below(64), y, rng.below(64)];
        let height = 1 + rng.below(64 - y);
        let width = 1 + rng.below(64 - position[0]);
        let sides = 1 + rng.below(63) as u8;
        let feet = rng.below(16) as u8;
        v.push(run(
            position,
            height,
            width,
            rng.next_u32() as u16,
            sides,
            feet,
        ));
    }
    v
}

pub(crate) fn chunk_draw_infos(rng: &mut Rng) -> Vec<ChunkDrawInfo> {
    let mut v = vec![
        ChunkDrawInfo {
            chunk: [0; 3],
            kind: 0,
            draw_count: -1,
            gigabuffer_index: -1,
        },
        ChunkDrawInfo {
            chunk: [i32::MIN, i32::MAX, -1],
            kind: 2,
            draw_count: i32::MAX,
            gigabuffer_index: i32::MAX,
        },
    ];
    v.extend((0..RANDOM).map(|_| ChunkDrawInfo {
        chunk: [coordinate(rng), coordinate(rng), coordinate(rng)],
        kind: rng.below(3),
        draw_count: sentinel(rng),
        gigabuffer_index: sentinel(rng),
    }));
    v
}

/// A random finite f32: random bits (subnormals, huge values), or an edge value.
fn finite(rng: &mut Rng) -> f32 {
    const EDGES: [f32; 8] = [
        0.0,
        -0.0,
        f32::MAX,
        f32::MIN,
        f32::MIN_POSITIVE,
        1.0e-45,
        0.5,
        -1.5,
    ];
    if rng.below(8) == 0 {
        return EDGES[rng.below(EDGES.len() as u32) as usize];
    }
    loop {
        let x = f32::from_bits(rng.next_u32());
        if x.is_finite() {
            return x;
        }
    }
}

/// Counts whose sum with `offset` fits in u32: small ones usually, a random split of all the
/// room that is left otherwise.
fn face_range(rng: &mut Rng) -> FaceLayerRange {
    let offset = if rng.below(4) == 0 {
        u32::MAX - rng.below(1 << 20)
    } else {
        rng.next_u32()
    };
    let mut room = u32::MAX - offset;
    let small = rng.below(2) == 0;
    let counts = std::array::from_fn(|_| {
        let c = if small {
            rng.below(room.min(5000) + 1)
        } else {
            rng.below(room)
        };
        room -= c;
        c
    });
    FaceLayerRange { offset, counts }
}

fn layer_range(rng: &mut Rng) -> LayerRange {
    let offset = rng.next_u32();
    LayerRange {
        offset,
        count: rng.below(u32::MAX - offset),
    }
}

pub(crate) fn meshed_chunk_infos(rng: &mut Rng) -> Vec<MeshedChunkInfo> {
    let zero = MeshedChunkInfo::default();
    let full = FaceLayerRange {
        offset: 0,
        counts: [u32::MAX, 0, 0, 0, 0, 0],
    };
    let last = FaceLayerRange {
        offset: u32::MAX - 21,
        counts: [1, 2, 3, 4, 5, 6],
    };
    let mut v = vec![
        zero,
        MeshedChunkInfo {
            chunk: [i32::MAX, i32::MIN, -1],
            lod: MeshedChunkInfo::MAX_LOD,
            centre: [f32::MAX, f32::MIN, -0.0],
            extent: [f32::MAX, 0.0, f32::MIN_POSITIVE],
            opaque_quads: full,
            transparent_quads: last,
            smooth_vertices: LayerRange {
                offset: u32::MAX,
                count: 0,
            },
            clutter_units: LayerRange {
                offset: 0,
                count: u32::MAX,
            },
        },
    ];
    v.extend((0..RANDOM).map(|_| MeshedChunkInfo {
        chunk: [coordinate(rng), coordinate(rng), coordinate(rng)],
        lod: rng.below(MeshedChunkInfo::MAX_LOD + 1),
        centre: [finite(rng), finite(rng), finite(rng)],
        extent: [finite(rng).abs(), finite(rng).abs(), finite(rng).abs()],
        opaque_quads: face_range(rng),
        transparent_quads: face_range(rng),
        smooth_vertices: layer_range(rng),
        clutter_units: layer_range(rng),
    }));
    v
}

/// Every 16-bit code, with random upper bits (the decoders must ignore them).
pub(crate) fn all_u16_codes(rng: &mut Rng) -> Vec<u32> {
    (0..=u32::from(u16::MAX))
        .map(|c| c | rng.next_u32() << 16)
        .collect()
}

/// Random 32-bit oct32 codes plus the square's corners and axes.
pub(crate) fn oct32_codes(rng: &mut Rng) -> Vec<u32> {
    let mut v = vec![
        0,
        0x7fff_7fff,
        0x8000_8000,
        0x8001_8001,
        0x7fff_8001,
        0x0000_7fff,
        0x8001_0000,
        u32::MAX,
    ];
    v.extend((0..RANDOM).map(|_| rng.next_u32()));
    v
}
