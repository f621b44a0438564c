//! Format inputs: [`FORMAT_BATCH`] valid field values per packed GPU format, spread over each
//! field's whole range, and unit normals for the octahedral encoders.
//!
//! Every value here encodes without error (a unit test checks it), so an encode bench measures
//! the checks and the packing, never the error path.

use glam::{Vec2, Vec3};
use voxel_core::formats::{
    BlockVertexFields, ChunkDrawIndirectFields, ChunkDrawInfoFields, ChunkKind, ClutterUnitFields,
    DrawBlockFields, DrawBlockFlags, FaceDirection, FaceLayerRange, LayerRange,
    MeshedChunkInfoFields, PackedQuadFields, UnormExtent,
};
use voxel_core::{BlockId, ChunkCoord, ChunkSize};

use crate::rng::Rng;

/// Fields per batch in the format benches: a few meshed chunks' worth of quads, and small
/// enough (at most 112 B x 4096 = 448 KiB per array) to stay in the L2 or L3 cache.
pub const FORMAT_BATCH: usize = 4096;

/// The position extent of the vertex formats: a padded 62^3 chunk.
pub const VERTEX_EXTENT: UnormExtent = UnormExtent::padded_chunk(ChunkSize::S62);

fn block(rng: &mut Rng) -> BlockId {
    BlockId(rng.below(1 << 16) as u16)
}

fn chunk(rng: &mut Rng) -> ChunkCoord {
    let mut axis = || rng.below(1 << 12) as i32 - (1 << 11);
    ChunkCoord::new(axis(), axis(), axis())
}

/// A random direction, uniform on the sphere (never zero).
fn direction(rng: &mut Rng) -> Vec3 {
    loop {
        let v = Vec3::new(
            rng.range_f32(-1.0, 1.0),
            rng.range_f32(-1.0, 1.0),
            rng.range_f32(-1.0, 1.0),
        );
        let len2 = v.length_squared();
        if len2 > 1e-4 && len2 <= 1.0 {
            return v / len2.sqrt();
        }
    }
}

fn position(rng: &mut Rng) -> Vec3 {
    let e = VERTEX_EXTENT.get();
    Vec3::new(
        rng.range_f32(0.0, e),
        rng.range_f32(0.0, e),
        rng.range_f32(0.0, e),
    )
}

fn uv(rng: &mut Rng) -> Vec2 {
    Vec2::new(rng.unit_f32(), rng.unit_f32())
}

/// `n` unit directions, uniform on the sphere.
pub fn unit_normals(n: usize, seed: u64) -> Vec<Vec3> {
    let mut rng = Rng::new(seed);
    (0..n).map(|_| direction(&mut rng)).collect()
}

/// `n` [`DrawBlockFields`]: positions in a 16^3 chunk, any flags, any block id.
pub fn draw_blocks(n: usize, seed: u64) -> Vec<DrawBlockFields> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|_| DrawBlockFields {
            position: [(); 3].map(|()| rng.below(16) as u32),
            flags: DrawBlockFlags::from_bits(rng.below(16) as u8).expect("4 bits"),
            block: block(&mut rng),
        })
        .collect()
}

/// `n` [`PackedQuadFields`]: positions in a 64^3 box, sizes 1..=64, any face, AO and block.
pub fn packed_quads(n: usize, seed: u64) -> Vec<PackedQuadFields> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|_| PackedQuadFields {
            position: [(); 3].map(|()| rng.below(64) as u32),
            width: 1 + rng.below(64) as u32,
            height: 1 + rng.below(64) as u32,
            face: FaceDirection::ALL[rng.below(6) as usize],
            ao: [(); 4].map(|()| rng.below(4) as u8),
            block: block(&mut rng),
        })
        .collect()
}

/// `n` [`BlockVertexFields`]: positions in [`VERTEX_EXTENT`], unit normals, uvs in `0..1`.
pub fn block_vertices(n: usize, seed: u64) -> Vec<BlockVertexFields> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|_| BlockVertexFields {
            position: position(&mut rng),
            normal: direction(&mut rng),
            uv: uv(&mut rng),
            block: block(&mut rng),
            extra: rng.next_u64() as u16,
        })
        .collect()
}

/// `n` [`ClutterUnitFields`]: positions in [`VERTEX_EXTENT`], every field over its range.
pub fn clutter_units(n: usize, seed: u64) -> Vec<ClutterUnitFields> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|_| ClutterUnitFields {
            position: position(&mut rng),
            normal: direction(&mut rng),
            kind: rng.next_u64() as u8,
            scale_step: rng.below(16) as u8,
            seed: rng.below(16) as u8,
            uv: uv(&mut rng),
            uv_size: uv(&mut rng),
            tint: (rng.next_u64() as u32).to_le_bytes(),
        })
        .collect()
}

