//! [`GreedyMesher`]: binary greedy meshing with AO-safe merging, from a [`PaddedChunk`] or from a
//! plain padded `u16` array.

use alloc::boxed::Box;
use alloc::vec::Vec;

use voxel_core::PaddedChunk;
use voxel_core::formats::PackedQuad;

use super::BlockyMesh;
use super::faces::SliceQuads;
use super::lone_x::lone_x;
use super::masks::{Content, Masks};
use super::merge::Keys;
use super::plain::{build_columns, padded_edge_of};
use super::slices::{Input, mesh_direction};
use crate::{BlockClasses, MeshError};

/// A reusable blocky mesher: greedy quads (or one quad per face) with per-vertex ambient
/// occlusion, written as [`PackedQuad`](voxel_core::formats::PackedQuad)s into a [`BlockyMesh`].
///
/// It holds its scratch (the masks in three layouts, 6 x 32 KiB at most, plus 26 KiB of keys,
/// equal-key masks and quad places, and a 32 KiB quad buffer for one slice), so meshing many
/// chunks with one mesher allocates nothing after the first chunk of the largest size.
///
/// # How
///
/// 1. The occupancy columns of the [`PaddedChunk`] (one `u64` per padded x-row, kept up to
///    date by voxel-core) are the opaque mask when the palette has no transparent material;
///    otherwise the transparent mask is derived row by row (SIMD compares against the few
///    transparent ids, only for rows that are not empty). An all-air
///    chunk, or one whose every padded voxel is opaque, returns here, before any face is looked
///    at (OR / AND of the columns).
/// 2. Faces per direction and slice are whole-line bit operations: `cur & !front`.
/// 3. Faces merge when their block id and their 4 corner AO values are equal, growing quads in
///    `block-mesh`'s order; AO comes from the opaque bits of the front slice through a
///    512-entry table per direction. Faces none of whose neighbours has an equal key are
///    1 x 1 quads in any order: every face is written as one while its key is computed, and
///    only the quads of faces with an equal neighbour are taken back out and grown.
/// 4. Lines (and ±X occupancy rows) of many faces with no neighbouring face, as on a
///    checkerboard, take a bulk path: the faces that share the first face's key are found
///    with whole-line bit operations and a SIMD compare of the ids, and cost an add and a
///    store each.
///
/// ```
/// use mesher::blocky::{BlockyMesh, GreedyMesher};
/// use mesher::BlockClasses;
/// use voxel_core::{BlockId, ChunkSize, Material, MaterialPalette, PaddedChunk};
///
/// let mut palette = MaterialPalette::new();
/// let stone = palette.push(Material::opaque(128, 128, 128)).unwrap();
/// let classes = BlockClasses::from_palette(&palette);
///
/// // A 2 x 2 x 2 cube in the middle of an 8^3 chunk.
/// let padded = PaddedChunk::from_fn(ChunkSize::S8, |x, y, z| {
///     if (3..5).contains(&x) && (3..5).contains(&y) && (3..5).contains(&z) { stone } else { BlockId::AIR }
/// });
/// let mut mesher = GreedyMesher::new();
/// let mut mesh = BlockyMesh::new();
/// mesher.mesh(&padded, &classes, &mut mesh).unwrap();
/// assert_eq!(mesh.opaque.len(), 6); // one 2 x 2 quad per side
/// assert!(mesh.transparent.is_empty());
/// ```
#[derive(Clone, Debug)]
pub struct GreedyMesher {
    masks: Masks,
    /// Face keys of the slice being merged.
    keys: Box<Keys>,
    /// Quads of the slice being meshed.
    quads: Box<SliceQuads>,
    /// Occupancy columns built by [`mesh_u16`](Self::mesh_u16).
    columns: Vec<u64>,
    ambient_occlusion: bool,
}

impl Default for GreedyMesher {
    fn default() -> Self {
        Self::new()
    }
}

