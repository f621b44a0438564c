//! Skirts close a chunk's side exactly as clearing that side's padding would: the normal mesh
//! plus one side's skirt covers the same faces as the mesh of the chunk with that side's padding
//! cleared, and the same blocks as that chunk's surface-block list.

#[allow(dead_code, reason = "each test file uses part of the shared helpers")]
mod surface_blocks_support;

use std::collections::BTreeSet;

use mesher::blocky::{BlockyLayer, BlockyMesh, GreedyMesher};
use mesher::lod::{Skirts, skirt_blocks, skirt_quads};
use mesher::surface_blocks::{hiding_mask, hiding_mask_words};
use mesher::{BlockClasses, MeshError, SurfaceBlocks, surface_blocks};
use proptest::prelude::*;
use surface_blocks_support::*;
use voxel_core::formats::PackedQuad;
use voxel_core::{BlockId, ChunkSize, FaceDirection, MaterialClass, PaddedChunk};

/// Unit faces `(voxel, face)` covered by opaque quads.
fn unit_faces<'a>(quads: impl Iterator<Item = &'a PackedQuad>) -> BTreeSet<([u32; 3], u8)> {
    let mut out = BTreeSet::new();
    for quad in quads {
        let f = quad.decode().expect("quads decode");
        for du in 0..f.width {
            for dv in 0..f.height {
                let mut p = f.position;
                p[f.face.width_axis()] += du;
                p[f.face.height_axis()] += dv;
                assert!(out.insert((p, f.face.index())), "face {p:?} covered twice");
            }
        }
    }
    out
}

fn opaque_faces(chunk: &PaddedChunk, classes: &BlockClasses) -> BTreeSet<([u32; 3], u8)> {
    let mut mesh = BlockyMesh::default();
    GreedyMesher::default()
        .mesh(chunk, classes, &mut mesh)
        .expect("meshes");
    unit_faces(mesh.layer(BlockyLayer::Opaque).iter())
}

fn block_positions(out: &SurfaceBlocks) -> BTreeSet<[u32; 3]> {
    out.iter_local().map(|(p, _)| p).collect()
}

fn cleared(chunk: &PaddedChunk, side: FaceDirection) -> PaddedChunk {
    let mut c = chunk.clone();
    c.clear_padding_face(side);
    c
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn mesh_plus_skirt_covers_what_a_cleared_side_covers(spec in chunk_spec()) {
        let chunk = spec.build();
        let palette = palette();
        let classes = BlockClasses::from_palette(&palette);
        let main = match GreedyMesher::default().mesh(&chunk, &classes, &mut BlockyMesh::default()) {
            Err(MeshError::UnknownBlock { .. }) => return Ok(()),
            other => { other.unwrap(); opaque_faces(&chunk, &classes) }
        };
        let mut skirts = Skirts::new();
        let result = skirt_quads(&chunk, &classes, &mut skirts);
        if let Err(e) = result {
            prop_assert!(matches!(e, MeshError::UnknownBlock { .. }), "{e}");
            prop_assert_eq!(skirts.quad_counts(), [0; 6]);
            return Ok(());
        }
        for side in FaceDirection::ALL {
            let skirt = unit_faces(skirts.quads(side).iter());
            prop_assert!(skirt.iter().all(|(_, f)| *f == side.index()), "skirt faces face their side");
            prop_assert!(skirt.is_disjoint(&main), "skirt faces are not in the normal mesh");
            let union: BTreeSet<_> = main.union(&skirt).copied().collect();
            let expected = match GreedyMesher::default()
                .mesh(&cleared(&chunk, side), &classes, &mut BlockyMesh::default())
            {
                Ok(()) => opaque_faces(&cleared(&chunk, side), &classes),
                Err(e) => { prop_assert!(false, "the cleared chunk failed: {e}"); unreachable!() }
            };
            prop_assert_eq!(union, expected, "side {:?}", side);
        }
    }

    #[test]
    fn surface_blocks_plus_skirt_blocks_equal_those_of_a_cleared_side(
        spec in chunk_spec().prop_filter("DrawBlocks address 16^3", |s| s.size.edge() <= 16)
    ) {
        let chunk = spec.build();
        let palette = palette();
        let classes = BlockClasses::from_palette(&palette);
        let mut main = SurfaceBlocks::new();
        if surface_blocks(&chunk, &classes, &mut main).is_err() {
            return Ok(());
        }
        let mut skirts = Skirts::new();
        if let Err(e) = skirt_blocks(&chunk, &classes, &mut skirts) {
            prop_assert!(matches!(e, MeshError::UnknownBlock { .. }), "{e}");
            return Ok(());
        }
        let main_positions = block_positions(&main);
        for side in FaceDirection::ALL {
            let skirt: BTreeSet<[u32; 3]> = skirts
                .blocks(side)
                .iter()
                .map(|b| b.decode().position)
                .collect();
            prop_assert_eq!(skirt.len(), skirts.blocks(side).len(), "no block twice");
            prop_assert!(skirt.is_disjoint(&main_positions));
            let mut expected = SurfaceBlocks::new();
            surface_blocks(&cleared(&chunk, side), &classes, &mut expected).unwrap();
            // Transparent voxels get no skirt: compare the opaque blocks.
            let opaque = |p: &[u32; 3]| {
                palette.get(id_at(&chunk, *p)).is_ok_and(|m| m.class != MaterialClass::Transparent)
            };
            let expected: BTreeSet<_> = block_positions(&expected).into_iter().filter(opaque).collect();
            let union: BTreeSet<_> = main_positions.iter().copied().filter(opaque).chain(skirt).collect();
            prop_assert_eq!(union, expected, "side {:?}", side);
        }
    }

    #[test]
    fn the_hiding_mask_has_one_bit_per_opaque_padded_voxel(spec in chunk_spec()) {
        let chunk = spec.build();
        let palette = palette();
        let classes = BlockClasses::from_palette(&palette);
        let mut bits = vec![7u32; 3];
        hiding_mask(&chunk, &classes, &mut bits);
        let edge = spec.size.edge();
        prop_assert_eq!(bits.len(), hiding_mask_words(edge));
        let p = edge + 2;
        for i in 0..(p * p * p) as usize {
            let (x, y, z) = (i as u32 % p, i as u32 / p % p, i as u32 / (p * p));
            let id = chunk.get(x, y, z).unwrap();
            let hides = !id.is_air() && palette.get(id).map_or(true, |m| m.class != MaterialClass::Transparent);
            prop_assert_eq!(bits[i / 32] >> (i % 32) & 1 == 1, hides, "padded ({}, {}, {})", x, y, z);
        }
        let used = (p * p * p) as usize;
        if !used.is_multiple_of(32) {
            prop_assert_eq!(bits[used / 32] >> (used % 32), 0, "bits past the box are zero");
        }
    }
}

