//! Smooth meshers: SurfaceNets on density grids ([`SurfaceNets`]) and on block occupancy,
//! NoCubes-style ([`NoCubes`]).
//!
//! # SurfaceNets on a density grid
//!
//! **Samples.** A grid of `dx * dy * dz` density samples, x fastest ([`GridShape`]), of type
//! `f32` or `i8`. **Negative is inside** (solid), zero and positive are outside, as in
//! `fast-surface-nets`; `-0.0` is outside. An `i8` sample `q` stands for the density
//! `q * I8_DENSITY_STEP` (`1 / 127`: `-127..=127` is `-1.0..=1.0`); [`quantize_density`] makes
//! one from an `f32`.
//!
//! **Vertices.** Each cell (the cube between 8 neighbouring samples) whose corners are not all
//! on one side gets one vertex: the average of the points where the surface crosses its edges
//! (linear interpolation of the density along each crossing edge), and a normal, the density
//! gradient there: on each axis the bilinear interpolation of the differences along the
//! cell's 4 edges of that axis (central differences at the edge midpoints). Both are the
//! formulas of `fast-surface-nets` 0.2, which the tests compare against (positions within
//! 1e-5, same count, same order).
//!
//! **Quads.** Each grid edge whose ends lie on different sides gives one quad joining the
//! vertices of the 4 cells around it, counter-clockwise seen from outside, split along its
//! shorter diagonal (see [`SmoothMesh`]).
//!
//! # Seamless chunks: the padding contract
//!
//! A chunk of `N^3` samples is meshed from the padded grid of `(N + 2)^3` samples
//! ([`GridShape::padded_chunk`]): its own samples at padded `1..=N` on each axis and one sample
//! of each neighbour on each side (the layout of `voxel_core::PaddedChunk`). Along one axis,
//! for the chunk at world sample `o` and the next one at `o + N`:
//!
//! ```text
//! world sample        o-1   o    o+1        o+N-1  o+N   o+N+1
//!                      |    |    |     ...    |     |     |
//! chunk A padded       0    1    2            N    N+1             (own: 1..=N)
//! chunk A cells         [ 0 ][ 1 ]   ...  [N-1][ N ]               (N + 1 cells)
//! chunk A edges             |----|   ...  |----|----|              (lower sample own)
//! chunk B padded                              0     1     2  ...   (own: 1..=N)
//! chunk B cells                                [ 0 ][ 1 ]  ...
//! chunk B edges                                     |----| ...
//! ```
//!
//! - **Vertices.** A grid makes a vertex in every surface cell (`0..=N` on each axis) that an
//!   owned crossing edge touches. A's cell `N` and B's cell `0` read the same 8 samples, so
//!   they get the same vertex (the same position up to the translation by `N`).
//! - **Quads.** A grid makes the quad of an edge only when the edge's lower sample is one of its
//!   own samples on all three axes. Every edge of the world has exactly one lower sample, owned
//!   by exactly one chunk: no edge is meshed twice and none is missed. The 4 cells around an
//!   owned edge lie in `0..=N` on each axis, so every quad's vertices exist in the grid.
//!
//! So the union of the chunk meshes, each translated by its origin, is the mesh of the whole
//! grid: no gaps and no double faces (tested in `tests/tests/smooth_seams.rs` by meshing
//! neighbouring chunks and the region they cover). Unlike `fast-surface-nets`, the packed mesh
//! has no vertices that no quad uses (surface cells on the grid's outer layers whose crossing
//! edges all belong to a neighbour): a few percent fewer vertices on a chunk that the
//! surface crosses often. The unquantized output ([`SmoothMeshF32`]) keeps them, in
//! `fast-surface-nets`' order, so that the two can be compared vertex for vertex.
//!
//! # Output and bytes
//!
//! [`SmoothMesh`]: 16-byte [`BlockVertex`](voxel_core::formats::BlockVertex)es (unorm16
//! position in sample coordinates over [`GridShape::extent`], which for a padded chunk is the
//! `BlockVertex` convention "chunk-local position + 1"; octahedral 8+8 normal, see
//! [`OCT16_FAST_MAX_ERROR_DEGREES`]; block id) and quads of 4 vertex indices, stored in the
//! narrowest of three forms that holds them ([`SmoothQuads`]):
//!
//! - **compact**, 6 B per quad ([`voxel_core::formats::compact_quad`]): `a`, `b` and one word
//!   of two 6-bit deltas and a 4-bit layout. Vertices are numbered in cell scan order, so the
//!   4 cells around a crossing edge are two pairs of neighbours along x or y whose indices are
//!   at most one row of cells apart: every quad of a grid with at most 64 samples a row (every
//!   chunk grid) fits, while the mesh has at most 65,536 vertices. The mesher writes each
//!   record from a table per edge axis and corner order, without searching.
//! - **u16**, 8 B per quad: where some quad does not fit (rows longer than 64 samples with many
//!   vertices).
//! - **u32**, 16 B per quad: past 65,536 vertices.
//!
//! So a chunk costs 16 B per vertex + 6 B per quad: on a closed surface (about one vertex per
//! quad) about 22 B per quad (the benchmark inputs' figures: `BENCHMARKS.md`, SurfaceNets).
//! [`SmoothMeshF32`] is the unquantized output for tests and tools.
//!
//! # How it is fast
//!
//! - One up-front pass reads the samples 64 at a time (4 per SIMD compare) into inside bits,
//!   checking for NaN / infinity on the way; rows of cells are then classified 64 at a time
//!   with bit operations (which cells get a vertex, which make quads), and rows whose samples
//!   are all on one side are skipped. Empty space costs about one bit operation per sample.
//! - Vertices are computed 4 cells per SIMD lane group, 8 cells per batch (two independent
//!   groups, so the division-bound dependency chains overlap), all 12 edges at once, without
//!   branches; normals are packed in the same lanes.
//! - Quads are made per z slice after its vertices, one pass per axis, with a table instead
//!   of branches for the winding and diagonal. Few branches depend on the data, so few are
//!   mispredicted, where `fast-surface-nets` branches per cell and per edge.
//!
//! # NoCubes: smoothing blocky data
//!
//! See [`NoCubes`]: smoothable blocks become a SurfaceNets surface, the other opaque blocks stay
//! cubes (greedy quads), meeting the smooth surface edge to edge.

