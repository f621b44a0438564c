//! [`SurfaceNets`]: naive surface nets on `f32` and `i8` density grids.

use alloc::vec::Vec;

use glam::{Mat4, Vec3A, Vec4};
use voxel_core::BlockId;
use voxel_core::formats::BlockVertex;

use super::cell::{Vertices4, cell_vertices};
use super::density::{Density, Fill, build_masks, words_per_row};
use super::mesh::{SmoothMesh, SmoothMeshF32};
use super::pack::PositionPacker;
use super::{GridShape, Quad, owned_corners};
use crate::MeshError;

/// A reusable SurfaceNets mesher: holds the scratch buffers (inside bits per sample, flat and
/// per row; two slices of cell-to-vertex indices; unquantized positions) so that meshing many
/// chunks allocates only while the buffers grow.
///
/// Every `mesh_*` method checks the whole grid first (length against the shape, then every
/// sample for NaN / infinity, in storage order) and returns the first problem without writing
/// any output except clearing `out`. Grids without both inside and outside samples return an
/// empty mesh right after that check.
///
/// ```
/// use mesher::smooth::{GridShape, SmoothMesh, SmoothQuads, SurfaceNets};
/// use voxel_core::{BlockId, ChunkSize};
///
/// // A sphere of radius 6 in the padded grid of a 16^3 chunk.
/// let shape = GridShape::padded_chunk(ChunkSize::S16);
/// let samples: Vec<f32> = (0..shape.sample_count())
///     .map(|i| {
///         let [x, y, z] = shape.coords(i).map(|a| a as f32 - 9.0);
///         (x * x + y * y + z * z).sqrt() - 6.0
///     })
///     .collect();
/// let mut mesher = SurfaceNets::new();
/// let mut mesh = SmoothMesh::new();
/// mesher.mesh_f32(&samples, shape, BlockId(1), &mut mesh).unwrap();
/// assert!(mesh.quad_count() > 100);
/// // Chunk grids (at most 64 samples a row) keep the 6-byte compact quads.
/// assert!(matches!(mesh.quads(), SmoothQuads::Compact(_)));
/// // 16 B per vertex + 6 B per quad; a closed sphere has 2 more vertices than quads.
/// assert!(mesh.bytes_per_quad() < 22.5);
/// ```
#[derive(Clone, Debug, Default)]
pub struct SurfaceNets {
    scratch: Scratch,
    positions: Vec<Vec3A>,
}

/// The scratch buffers of [`extract`].
#[derive(Clone, Debug, Default)]
struct Scratch {
    flat: Vec<u64>,
    masks: Vec<u64>,
    map: Vec<u32>,
    row_quads: Vec<RowQuads>,
}

impl SurfaceNets {
    /// A mesher with empty scratch buffers.
    pub fn new() -> Self {
        SurfaceNets::default()
    }

    /// Meshes an `f32` density grid into `out` (cleared first). Every vertex gets `block` as
    /// its block id, a zero uv and zero extra bits; positions are packed over
    /// [`GridShape::extent`].
    pub fn mesh_f32(
        &mut self,
        samples: &[f32],
        shape: GridShape,
        block: BlockId,
        out: &mut SmoothMesh,
    ) -> Result<(), MeshError> {
        self.mesh_packed(samples, shape, block, out)
    }

    /// Meshes an `i8` density grid (sample `q` is the density `q * I8_DENSITY_STEP`) into
    /// `out`, as [`mesh_f32`](Self::mesh_f32) would mesh those densities: on grids of values
    /// `q as f32 * I8_DENSITY_STEP` the two produce identical meshes.
    pub fn mesh_i8(
        &mut self,
        samples: &[i8],
        shape: GridShape,
        block: BlockId,
        out: &mut SmoothMesh,
    ) -> Result<(), MeshError> {
        self.mesh_packed(samples, shape, block, out)
    }

