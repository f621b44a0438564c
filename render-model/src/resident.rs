//! What the renderer records about a resident node: where its layers landed in the gigabuffer
//! ([`ChunkRanges`]), its smooth layer ([`SmoothRanges`]), its bounds ([`mesh_bounds`]) and its
//! chunk-table record ([`chunk_record`]). The GPU side of residency (allocation, tables,
//! uploads) is `gpu_backend::residency`; these are the rules it follows, without wgpu.

use voxel_core::ChunkCoord;
use voxel_core::formats::quantize::UnormExtent;
use voxel_core::formats::{
    ChunkLayersData, DataKind, FaceLayerRange, LayerRange, MeshedChunkInfo, MeshedChunkInfoFields,
    PackedQuad, SmoothQuadForm,
};

/// Where an uploaded chunk's layers live: global element offsets (page * page_capacity +
/// offset in page, see [`PageLayout`](crate::pages::PageLayout)) and counts, per layer. Empty layers
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
    /// for it.
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
    /// Vertical shell runs ([`DataKind::Shells`]).
    pub shell_runs: LayerRange,
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
            DataKind::Shells => self.shell_runs,
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

/// One chunk's mesh, ready to upload: its coordinate, its level of detail and its packed layers
/// (borrowed from the mesher's output; see [`ChunkLayersData`]).
#[derive(Clone, Copy, Debug)]
pub struct ChunkMeshData<'a> {
    /// The chunk's coordinate at its level: a node of level `k` covers the level-0 chunks
    /// `coord * 2^k ..= coord * 2^k + 2^k - 1` on each axis.
    pub coord: ChunkCoord,
    /// Level of detail, `0..=15`: the chunk's voxels are `2^lod` blocks wide.
    pub lod: u32,
    /// Its packed layers (clutter is drawn by the grass pass of a renderer made with clutter).
    pub layers: ChunkLayersData<'a>,
}

/// The smooth layer of a resident chunk (global element ranges).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SmoothRanges {
    /// Vertices in the smooth-vertex gigabuffer.
    pub vertices: LayerRange,
    /// The quads' words in the smooth-quad gigabuffer (indices relative to the first vertex).
    pub quads: LayerRange,
    /// Number of quads.
    pub quad_count: u32,
    /// The form of the quads' words.
    pub form: SmoothQuadForm,
}

/// How smooth vertex positions map to chunk-local blocks: decode over `0..=extent`, then
/// subtract `origin` (the mesher's NoCubes output: `UnormExtent::padded_lattice`, origin 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmoothFrame {
    /// The unorm16 extent the mesher packed positions over.
    pub extent: f32,
    /// The chunk-local position of decoded 0.
    pub origin: f32,
}

impl SmoothFrame {
    /// The frame of the mesher's NoCubes output for chunks of `size`.
    pub fn nocubes(size: voxel_core::ChunkSize) -> SmoothFrame {
        SmoothFrame {
            extent: UnormExtent::padded_lattice(size).get(),
            origin: 1.0,
        }
    }
}

/// The chunk-local bounding box (centre, half extent) of a chunk's quads and smooth vertices,
/// or `None` when it has neither.
pub fn mesh_bounds(
    layers: &ChunkLayersData<'_>,
    smooth: SmoothFrame,
) -> Option<([f32; 3], [f32; 3])> {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    let mut grow = |p: [f32; 3]| {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    };
    let quads = layers
        .opaque_quads
        .iter()
        .chain(&layers.opaque_skirts)
        .chain(&layers.transparent_quads);
    for quad in quads.flat_map(|f| f.iter()) {
        // A quad that does not decode is drawn as garbage by the GPU but cannot be bounded;
        // bound it by its raw position so it still lands in the box.
        let fields = PackedQuad::decode(*quad);
        match fields {
            Ok(f) => f.corners().iter().for_each(|c| grow(c.map(|v| v as f32))),
            Err(_) => grow([0.0; 3]),
        }
    }
    // Far-draw blocks (skirt blocks too) as their unit cubes; positions are 4-bit fields.
    let blocks = layers
        .draw_blocks
        .iter()
        .chain(layers.draw_block_skirts.iter().flat_map(|s| s.iter()));
    for block in blocks {
        let p = block.decode().position.map(|c| c as f32);
        grow(p);
        grow(p.map(|c| c + 1.0));
    }
    // Shell runs as their boxes (byte fields: a bad run is drawn as garbage but still bounded).
    for run in layers.shell_runs {
        let p = [run.x, run.y, run.z].map(f32::from);
        grow(p);
        grow([
            p[0] + run.width() as f32,
            p[1] + f32::from(run.height),
            p[2] + 1.0,
        ]);
    }
    let extent = UnormExtent::new(smooth.extent).unwrap_or(UnormExtent::UNIT);
    for v in layers.smooth_vertices {
        let p = v.decode(extent).position.to_array();
        grow(p.map(|c| c - smooth.origin));
    }
    (lo[0] <= hi[0]).then(|| {
        (
            std::array::from_fn(|i| (lo[i] + hi[i]) * 0.5),
            std::array::from_fn(|i| (hi[i] - lo[i]) * 0.5),
        )
    })
}

/// The chunk-table record of a chunk of level `lod` uploaded at `ranges`.
pub fn chunk_record(
    coord: ChunkCoord,
    lod: u32,
    bounds: Option<([f32; 3], [f32; 3])>,
    ranges: &ChunkRanges,
) -> Result<MeshedChunkInfo, voxel_core::FormatError> {
    let (centre, extent) = bounds.unwrap_or(([0.0; 3], [0.0; 3]));
    let mut fields = MeshedChunkInfoFields {
        chunk: coord,
        lod,
        centre: centre.into(),
        extent: extent.into(),
        ..Default::default()
    };
    ranges.apply_to(&mut fields);
    MeshedChunkInfo::encode(&fields)
}
