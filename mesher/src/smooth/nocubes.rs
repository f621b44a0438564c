//! [`NoCubes`]: SurfaceNets smoothing of blocky data (the approach of the NoCubes mod, which
//! Project Ascendant uses for its near field): smoothable blocks become a smooth surface, the
//! other opaque blocks stay cubes, in one closed mesh.

use alloc::boxed::Box;
use alloc::vec::Vec;

use glam::{Vec3A, Vec4};
use voxel_core::formats::BlockVertex;
use voxel_core::formats::quantize::UnormExtent;
use voxel_core::{BlockId, MaterialClass, PaddedChunk};

use super::cell::cell_vertices;
use super::mesh::SmoothMesh;
use super::pack::{PositionPacker, oct16_encode_fast};
use super::{EdgeLanes, Quad, owned_corners};
use crate::{BlockClasses, MeshError};

/// The bit that [`NoCubes`] sets in `BlockVertex::extra` for the vertices of cube faces (the
/// smooth surface's vertices have `extra = 0`), so that a shader can map textures per face on
/// cubes and triplanar on the smooth surface.
pub const CUBE_FACE_FLAG: u16 = 1;

/// Counts of what [`NoCubes::mesh`] wrote.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NoCubesStats {
    /// Vertices of the smooth surface (one per cell that a smooth face touches).
    pub smooth_vertices: usize,
    /// Quads of the smooth surface: one per visible face of a smoothable block.
    pub smooth_quads: usize,
    /// Vertices of cube faces (shared between faces of one direction and block id).
    pub cube_vertices: usize,
    /// Cube faces: one per visible face of a non-smoothable opaque block.
    pub cube_quads: usize,
}

/// What a cell's corner configuration gives a smooth vertex.
#[derive(Clone, Copy, Debug, Default)]
struct CellShape {
    /// Position relative to the cell's minimum voxel, in voxel coordinates.
    offset: Vec3A,
    /// Packed normal.
    normal: u16,
}

/// A reusable NoCubes mesher: SurfaceNets on the block occupancy of a [`PaddedChunk`].
///
/// # The rule
///
/// - **Samples** are the voxels: voxel `p` (padded) is a sample at its centre `p + 0.5`, inside
///   when its material is opaque (`Opaque`, `ClutterBearing` or `Smoothable`). Air and
///   transparent blocks are outside: this is the opaque layer; water and glass are another
///   mesher's job. The density is `-1` inside and `+1` outside, so every crossing is at an
///   edge midpoint. (A box-filtered occupancy would round corners further, but it moves the
///   zero crossing off the voxel faces, which can open holes against cubes and changes the
///   topology of thin features; the binary density keeps the blocky topology exactly.)
/// - **Faces.** Every face between an opaque and a non-opaque voxel gives one quad (the
///   SurfaceNets quad of that sample edge), owned as in the
///   [padding contract](super#seamless-chunks-the-padding-contract): the edge's lower voxel
///   is one of the chunk's own voxels (padded `1..=edge` on every axis). A face of a
///   smoothable block is a **smooth quad**; a face of any other opaque block is a **cube
///   face**.
/// - **Smooth vertices**, one per cell (8 voxels around a lattice point) that one of this
///   chunk's smooth quads uses: the SurfaceNets vertex (average of the crossing edges' midpoints, normal from
///   the occupancy gradient, both looked up from a 256-entry table), **except** in cells that
///   contain a non-smoothable opaque voxel: there the vertex is **pinned** to the cell's
///   lattice point, which is exactly where the cube faces of that voxel have their corner.
///   So smooth surface and cubes meet edge to edge and the mesh has no holes: welded by
///   position, a closed blocky input gives a closed mesh (no boundary edges; tested).
/// - **Block ids.** A smooth vertex carries the most common smoothable id among its cell's 8
///   voxels (ties: the smallest id). A cube face carries its block's id.
/// - **Cube faces** are four `BlockVertex`es with the face's axis normal at the face's lattice
///   corners, so the whole mesh is one vertex buffer; a vertex is shared by the faces of one
///   direction and one block id that meet at it (a flat floor costs about one vertex per
///   face); their `extra` is [`CUBE_FACE_FLAG`]. Texture coordinates are zero everywhere: the
///   shader maps textures from the position (planar on cube faces, triplanar on the smooth
///   surface), since shared corners cannot carry per-face uvs.
///
/// Positions are padded voxel coordinates (chunk-local + 1) over
/// [`UnormExtent::padded_chunk`]. Unknown block ids are reported as
/// [`MeshError::UnknownBlock`] before anything is written.
///
/// **Quad form.** A chunk of smoothable blocks only keeps compact quads (6 B, see
/// [`SmoothMesh`]): its vertices are numbered in cell scan order, as in SurfaceNets. Cube-face
/// vertices are made as their faces are, between the smooth ones, so a chunk with cube faces
/// usually has a quad whose indices lie too far apart and falls back to `u16` quads (8 B; the
/// benchmark's terrain chunk: 36 B per quad, 2.35 vertices per cube face).
///
/// ```
/// use mesher::BlockClasses;
/// use mesher::smooth::{NoCubes, SmoothMesh, SmoothQuads};
/// use voxel_core::{BlockId, ChunkSize, Material, MaterialClass, MaterialPalette, PaddedChunk};
///
/// let mut palette = MaterialPalette::new();
/// let dirt = palette
///     .push(Material::opaque(120, 85, 55).with_class(MaterialClass::Smoothable))
///     .unwrap();
/// let classes = BlockClasses::from_palette(&palette);
/// // A 4x4x4 block of dirt in the middle of an 8^3 chunk.
/// let chunk = PaddedChunk::from_fn(ChunkSize::S8, |x, y, z| {
///     if [x, y, z].iter().all(|a| (3..7).contains(a)) { dirt } else { BlockId::AIR }
/// });
/// let mut mesh = SmoothMesh::new();
/// let stats = NoCubes::new().mesh(&chunk, &classes, &mut mesh).unwrap();
/// assert_eq!(stats.smooth_quads, 6 * 16); // one quad per visible face
/// assert_eq!(stats.cube_quads, 0);
/// // Smooth quads only: 6-byte compact quads.
/// assert!(matches!(mesh.quads(), SmoothQuads::Compact(_)));
/// ```
#[derive(Clone, Debug)]
pub struct NoCubes {
    table: Box<[CellShape; 256]>,
    axis_normals: [u16; 6],
    opaque: Vec<u64>,
    smooth: Vec<u64>,
    map: Vec<u32>,
    cube: Vec<u32>,
}