mod cell;
mod density;
mod mesh;
mod nets;
mod nocubes;
mod pack;
mod shape;

pub use density::{I8_DENSITY_STEP, quantize_density};
pub use mesh::{SmoothMesh, SmoothMeshF32, SmoothQuads, U16_INDEX_LIMIT};
pub use nets::SurfaceNets;
pub use nocubes::{NoCubes, NoCubesStats};
pub use pack::{FALLBACK_NORMAL, OCT16_FAST_MAX_ERROR_DEGREES, PositionPacker, oct16_encode_fast};
pub use shape::GridShape;

use voxel_core::formats::compact_quad::COMPACT_QUAD_FORMS;

/// The corners of a cell (bit `i` = corner `i`) that are owned samples of the grid, from one
/// axis: the cell at coordinate `c` of `cells` cells on `axis` (0 = x, 1 = y, 2 = z) has
/// corners at samples `c` and `c + 1`, and the owned samples are `1..=cells - 1`. AND the three
/// axes' masks for the cell's mask.
#[inline]
pub(crate) fn owned_corners(axis: u32, c: usize, cells: usize) -> u8 {
    // Corners with axis bit 0 / 1, for x, y and z.
    const LOW: [u8; 3] = [0x55, 0x33, 0x0f];
    let low = if c >= 1 { LOW[axis as usize] } else { 0 };
    let high = if c + 1 < cells {
        !LOW[axis as usize]
    } else {
        0
    };
    low | high
}

/// The edges of a cell that cross the surface, one byte per axis: bit `i` of `x` is the x edge
/// whose lower corner is corner `i` (so only corners with x bit 0 appear), likewise `y`, `z`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct EdgeLanes {
    x: u8,
    y: u8,
    z: u8,
}

impl EdgeLanes {
    /// The edges joining a `smooth` corner and a corner that is not `opaque` (`smooth` is a
    /// subset of `opaque`).
    #[inline]
    pub(crate) fn smooth_faces(opaque: u8, smooth: u8) -> EdgeLanes {
        let along = |shift: u32, lanes: u8| {
            ((smooth & !(opaque >> shift)) | ((smooth >> shift) & !opaque)) & lanes
        };
        EdgeLanes {
            x: along(1, 0x55),
            y: along(2, 0x33),
            z: along(4, 0x0f),
        }
    }

