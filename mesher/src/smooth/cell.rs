//! The vertices of 4 cells at once, one cell per SIMD lane: the average of each cell's edge
//! crossings, the density gradient there, and the packed normal, with the formulas of
//! `fast-surface-nets` (so the two agree to rounding).
//!
//! Corner `i` of a cell is at offset `(i & 1, (i >> 1) & 1, i >> 2)` from its minimum corner.

use glam::Vec4;

use super::pack::oct16_encode_lanes;

/// The 12 cell edges as (lower corner, upper corner): 4 along x, 4 along y, 4 along z (in the
/// order [`cell_vertices`] and the row masks use).
pub(crate) const EDGES: [[usize; 2]; 12] = [
    [0, 1],
    [2, 3],
    [4, 5],
    [6, 7],
    [0, 2],
    [1, 3],
    [4, 6],
    [5, 7],
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7],
];

/// What [`cell_vertices`] computes for its 4 lanes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Vertices4 {
    /// Positions relative to each cell's minimum corner, x, y, z (each in `0..=1`).
    pub s: [Vec4; 3],
    /// Density gradients, x, y, z (not normalized).
    pub g: [Vec4; 3],
    /// The gradients packed as 8+8 bit octahedral normals ([`oct16_encode_lanes`]).
    pub normal: [u16; 4],
}

/// The vertices of 4 cells whose corner `i` densities are the lanes of `v[i]`. Every lane must
/// have corners on both sides of the surface (negative is inside).
///
/// A crossing edge from corner `a` to `b` crosses at `a + (b - a) * t` with
/// `t = v[a] / (v[a] - v[b])`; the vertex is the average of the crossings. The gradient along
/// an axis is the bilinear interpolation, at the vertex, of the differences `v[b] - v[a]` along
/// the 4 edges of that axis (central differences at the edge midpoints).
#[inline(always)]
pub(crate) fn cell_vertices(v: &[Vec4; 8]) -> Vertices4 {
    let i = v.map(|c| c.cmplt(Vec4::ZERO));
    // One edge from corner `a` to corner `b`: the crossing parameter (0 where the edge does
    // not cross; lanes that do not cross may divide by zero, `select` drops them), 1 where it
    // crosses, and `v[a] - v[b]`. Written out edge by edge so that it compiles to straight
    // SIMD code.
    let edge = |a: usize, b: usize| {
        let crosses = i[a] ^ i[b];
        let d = v[a] - v[b];
        (
            Vec4::select(crosses, v[a] / d, Vec4::ZERO),
            Vec4::select(crosses, Vec4::ONE, Vec4::ZERO),
            d,
        )
    };
    let (t01, o01, d01) = edge(0, 1);
    let (t23, o23, d23) = edge(2, 3);
    let (t45, o45, d45) = edge(4, 5);
    let (t67, o67, d67) = edge(6, 7);
    let (t02, o02, d02) = edge(0, 2);
    let (t13, o13, d13) = edge(1, 3);
    let (t46, o46, d46) = edge(4, 6);
    let (t57, o57, d57) = edge(5, 7);
    let (t04, o04, d04) = edge(0, 4);
    let (t15, o15, d15) = edge(1, 5);
    let (t26, o26, d26) = edge(2, 6);
    let (t37, o37, d37) = edge(3, 7);
    // Each crossing adds its parameter on its own axis and its lower corner's coordinates
    // (0 or 1) on the two others.
    let count =
        ((o01 + o23) + (o45 + o67)) + ((o02 + o13) + (o46 + o57)) + ((o04 + o15) + (o26 + o37));
    let sx = ((t01 + t23) + (t45 + t67)) + (o13 + o57) + (o15 + o37);
    let sy = ((t02 + t13) + (t46 + t57)) + (o23 + o67) + (o26 + o37);
    let sz = ((t04 + t15) + (t26 + t37)) + (o45 + o67) + (o46 + o57);
    let inv = Vec4::ONE / count;
    let s = [sx * inv, sy * inv, sz * inv];
    let [nx, ny, nz] = s.map(|c| Vec4::ONE - c);
    let [px, py, pz] = s;

    // The 4 edges of an axis sit low/high on the first of the two other axes, then low/high on
    // the second; the gradient is minus the weighted sum of `v[a] - v[b]`.
    let bilinear = |d: [Vec4; 4], lo1: Vec4, hi1: Vec4, lo2: Vec4, hi2: Vec4| {
        -((d[0] * lo1 + d[1] * hi1) * lo2 + (d[2] * lo1 + d[3] * hi1) * hi2)
    };
    let g = [
        bilinear([d01, d23, d45, d67], ny, py, nz, pz),
        bilinear([d02, d13, d46, d57], nx, px, nz, pz),
        bilinear([d04, d15, d26, d37], nx, px, ny, py),
    ];
    Vertices4 {
        s,
        g,
        normal: oct16_encode_lanes(g),
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3A;

    use super::*;

    /// The vertex of lane 0 of a single cell with corner densities `v`.
    fn one(v: [f32; 8]) -> (Vec3A, Vec3A) {
        let out = cell_vertices(&v.map(Vec4::splat));
        let s = Vec3A::new(out.s[0].x, out.s[1].x, out.s[2].x);
        let g = Vec3A::new(out.g[0].x, out.g[1].x, out.g[2].x);
        (s, g)
    }

    #[test]
    fn one_inside_corner() {
        // Corner 0 at -1, the rest at +1: crossings at the midpoints of the 3 edges from corner
        // 0, gradient pointing out of it.
        let mut v = [1.0f32; 8];
        v[0] = -1.0;
        let (s, g) = one(v);
        assert!(
            (s - Vec3A::splat(0.5 / 3.0)).abs().max_element() < 1e-6,
            "{s}"
        );
        assert!(g.min_element() > 0.0, "{g}");
    }

    #[test]
    fn flat_floor() {
        // Lower face inside at -1, upper face outside at +3: crossings at z = 0.25.
        let (s, g) = one([-1.0, -1.0, -1.0, -1.0, 3.0, 3.0, 3.0, 3.0]);
        assert_eq!(s, Vec3A::new(0.5, 0.5, 0.25));
        assert_eq!(g, Vec3A::new(0.0, 0.0, 4.0));
    }

    #[test]
    fn lanes_are_independent() {
        let mut v = [Vec4::ONE; 8];
        v[0] = Vec4::new(-1.0, 1.0, 1.0, -1.0);
        v[7] = Vec4::new(1.0, -1.0, 1.0, -1.0);
        v[3] = Vec4::new(1.0, 1.0, -2.0, 1.0);
        let out = cell_vertices(&v);
        for k in 0..4 {
            let lane = v.map(|c| Vec4::splat(c.to_array()[k]));
            let single = cell_vertices(&lane);
            for a in 0..3 {
                assert_eq!(out.s[a].to_array()[k], single.s[a].x);
                assert_eq!(out.g[a].to_array()[k], single.g[a].x);
            }
            assert_eq!(out.normal[k], single.normal[0]);
        }
    }
}
