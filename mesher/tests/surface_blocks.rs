//! Surface-block lists against a per-voxel reference: exactly the voxels with a visible face,
//! flags from the material, positions recovered from sub-block origin + packed position.

#[allow(dead_code, reason = "each test file uses part of the shared helpers")]
mod surface_blocks_support;

use std::collections::BTreeMap;

use mesher::{BlockClasses, MeshError, SUB_BLOCK_EDGE, SurfaceBlocks, surface_blocks};
use proptest::prelude::*;
use surface_blocks_support::*;
use voxel_core::formats::DrawBlockFlags;
use voxel_core::{BlockId, ChunkSize, MaterialClass, MaterialPalette, PaddedChunk};

/// Reference: chunk-local position -> (id, flags) of every voxel with a visible face.
fn reference(chunk: &PaddedChunk, palette: &MaterialPalette) -> BTreeMap<[u32; 3], (BlockId, u8)> {
    let mut out = BTreeMap::new();
    for pos in positions(chunk.size()) {
        if !faces_of(chunk, palette, pos).contains(&true) {
            continue;
        }
        let id = id_at(chunk, pos);
        let material = palette.get(id).unwrap();
        let above = chunk.get(pos[0] + 1, pos[1] + 2, pos[2] + 1).unwrap();
        let mut flags = DrawBlockFlags::EMPTY;
        if material.class == MaterialClass::Transparent {
            flags |= DrawBlockFlags::TRANSPARENT;
        }
        if material.emission > 0 {
            flags |= DrawBlockFlags::EMISSIVE;
        }
        if material.class == MaterialClass::Smoothable {
            flags |= DrawBlockFlags::SMOOTH;
        }
        if material.class == MaterialClass::ClutterBearing && above.is_air() {
            flags |= DrawBlockFlags::HAS_CLUTTER;
        }
        out.insert(pos, (id, flags.bits()));
    }
    out
}

/// Checks the sub-block structure and returns the blocks by chunk-local position.
fn decoded(out: &SurfaceBlocks, size: ChunkSize) -> BTreeMap<[u32; 3], (BlockId, u8)> {
    let per_axis = size.edge().div_ceil(SUB_BLOCK_EDGE);
    let mut next = 0;
    let mut previous_coord = None;
    let mut map = BTreeMap::new();
    for range in out.sub_blocks() {
        assert_eq!(
            range.offset as usize, next,
            "ranges are contiguous, in order"
        );
        assert!(range.count >= 1, "only non-empty sub-blocks are listed");
        next += range.count as usize;
        assert!(range.coord.iter().all(|&c| u32::from(c) < per_axis));
        let key = [range.coord[2], range.coord[1], range.coord[0]];
        assert!(
            previous_coord < Some(key),
            "sub-blocks ordered z, y, x, each once"
        );
        previous_coord = Some(key);
        let origin = range.origin();
        for block in out.sub_block(range) {
            let fields = block.decode();
            let pos: [u32; 3] = std::array::from_fn(|a| origin[a] + fields.position[a]);
            assert!(
                pos.iter().all(|&a| a < size.edge()),
                "{pos:?} outside the chunk"
            );
            let previous = map.insert(pos, (fields.block, fields.flags.bits()));
            assert_eq!(previous, None, "{pos:?} listed twice");
        }
    }
    assert_eq!(next, out.len(), "the ranges cover every block");
    let by_iter: BTreeMap<_, _> = out
        .iter_local()
        .map(|(pos, f)| (pos, (f.block, f.flags.bits())))
        .collect();
    assert_eq!(by_iter, map);
    map
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn surface_blocks_are_exactly_the_voxels_with_a_visible_face(spec in chunk_spec()) {
        let palette = palette();
        let classes = BlockClasses::from_palette(&palette);
        let chunk = spec.build();
        let mut out = SurfaceBlocks::new();
        surface_blocks(&chunk, &classes, &mut out).unwrap();
        let expected = reference(&chunk, &palette);
        let got = decoded(&out, spec.size);
        prop_assert_eq!(got.len(), expected.len());
        prop_assert_eq!(got, expected);
    }

    #[test]
    fn a_reused_buffer_gives_what_a_fresh_one_gives(a in chunk_spec(), b in chunk_spec()) {
        let classes = BlockClasses::from_palette(&palette());
        let mut reused = SurfaceBlocks::new();
        surface_blocks(&a.build(), &classes, &mut reused).unwrap();
        let chunk = b.build();
        surface_blocks(&chunk, &classes, &mut reused).unwrap();
        let mut fresh = SurfaceBlocks::new();
        surface_blocks(&chunk, &classes, &mut fresh).unwrap();
        prop_assert_eq!(reused.blocks(), fresh.blocks());
        prop_assert_eq!(reused.sub_blocks(), fresh.sub_blocks());
    }

    #[test]
    fn exposed_unknown_ids_are_errors_and_leave_the_buffer_empty(
        size in size(),
        at in any::<[u32; 3]>(),
    ) {
        let classes = BlockClasses::from_palette(&palette());
        let e = size.edge();
        let at = at.map(|a| a % e + 1);
        let chunk = PaddedChunk::from_fn(size, |x, y, z| {
            if [x, y, z] == at { UNKNOWN } else if y <= at[1] { STONE } else { BlockId::AIR }
        });
        let mut out = SurfaceBlocks::new();
        let floor = PaddedChunk::from_fn(size, |_, y, _| if y == 1 { STONE } else { BlockId::AIR });
        surface_blocks(&floor, &classes, &mut out).unwrap();
        prop_assert!(!out.is_empty());
        // The unknown voxel has air above it: exposed.
        let result = surface_blocks(&chunk, &classes, &mut out);
        prop_assert_eq!(result, Err(MeshError::UnknownBlock { id: UNKNOWN, position: at }));
        prop_assert!(out.is_empty() && out.sub_blocks().is_empty());
    }
}

