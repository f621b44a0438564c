//! Per-vertex ambient occlusion: the corner rule, the lookup tables the meshers use, and the
//! quad-diagonal flip.
//!
//! # The rule
//!
//! A face's corner touches three voxels of the layer in front of the face (the layer the face
//! looks into): the two that share an edge with the corner (`side1`, `side2`) and the one that
//! only shares the corner point (`corner`). Only opaque voxels occlude:
//!
//! ```text
//!   front layer, seen from outside          ao = 0  if side1 and side2
//!   +--------+--------+                      ao = 3 - (side1 + side2 + corner)  otherwise
//!   | corner | side2  |
//!   +--------*--------+  * = the face corner  (3 = unoccluded, 0 = darkest)
//!   | side1  | (front |
//!   |        |  cell) |
//!   +--------+--------+
//! ```
//!
//! Values are stored per corner in [`PackedQuad`] in the order
//! of `PackedQuadFields::corners`.
//!
//! # The flip
//!
//! A quad is two triangles, and the colour is interpolated per triangle, so a quad whose AO
//! varies looks different depending on which diagonal splits it. [`triangle_indices`] picks
//! the diagonal whose corners are brighter in sum, which keeps a single dark corner inside one
//! triangle instead of smearing it along the diagonal. The GPU shader mirrors it from the AO
//! bits alone (no extra bit is stored):
//!
//! ```text
//! flip   = ao1 + ao3 > ao0 + ao2            // split along corners 1-3 instead of 0-2
//! corner = ([0, 1, 2, 0, 2, 3][vertex_in_quad] + select(0, 1, flip)) % 4
//! ```

use voxel_core::FaceDirection;
use voxel_core::formats::PackedQuad;

/// Ambient occlusion of one face corner from its three front-layer neighbours (see the
/// [module docs](self)): `3` unoccluded, `0` darkest.
#[inline]
pub const fn corner_ao(side1: bool, side2: bool, corner: bool) -> u8 {
    if side1 && side2 {
        0
    } else {
        3 - (side1 as u8 + side2 as u8 + corner as u8)
    }
}

/// Local vertex indices (into the quad's 4 corners, order of `PackedQuadFields::corners`) of
/// the two counter-clockwise triangles of a quad with per-corner AO `ao`.
///
/// The default split is along the 0-2 diagonal: `(0, 1, 2), (0, 2, 3)`. When
/// `ao[1] + ao[3] > ao[0] + ao[2]` the quad is split along the 1-3 diagonal instead:
/// `(1, 2, 3), (1, 3, 0)`, which is the default pattern with every index plus one (mod 4), so
/// a shader can derive it from the AO bits as shown in the [module docs](self). Both keep the
/// counter-clockwise winding.
///
/// ```
/// use mesher::blocky::triangle_indices;
/// assert_eq!(triangle_indices([3, 3, 3, 3]), [0, 1, 2, 0, 2, 3]);
/// // One dark corner (0): split along 1-3 so only one triangle touches it.
/// assert_eq!(triangle_indices([0, 3, 3, 3]), [1, 2, 3, 1, 3, 0]);
/// ```
#[inline]
pub const fn triangle_indices(ao: [u8; 4]) -> [u32; 6] {
    let flip = (ao[1] as u32 + ao[3] as u32 > ao[0] as u32 + ao[2] as u32) as u32;
    let base = [0u32, 1, 2, 0, 2, 3];
    let mut out = [0u32; 6];
    let mut i = 0;
    while i < 6 {
        out[i] = (base[i] + flip) & 3;
        i += 1;
    }
    out
}

/// The `(du, dv)` steps of the 4 corners along the width and height axes, in the order of
/// `PackedQuadFields::corners` (the second row swaps them; see that method's table).
const fn corner_steps(face: FaceDirection) -> [(i32, i32); 4] {
    let swap = matches!(
        face,
        FaceDirection::PosX | FaceDirection::PosY | FaceDirection::NegZ
    );
    let steps = [(0, 0), (1, 0), (1, 1), (0, 1)];
    let mut out = [(0, 0); 4];
    let mut i = 0;
    while i < 4 {
        let (a, b) = steps[i];
        out[i] = if swap { (b, a) } else { (a, b) };
        i += 1;
    }
    out
}