impl GreedyMesher {
    /// A mesher with ambient occlusion on.
    pub fn new() -> Self {
        GreedyMesher {
            masks: Masks::default(),
            keys: Box::new(Keys::new()),
            quads: Box::new([PackedQuad::default(); 4096]),
            columns: Vec::new(),
            ambient_occlusion: true,
        }
    }

    /// Turns ambient occlusion on (default) or off. Off, every corner is unoccluded (3) and
    /// faces merge on block id alone, which gives fewer quads (exactly `block-mesh`'s
    /// `greedy_quads`).
    pub fn with_ambient_occlusion(mut self, on: bool) -> Self {
        self.ambient_occlusion = on;
        self
    }

    /// Whether ambient occlusion is computed.
    pub fn ambient_occlusion(&self) -> bool {
        self.ambient_occlusion
    }

    /// Greedy-meshes `padded` into `out` (cleared first): opaque faces into `out.opaque`,
    /// transparent ones into `out.transparent`.
    ///
    /// Fails with [`MeshError::UnknownBlock`] if a visible face belongs to an id `classes` does
    /// not know (then `out` is left empty). Ids that show no face are not checked.
    pub fn mesh(
        &mut self,
        padded: &PaddedChunk,
        classes: &BlockClasses,
        out: &mut BlockyMesh,
    ) -> Result<(), MeshError> {
        self.run_padded(padded, classes, true, out)
    }

    /// One quad per visible face (no merging), with AO, into `out` (cleared first). Same rules
    /// and errors as [`mesh`](Self::mesh); the free function
    /// [`visible_faces`](super::visible_faces) does the same with a fresh mesher.
    pub fn visible_faces(
        &mut self,
        padded: &PaddedChunk,
        classes: &BlockClasses,
        out: &mut BlockyMesh,
    ) -> Result<(), MeshError> {
        self.run_padded(padded, classes, false, out)
    }

    /// [`mesh`](Self::mesh) (`merge`) or [`visible_faces`](Self::visible_faces) on a padded
    /// chunk's voxels and stored occupancy columns.
    fn run_padded(
        &mut self,
        padded: &PaddedChunk,
        classes: &BlockClasses,
        merge: bool,
        out: &mut BlockyMesh,
    ) -> Result<(), MeshError> {
        let voxels: &[u16] = bytemuck::cast_slice(padded.voxels());
        run(
            &mut self.masks,
            &mut self.keys,
            &mut self.quads,
            padded.padded_edge(),
            voxels,
            padded.columns(),
            classes,
            self.ambient_occlusion,
            merge,
            out,
        )
    }

    /// Greedy-meshes a plain padded array of block ids, the input other meshers take: `p^3`
    /// ids, x fastest (index `x + p * (y + p * z)`), for a padded edge `p` of 10, 18, 34 or 64
    /// (chunks of 8, 16, 32 or 62). The occupancy masks are built here first (SIMD compares,
    /// one `u64` per row), then meshing goes on as in [`mesh`](Self::mesh).
    ///
    /// Fails with [`MeshError::BadShape`] for any other length.
    pub fn mesh_u16(
        &mut self,
        voxels: &[u16],
        classes: &BlockClasses,
        out: &mut BlockyMesh,
    ) -> Result<(), MeshError> {
        let p = padded_edge_of(voxels.len())?;
        build_columns(p, voxels, &mut self.columns);
        run(
            &mut self.masks,
            &mut self.keys,
            &mut self.quads,
            p,
            voxels,
            &self.columns,
            classes,
            self.ambient_occlusion,
            true,
            out,
        )
    }
}