    /// Meshes an `f32` grid without quantizing: `f32` positions, raw gradients and the cell of
    /// each vertex (for tests and tools; the packed path computes the same values).
    pub fn mesh_f32_unpacked(
        &mut self,
        samples: &[f32],
        shape: GridShape,
        out: &mut SmoothMeshF32,
    ) -> Result<(), MeshError> {
        self.mesh_unpacked(samples, shape, out)
    }

    /// [`mesh_f32_unpacked`](Self::mesh_f32_unpacked) for `i8` samples.
    pub fn mesh_i8_unpacked(
        &mut self,
        samples: &[i8],
        shape: GridShape,
        out: &mut SmoothMeshF32,
    ) -> Result<(), MeshError> {
        self.mesh_unpacked(samples, shape, out)
    }

    fn mesh_packed<D: Density>(
        &mut self,
        samples: &[D],
        shape: GridShape,
        block: BlockId,
        out: &mut SmoothMesh,
    ) -> Result<(), MeshError> {
        out.reset(shape.extent());
        let scratch = &mut self.scratch;
        if build_masks(samples, shape, &mut scratch.flat, &mut scratch.masks)? != Fill::Mixed {
            return Ok(());
        }
        self.positions.clear();
        let mut sink = PackedSink {
            packer: PositionPacker::new(shape.extent()),
            mesh: out,
            positions: &mut self.positions,
            block: block.0,
        };
        extract_any_width(samples, shape, &mut self.scratch, &mut sink);
        Ok(())
    }

    fn mesh_unpacked<D: Density>(
        &mut self,
        samples: &[D],
        shape: GridShape,
        out: &mut SmoothMeshF32,
    ) -> Result<(), MeshError> {
        out.clear();
        let scratch = &mut self.scratch;
        if build_masks(samples, shape, &mut scratch.flat, &mut scratch.masks)? != Fill::Mixed {
            return Ok(());
        }
        extract_any_width(samples, shape, &mut self.scratch, out);
        Ok(())
    }
}

/// The vertices of a batch of 4 cells (lanes), of which the first `len` are real.
pub(crate) struct Vertices<'a> {
    len: usize,
    cells: &'a [[u32; 3]; 4],
    positions: [Vec3A; 4],
    gradients: [Vec3A; 4],
    normals: [u16; 4],
}

/// Where [`extract`] writes vertices and quads.
pub(crate) trait Sink {
    /// Give every surface cell a vertex, even those no quad uses.
    const ALL_CELLS: bool;
    /// Adds the real vertices of a batch and returns the index of the first (the others
    /// follow in order).
    fn push_vertices(&mut self, v: &Vertices<'_>) -> u32;
    /// Adds a quad (see [`Quad`]).
    fn push_quad(&mut self, quad: Quad);
}

/// Packs into a [`SmoothMesh`], keeping the unquantized positions to choose quad diagonals
/// exactly as the unpacked path does.
struct PackedSink<'a> {
    mesh: &'a mut SmoothMesh,
    positions: &'a mut Vec<Vec3A>,
    packer: PositionPacker,
    block: u16,
}

impl Sink for PackedSink<'_> {
    const ALL_CELLS: bool = false;

    #[inline(always)]
    fn push_vertices(&mut self, v: &Vertices<'_>) -> u32 {
        let packed: [BlockVertex; 4] = core::array::from_fn(|k| BlockVertex {
            position: self.packer.pack(v.positions[k]),
            normal: v.normals[k],
            uv: [0; 2],
            block: self.block,
            extra: 0,
        });
        let n = v.len.min(4);
        self.positions.extend_from_slice(&v.positions[..n]);
        self.mesh.extend_vertices(&packed[..n])
    }

    #[inline(always)]
    fn push_quad(&mut self, quad: Quad) {
        let p = &self.positions;
        let q = quad.paired(|a, b| p[a as usize].distance_squared(p[b as usize]));
        self.mesh.push_paired_quad(q);
    }
}