/// For each corner (order of `PackedQuadFields::corners`), the line and bit offsets (each
/// `-1` or `+1`) of its diagonal front voxel, the way the meshers see a slice (see
/// [`super::slices`], bits along the face's width axis and lines along its height axis): the
/// corner's two side voxels are at `(line, 0)` and `(0, bit)`.
const fn corner_offsets(face: FaceDirection) -> [(i32, i32); 4] {
    let steps = corner_steps(face);
    let mut out = [(0, 0); 4];
    let mut i = 0;
    while i < 4 {
        let (du, dv) = steps[i];
        let (dw, dh) = (2 * du - 1, 2 * dv - 1);
        out[i] = (dh, dw);
        i += 1;
    }
    out
}

/// The packed AO byte (corner `i` at bits `2i..2i+2`) for every 3 x 3 neighbourhood of the
/// front layer, for one face direction.
///
/// The neighbourhood is indexed the way the meshers see a slice: `lines` and `bits` (see
/// [`super::slices`]). Code bit `3 * r + c` is the front voxel at line offset `r - 1` and bit
/// offset `c - 1`.
const fn ao_table(face: FaceDirection) -> [u8; 512] {
    let corners = corner_offsets(face);
    let mut table = [0u8; 512];
    let mut code = 0usize;
    while code < 512 {
        let mut ao = [0u8; 4];
        let mut i = 0;
        while i < 4 {
            let (dl, db) = corners[i];
            ao[i] = corner_ao(solid(code, dl, 0), solid(code, 0, db), solid(code, dl, db));
            i += 1;
        }
        table[code] = PackedQuad::pack_ao(ao) as u8;
        code += 1;
    }
    table
}

/// True if neighbourhood `code` has an opaque voxel at line offset `line`, bit offset `bit`.
const fn solid(code: usize, line: i32, bit: i32) -> bool {
    (code >> (3 * (line + 1) + (bit + 1)) as usize) & 1 == 1
}

/// The AO tables of the six directions, in [`FaceDirection::ALL`] order.
pub(crate) static AO_TABLES: [[u8; 512]; 6] = [
    ao_table(FaceDirection::PosX),
    ao_table(FaceDirection::NegX),
    ao_table(FaceDirection::PosY),
    ao_table(FaceDirection::NegY),
    ao_table(FaceDirection::PosZ),
    ao_table(FaceDirection::NegZ),
];

/// Unpacks an AO byte into the 4 corner values.
#[cfg(test)]
pub(crate) const fn unpack(ao: u8) -> [u8; 4] {
    PackedQuad::unpack_ao(ao as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corner_rule() {
        assert_eq!(corner_ao(false, false, false), 3);
        assert_eq!(corner_ao(false, false, true), 2);
        assert_eq!(corner_ao(true, false, false), 2);
        assert_eq!(corner_ao(true, false, true), 1);
        assert_eq!(corner_ao(true, true, false), 0);
        assert_eq!(corner_ao(true, true, true), 0);
    }

    #[test]
    fn empty_neighbourhood_is_unoccluded_and_full_is_dark() {
        for table in &AO_TABLES {
            assert_eq!(unpack(table[0]), [3; 4]);
            // Everything but the centre (the front cell itself, never opaque for a visible face).
            assert_eq!(unpack(table[511 & !(1 << 4)]), [0; 4]);
        }
    }

    #[test]
    fn flip_keeps_winding_and_uses_every_corner() {
        for code in 0..256u32 {
            let ao = unpack(code as u8);
            let idx = triangle_indices(ao);
            let mut seen = [false; 4];
            idx.iter().for_each(|&i| seen[i as usize] = true);
            assert!(seen.iter().all(|&s| s));
            // Both triangles are cyclic rotations of a counter-clockwise walk 0-1-2-3.
            for tri in idx.chunks_exact(3) {
                let turns = (tri[1] + 4 - tri[0]) % 4
                    + (tri[2] + 4 - tri[1]) % 4
                    + (tri[0] + 4 - tri[2]) % 4;
                assert_eq!(turns, 4, "{idx:?}");
            }
        }
    }
}