    /// The lower corners of all the edges.
    #[inline]
    pub(crate) fn any(self) -> u8 {
        self.x | self.y | self.z
    }

    /// The edges from corner 0 whose corner 0 is in `owned`: bit 0 = x, 1 = y, 2 = z.
    #[inline]
    pub(crate) fn at_corner0(self, owned: u8) -> u8 {
        if owned & 1 == 0 {
            0
        } else {
            (self.x & 1) | (self.y & 1) << 1 | (self.z & 1) << 2
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_faces_need_a_smoothable_voxel_next_to_a_hole() {
        // Corner 0 smoothable, corner 1 air: the x edge from corner 0.
        assert_eq!(EdgeLanes::smooth_faces(0b0000_0001, 0b0000_0001).x, 1);
        // Corner 0 is a cube, everything else air: no smooth face.
        assert_eq!(EdgeLanes::smooth_faces(0b0000_0001, 0).any(), 0);
        // Smoothable corner 0 surrounded by cubes on its 3 edges, air at corner 7: none.
        assert_eq!(EdgeLanes::smooth_faces(0b0111_1111, 0b0000_0001).any(), 0);
        // Air at corner 3, smoothable at corner 2: the x edge 2-3.
        let lanes = EdgeLanes::smooth_faces(0b1111_0111, 0b0000_0100);
        assert_eq!((lanes.x, lanes.y, lanes.z), (0b100, 0, 0));
    }

    #[test]
    fn owned_corners_on_the_borders() {
        assert_eq!(owned_corners(0, 0, 5), 0xaa);
        assert_eq!(owned_corners(0, 2, 5), 0xff);
        assert_eq!(owned_corners(0, 4, 5), 0x55);
        assert_eq!(owned_corners(2, 0, 5), 0xf0);
        assert_eq!(owned_corners(1, 4, 5), 0x33);
        // One cell: no owned sample.
        assert_eq!(owned_corners(1, 0, 1), 0);
    }
}

/// The quad of one crossing edge: the vertices of the 4 cells around it, in the order
/// `v1` = the cell whose minimum corner is the edge's lower sample, `v2` and `v3` one step back
/// along the two other axes (in the order `y, z` for an x edge, `z, x` for y, `x, y` for z),
/// `v4` both steps back.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Quad {
    /// The lower sample is inside, so the surface faces along +axis.
    outward: bool,
    /// The edge's axis (0 = x, 1 = y, 2 = z).
    axis: u8,
    v: [u32; 4],
}

/// Indices into [`Quad::v`] (v1..v4 = 0..3) of the corners, by (v1-v4 shorter, outward); a
/// table instead of branches, since both conditions are unpredictable.
const ORDER: [[usize; 4]; 4] = [
    [1, 0, 2, 3], // long, inward:   v2 v1 v3 v4
    [1, 3, 2, 0], // long, outward:  v2 v4 v3 v1
    [0, 2, 3, 1], // short, inward:  v1 v3 v4 v2
    [0, 1, 3, 2], // short, outward: v1 v2 v4 v3
];

/// The compact-quad `form | rotation << 2` of each [`ORDER`] row, for quads whose pairs are
/// `(v1, v2)` and `(v3, v4)` (x and z edges: `v2` is one step back along y or x from `v1`, `v4`
/// from `v3`) and for quads whose pairs are `(v1, v3)` and `(v2, v4)` (y edges: the step along
/// x is `v3`), with `a = v1` and `b` the other pair's first vertex. Found at compile time by
/// matching each row against [`COMPACT_QUAD_FORMS`]; a row without a match fails the build.
const PAIRED_CODES: [[u32; 4]; 2] = {
    // Selector (0 = a, 1 = a - da, 2 = b, 3 = b - db) of v1..v4 for each pairing.
    let selectors: [[u8; 4]; 2] = [[0, 1, 2, 3], [0, 2, 1, 3]];
    let mut codes = [[u32::MAX; 4]; 2];
    let mut pairing = 0;
    while pairing < 2 {
        let mut o = 0;
        while o < 4 {
            let mut code = 0;
            while code < 16 {
                let (form, rotation) = (code & 3, code >> 2);
                let mut i = 0;
                while i < 4 {
                    let want = selectors[pairing][ORDER[o][i]];
                    if COMPACT_QUAD_FORMS[form][(i + rotation) % 4] != want {
                        break;
                    }
                    i += 1;
                }
                if i == 4 {
                    codes[pairing][o] = code as u32;
                    break;
                }
                code += 1;
            }
            assert!(code < 16, "every quad layout is a compact form");
            o += 1;
        }
        pairing += 1;
    }
    codes
};

/// A quad's corners and the fields of its compact record (see
/// [`voxel_core::formats::compact_quad`]); the deltas are not checked: [`SmoothMesh`] stores
/// the record only when both are in `1..=63`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PairedQuad {
    pub(crate) corners: [u32; 4],
    pub(crate) a: u32,
    pub(crate) da: u32,
    pub(crate) b: u32,
    pub(crate) db: u32,
    /// `form | rotation << 2`.
    pub(crate) code: u32,
}