/// `n` [`ChunkDrawInfoFields`]: every kind, counts and slots with and without the sentinel.
pub fn chunk_draw_infos(n: usize, seed: u64) -> Vec<ChunkDrawInfoFields> {
    let mut rng = Rng::new(seed);
    // A quarter of the counts and slots are the -1 sentinel.
    let optional = |rng: &mut Rng| (rng.below(4) != 0).then(|| rng.below(1 << 31) as u32);
    (0..n)
        .map(|_| ChunkDrawInfoFields {
            chunk: chunk(&mut rng),
            kind: ChunkKind::ALL[rng.below(3) as usize],
            draw_count: optional(&mut rng),
            gigabuffer_index: optional(&mut rng),
        })
        .collect()
}

fn face_range(rng: &mut Rng) -> FaceLayerRange {
    FaceLayerRange {
        offset: rng.below(1 << 24) as u32,
        counts: [(); 6].map(|()| rng.below(1 << 12) as u32),
    }
}

fn layer_range(rng: &mut Rng) -> LayerRange {
    LayerRange {
        offset: rng.below(1 << 24) as u32,
        count: rng.below(1 << 16) as u32,
    }
}

/// `n` [`MeshedChunkInfoFields`]: lods 0..=15, bounds inside a 62^3 chunk, ranges that fit.
pub fn meshed_chunk_infos(n: usize, seed: u64) -> Vec<MeshedChunkInfoFields> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|_| MeshedChunkInfoFields {
            chunk: chunk(&mut rng),
            lod: rng.below(16) as u32,
            centre: Vec3::new(
                rng.range_f32(0.0, 62.0),
                rng.range_f32(0.0, 62.0),
                rng.range_f32(0.0, 62.0),
            ),
            extent: Vec3::new(
                rng.range_f32(0.0, 31.0),
                rng.range_f32(0.0, 31.0),
                rng.range_f32(0.0, 31.0),
            ),
            opaque_quads: face_range(&mut rng),
            transparent_quads: face_range(&mut rng),
            smooth_vertices: layer_range(&mut rng),
            clutter_units: layer_range(&mut rng),
        })
        .collect()
}

/// `n` [`ChunkDrawIndirectFields`]: index counts of up to 2^20, any base vertex and chunk.
pub fn chunk_draw_indirects(n: usize, seed: u64) -> Vec<ChunkDrawIndirectFields> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|_| ChunkDrawIndirectFields {
            index_count: rng.below(1 << 20) as u32,
            instance_count: 1,
            first_index: rng.below(1 << 28) as u32,
            base_vertex: rng.next_u64() as i32,
            first_instance: rng.below(1 << 16) as u32,
            chunk: chunk(&mut rng),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use voxel_core::formats::{
        BlockVertex, ChunkDrawIndirect, ChunkDrawInfo, ClutterUnit, DrawBlock, MeshedChunkInfo,
        PackedQuad, oct16_encode, oct32_encode,
    };

    use super::*;

    const N: usize = 512;

    #[test]
    fn every_input_encodes() {
        for f in draw_blocks(N, 1) {
            DrawBlock::encode(&f).unwrap();
        }
        for f in packed_quads(N, 2) {
            PackedQuad::encode(&f).unwrap();
        }
        for f in block_vertices(N, 3) {
            BlockVertex::encode(&f, VERTEX_EXTENT).unwrap();
        }
        for f in clutter_units(N, 4) {
            ClutterUnit::encode(&f, VERTEX_EXTENT).unwrap();
        }
        for f in chunk_draw_infos(N, 5) {
            ChunkDrawInfo::encode(&f).unwrap();
        }
        for f in meshed_chunk_infos(N, 6) {
            MeshedChunkInfo::encode(&f).unwrap();
        }
        for f in chunk_draw_indirects(N, 7) {
            let _ = ChunkDrawIndirect::encode(&f);
        }
        for v in unit_normals(N, 8) {
            assert!((v.length() - 1.0).abs() < 1e-5);
            oct16_encode(v).unwrap();
            oct32_encode(v).unwrap();
        }
    }

    #[test]
    fn inputs_are_deterministic() {
        assert_eq!(packed_quads(64, 9), packed_quads(64, 9));
        assert_eq!(unit_normals(64, 9), unit_normals(64, 9));
        assert_ne!(packed_quads(64, 9), packed_quads(64, 10));
    }
}