impl Sink for SmoothMeshF32 {
    const ALL_CELLS: bool = true;

    #[inline]
    fn push_vertices(&mut self, v: &Vertices<'_>) -> u32 {
        let first = self.positions.len() as u32;
        for k in 0..v.len.min(4) {
            self.positions.push(v.positions[k].into());
            self.normals.push(v.gradients[k].into());
            self.cells.push(v.cells[k]);
        }
        first
    }

    #[inline]
    fn push_quad(&mut self, quad: Quad) {
        let q = quad.corners(|a, b| {
            let pa = Vec3A::from(self.positions[a as usize]);
            let pb = Vec3A::from(self.positions[b as usize]);
            pa.distance_squared(pb)
        });
        self.quads.push(q);
    }
}

/// The bits `x` of word `w` of a row mask (`wpr` words per row, the row at `r`) shifted down by
/// one: bit `x` is sample `x + 1`.
#[inline]
fn upper(masks: &[u64], r: usize, w: usize, wpr: usize) -> u64 {
    let next = if w + 1 < wpr { masks[r + w + 1] } else { 0 };
    (masks[r + w] >> 1) | (next << 63)
}

/// What one word of a row of cells needs, as bitmasks over the cells `x` of the word.
struct RowCells {
    /// Cells that get a vertex.
    vertices: u64,
    /// Cells whose minimum corner starts an owned crossing edge along x, y, z.
    quads: [u64; 3],
    /// Cells whose minimum corner is inside.
    inside: u64,
}

/// The cells of word `w` of the row `(y, z)` from the inside masks of the 4 sample rows at
/// `rows`, all at once: corner `i` of every cell is one mask (`c[i]`), so an edge crosses
/// where its two corners' masks differ.
#[inline(always)]
#[expect(
    clippy::too_many_arguments,
    reason = "one call site, inlined; all are per-row values"
)]
fn row_cells(
    masks: &[u64],
    rows: [usize; 4],
    w: usize,
    wpr: usize,
    owned_yz: u8,
    valid: u64,
    x_edges: [u64; 2],
    all_cells: bool,
) -> RowCells {
    let c: [u64; 8] = core::array::from_fn(|i| {
        let r = rows[i >> 1];
        if i & 1 == 0 {
            masks[r + w]
        } else {
            upper(masks, r, w, wpr)
        }
    });
    // The cells in which corner `i` is an owned sample: its y and z from the row, its x from
    // the cell's position in the row (`x_edges`: cells whose low / high x sample is owned).
    let owned: [u64; 8] = core::array::from_fn(|i| {
        if owned_yz & (1 << i) == 0 {
            0
        } else {
            x_edges[i & 1]
        }
    });
    let mut any = 0;
    let mut touched = 0;
    for [a, b] in super::cell::EDGES {
        let crossing = c[a] ^ c[b];
        any |= crossing;
        touched |= crossing & owned[a];
    }
    let from0 = |b: usize| (c[0] ^ c[b]) & owned[0] & valid;
    RowCells {
        vertices: if all_cells { any } else { touched } & valid,
        quads: [from0(1), from0(2), from0(4)],
        inside: c[0],
    }
}

/// Cells per batch: two groups of 4 SIMD lanes, computed back to back so that the processor
/// overlaps their (long, division-bound) dependency chains.
const LANES: usize = 8;

/// Up to [`LANES`] cells of one z slice whose vertices are computed together, one per SIMD
/// lane.
struct Batch {
    /// Lane `k`'s corners 0..4 and 4..8, unscaled ([`Density::raw`]). Stored a cell at a time
    /// (whole vectors, which the loads that follow can forward) and transposed to a corner
    /// per vector when the batch is computed.
    cells_lo_hi: [[Vec4; 2]; LANES],
    /// Lane `k`'s cell.
    cells: [[u32; 3]; LANES],
    /// Lane `k`'s cell as `f32` (x, y, z, 0).
    origins: [Vec4; LANES],
    len: usize,
}