fn filled(size: ChunkSize, f: impl Fn([u32; 3], bool) -> BlockId) -> PaddedChunk {
    let p = size.padded_edge() as u32;
    PaddedChunk::from_fn(size, |x, y, z| {
        let border = [x, y, z].iter().any(|&a| a == 0 || a == p - 1);
        f([x, y, z], border)
    })
}

#[test]
fn empty_and_buried_full_chunks_give_nothing() {
    let classes = BlockClasses::from_palette(&palette());
    let mut out = SurfaceBlocks::new();
    for size in ChunkSize::ALL {
        // Empty, with a solid border: the border itself is never listed.
        surface_blocks(
            &filled(size, |_, b| if b { STONE } else { BlockId::AIR }),
            &classes,
            &mut out,
        )
        .unwrap();
        assert!(out.is_empty() && out.sub_blocks().is_empty(), "{size:?}");
        // Full and buried, of one opaque id, of mixed opaque ids, and of one transparent id.
        for id in [STONE, GRASS, WATER] {
            surface_blocks(&filled(size, |_, _| id), &classes, &mut out).unwrap();
            assert!(out.is_empty(), "{size:?} {id:?}");
        }
        let mixed = filled(size, |p, _| {
            if (p[0] + p[1] + p[2]) % 2 == 0 {
                STONE
            } else {
                SAND
            }
        });
        surface_blocks(&mixed, &classes, &mut out).unwrap();
        assert!(out.is_empty(), "{size:?} mixed");
        // A buried unknown id is not an error.
        let centre = size.edge() / 2;
        let buried = filled(size, |p, _| if p == [centre; 3] { UNKNOWN } else { STONE });
        surface_blocks(&buried, &classes, &mut out).unwrap();
        assert!(out.is_empty(), "{size:?} buried unknown");
    }
}

#[test]
fn full_chunks_show_their_shell_where_the_border_is_air_or_another_transparent_id() {
    let classes = BlockClasses::from_palette(&palette());
    let mut out = SurfaceBlocks::new();
    for size in ChunkSize::ALL {
        let e = size.edge() as usize;
        let shell = e * e * e - (e - 2) * (e - 2) * (e - 2);
        for (inside, border) in [(STONE, BlockId::AIR), (STONE, WATER), (WATER, GLASS)] {
            let chunk = filled(size, |_, b| if b { border } else { inside });
            surface_blocks(&chunk, &classes, &mut out).unwrap();
            assert_eq!(out.len(), shell, "{size:?} {inside:?} in {border:?}");
            // Only the sub-blocks touching the chunk's faces hold shell voxels.
            let n = e.div_ceil(16);
            let touching = n.pow(3) - n.saturating_sub(2).pow(3);
            assert_eq!(out.sub_blocks().len(), touching, "{size:?}");
        }
        // Stone next to water is exposed; water next to stone is not.
        let chunk = filled(size, |_, b| if b { STONE } else { WATER });
        surface_blocks(&chunk, &classes, &mut out).unwrap();
        assert!(out.is_empty(), "{size:?} water walled in by stone");
    }
}

#[test]
fn flags_follow_the_material_and_the_block_above() {
    let classes = BlockClasses::from_palette(&palette());
    let mut out = SurfaceBlocks::new();
    // A row of single blocks on the floor y = 0, each with what is above it at y = 1.
    let cases = [
        (STONE, BlockId::AIR, DrawBlockFlags::EMPTY),
        (GRASS, BlockId::AIR, DrawBlockFlags::HAS_CLUTTER),
        (GRASS, WATER, DrawBlockFlags::EMPTY),
        (GRASS, STONE, DrawBlockFlags::EMPTY),
        (
            MOSS,
            BlockId::AIR,
            DrawBlockFlags::HAS_CLUTTER | DrawBlockFlags::EMISSIVE,
        ),
        (SAND, BlockId::AIR, DrawBlockFlags::SMOOTH),
        (
            GLOW_SAND,
            BlockId::AIR,
            DrawBlockFlags::SMOOTH | DrawBlockFlags::EMISSIVE,
        ),
        (LAMP, BlockId::AIR, DrawBlockFlags::EMISSIVE),
        (WATER, BlockId::AIR, DrawBlockFlags::TRANSPARENT),
        (
            GLOW_GLASS,
            BlockId::AIR,
            DrawBlockFlags::TRANSPARENT | DrawBlockFlags::EMISSIVE,
        ),
    ];
    let chunk = PaddedChunk::from_fn(ChunkSize::S32, |x, y, z| {
        let i = x as usize / 2;
        if z != 1 || x % 2 == 0 || i >= cases.len() {
            return BlockId::AIR;
        }
        match y {
            1 => cases[i].0,
            2 => cases[i].1,
            _ => BlockId::AIR,
        }
    });
    surface_blocks(&chunk, &classes, &mut out).unwrap();
    let got: BTreeMap<[u32; 3], _> = out
        .iter_local()
        .map(|(pos, f)| (pos, (f.block, f.flags)))
        .collect();
    for (i, (id, above, flags)) in cases.into_iter().enumerate() {
        let pos = [2 * i as u32, 0, 0];
        assert_eq!(got.get(&pos), Some(&(id, flags)), "{id:?} under {above:?}");
    }
}