#[test]
fn a_buried_chunk_has_a_full_skirt_on_every_side_and_blocks_only_on_its_shell() {
    let palette = palette();
    let classes = BlockClasses::from_palette(&palette);
    let chunk = PaddedChunk::from_fn(ChunkSize::S8, |_, _, _| STONE);
    let mut skirts = Skirts::new();
    skirt_quads(&chunk, &classes, &mut skirts).unwrap();
    for side in FaceDirection::ALL {
        let quads = skirts.quads(side);
        assert_eq!(quads.len(), 1, "one merged quad on {side:?}");
        let f = quads[0].decode().unwrap();
        assert_eq!((f.width, f.height, f.ao, f.block), (8, 8, [3; 4], STONE));
    }
    skirt_blocks(&chunk, &classes, &mut skirts).unwrap();
    // Every border block of a side, each buried in the real neighbourhood.
    assert_eq!(skirts.block_counts(), [64; 6]);
    assert_eq!(
        skirts.quad_counts(),
        [0; 6],
        "skirt_blocks clears the quads"
    );
}

#[test]
fn water_and_air_beyond_the_border_need_no_skirt() {
    let palette = palette();
    let classes = BlockClasses::from_palette(&palette);
    // Stone chunk, water padding on +X, air padding elsewhere.
    let chunk = PaddedChunk::from_fn(ChunkSize::S8, |x, y, z| {
        let inside = (1..=8).contains(&x) && (1..=8).contains(&y) && (1..=8).contains(&z);
        if inside {
            STONE
        } else if x == 9 {
            WATER
        } else {
            BlockId::AIR
        }
    });
    let mut skirts = Skirts::new();
    skirt_quads(&chunk, &classes, &mut skirts).unwrap();
    assert_eq!(skirts.quad_counts(), [0; 6]);
    skirt_blocks(&chunk, &classes, &mut skirts).unwrap();
    assert_eq!(skirts.block_counts(), [0; 6]);
}

#[test]
fn skirts_reject_unknown_ids_they_would_show_and_wide_chunks_for_blocks() {
    let palette = palette();
    let classes = BlockClasses::from_palette(&palette);
    let chunk = PaddedChunk::from_fn(ChunkSize::S8, |_, _, _| UNKNOWN);
    let mut skirts = Skirts::new();
    let e = skirt_quads(&chunk, &classes, &mut skirts).unwrap_err();
    assert!(
        matches!(e, MeshError::UnknownBlock { id, .. } if id == UNKNOWN),
        "{e}"
    );
    assert_eq!(skirts.quad_counts(), [0; 6]);
    let wide = PaddedChunk::from_fn(ChunkSize::S32, |_, _, _| STONE);
    let e = skirt_blocks(&wide, &classes, &mut skirts).unwrap_err();
    assert!(e.to_string().contains("16^3"), "{e}");
    skirt_quads(&wide, &classes, &mut skirts).expect("quads work at any size");
    assert_eq!(skirts.quad_counts(), [1; 6]);
}