impl Batch {
    fn new() -> Self {
        // Corner 0 inside, the others outside, in every lane: unused lanes always hold a cell
        // with a surface (this one, or an earlier real one).
        Batch {
            cells_lo_hi: [[Vec4::new(-1.0, 1.0, 1.0, 1.0), Vec4::ONE]; LANES],
            cells: [[0; 3]; LANES],
            origins: [Vec4::ZERO; LANES],
            len: 0,
        }
    }

    /// The vertices of the 4 lanes from `first`.
    #[inline(always)]
    fn group<D: Density>(&self, first: usize) -> Vertices4 {
        let half = |h: usize| {
            let c = |k: usize| self.cells_lo_hi[first + k][h];
            let t = Mat4::from_cols(c(0), c(1), c(2), c(3)).transpose();
            [t.x_axis, t.y_axis, t.z_axis, t.w_axis]
        };
        let (lo, hi) = (half(0), half(1));
        let corners: [Vec4; 8] = core::array::from_fn(|i| {
            let c = if i < 4 { lo[i] } else { hi[i - 4] };
            if D::SCALED { c * D::SCALE } else { c }
        });
        cell_vertices(&corners)
    }

    /// Hands the `len` (1..=4) real vertices of the group at `first` to `sink` and records
    /// their indices in the slice's map `cur` (`cx` cells per row).
    #[inline(always)]
    fn emit<S: Sink>(
        &self,
        first: usize,
        len: usize,
        out: &Vertices4,
        sink: &mut S,
        cur: &mut [u32],
        cx: usize,
    ) {
        let per_lane = |a: Vec4, b: Vec4, c: Vec4| {
            let t = Mat4::from_cols(a, b, c, Vec4::ZERO).transpose();
            [t.x_axis, t.y_axis, t.z_axis, t.w_axis]
        };
        let [sx, sy, sz] = out.s;
        let [gx, gy, gz] = out.g;
        let s = per_lane(sx, sy, sz);
        let positions: [Vec3A; 4] =
            core::array::from_fn(|k| Vec3A::from_vec4(self.origins[first + k] + s[k]));
        let gradients = per_lane(gx, gy, gz).map(Vec3A::from_vec4);
        let cells: &[[u32; 3]; 4] = self.cells[first..first + 4]
            .try_into()
            .unwrap_or(&[[0; 3]; 4]);
        let index = sink.push_vertices(&Vertices {
            len,
            cells,
            positions,
            gradients,
            normals: out.normal,
        });
        for (k, cell) in cells[..len.min(4)].iter().enumerate() {
            if let Some(slot) = cur.get_mut(cell[1] as usize * cx + cell[0] as usize) {
                *slot = index + k as u32;
            }
        }
    }

    /// Computes the batch's vertices (all in one z slice), hands them to `sink` and records
    /// their indices in the slice's map `cur` (`cx` cells per row); empties the batch.
    #[inline]
    fn flush<D: Density, S: Sink>(&mut self, cx: usize, sink: &mut S, cur: &mut [u32]) {
        match self.len {
            0 => {}
            1..=4 => {
                let a = self.group::<D>(0);
                self.emit(0, self.len, &a, sink, cur, cx);
            }
            _ => {
                let (a, b) = (self.group::<D>(0), self.group::<D>(4));
                self.emit(0, 4, &a, sink, cur, cx);
                self.emit(4, self.len - 4, &b, sink, cur, cx);
            }
        }
        self.len = 0;
    }
}

/// The quads one word of a row of cells makes (see [`RowCells`]).
#[derive(Clone, Copy, Debug)]
struct RowQuads {
    y: usize,
    first: usize,
    quads: [u64; 3],
    inside: u64,
}

