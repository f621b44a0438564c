//! [`NoCubes`]: SurfaceNets smoothing of blocky data (the approach of the NoCubes mod, which
//! Project Ascendant uses for its near field): smoothable blocks become a smooth surface, the
//! other opaque blocks stay cubes (greedy quads), and the two meet edge to edge.

use alloc::boxed::Box;
use alloc::vec::Vec;

use glam::{Vec3A, Vec4};
use voxel_core::formats::quantize::UnormExtent;
use voxel_core::formats::{BlockVertex, PackedQuad};
use voxel_core::{BlockId, MaterialClass, PaddedChunk};

use super::cell::cell_vertices;
use super::mesh::SmoothMesh;
use super::pack::PositionPacker;
use super::{EdgeLanes, Quad, owned_corners};
use crate::blocky::{BlockyMesh, GreedyMesher};
use crate::{BlockClasses, MeshError};

/// Counts of what [`NoCubes::mesh`] wrote.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NoCubesStats {
    /// Vertices of the smooth surface (one per cell that a smooth face touches).
    pub smooth_vertices: usize,
    /// Quads of the smooth surface: one per visible face of a smoothable block.
    pub smooth_quads: usize,
    /// Greedy quads of the cube faces (visible faces of non-smoothable opaque blocks).
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

/// A reusable NoCubes mesher: SurfaceNets on the block occupancy of a [`PaddedChunk`] for the
/// smoothable blocks, greedy quads for the other blocks.
///
/// # The rule
///
/// - **Samples** are the voxels: voxel `p` (padded) is a sample at its centre `p + 0.5`, inside
///   when its material is opaque (`Opaque`, `ClutterBearing` or `Smoothable`). Air and
///   transparent blocks are outside. The density is `-1` inside and `+1` outside, so every
///   crossing is at an edge midpoint. (A box-filtered occupancy would round corners further,
///   but it moves the zero crossing off the voxel faces, which can open holes against cubes
///   and changes the topology of thin features; the binary density keeps the blocky topology
///   exactly.)
/// - **Smooth quads.** Every face between a smoothable voxel and a non-opaque one gives one
///   quad of the [`SmoothMesh`] (the SurfaceNets quad of that sample edge), owned as in the
///   [padding contract](super#seamless-chunks-the-padding-contract): the edge's lower voxel
///   is one of the chunk's own voxels (padded `1..=edge` on every axis).
/// - **Cube faces.** The faces of every other opaque block are the greedy quads
///   ([`GreedyMesher::mesh`], with ambient occlusion) of the [`BlockyMesh`]'s opaque layer,
///   8 bytes each, drawn by the blocky pipeline; quads of smoothable blocks are dropped from
///   it. Its transparent layer holds the transparent blocks' greedy quads as usual, so the
///   two outputs are the chunk's whole mesh.
/// - **Smooth vertices**, one per cell (8 voxels around a lattice point) that one of this
///   chunk's smooth quads uses: the SurfaceNets vertex (average of the crossing edges'
///   midpoints, normal from the occupancy gradient, both looked up from a 256-entry table),
///   **except** in cells that contain a non-smoothable opaque voxel: there the vertex is
///   **pinned** to the cell's lattice point, which is where that voxel's cube faces have
///   their corner. Positions are packed over [`UnormExtent::padded_lattice`], on which a
///   lattice point's code is exact, so a pinned vertex decodes to the integer corner of the
///   cube quads within a few `f32` rounding steps (about 1e-5 voxels).
/// - **Seams.** Where a smooth quad meets a cube face they share a lattice edge whose two ends
///   are pinned, so welded by position, smooth quads plus the cube quads split into unit
///   faces form a closed surface for a closed input (tested). A greedy cube quad may span
///   several smooth quads' edges: a T-junction, like those between greedy quads of different
///   sizes, which the GPU renderer covers by growing quads by a hair.
/// - **Block ids.** A smooth vertex carries the most common smoothable id among its cell's 8
///   voxels (ties: the smallest id). Cube quads carry their block's id.
///
/// Positions are padded voxel coordinates (chunk-local + 1). An unknown block id anywhere in
/// the padded chunk is reported as [`MeshError::UnknownBlock`] (the first in storage order)
/// and both outputs are left empty.
///
/// **Bytes.** The smooth mesh numbers its vertices in cell scan order, as SurfaceNets does,
/// so every smooth quad of a chunk grid is a 6-byte compact quad ([`SmoothMesh`]): about
/// 22-23 bytes per smooth quad with its share of the 16-byte vertices. Cube faces cost 8 bytes
/// per greedy quad.
///
/// ```
/// use mesher::BlockClasses;
/// use mesher::blocky::BlockyMesh;
/// use mesher::smooth::{NoCubes, SmoothMesh, SmoothQuads};
/// use voxel_core::{BlockId, ChunkSize, Material, MaterialClass, MaterialPalette, PaddedChunk};
///
/// let mut palette = MaterialPalette::new();
/// let dirt = palette
///     .push(Material::opaque(120, 85, 55).with_class(MaterialClass::Smoothable))
///     .unwrap();
/// let stone = palette.push(Material::opaque(90, 90, 90)).unwrap();
/// let classes = BlockClasses::from_palette(&palette);
/// // A 4x4x4 block of dirt in the middle of an 8^3 chunk, on a stone floor.
/// let chunk = PaddedChunk::from_fn(ChunkSize::S8, |x, y, z| {
///     if y == 2 { stone }
///     else if [x, y, z].iter().all(|a| (3..7).contains(a)) { dirt }
///     else { BlockId::AIR }
/// });
/// let (mut smooth, mut cubes) = (SmoothMesh::new(), BlockyMesh::new());
/// let stats = NoCubes::new().mesh(&chunk, &classes, &mut smooth, &mut cubes).unwrap();
/// assert_eq!(stats.smooth_quads, 5 * 16); // one quad per visible dirt face
/// assert!(matches!(smooth.quads(), SmoothQuads::Compact(_))); // 6 bytes each
/// assert!(stats.cube_quads > 0 && stats.cube_quads == cubes.opaque.len());
/// ```
#[derive(Clone, Debug)]
pub struct NoCubes {
    table: Box<[CellShape; 256]>,
    greedy: GreedyMesher,
    opaque: Vec<u64>,
    smooth: Vec<u64>,
    map: Vec<u32>,
}

