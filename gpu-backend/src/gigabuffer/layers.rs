//! The input of an upload (a chunk's packed layers) and its result (where they landed).

use voxel_core::formats::{
    BlockVertex, ClutterUnit, DrawBlock, FaceLayerRange, LayerRange, MeshedChunkInfoFields,
    PackedQuad, SmoothQuadForm, SmoothQuads,
};

use super::{DataKind, PerKind};

/// One chunk's packed layers, borrowed from the mesher's output. Every field may be empty;
/// empty layers take no gigabuffer space.
///
/// Quads are grouped by face direction, indexed by `FaceDirection::index` (the mesher's
/// `QuadLayer::faces`), so the cull pass can skip the groups that face away from the camera.
///
/// ```
/// use gpu_backend::gigabuffer::ChunkLayersData;
/// use voxel_core::formats::PackedQuad;
///
/// let up = [PackedQuad::default(); 3];
/// let mut layers = ChunkLayersData::default();
/// layers.opaque_quads[2] = &up; // FaceDirection::PosY
/// assert_eq!(layers.quad_count(), 3);
/// ```
#[derive(Clone, Copy, Debug, Default)]
pub struct ChunkLayersData<'a> {
    /// Opaque greedy quads, one slice per face direction.
    pub opaque_quads: [&'a [PackedQuad]; 6],
    /// Transparent greedy quads, one slice per face direction.
    pub transparent_quads: [&'a [PackedQuad]; 6],
    /// Smooth-surface vertices.
    pub smooth_vertices: &'a [BlockVertex],
    /// Smooth-surface quads in the mesher's form (`SmoothMesh::quads`): 4 indices into
    /// `smooth_vertices` each (checked on upload), uploaded byte for byte.
    pub smooth_quads: SmoothQuads<'a>,
    /// Clutter instances.
    pub clutter_units: &'a [ClutterUnit],
    /// Surface blocks (far-field data): the chunk's `SurfaceBlocks` list.
    pub draw_blocks: &'a [DrawBlock],
    /// Opaque skirt quads per side (`mesher::lod::Skirts`): stored right after the opaque
    /// quads of the same face direction, drawn only while the neighbour on that side is drawn
    /// at another level of detail.
    pub opaque_skirts: [&'a [PackedQuad]; 6],
    /// Skirt blocks per side, stored after `draw_blocks` (drawn like the skirt quads).
    pub draw_block_skirts: [&'a [DrawBlock]; 6],
    /// The hiding occupancy of the chunk's padded neighbourhood
    /// (`mesher::surface_blocks::hiding_mask`), stored after the skirt blocks in the
    /// draw-block gigabuffer: far draws read it for ambient occlusion.
    pub hiding_mask: &'a [u32],
    /// The transparent occupancy of the same neighbourhood
    /// (`mesher::surface_blocks::transparent_mask`; empty when it has no transparent voxel),
    /// stored right after the hiding mask.
    pub transparent_mask: &'a [u32],
}

impl<'a> ChunkLayersData<'a> {
    /// Splits quads sorted by face direction into the six groups `counts` describes, or `None`
    /// if the counts do not add up to `quads.len()`.
    pub fn split_by_face(
        quads: &'a [PackedQuad],
        counts: [u32; 6],
    ) -> Option<[&'a [PackedQuad]; 6]> {
        let total: u64 = counts.iter().map(|&c| u64::from(c)).sum();
        if total != quads.len() as u64 {
            return None;
        }
        let mut rest = quads;
        Some(counts.map(|c| {
            let (head, tail) = rest.split_at(c as usize);
            rest = tail;
            head
        }))
    }

    /// Opaque quads, their skirts and transparent quads.
    pub fn quad_count(&self) -> u64 {
        let sum = |faces: &[&[PackedQuad]; 6]| faces.iter().map(|f| f.len() as u64).sum::<u64>();
        sum(&self.opaque_quads) + sum(&self.opaque_skirts) + sum(&self.transparent_quads)
    }

    /// Draw blocks, their skirts and the hiding mask's words: the chunk's elements of
    /// [`DataKind::DrawBlocks`].
    pub fn draw_block_words(&self) -> u64 {
        let skirts: u64 = self.draw_block_skirts.iter().map(|s| s.len() as u64).sum();
        self.draw_blocks.len() as u64
            + skirts
            + self.hiding_mask.len() as u64
            + self.transparent_mask.len() as u64
    }

    /// Elements of each kind this chunk needs.
    pub fn element_counts(&self) -> PerKind<u64> {
        let mut counts = PerKind::default();
        *counts.get_mut(DataKind::Quads) = self.quad_count();
        *counts.get_mut(DataKind::SmoothVertices) = self.smooth_vertices.len() as u64;
        *counts.get_mut(DataKind::SmoothQuads) = self.smooth_quads.word_len() as u64;
        *counts.get_mut(DataKind::Clutter) = self.clutter_units.len() as u64;
        *counts.get_mut(DataKind::DrawBlocks) = self.draw_block_words();
        counts
    }

    /// Bytes this chunk occupies once uploaded.
    pub fn byte_len(&self) -> u64 {
        self.element_counts()
            .iter()
            .map(|(kind, &n)| n * u64::from(kind.element_size()))
            .sum()
    }
}

/// Where an uploaded chunk's layers live: global element offsets (page * page_capacity +
/// offset in page, see [`PageLayout`](super::PageLayout)) and counts, per layer. Empty layers
/// have offset 0 and count 0.
///
/// The quads of a chunk are one allocation: opaque groups first (each face direction's quads
/// followed by that side's skirt quads, counted in the group), then transparent ones, so
/// `transparent_quads.offset = opaque_quads.offset + opaque total`. The draw-block allocation
/// holds the blocks, then the skirt blocks side by side, then the hiding mask.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ChunkRanges {
    /// Opaque quads, by face direction, in the quad gigabuffer: each group is the face's
    /// quads followed by its skirt quads.
    pub opaque_quads: FaceLayerRange,
    /// The skirt quads at the end of each opaque group.
    pub opaque_skirts: [u32; 6],
    /// Transparent quads, by face direction, in the quad gigabuffer.
    pub transparent_quads: FaceLayerRange,
    /// Smooth vertices, in the smooth-vertex gigabuffer.
    pub smooth_vertices: LayerRange,
    /// Smooth quads (indices relative to `smooth_vertices.offset`), in the smooth-quad
    /// gigabuffer: its words (`DataKind::SmoothQuads` elements), in the form
    /// `smooth_quad_form`, holding `smooth_quad_count` quads. `MeshedChunkInfo` has no field
    /// for it yet.
    pub smooth_quads: LayerRange,
    /// Number of smooth quads.
    pub smooth_quad_count: u32,
    /// The form of the smooth quads' words.
    pub smooth_quad_form: SmoothQuadForm,
    /// Clutter units, in the clutter gigabuffer.
    pub clutter_units: LayerRange,
    /// Surface blocks, in the draw-block gigabuffer (without their skirts).
    pub draw_blocks: LayerRange,
    /// Skirt blocks per side, stored one side after the other right after `draw_blocks`.
    pub draw_block_skirts: [u32; 6],
    /// The hiding mask's words, after the skirt blocks (count 0 when none was uploaded).
    pub hiding_mask: LayerRange,
    /// The transparent mask's words, right after the hiding mask (count 0 when none).
    pub transparent_mask: LayerRange,
}

impl ChunkRanges {
    /// Writes the layer ranges `MeshedChunkInfo` holds into `fields`, leaving the chunk
    /// coordinate, lod and bounds as they are.
    pub fn apply_to(&self, fields: &mut MeshedChunkInfoFields) {
        fields.opaque_quads = self.opaque_quads;
        fields.transparent_quads = self.transparent_quads;
        fields.smooth_vertices = self.smooth_vertices;
        fields.clutter_units = self.clutter_units;
    }

    /// The global range of `kind`'s allocation (both quad layers together for
    /// [`DataKind::Quads`]).
    pub fn range_of(&self, kind: DataKind) -> LayerRange {
        match kind {
            DataKind::Quads => LayerRange {
                offset: self.opaque_quads.offset,
                count: (self.opaque_quads.total() + self.transparent_quads.total()) as u32,
            },
            DataKind::SmoothVertices => self.smooth_vertices,
            DataKind::SmoothQuads => self.smooth_quads,
            DataKind::Clutter => self.clutter_units,
            DataKind::DrawBlocks => LayerRange {
                offset: self.draw_blocks.offset,
                count: self.draw_blocks.count
                    + self.draw_block_skirts.iter().sum::<u32>()
                    + self.hiding_mask.count
                    + self.transparent_mask.count,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_by_face_checks_the_counts() {
        let quads = [PackedQuad::default(); 6];
        let faces = ChunkLayersData::split_by_face(&quads, [1, 0, 2, 0, 3, 0]).unwrap();
        assert_eq!(faces.map(<[_]>::len), [1, 0, 2, 0, 3, 0]);
        assert!(ChunkLayersData::split_by_face(&quads, [1, 0, 2, 0, 3, 1]).is_none());
        assert!(ChunkLayersData::split_by_face(&quads, [u32::MAX, 0, 0, 0, 0, 7]).is_none());
    }

    #[test]
    fn counts_and_bytes() {
        let quads = [PackedQuad::default(); 4];
        let vertices = [BlockVertex::default(); 3];
        let mut layers = ChunkLayersData {
            smooth_vertices: &vertices,
            ..Default::default()
        };
        layers.opaque_quads[0] = &quads[..1];
        layers.transparent_quads[5] = &quads[1..];
        let counts = layers.element_counts();
        assert_eq!(*counts.get(DataKind::Quads), 4);
        assert_eq!(*counts.get(DataKind::SmoothVertices), 3);
        assert_eq!(layers.byte_len(), 4 * 8 + 3 * 16);
        // Smooth quads take whole words: 3 compact records (18 bytes) take 5.
        let records = [[2, 1, 1 | 1 << 6]; 3];
        layers.smooth_quads = SmoothQuads::Compact(&records);
        assert_eq!(*layers.element_counts().get(DataKind::SmoothQuads), 5);
        assert_eq!(layers.byte_len(), 4 * 8 + 3 * 16 + 20);
        let wide = [[0u32, 1, 2, 0]; 2];
        layers.smooth_quads = SmoothQuads::U32(&wide);
        assert_eq!(*layers.element_counts().get(DataKind::SmoothQuads), 8);
    }
}
