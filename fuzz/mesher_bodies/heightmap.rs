//! The `heightmap_boxes` body.

use mesher::MeshError;
use mesher::heightmap::heightmap_boxes as boxes_of;
use voxel_core::PaddedChunk;
use voxel_core::formats::{FaceDirection, ShellRun};

use super::input::{ChunkInput, chunk_input};
use super::{id_at, unknown};

/// `heightmap_boxes` on an arbitrary chunk ([`ChunkInput`]), appended to a list that already
/// holds a box. Against a per-column reference of the documented rule:
///
/// - it fails exactly when some column, read from the apron above down to its highest opaque
///   voxel, meets an unknown id inside the node first, naming such a voxel, and leaves the
///   list as it was;
/// - otherwise every box decodes and lies inside the node, no two boxes share a voxel, a
///   column with no opaque voxel in the node is under no box, and a column whose highest
///   opaque voxel in the node has no opaque voxel above it is under exactly one box with a
///   top face, at that voxel, of that voxel's id; no other box has a top face.
pub(crate) fn heightmap_boxes(data: &[u8]) {
    let Some(input) = chunk_input(data) else {
        return;
    };
    let ChunkInput {
        padded, classes, ..
    } = &input;
    let e = padded.size().edge();
    let first = ShellRun::new(0, 0, 0, 1, 1, 1);
    let mut out = vec![first];
    let result = boxes_of(padded, classes, &mut out);
    // The first unknown id each column meets from the top before an opaque voxel.
    let column_unknown = |x: u32, z: u32| {
        for py in (0..=e + 1).rev() {
            let id = id_at(padded, [x, py, z]);
            let inside = (1..=e).contains(&py);
            if inside && unknown(classes, id) {
                return Some(py);
            }
            if classes.is_opaque(id) {
                return None;
            }
        }
        None
    };
    let columns = || (1..=e).flat_map(|z| (1..=e).map(move |x| (x, z)));
    let any_unknown = columns().any(|(x, z)| column_unknown(x, z).is_some());
    match result {
        Err(MeshError::UnknownBlock { id, position }) => {
            assert!(
                any_unknown,
                "{id:?} at {position:?} refused, but no column meets one"
            );
            let [x, py, z] = position;
            assert!(unknown(classes, id) && id_at(padded, position) == id);
            assert_eq!(column_unknown(x, z), Some(py), "{position:?}");
            assert_eq!(out, [first], "the list changed on an error");
        }
        Err(other) => panic!("unexpected error {other}"),
        Ok(()) => {
            assert!(!any_unknown, "a column meets an unknown id and was boxed");
            assert_eq!(out[0], first, "the list's first box changed");
            check_boxes(padded, classes, &out[1..]);
        }
    }
}

fn check_boxes(padded: &PaddedChunk, classes: &mesher::BlockClasses, boxes: &[ShellRun]) {
    let e = padded.size().edge();
    let n = e as usize;
    let mut owner = vec![usize::MAX; n * n * n];
    let mut tops = vec![0u32; n * n];
    for (i, b) in boxes.iter().enumerate() {
        let f = b.decode().unwrap_or_else(|err| panic!("{b:?}: {err}"));
        let [x, y, z] = f.position;
        assert!(
            x + f.width <= e && y + f.height <= e && z < e,
            "{b:?} leaves the node"
        );
        for [vx, vy, vz] in b.voxels() {
            let at = vx as usize + n * (vy as usize + n * vz as usize);
            assert_eq!(owner[at], usize::MAX, "{b:?} overlaps box {}", owner[at]);
            owner[at] = i;
        }
        if b.has_side(FaceDirection::PosY) {
            let top = y + f.height - 1;
            for vx in x..x + f.width {
                let pos = [vx + 1, top + 1, z + 1];
                assert_eq!(id_at(padded, pos).0, b.block, "top of {b:?} at {pos:?}");
                tops[vx as usize + n * z as usize] += 1;
                // Its top voxel is the column's highest opaque voxel, open above.
                assert!(classes.is_opaque(id_at(padded, pos)), "{b:?} tops {pos:?}");
                assert!(!classes.is_opaque(id_at(padded, [vx + 1, top + 2, z + 1])));
                for py in top + 2..=e {
                    assert!(
                        !classes.is_opaque(id_at(padded, [vx + 1, py, z + 1])),
                        "{b:?}: an opaque voxel above its top"
                    );
                }
            }
        }
    }
    for z in 1..=e {
        for x in 1..=e {
            let highest = (1..=e)
                .rev()
                .find(|&py| classes.is_opaque(id_at(padded, [x, py, z])));
            let col = (x - 1) as usize + n * (z - 1) as usize;
            let boxed = (0..n)
                .any(|y| owner[(x - 1) as usize + n * (y + n * (z - 1) as usize)] != usize::MAX);
            match highest {
                None => assert!(!boxed, "column ({x}, {z}) has no opaque voxel but a box"),
                Some(t) => {
                    let open = !classes.is_opaque(id_at(padded, [x, t + 1, z]));
                    assert_eq!(tops[col], u32::from(open), "top faces of column ({x}, {z})");
                }
            }
        }
    }
}
