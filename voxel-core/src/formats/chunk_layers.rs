//! One chunk's packed layers as the GPU backend uploads them ([`ChunkLayersData`]), and the
//! kinds of data they hold ([`DataKind`]): the mesher returns this view of its buffers and the
//! backend stores each kind in its own gigabuffer, so neither names the other.

use super::{BlockVertex, ClutterUnit, DrawBlock, PackedQuad, ShellRun, SmoothQuads};

/// The copy alignment of GPU buffer copies, bytes: every element size is a multiple of it.
const COPY_ALIGNMENT: u32 = 4;

/// One kind of per-chunk GPU data. Each kind lives in its own gigabuffer (a set of pages) whose
/// element type is fixed, so offsets are element indices of that type.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum DataKind {
    /// Greedy quads, [`PackedQuad`], 8 bytes: a chunk's opaque and transparent quad layers,
    /// each grouped by face direction.
    Quads,
    /// Smooth-surface vertices, [`BlockVertex`], 16 bytes.
    SmoothVertices,
    /// Smooth-surface quads, as `u32` words (4 bytes): a chunk's quads are the bytes of the
    /// mesher's [`SmoothQuads`] (compact 6-byte records, or 4
    /// `u16` / `u32` vertex indices per quad, relative to the chunk's first smooth vertex),
    /// zero-padded to a whole word; the draw record carries the form.
    SmoothQuads,
    /// Clutter instances, [`ClutterUnit`], 20 bytes.
    Clutter,
    /// Surface blocks, [`DrawBlock`], 4 bytes: the block list far chunks are raycast from.
    DrawBlocks,
    /// Vertical shells, [`ShellRun`], 8 bytes: a chunk's opaque runs, drawn as boxes instead
    /// of its opaque greedy quads when the mesher is asked for shells.
    Shells,
}

impl DataKind {
    /// Number of kinds.
    pub const COUNT: usize = 6;

    /// Every kind, in index order.
    pub const ALL: [DataKind; DataKind::COUNT] = [
        DataKind::Quads,
        DataKind::SmoothVertices,
        DataKind::SmoothQuads,
        DataKind::Clutter,
        DataKind::DrawBlocks,
        DataKind::Shells,
    ];

    /// Position in [`DataKind::ALL`].
    pub const fn index(self) -> usize {
        self as usize
    }

    /// Bytes per element. Every size is a multiple of 4 (the copy alignment of wgpu and
    /// Vulkan), so every element offset is a valid copy offset.
    pub const fn element_size(self) -> u32 {
        (match self {
            DataKind::Quads => size_of::<PackedQuad>(),
            DataKind::SmoothVertices => size_of::<BlockVertex>(),
            DataKind::SmoothQuads => size_of::<u32>(),
            DataKind::Clutter => size_of::<ClutterUnit>(),
            DataKind::DrawBlocks => size_of::<DrawBlock>(),
            DataKind::Shells => size_of::<ShellRun>(),
        }) as u32
    }

    /// The name used in buffer labels and reports.
    pub const fn name(self) -> &'static str {
        match self {
            DataKind::Quads => "quads",
            DataKind::SmoothVertices => "smooth vertices",
            DataKind::SmoothQuads => "smooth quads",
            DataKind::Clutter => "clutter",
            DataKind::DrawBlocks => "draw blocks",
            DataKind::Shells => "shell runs",
        }
    }
}

const _: () = {
    let mut i = 0;
    while i < DataKind::COUNT {
        assert!(
            DataKind::ALL[i]
                .element_size()
                .is_multiple_of(COPY_ALIGNMENT),
            "element sizes must be multiples of the copy alignment"
        );
        assert!(DataKind::ALL[i].index() == i, "ALL is in index order");
        i += 1;
    }
};

impl core::fmt::Display for DataKind {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// One value per [`DataKind`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PerKind<T>(pub [T; DataKind::COUNT]);

impl<T> PerKind<T> {
    /// The value of `kind`.
    pub fn get(&self, kind: DataKind) -> &T {
        &self.0[kind.index()]
    }

    /// The value of `kind`, mutably.
    pub fn get_mut(&mut self, kind: DataKind) -> &mut T {
        &mut self.0[kind.index()]
    }

    /// `(kind, value)` pairs in kind order.
    pub fn iter(&self) -> impl Iterator<Item = (DataKind, &T)> {
        DataKind::ALL.into_iter().zip(self.0.iter())
    }
}

/// One chunk's packed layers, borrowed from the mesher's output (`mesher::ChunkMesh::layers`,
/// `mesher::lod::NodeMesh::layers`). Every field may be empty;
/// empty layers take no gigabuffer space.
///
/// Quads are grouped by face direction, indexed by `FaceDirection::index` (the mesher's
/// `QuadLayer::faces`), so the cull pass can skip the groups that face away from the camera.
///
/// ```
/// use voxel_core::formats::ChunkLayersData;
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
    /// Opaque vertical shells (`mesher::ShellRuns`), when the node was meshed as shells: they
    /// stand for its opaque greedy quads, which are then empty.
    pub shell_runs: &'a [ShellRun],
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
        *counts.get_mut(DataKind::Shells) = self.shell_runs.len() as u64;
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
        let runs = [ShellRun::new(0, 0, 0, 1, 1, 1); 2];
        layers.shell_runs = &runs;
        assert_eq!(*layers.element_counts().get(DataKind::Shells), 2);
        assert_eq!(layers.byte_len(), 4 * 8 + 3 * 16 + 2 * 8);
        layers.shell_runs = &[];
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