impl Default for NoCubes {
    fn default() -> Self {
        NoCubes::new()
    }
}

/// Cube face directions: `2 * axis + (1 if facing -axis)`.
const AXES: [Vec3A; 3] = [Vec3A::X, Vec3A::Y, Vec3A::Z];

impl NoCubes {
    /// A mesher with its configuration table built and empty scratch buffers.
    pub fn new() -> Self {
        let mut table = Box::new([CellShape::default(); 256]);
        // Configurations 1..=254 (0 and 255 have no surface), 4 per call.
        for first in (1..255).step_by(4) {
            let configs: [usize; 4] = core::array::from_fn(|k| (first + k).min(254));
            let v: [Vec4; 8] = core::array::from_fn(|i| {
                Vec4::from_array(configs.map(|c| if (c >> i) & 1 != 0 { -1.0 } else { 1.0 }))
            });
            let out = cell_vertices(&v);
            let s = out.s.map(|a| a.to_array());
            for (k, &c) in configs.iter().enumerate() {
                table[c] = CellShape {
                    offset: Vec3A::new(s[0][k], s[1][k], s[2][k]) + Vec3A::splat(0.5),
                    normal: out.normal[k],
                };
            }
        }
        let axis_normals = core::array::from_fn(|d| {
            oct16_encode_fast(if d % 2 == 0 {
                AXES[d / 2]
            } else {
                -AXES[d / 2]
            })
        });
        NoCubes {
            table,
            axis_normals,
            opaque: Vec::new(),
            smooth: Vec::new(),
            map: Vec::new(),
            cube: Vec::new(),
        }
    }

    /// Meshes `chunk` into `out` (cleared first) and returns what it wrote. See the type docs.
    pub fn mesh(
        &mut self,
        chunk: &PaddedChunk,
        classes: &BlockClasses,
        out: &mut SmoothMesh,
    ) -> Result<NoCubesStats, MeshError> {
        let extent = UnormExtent::padded_chunk(chunk.size());
        out.reset(extent);
        if !self.build_masks(chunk, classes)? {
            return Ok(NoCubesStats::default());
        }
        Ok(self.extract(chunk, PositionPacker::new(extent), out))
    }