/// [`extract`] for grids of any width.
fn extract_any_width<D: Density, S: Sink>(
    samples: &[D],
    shape: GridShape,
    scratch: &mut Scratch,
    sink: &mut S,
) {
    let Scratch {
        masks,
        map,
        row_quads,
        ..
    } = scratch;
    if shape.dims()[0] <= 64 {
        extract::<D, S, true>(samples, shape, masks, map, row_quads, sink);
    } else {
        extract::<D, S, false>(samples, shape, masks, map, row_quads, sink);
    }
}

/// The surface nets pass over a checked grid whose inside `masks` are built.
///
/// Rows of cells are visited z, then y, skipping rows whose samples are all on one side. In
/// each row, bit operations on the 4 sample rows' masks find, for all 64 cells of a word at
/// once ([`row_cells`]):
///
/// - the cells that get a vertex: one of their 12 edges crosses the surface and is owned (its
///   lower sample is an owned sample, see [`owned_corners`]), since exactly the quads of those
///   edges use the cell (a sink with [`Sink::ALL_CELLS`] takes every surface cell instead, as
///   `fast-surface-nets` does);
/// - the cells that make quads: a crossing edge starts at their minimum corner, which is owned.
///
/// The vertices of a z slice are computed first, 4 cells at a time ([`cell_vertices`]), then
/// its quads are made: the 4 cells around each such edge have no larger coordinate than the
/// cell that makes it, so their vertices exist. `map` keeps the vertex index of those cells
/// for the current and the previous z slice (other entries are never read, so it is never
/// cleared).
///
/// `NARROW` is `dx <= 64` (one mask word per row, the common case), which lets the compiler
/// drop the word loop.
fn extract<D: Density, S: Sink, const NARROW: bool>(
    samples: &[D],
    shape: GridShape,
    masks: &[u64],
    map: &mut Vec<u32>,
    row_quads: &mut Vec<RowQuads>,
    sink: &mut S,
) {
    let [dx, dy, dz] = shape.dims();
    let (cx, cy, cz) = (dx as usize - 1, dy as usize - 1, dz as usize - 1);
    let (sy, rows_y) = (dx as usize, dy as usize);
    let wpr = if NARROW { 1 } else { words_per_row(dx) };
    let slice = cx * cy;
    if map.len() < 2 * slice {
        map.resize(2 * slice, u32::MAX);
    }
    let (even, odd) = map[..2 * slice].split_at_mut(slice);
    let mut batch = Batch::new();
    for z in 0..cz {
        // This slice's and the previous slice's cell-to-vertex maps.
        let (cur, prev) = if z & 1 == 0 {
            (&mut *even, &*odd)
        } else {
            (&mut *odd, &*even)
        };
        let owned_z = owned_corners(2, z, cz);

        // Phase 1: the slice's vertices, a batch at a time; note the rows that make quads.
        row_quads.clear();
        for y in 0..cy {
            let r00 = (y + rows_y * z) * wpr;
            let rows = [r00, r00 + wpr, r00 + rows_y * wpr, r00 + (rows_y + 1) * wpr];
            if NARROW {
                // No cell of the row has a surface when the 4 sample rows are all outside or
                // all inside (bits past `dx` are 0 in every mask).
                let m = rows.map(|r| masks[r]);
                let any = m[0] | m[1] | m[2] | m[3];
                let all = m[0] & m[1] & m[2] & m[3];
                if any == 0 || all.count_ones() == dx {
                    continue;
                }
            }
            let owned_yz = owned_z & owned_corners(1, y, cy);
            for w in 0..wpr {
                // Cells 64 w.. of the row: valid below `cx`; their low x sample is owned from
                // x = 1, their high one up to x = cx - 2.
                let first = 64 * w;
                let span = (cx - first.min(cx)).min(64);
                let valid = if span == 64 {
                    u64::MAX
                } else {
                    (1u64 << span) - 1
                };
                let low_ok = if w == 0 { valid & !1 } else { valid };
                let last = cx - 1 - first.min(cx - 1);
                let high_ok = if last < 64 {
                    valid & !(1u64 << last)
                } else {
                    valid
                };
                let edges = [low_ok, high_ok];
                let cells = row_cells(masks, rows, w, wpr, owned_yz, valid, edges, S::ALL_CELLS);
                if cells.quads != [0; 3] {
                    row_quads.push(RowQuads {
                        y,
                        first,
                        quads: cells.quads,
                        inside: cells.inside,
                    });
                }
                if cells.vertices == 0 {
                    continue;
                }
                let sample_row = |r: usize| {
                    let start = (y + (r & 1) + rows_y * (z + (r >> 1))) * sy;
                    &samples[start..start + sy]
                };
                let sample_rows = [sample_row(0), sample_row(1), sample_row(2), sample_row(3)];
                let mut bits = cells.vertices;
                while bits != 0 {
                    let x = first + bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    if x + 1 >= sy {
                        break; // never: `valid` keeps x below `cx`; lets the loads go unchecked
                    }
                    let k = batch.len % LANES;
                    let pair = |r: usize| [sample_rows[r][x].raw(), sample_rows[r][x + 1].raw()];
                    let ([c0, c1], [c2, c3]) = (pair(0), pair(1));
                    let ([c4, c5], [c6, c7]) = (pair(2), pair(3));
                    batch.cells_lo_hi[k] = [Vec4::new(c0, c1, c2, c3), Vec4::new(c4, c5, c6, c7)];
                    batch.cells[k] = [x as u32, y as u32, z as u32];
                    batch.origins[k] = Vec4::new(x as f32, y as f32, z as f32, 0.0);
                    batch.len += 1;
                    if batch.len == LANES {
                        batch.flush::<D, S>(cx, sink, cur);
                    }
                }
            }
        }
        batch.flush::<D, S>(cx, sink, cur);

        // Phase 2: the quads. Rows y and y - 1 of both slices' maps (no quads are made at
        // y = 0 or x = 0).
        let cur = &*cur;
        for &RowQuads {
            y,
            first,
            quads: [qx, qy, qz],
            inside,
        } in row_quads.iter()
        {
            if y == 0 {
                continue; // never: owned corners need y >= 1
            }
            let cur_row = &cur[y * cx..(y + 1) * cx];
            let cur_back = &cur[(y - 1) * cx..y * cx];
            let prev_row = &prev[y * cx..(y + 1) * cx];
            let prev_back = &prev[(y - 1) * cx..y * cx];
            // One pass per axis: every cell in the mask makes exactly one quad.
            let x_of = |bits: u64| first + bits.trailing_zeros() as usize;
            let outward = |x: usize| (inside >> (x - first)) & 1 != 0;
            let mut bits = qx;
            while bits != 0 {
                let x = x_of(bits);
                bits &= bits - 1;
                if x == 0 || x >= cx {
                    break; // never: owned corners need x >= 1
                }
                // Edge along x: the cells around it step back along y and z.
                let q = [cur_row[x], cur_back[x], prev_row[x], prev_back[x]];
                sink.push_quad(Quad::new(0, outward(x), q));
            }
            let mut bits = qy;
            while bits != 0 {
                let x = x_of(bits);
                bits &= bits - 1;
                if x == 0 || x >= cx {
                    break;
                }
                let q = [cur_row[x], prev_row[x], cur_row[x - 1], prev_row[x - 1]];
                sink.push_quad(Quad::new(1, outward(x), q));
            }
            let mut bits = qz;
            while bits != 0 {
                let x = x_of(bits);
                bits &= bits - 1;
                if x == 0 || x >= cx {
                    break;
                }
                let q = [cur_row[x], cur_row[x - 1], cur_back[x], cur_back[x - 1]];
                sink.push_quad(Quad::new(2, outward(x), q));
            }
        }
    }
}
