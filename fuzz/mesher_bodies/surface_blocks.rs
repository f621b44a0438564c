//! The `surface_blocks` body.

use mesher::{MeshError, SUB_BLOCK_EDGE, SurfaceBlocks};
use voxel_core::formats::{DrawBlockFields, DrawBlockFlags};
use voxel_core::{MaterialClass, PaddedChunk};

use super::input::{ChunkInput, chunk_input};
use super::shells::{chunk_index, face_bits, other_chunk};
use super::{id_at, unknown};

/// Every chunk-local position in the documented output order: sub-blocks of 16^3 in z, y, x
/// order, and within each, z, then y, then x.
fn output_order(padded: &PaddedChunk) -> Vec<[u32; 3]> {
    let e = padded.size().edge();
    let per_axis = e.div_ceil(SUB_BLOCK_EDGE);
    let span = |s: u32| s * SUB_BLOCK_EDGE..((s + 1) * SUB_BLOCK_EDGE).min(e);
    let mut order = Vec::new();
    for sz in 0..per_axis {
        for sy in 0..per_axis {
            for sx in 0..per_axis {
                for z in span(sz) {
                    for y in span(sy) {
                        order.extend(span(sx).map(|x| [x, y, z]));
                    }
                }
            }
        }
    }
    order
}

/// `surface_blocks` on an arbitrary chunk ([`ChunkInput`]), in a fresh buffer and in one that
/// first held another chunk (same result). Against the per-voxel exposure rule:
///
/// - it fails exactly when an exposed voxel holds an unknown id, naming the first such voxel in
///   output order, and leaves the buffer empty;
/// - otherwise the blocks are exactly the exposed voxels, in the documented order (sub-blocks in
///   z, y, x order, then z, y, x within each), each with its id and the flags of its material:
///   `TRANSPARENT` for the transparent class, `EMISSIVE` for `emission > 0`, `SMOOTH` for the
///   smoothable class, `HAS_CLUTTER` for a clutter-bearing block with air above (the border
///   included); sub-block ranges list only non-empty sub-blocks, in order, contiguous, and each
///   block's packed position lies inside its sub-block.
pub(crate) fn surface_blocks(data: &[u8]) {
    let Some(input) = chunk_input(data) else {
        return;
    };
    let ChunkInput {
        padded,
        palette,
        classes,
    } = &input;
    let faces = face_bits(padded, classes);
    let padded_of = |local: [u32; 3]| local.map(|a| a + 1);
    let exposed: Vec<[u32; 3]> = output_order(padded)
        .into_iter()
        .filter(|&local| faces[chunk_index(padded, padded_of(local))] != 0)
        .collect();
    let first_unknown = exposed
        .iter()
        .map(|&local| (padded_of(local), id_at(padded, padded_of(local))))
        .find(|&(_, id)| unknown(classes, id));

    let mut fresh = SurfaceBlocks::new();
    let result = mesher::surface_blocks(padded, classes, &mut fresh);
    let mut reused = SurfaceBlocks::new();
    // The other chunk's result does not matter, only that the buffer held it.
    let _ = mesher::surface_blocks(&other_chunk(padded.size()), classes, &mut reused);
    let again = mesher::surface_blocks(padded, classes, &mut reused);
    assert_eq!(result, again, "a reused buffer gives another result");
    assert_eq!(
        fresh.blocks(),
        reused.blocks(),
        "a reused buffer gives other blocks"
    );
    assert_eq!(
        fresh.sub_blocks(),
        reused.sub_blocks(),
        "a reused buffer gives other ranges"
    );

    match result {
        Ok(()) => {
            assert_eq!(first_unknown, None, "an exposed unknown id was listed");
            check_sub_blocks(padded, &fresh);
            let expected: Vec<([u32; 3], DrawBlockFields)> = exposed
                .iter()
                .map(|&local| {
                    let pos = padded_of(local);
                    let block = id_at(padded, pos);
                    let material = palette.get(block).expect("a known id");
                    let above = id_at(padded, [pos[0], pos[1] + 1, pos[2]]);
                    let flag = |on: bool, flag: DrawBlockFlags| {
                        if on { flag } else { DrawBlockFlags::EMPTY }
                    };
                    let flags = flag(
                        material.class == MaterialClass::Transparent,
                        DrawBlockFlags::TRANSPARENT,
                    )
                    .union(flag(material.emission > 0, DrawBlockFlags::EMISSIVE))
                    .union(flag(
                        material.class == MaterialClass::Smoothable,
                        DrawBlockFlags::SMOOTH,
                    ))
                    .union(flag(
                        material.class == MaterialClass::ClutterBearing && above.is_air(),
                        DrawBlockFlags::HAS_CLUTTER,
                    ));
                    let sub = local.map(|a| a % SUB_BLOCK_EDGE);
                    let fields = DrawBlockFields {
                        position: sub,
                        flags,
                        block,
                    };
                    (local, fields)
                })
                .collect();
            let got: Vec<([u32; 3], DrawBlockFields)> = fresh.iter_local().collect();
            assert_eq!(got.len(), expected.len(), "number of surface blocks");
            for (g, x) in got.iter().zip(&expected) {
                assert_eq!(g, x, "surface block (got, expected)");
            }
        }
        Err(MeshError::UnknownBlock { id, position }) => {
            assert_eq!(
                Some((position, id)),
                first_unknown,
                "not the first exposed unknown voxel in output order"
            );
            assert!(
                fresh.is_empty() && fresh.sub_blocks().is_empty(),
                "blocks left after an error"
            );
        }
        Err(other) => panic!("unexpected error {other:?}"),
    }
}

/// The sub-block ranges: in order, non-empty, contiguous from 0 to the last block, and every
/// block's packed position inside its sub-block (the last sub-block of a 62^3 chunk is 14
/// voxels wide).
fn check_sub_blocks(padded: &PaddedChunk, out: &SurfaceBlocks) {
    let e = padded.size().edge();
    let per_axis = e.div_ceil(SUB_BLOCK_EDGE);
    let mut next = 0usize;
    let mut previous: Option<[u8; 3]> = None;
    for range in out.sub_blocks() {
        let c = range.coord.map(u32::from);
        assert!(c.iter().all(|&a| a < per_axis), "{range:?}");
        let key = |c: [u8; 3]| (c[2], c[1], c[0]);
        if let Some(p) = previous {
            assert!(
                key(p) < key(range.coord),
                "sub-blocks out of order: {p:?}, {range:?}"
            );
        }
        previous = Some(range.coord);
        assert!(range.count >= 1, "an empty sub-block is listed: {range:?}");
        assert_eq!(
            range.offset as usize, next,
            "{range:?} does not follow the last"
        );
        next += range.count as usize;
        let blocks = out.sub_block(range);
        assert_eq!(blocks.len(), range.count as usize, "{range:?}");
        for block in blocks {
            let fields = block.decode();
            for (axis, &p) in fields.position.iter().enumerate() {
                let width = SUB_BLOCK_EDGE.min(e - c[axis] * SUB_BLOCK_EDGE);
                assert!(p < width, "{fields:?} outside {range:?}");
            }
        }
    }
    assert_eq!(next, out.len(), "the ranges do not cover every block");
}
