//! Scene-graph transforms: MagicaVoxel's rotations (signed permutation matrices) plus integer
//! translations, and where they put a model's voxels.

use super::error::VoxError;
use super::reader::Dict;

/// A signed permutation matrix (MagicaVoxel's `_r`) and a translation (`_t`), in file axes
/// (z up).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Transform {
    /// `rows[r] = (column, sign)`: output axis `r` takes `sign * input[column]`.
    rows: [(usize, i64); 3],
    translation: [i64; 3],
}

impl Transform {
    /// No rotation, no translation.
    pub(super) const IDENTITY: Transform = Transform {
        rows: [(0, 1), (1, 1), (2, 1)],
        translation: [0; 3],
    };

    fn rotate(&self, v: [i64; 3]) -> [i64; 3] {
        self.rows.map(|(column, sign)| sign * v[column])
    }

    /// `v` rotated, then translated.
    pub(super) fn apply(&self, v: [i64; 3]) -> [i64; 3] {
        let r = self.rotate(v);
        std::array::from_fn(|i| r[i] + self.translation[i])
    }

    /// `self` after `child`: maps a point of the child's space into `self`'s parent space.
    /// Translations stay far inside `i64`: each is an `i32` and the graph is at most
    /// [`MAX_SCENE_DEPTH`](super::MAX_SCENE_DEPTH) deep.
    pub(super) fn then_child(&self, child: &Transform) -> Transform {
        let mut rows = [(0, 0); 3];
        for (r, row) in rows.iter_mut().enumerate() {
            let (mid, sign_outer) = self.rows[r];
            let (column, sign_inner) = child.rows[mid];
            *row = (column, sign_outer * sign_inner);
        }
        Transform {
            rows,
            translation: self.apply(child.translation),
        }
    }

    /// Where voxel `v` of a model of `size` lands (file axes).
    ///
    /// MagicaVoxel places a model with the centre of its box at the translation and rotates
    /// it about that point: the voxel's centre, relative to the box centre, is
    /// `v + 0.5 - size / 2`; it is rotated and translated, and the voxel it lands in is the
    /// floor of the result. Computed in doubled integers, so it is exact. Unrotated, this is
    /// `t + v - floor(size / 2)`, the convention of every MagicaVoxel reader.
    pub(super) fn place_voxel(&self, v: [u8; 3], size: [u32; 3]) -> [i64; 3] {
        let doubled_centre: [i64; 3] =
            std::array::from_fn(|i| 2 * i64::from(v[i]) + 1 - i64::from(size[i]));
        let r = self.rotate(doubled_centre);
        std::array::from_fn(|i| (r[i] + 2 * self.translation[i]).div_euclid(2))
    }