    /// Fills the opaque and smoothable row masks; false when no cell can have a surface.
    fn build_masks(
        &mut self,
        chunk: &PaddedChunk,
        classes: &BlockClasses,
    ) -> Result<bool, MeshError> {
        let p = chunk.padded_edge();
        let full_row = if p == 64 { u64::MAX } else { (1u64 << p) - 1 };
        self.opaque.clear();
        self.smooth.clear();
        let (mut any, mut all) = (0u64, full_row);
        let mut last = (BlockId::AIR, Some(MaterialClass::Air));
        for (r, (&column, row)) in chunk
            .columns()
            .iter()
            .zip(chunk.voxels().chunks_exact(p))
            .enumerate()
        {
            let (mut o, mut s) = (0u64, 0u64);
            let mut bits = column;
            while bits != 0 {
                let x = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let id = row[x];
                if id != last.0 {
                    last = (id, classes.class(id));
                }
                match last.1 {
                    None => {
                        return Err(MeshError::UnknownBlock {
                            id,
                            position: [x as u32, (r % p) as u32, (r / p) as u32],
                        });
                    }
                    Some(class) => {
                        o |= u64::from(class.is_opaque()) << x;
                        s |= u64::from(class == MaterialClass::Smoothable) << x;
                    }
                }
            }
            self.opaque.push(o);
            self.smooth.push(s);
            any |= o;
            all &= o;
        }
        Ok(any != 0 && all != full_row)
    }

    fn extract(
        &mut self,
        chunk: &PaddedChunk,
        packer: PositionPacker,
        out: &mut SmoothMesh,
    ) -> NoCubesStats {
        let p = chunk.padded_edge();
        let c = p - 1;
        let slice = c * c;
        if self.map.len() < 2 * slice {
            self.map.resize(2 * slice, u32::MAX);
            self.cube.resize(12 * slice, u32::MAX);
        }
        let valid = (1u64 << c) - 1;
        let voxels = chunk.voxels();
        let (o_rows, s_rows) = (&self.opaque, &self.smooth);
        let mut stats = NoCubesStats::default();
        let mut cubes = CubeFaces {
            slots: &mut self.cube,
            normals: self.axis_normals,
            packer,
            vertices: 0,
        };

        for z in 0..c {
            let (cur, prev) = if z & 1 == 0 { (0, slice) } else { (slice, 0) };
            let owned_z = owned_corners(2, z, c);
            for y in 0..c {
                let owned_yz = owned_z & owned_corners(1, y, c);
                let r = y + p * z;
                let rows = [r, r + 1, r + p, r + p + 1];
                let o4 = rows.map(|r| o_rows[r]);
                let s4 = rows.map(|r| s_rows[r]);
                let (mut all_in, mut any_in) = (u64::MAX, 0u64);
                for m in o4 {
                    all_in &= m & (m >> 1);
                    any_in |= m | (m >> 1);
                }
                let mut bits = any_in & !all_in & valid;
                while bits != 0 {
                    let x = bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    let o = corner_bits(o4, x);
                    let s = corner_bits(s4, x);
                    let m = cur + y * c + x;
                    let cell = Vec3A::new(x as f32, y as f32, z as f32);
                    let base = x + p * (y + p * z);

                    let owned = owned_yz & owned_corners(0, x, c);

                    if EdgeLanes::smooth_faces(o, s).any() & owned != 0 {
                        let position = if o & !s != 0 {
                            cell + Vec3A::ONE
                        } else {
                            cell + self.table[usize::from(o)].offset
                        };
                        self.map[m] = out.push_vertex(BlockVertex {
                            position: packer.pack(position),
                            normal: self.table[usize::from(o)].normal,
                            uv: [0; 2],
                            block: most_common_id(voxels, base, p, s),
                            extra: 0,
                        });
                        stats.smooth_vertices += 1;
                    }

                    let here = EdgeLanes::crossing(o).at_corner0(owned);
                    if here == 0 {
                        continue;
                    }
                    let q = prev + y * c + x;
                    let map = &self.map;
                    let outward = o & 1 != 0;
                    // (corner bit of the edge's upper voxel, its 4 cells' map indices, their
                    // coordinates) for the edges along x, y and z.
                    let edges = [
                        (
                            1,
                            [m, m - c, q, q - c],
                            [[0, 0, 0], [0, 1, 0], [0, 0, 1], [0, 1, 1]],
                        ),
                        (
                            2,
                            [m, q, m - 1, q - 1],
                            [[0, 0, 0], [0, 0, 1], [1, 0, 0], [1, 0, 1]],
                        ),
                        (
                            4,
                            [m, m - 1, m - c, m - c - 1],
                            [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]],
                        ),
                    ];
                    for (axis, (bit, cells, back)) in edges.into_iter().enumerate() {
                        if (here >> axis) & 1 == 0 {
                            continue;
                        }
                        let solid = if outward { 0 } else { bit };
                        if (s >> solid) & 1 != 0 {
                            let quad = Quad::new(axis as u8, outward, cells.map(|i| map[i]));
                            let paired = quad.paired(|a, b| out.dist2(a, b));
                            out.push_paired_quad(paired);
                            stats.smooth_quads += 1;
                        } else {
                            let id = voxels[base + corner_offset(solid, p)];
                            let dir = 2 * axis + usize::from(!outward);
                            let corners: [u32; 4] = core::array::from_fn(|k| {
                                let [bx, by, bz] = back[k];
                                let lattice =
                                    cell + Vec3A::ONE - Vec3A::new(bx as f32, by as f32, bz as f32);
                                cubes.vertex(out, cells[k] * 6 + dir, lattice, dir, id)
                            });
                            let quad = Quad::new(axis as u8, outward, corners);
                            out.push_quad(quad.corners(|a, b| out.dist2(a, b)));
                            stats.cube_quads += 1;
                        }
                    }
                }
            }
        }
        stats.cube_vertices = cubes.vertices;
        stats
    }
}