/// Meshes one padded chunk of edge `p`.
#[expect(
    clippy::too_many_arguments,
    reason = "one internal entry shared by the three public ones"
)]
fn run(
    masks: &mut Masks,
    keys: &mut Keys,
    quads: &mut SliceQuads,
    p: usize,
    voxels: &[u16],
    columns: &[u64],
    classes: &BlockClasses,
    ao: bool,
    merge: bool,
    out: &mut BlockyMesh,
) -> Result<(), MeshError> {
    out.clear();
    keys.known = 0;
    keys.speculate = [true; 6];
    if masks.build(p, voxels, columns, classes) != Content::Surface {
        return Ok(());
    }
    let mut input = Input {
        voxels,
        p,
        opaque: masks.opaque(columns),
        transparent: masks.transparent(),
        mixed_transparent: masks.mixed_transparent,
        ao,
        merge,
        handled: [[0; 64]; 2],
        lone_x_rows: false,
    };
    let [o0, o1, ..] = &mut out.opaque.faces;
    let mut handled = [[0; 64]; 2];
    let lone = lone_x::<0>(&input, classes, o0, &mut handled[0])
        .and_then(|()| lone_x::<1>(&input, classes, o1, &mut handled[1]));
    if let Err(e) = lone {
        out.clear();
        return Err(e);
    }
    input.lone_x_rows = handled.iter().flatten().any(|&rows| rows != 0);
    input.handled = handled;
    let [o0, o1, o2, o3, o4, o5] = &mut out.opaque.faces;
    let [t0, t1, t2, t3, t4, t5] = &mut out.transparent.faces;
    let result = mesh_direction::<0>(&input, classes, keys, quads, o0, t0)
        .and_then(|()| mesh_direction::<1>(&input, classes, keys, quads, o1, t1))
        .and_then(|()| mesh_direction::<2>(&input, classes, keys, quads, o2, t2))
        .and_then(|()| mesh_direction::<3>(&input, classes, keys, quads, o3, t3))
        .and_then(|()| mesh_direction::<4>(&input, classes, keys, quads, o4, t4))
        .and_then(|()| mesh_direction::<5>(&input, classes, keys, quads, o5, t5));
    if let Err(e) = result {
        out.clear();
        return Err(e);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use voxel_core::{BlockId, ChunkSize, FaceDirection, Material, MaterialPalette, PaddedChunk};

    use super::*;

    /// A floor whose diagonal is another id: its top faces have no neighbour with an equal key
    /// (the pass that emits such faces before growing quads), the others merge (the passes
    /// that grow quads from the equal-key masks).
    #[test]
    fn faces_without_an_equal_neighbour_stay_single() {
        let mut palette = MaterialPalette::new();
        let stone = palette.push(Material::opaque(128, 128, 128)).unwrap();
        let ore = palette.push(Material::opaque(200, 50, 50)).unwrap();
        let classes = BlockClasses::from_palette(&palette);
        // Padded coordinates: the floor is the first interior layer, the border is air.
        let inside = |v: u32| (1..=16).contains(&v);
        let padded = PaddedChunk::from_fn(ChunkSize::S16, |x, y, z| {
            match (y == 1 && inside(x) && inside(z), x == z) {
                (true, true) => ore,
                (true, false) => stone,
                (false, _) => BlockId::AIR,
            }
        });
        for ao in [true, false] {
            let mut mesher = GreedyMesher::new().with_ambient_occlusion(ao);
            let mut mesh = BlockyMesh::new();
            mesher.mesh(&padded, &classes, &mut mesh).unwrap();
            let top = &mesh.opaque.faces[FaceDirection::PosY as usize];
            let fields: Vec<_> = top.iter().map(|q| q.decode().unwrap()).collect();
            let area = |id: BlockId| -> u32 {
                fields
                    .iter()
                    .filter(|f| f.block == id)
                    .map(|f| f.width * f.height)
                    .sum()
            };
            assert_eq!(area(ore), 16, "ao {ao}");
            assert_eq!(area(stone), 240, "ao {ao}");
            let ores: Vec<_> = fields.iter().filter(|f| f.block == ore).collect();
            assert_eq!(ores.len(), 16, "ao {ao}");
            assert!(ores.iter().all(|f| f.width == 1 && f.height == 1));
            // The two stone triangles merge into far fewer quads than faces.
            assert!(fields.len() - 16 < 40, "ao {ao}: {} quads", fields.len());
        }
    }
}