impl Default for NoCubes {
    fn default() -> Self {
        NoCubes::new()
    }
}

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
        NoCubes {
            table,
            greedy: GreedyMesher::new(),
            opaque: Vec::new(),
            smooth: Vec::new(),
            map: Vec::new(),
        }
    }

    /// Meshes `chunk`: the smooth surface into `smooth`, the cube faces and the transparent
    /// blocks' faces into `cubes` (both cleared first). Returns what it wrote. See the type
    /// docs. On error both outputs are left empty.
    pub fn mesh(
        &mut self,
        chunk: &PaddedChunk,
        classes: &BlockClasses,
        smooth: &mut SmoothMesh,
        cubes: &mut BlockyMesh,
    ) -> Result<NoCubesStats, MeshError> {
        let extent = UnormExtent::padded_lattice(chunk.size());
        smooth.reset(extent);
        // The masks first: they name the first unknown id in storage order, anywhere in the
        // padded chunk, before anything is written.
        let any_smooth_face = self
            .build_masks(chunk, classes)
            .and_then(|any| self.greedy.mesh(chunk, classes, cubes).map(|()| any));
        let any_smooth_face = match any_smooth_face {
            Ok(any) => any,
            Err(e) => {
                cubes.clear();
                return Err(e);
            }
        };
        let mut stats = NoCubesStats::default();
        if classes.any_smoothable() {
            drop_smoothable_quads(&mut cubes.opaque.faces, classes);
        }
        if any_smooth_face {
            stats = self.extract(chunk, PositionPacker::new(extent), smooth);
        }
        stats.cube_quads = cubes.opaque.len();
        Ok(stats)
    }

    /// Fills the opaque and smoothable row masks; false when no cell can have a smooth face.
    fn build_masks(
        &mut self,
        chunk: &PaddedChunk,
        classes: &BlockClasses,
    ) -> Result<bool, MeshError> {
        let p = chunk.padded_edge();
        let full_row = if p == 64 { u64::MAX } else { (1u64 << p) - 1 };
        self.opaque.clear();
        self.smooth.clear();
        let (mut any_smooth, mut all) = (0u64, full_row);
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
            any_smooth |= s;
            all &= o;
        }
        Ok(any_smooth != 0 && all != full_row)
    }

    /// Writes the smooth vertices and quads (the masks are built).
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
        }
        let valid = (1u64 << c) - 1;
        let voxels = chunk.voxels();
        let (o_rows, s_rows) = (&self.opaque, &self.smooth);
        let mut stats = NoCubesStats::default();

        for z in 0..c {
            let (cur, prev) = if z & 1 == 0 { (0, slice) } else { (slice, 0) };
            let owned_z = owned_corners(2, z, c);
            for y in 0..c {
                let owned_yz = owned_z & owned_corners(1, y, c);
                let r = y + p * z;
                let rows = [r, r + 1, r + p, r + p + 1];
                let o4 = rows.map(|r| o_rows[r]);
                let s4 = rows.map(|r| s_rows[r]);
                // Cells with a smoothable corner, not all corners opaque: only these can touch
                // a smooth face.
                let (mut all_in, mut any_smooth) = (u64::MAX, 0u64);
                for (o, s) in o4.into_iter().zip(s4) {
                    all_in &= o & (o >> 1);
                    any_smooth |= s | (s >> 1);
                }
                let mut bits = any_smooth & !all_in & valid;
                while bits != 0 {
                    let x = bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    let o = corner_bits(o4, x);
                    let s = corner_bits(s4, x);
                    let m = cur + y * c + x;
                    let owned = owned_yz & owned_corners(0, x, c);
                    let faces = EdgeLanes::smooth_faces(o, s);
                    if faces.any() & owned == 0 {
                        continue;
                    }
                    let cell = Vec3A::new(x as f32, y as f32, z as f32);
                    let position = if o & !s != 0 {
                        cell + Vec3A::ONE
                    } else {
                        cell + self.table[usize::from(o)].offset
                    };
                    self.map[m] = out.push_vertex(BlockVertex {
                        position: packer.pack(position),
                        normal: self.table[usize::from(o)].normal,
                        uv: [0; 2],
                        block: most_common_id(voxels, x + p * (y + p * z), p, s),
                        extra: 0,
                    });
                    stats.smooth_vertices += 1;

                    let here = faces.at_corner0(owned);
                    if here == 0 {
                        continue;
                    }
                    let q = prev + y * c + x;
                    let outward = o & 1 != 0;
                    // The 4 cells' map indices around the edges along x, y and z.
                    let edges = [
                        [m, m - c, q, q - c],
                        [m, q, m - 1, q - 1],
                        [m, m - 1, m - c, m - c - 1],
                    ];
                    for (axis, cells) in edges.into_iter().enumerate() {
                        if (here >> axis) & 1 != 0 {
                            let quad = Quad::new(axis as u8, outward, cells.map(|i| self.map[i]));
                            out.push_paired_quad(quad.paired(|a, b| out.dist2(a, b)));
                            stats.smooth_quads += 1;
                        }
                    }
                }
            }
        }
        stats
    }
}

/// Removes the quads of smoothable blocks (the smooth surface replaces them).
fn drop_smoothable_quads(faces: &mut [Vec<PackedQuad>; 6], classes: &BlockClasses) {
    for quads in faces {
        quads.retain(|q| classes.class(q.block()) != Some(MaterialClass::Smoothable));
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
