//! The brute-force reference of the blocky meshers' output, written voxel by voxel with no bit
//! tricks: which unit faces are visible (with their id and corner AO), and which unit faces a
//! layer of quads covers.
//!
//! One file, included by path wherever a reference is needed, so there is one reference: the
//! mesher's property tests (`blocky_support/mod.rs`), the sample-model test
//! (`tests/tests/blocky_vox.rs`) and the fuzz bodies (`fuzz/bodies.rs`, also built by the
//! separate fuzz crate). It uses only `std`, `voxel_core` and `mesher`.

use std::collections::HashSet;

use mesher::BlockClasses;
use voxel_core::formats::{PackedQuad, PackedQuadFields};
use voxel_core::{BlockId, FaceDirection, PaddedChunk};

/// One unit face, as the reference sees it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct UnitFace {
    /// Padded position of the voxel.
    pub pos: [u32; 3],
    pub face: u8,
    pub id: u16,
    pub ao: [u8; 4],
}

/// Reads a padded voxel; out of the box is air.
pub(crate) fn voxel(padded: &PaddedChunk, pos: [i64; 3]) -> u16 {
    let p = padded.padded_edge() as i64;
    if pos.iter().any(|&a| a < 0 || a >= p) {
        return 0;
    }
    padded
        .get(pos[0] as u32, pos[1] as u32, pos[2] as u32)
        .unwrap()
        .0
}

/// Opaque for the purpose of hiding faces and occluding corners: not air and not transparent
/// (unknown ids count as opaque, as the meshers treat them).
pub(crate) fn solid(classes: &BlockClasses, id: u16) -> bool {
    id != 0 && !classes.is_transparent(BlockId(id))
}

/// The reference visibility rule.
pub(crate) fn face_visible(classes: &BlockClasses, id: u16, neighbour: u16) -> bool {
    if id == 0 {
        return false;
    }
    if classes.is_transparent(BlockId(id)) {
        neighbour == 0 || (classes.is_transparent(BlockId(neighbour)) && neighbour != id)
    } else {
        !solid(classes, neighbour)
    }
}

fn add(a: [i64; 3], b: [i64; 3]) -> [i64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn unit(axis: usize, k: i64) -> [i64; 3] {
    let mut v = [0; 3];
    v[axis] = k;
    v
}

/// The corner `(du, dv)` steps of `corners()` for a face (read back from voxel-core itself on a
/// unit quad, so the reference follows the documented corner order).
pub(crate) fn corner_steps(face: FaceDirection) -> [(i64, i64); 4] {
    let fields = PackedQuadFields {
        position: [0; 3],
        width: 1,
        height: 1,
        face,
        ao: [3; 4],
        block: BlockId(1),
    };
    let base = {
        let mut b = [0u32; 3];
        if face.is_positive() {
            b[face.normal_axis()] = 1;
        }
        b
    };
    fields.corners().map(|c| {
        (
            i64::from(c[face.width_axis()]) - i64::from(base[face.width_axis()]),
            i64::from(c[face.height_axis()]) - i64::from(base[face.height_axis()]),
        )
    })
}

/// The reference AO of the face of voxel `pos` facing `face`.
pub(crate) fn reference_ao(
    padded: &PaddedChunk,
    classes: &BlockClasses,
    pos: [i64; 3],
    face: FaceDirection,
) -> [u8; 4] {
    let n: [i64; 3] = face.normal().map(i64::from);
    let front = add(pos, n);
    let (wa, ha) = (face.width_axis(), face.height_axis());
    corner_steps(face).map(|(du, dv)| {
        let w = unit(wa, 2 * du - 1);
        let h = unit(ha, 2 * dv - 1);
        let s1 = solid(classes, voxel(padded, add(front, w)));
        let s2 = solid(classes, voxel(padded, add(front, h)));
        let c = solid(classes, voxel(padded, add(add(front, w), h)));
        if s1 && s2 {
            0
        } else {
            3 - (s1 as u8 + s2 as u8 + c as u8)
        }
    })
}

/// Every visible unit face of the chunk interior, split into (opaque, transparent), by brute
/// force over every voxel and direction.
pub(crate) fn reference_faces(
    padded: &PaddedChunk,
    classes: &BlockClasses,
    ao: bool,
) -> (Vec<UnitFace>, Vec<UnitFace>) {
    let e = padded.size().edge() as i64;
    let (mut opaque, mut transparent) = (Vec::new(), Vec::new());
    for z in 1..=e {
        for y in 1..=e {
            for x in 1..=e {
                let pos = [x, y, z];
                let id = voxel(padded, pos);
                for face in FaceDirection::ALL {
                    let nb = voxel(padded, add(pos, face.normal().map(i64::from)));
                    if !face_visible(classes, id, nb) {
                        continue;
                    }
                    let f = UnitFace {
                        pos: [x as u32, y as u32, z as u32],
                        face: face.index(),
                        id,
                        ao: if ao {
                            reference_ao(padded, classes, pos, face)
                        } else {
                            [3; 4]
                        },
                    };
                    if classes.is_transparent(BlockId(id)) {
                        transparent.push(f);
                    } else {
                        opaque.push(f);
                    }
                }
            }
        }
    }
    opaque.sort();
    transparent.sort();
    (opaque, transparent)
}

/// Expands quads into unit faces, reading each covered voxel's id and AO from the quad, and
/// checks on the way that a quad sits in its own direction group and stays in the chunk.
pub(crate) fn expand(quads: &[PackedQuad], face_index: usize, e: u32) -> Vec<UnitFace> {
    let mut out = Vec::new();
    for q in quads {
        let f = q.decode().expect("every emitted quad decodes");
        assert_eq!(
            usize::from(f.face.index()),
            face_index,
            "quad in the wrong direction group"
        );
        for j in 0..f.height {
            for i in 0..f.width {
                let mut pos = f.position.map(|a| a + 1);
                pos[f.face.width_axis()] += i;
                pos[f.face.height_axis()] += j;
                assert!(
                    pos.iter().all(|&a| (1..=e).contains(&a)),
                    "quad {f:?} leaves the chunk"
                );
                out.push(UnitFace {
                    pos,
                    face: f.face.index(),
                    id: f.block.0,
                    ao: f.ao,
                });
            }
        }
    }
    out
}

/// All unit faces covered by a layer, sorted, failing if two quads cover the same face.
pub(crate) fn covered(layer: &mesher::QuadLayer, e: u32) -> Vec<UnitFace> {
    let mut all = Vec::new();
    for (d, quads) in layer.faces.iter().enumerate() {
        all.extend(expand(quads, d, e));
    }
    let mut seen = HashSet::new();
    for f in &all {
        assert!(
            seen.insert((f.pos, f.face)),
            "two quads cover the face {f:?}"
        );
    }
    all.sort();
    all
}