    /// The transform of a frame's `_r` and `_t` attributes (absent ones are the identity);
    /// `owner` names the node in errors.
    ///
    /// `_r` is a byte: bits 0-1 and 2-3 are the columns of the non-zero entries of rows 0 and
    /// 1 (row 2 takes the remaining column), bits 4-6 the signs of rows 0-2 (1 = negative).
    /// `_t` is three integers separated by spaces.
    pub(super) fn from_frame(
        frame: &Dict,
        owner: &dyn Fn() -> String,
    ) -> Result<Transform, VoxError> {
        let bad = |key: &str, value: &str, expected| VoxError::BadValue {
            owner: owner(),
            key: key.to_owned(),
            value: value.to_owned(),
            expected,
        };
        let mut t = Transform::IDENTITY;
        if let Some(r) = frame.get("_r") {
            const EXPECTED: &str = "a rotation byte (two different columns 0-2 in bits 0-3, signs in bits 4-6, bit 7 clear)";
            let byte: u8 = r.trim().parse().map_err(|_| bad("_r", r, EXPECTED))?;
            let (c0, c1) = (usize::from(byte & 3), usize::from((byte >> 2) & 3));
            if c0 == c1 || c0 > 2 || c1 > 2 || byte & 0x80 != 0 {
                return Err(bad("_r", r, EXPECTED));
            }
            let c2 = 3 - c0 - c1;
            let sign = |bit: u8| if byte & (1 << bit) != 0 { -1 } else { 1 };
            t.rows = [(c0, sign(4)), (c1, sign(5)), (c2, sign(6))];
        }
        if let Some(v) = frame.get("_t") {
            const EXPECTED: &str = "three 32-bit integers separated by spaces";
            let parts: Vec<i32> = v
                .split_whitespace()
                .map(str::parse)
                .collect::<Result<_, _>>()
                .map_err(|_| bad("_t", v, EXPECTED))?;
            let [x, y, z] = parts[..] else {
                return Err(bad("_t", v, EXPECTED));
            };
            t.translation = [x, y, z].map(i64::from);
        }
        Ok(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(r: Option<&str>, t: Option<&str>) -> Dict {
        let mut pairs = Vec::new();
        if let Some(r) = r {
            pairs.push(("_r", r));
        }
        if let Some(t) = t {
            pairs.push(("_t", t));
        }
        Dict::from_pairs(&pairs)
    }

    fn parse(r: Option<&str>, t: Option<&str>) -> Result<Transform, VoxError> {
        Transform::from_frame(&frame(r, t), &|| "node".into())
    }

    #[test]
    fn rotation_bytes_decode_to_signed_permutations() {
        // 4 = rows (x, y, z): identity.
        assert_eq!(parse(Some("4"), None).unwrap(), Transform::IDENTITY);
        // 0b0010001 = row 0 takes y, row 1 takes x, row 2 takes z; row 0 negated.
        let t = parse(Some("17"), Some("1 2 -3")).unwrap();
        assert_eq!(t.apply([1, 0, 0]), [1, 3, -3]);
        assert_eq!(t.apply([0, 1, 0]), [0, 2, -3]);
        // The format text's example: rows (0 1 0), (0 0 -1), (-1 0 0).
        let t = parse(Some(&(1 | 2 << 2 | 1 << 5 | 1 << 6).to_string()), None).unwrap();
        assert_eq!(t.apply([1, 2, 3]), [2, -3, -1]);
        for bad in ["3", "0", "abc", "300", "15", "132", "-4", ""] {
            assert!(
                matches!(parse(Some(bad), None), Err(VoxError::BadValue { .. })),
                "{bad:?}"
            );
        }
        for bad in ["1 2", "1 2 3 4", "1 x 3", "1 2 99999999999"] {
            assert!(
                matches!(parse(None, Some(bad)), Err(VoxError::BadValue { .. })),
                "{bad:?}"
            );
        }
    }

    #[test]
    fn composing_transforms_equals_applying_them_in_turn() {
        let parent = parse(Some("17"), Some("10 0 5")).unwrap();
        let child = parse(Some("40"), Some("-2 7 1")).unwrap();
        let composed = parent.then_child(&child);
        for p in [[0, 0, 0], [1, 2, 3], [-4, 5, -6]] {
            assert_eq!(composed.apply(p), parent.apply(child.apply(p)));
        }
    }

    #[test]
    fn unrotated_models_sit_at_translation_minus_half_their_size() {
        let t = parse(None, Some("10 -4 0")).unwrap();
        for size in [[1, 2, 3], [4, 5, 6], [256, 1, 7]] {
            for v in [[0, 0, 0], [0, 1, 2], [0, 0, 0]] {
                let placed = t.place_voxel(v, size);
                for i in 0..3 {
                    let expected = t.translation[i] + i64::from(v[i]) - i64::from(size[i] / 2);
                    assert_eq!(placed[i], expected, "size {size:?} voxel {v:?}");
                }
            }
        }
    }

    #[test]
    fn rotation_turns_a_model_about_its_box_centre() {
        // A half turn about z (rows 0 and 1 negated) keeps the box of a model whose x and y
        // sides are both odd or both even, and maps corner to opposite corner.
        let half_turn = parse(Some(&(4 | 1 << 4 | 1 << 5).to_string()), Some("3 3 3")).unwrap();
        for size in [[3, 5, 2], [4, 2, 3]] {
            let corner = half_turn.place_voxel([0, 0, 0], size);
            let opposite = Transform {
                translation: [3, 3, 3],
                ..Transform::IDENTITY
            }
            .place_voxel([(size[0] - 1) as u8, (size[1] - 1) as u8, 0], size);
            assert_eq!(corner[..2], opposite[..2], "size {size:?}");
        }
        // A quarter turn keeps the centre voxel of an odd cube where it was.
        let quarter = parse(Some("17"), Some("0 0 0")).unwrap();
        assert_eq!(quarter.place_voxel([1, 1, 1], [3, 3, 3]), [0, 0, 0]);
    }
}