impl Quad {
    #[inline]
    pub(crate) fn new(axis: u8, outward: bool, v: [u32; 4]) -> Quad {
        Quad { outward, axis, v }
    }

    /// The row of [`ORDER`] for this quad (`dist2` gives squared distances; on a tie the
    /// `v2`-`v3` diagonal is the shorter).
    #[inline(always)]
    fn order<D: PartialOrd>(&self, dist2: impl Fn(u32, u32) -> D) -> usize {
        let [v1, v2, v3, v4] = self.v;
        let short_14 = dist2(v1, v4) < dist2(v2, v3);
        usize::from(short_14) * 2 + usize::from(self.outward)
    }

    /// The corners counter-clockwise from outside, rotated so that corners 0 and 2 span the
    /// shorter diagonal (`dist2` gives squared distances; on a tie the `v2`-`v3` diagonal).
    #[inline]
    pub(crate) fn corners<D: PartialOrd>(self, dist2: impl Fn(u32, u32) -> D) -> [u32; 4] {
        let order = ORDER[self.order(dist2)];
        order.map(|i| self.v[i])
    }

    /// [`corners`](Self::corners) and the compact record fields of a SurfaceNets quad, whose
    /// vertices are numbered in cell scan order: `v1` has the largest index, and the cell one
    /// step back along x has the index just below its neighbour's, so along y the step is at
    /// most a row of cells. With a table per axis instead of the general encoder's search.
    #[inline(always)]
    pub(crate) fn paired<D: PartialOrd>(self, dist2: impl Fn(u32, u32) -> D) -> PairedQuad {
        let o = self.order(dist2);
        let [v1, v2, v3, v4] = self.v;
        let y_edge = self.axis == 1;
        let (first_back, b) = if y_edge { (v3, v2) } else { (v2, v3) };
        PairedQuad {
            corners: ORDER[o].map(|i| self.v[i]),
            a: v1,
            da: v1.wrapping_sub(first_back),
            b,
            db: b.wrapping_sub(v4),
            code: PAIRED_CODES[usize::from(y_edge)][o],
        }
    }
}

#[cfg(test)]
mod quad_tests {
    use voxel_core::formats::compact_quad_decode;

    use super::*;

    #[test]
    fn paired_quads_give_records_of_their_corners() {
        for axis in 0..3u8 {
            for outward in [false, true] {
                for short_14 in [false, true] {
                    for (da, db) in [(1, 1), (63, 1), (1, 63), (63, 63)] {
                        // v1 and its step back along the first pair's axis, and the other pair.
                        let (a, b) = (5000, 3000);
                        let v = if axis == 1 {
                            [a, b, a - da, b - db]
                        } else {
                            [a, a - da, b, b - db]
                        };
                        let quad = Quad::new(axis, outward, v);
                        let dist2 = |p: u32, q: u32| {
                            let diagonal_14 = (p, q) == (v[0], v[3]);
                            if diagonal_14 == short_14 { 1 } else { 2 }
                        };
                        let paired = quad.paired(dist2);
                        assert_eq!(paired.corners, quad.corners(dist2));
                        assert_eq!((paired.a, paired.da, paired.b, paired.db), (a, da, b, db));
                        let record = [a, b, da | db << 6 | paired.code << 12].map(|x| x as u16);
                        assert_eq!(compact_quad_decode(record), Ok(paired.corners));
                    }
                }
            }
        }
    }
}