/// The shared vertices of cube faces: one slot per cell of the two current slices and face
/// direction, holding the index of the last vertex made there.
struct CubeFaces<'a> {
    slots: &'a mut [u32],
    normals: [u16; 6],
    packer: PositionPacker,
    vertices: usize,
}

impl CubeFaces<'_> {
    /// The vertex at `lattice` facing `dir` with `id`: the slot's vertex if it is exactly that
    /// vertex (slots are never cleared: a stale index fails this comparison), else a new one.
    #[inline]
    fn vertex(
        &mut self,
        out: &mut SmoothMesh,
        slot: usize,
        lattice: Vec3A,
        dir: usize,
        id: BlockId,
    ) -> u32 {
        let wanted = BlockVertex {
            position: self.packer.pack(lattice),
            normal: self.normals[dir],
            uv: [0; 2],
            block: id.0,
            extra: CUBE_FACE_FLAG,
        };
        let i = self.slots[slot];
        if out.vertex(i) == Some(&wanted) {
            return i;
        }
        let i = out.push_vertex(wanted);
        self.slots[slot] = i;
        self.vertices += 1;
        i
    }
}

/// The 8 corner bits of cell `x` from the masks of rows `(y, z)`, `(y + 1, z)`, `(y, z + 1)`,
/// `(y + 1, z + 1)`: bit `i` is corner `(i & 1, (i >> 1) & 1, i >> 2)`.
#[inline]
fn corner_bits(rows: [u64; 4], x: usize) -> u8 {
    let two = |m: u64| ((m >> x) & 3) as u8;
    two(rows[0]) | two(rows[1]) << 2 | two(rows[2]) << 4 | two(rows[3]) << 6
}

/// Offset of corner `i` from a cell's minimum voxel in a padded chunk of edge `p`.
#[inline]
fn corner_offset(i: u8, p: usize) -> usize {
    usize::from(i & 1) + p * usize::from((i >> 1) & 1) + p * p * usize::from(i >> 2)
}

/// The most common id among the smoothable corners `s` (not empty) of the cell at `base`;
/// ties go to the smallest id.
#[inline]
fn most_common_id(voxels: &[BlockId], base: usize, p: usize, s: u8) -> u16 {
    let mut ids = [0u16; 8];
    let mut n = 0;
    let mut bits = s;
    while bits != 0 {
        let i = bits.trailing_zeros() as u8;
        bits &= bits - 1;
        ids[n] = voxels[base + corner_offset(i, p)].0;
        n += 1;
    }
    let ids = &ids[..n];
    let mut best = (0usize, u16::MAX);
    for &id in ids {
        let count = ids.iter().filter(|&&o| o == id).count();
        if count > best.0 || (count == best.0 && id < best.1) {
            best = (count, id);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn most_common_id_breaks_ties_low() {
        let p = 4;
        let mut voxels = alloc::vec![BlockId::AIR; p * p * p];
        voxels[0] = BlockId(9);
        voxels[1] = BlockId(5);
        assert_eq!(most_common_id(&voxels, 0, p, 0b11), 5);
        voxels[p] = BlockId(9);
        assert_eq!(most_common_id(&voxels, 0, p, 0b111), 9);
    }
}
