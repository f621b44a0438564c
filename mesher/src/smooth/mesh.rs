//! The outputs of the smooth meshers: [`SmoothMesh`] (packed, for the GPU) and [`SmoothMeshF32`]
//! (unquantized, for tests and tools).

use alloc::vec::Vec;

pub use voxel_core::formats::SmoothQuads;
use voxel_core::formats::quantize::UnormExtent;
use voxel_core::formats::{
    BlockVertex, COMPACT_QUAD_MAX_DELTA, compact_quad_decode, compact_quad_encode,
};

use super::PairedQuad;

/// Vertex count up to which quads use 16-bit indices (compact or `u16`).
pub const U16_INDEX_LIMIT: usize = 1 << 16;

/// A packed smooth mesh: [`BlockVertex`]es and quads of 4 vertex indices.
///
/// Each quad `[a, b, c, d]` lists its corners counter-clockwise seen from outside (the side the
/// normals point to) and stands for the triangles `(a, b, c)` and `(a, c, d)`: the mesher
/// rotates the corners so that `a`-`c` is the shorter diagonal. A renderer either expands the
/// quads on the GPU (vertex pulling: vertex `i` of the draw reads quad `i / 6`, corner
/// `[0, 1, 2, 0, 2, 3][i % 6]`) or calls [`triangles`](Self::triangles).
///
/// **Quad forms.** The quads are stored in one of three forms per mesh ([`SmoothQuads`],
/// defined in voxel-core, whose bytes a GPU reads as they are), chosen while they are written:
///
/// | form | bytes per quad | holds |
/// | --- | ---: | --- |
/// | [`Compact`](SmoothQuads::Compact) | 6 | quads whose corners are two pairs of neighbouring corners with indices at most 63 apart, indices up to 65,535 ([`compact_quad`](voxel_core::formats::compact_quad)) |
/// | [`U16`](SmoothQuads::U16) | 8 | any quad of a mesh with at most [`U16_INDEX_LIMIT`] (65,536) vertices |
/// | [`U32`](SmoothQuads::U32) | 16 | any quad |
///
/// A mesh starts compact. Every SurfaceNets quad of a grid with at most 64 samples a row (every
/// chunk grid: a padded 62^3 chunk has 64) fits the compact form, since its vertices are
/// numbered in cell scan order (see the `compact_quad` docs). The first quad that does not fit
/// switches the whole mesh, once, to the narrowest form that holds it: `u16`, or `u32` past
/// 65,536 vertices (a `u16` mesh switches to `u32` in the same way when it grows past that).
/// The quads written so far are converted exactly; the vertex buffer is unchanged and the mesh
/// is never split. Grids with rows longer than 64 samples usually end up `u16`.
///
/// **Bytes.** 16 per vertex plus 6 per quad (8 or 16 in the wider forms). On a closed surface
/// there is about one vertex per quad, so about 22 bytes per quad;
/// [`bytes_per_quad`](Self::bytes_per_quad) reports the exact figure of a mesh. The GPU
/// backend uploads [`vertex_bytes`](Self::vertex_bytes) and the quads'
/// [`bytes`](SmoothQuads::bytes) as they are (padded to whole words), so these are the bytes a
/// chunk occupies on the GPU too.
///
/// Positions are packed over [`extent`](Self::extent) (decode with
/// [`BlockVertex::decode`]). [`clear`](Self::clear) keeps every buffer's capacity.
#[derive(Clone, Debug, PartialEq)]
pub struct SmoothMesh {
    vertices: Vec<BlockVertex>,
    compact: Vec<[u16; 3]>,
    quads16: Vec<[u16; 4]>,
    quads32: Vec<[u32; 4]>,
    form: QuadForm,
    extent: UnormExtent,
}

/// Which buffer of a [`SmoothMesh`] holds its quads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum QuadForm {
    Compact,
    U16,
    U32,
}

impl Default for SmoothMesh {
    fn default() -> Self {
        SmoothMesh::new()
    }
}

impl SmoothMesh {
    /// An empty mesh.
    pub const fn new() -> Self {
        SmoothMesh {
            vertices: Vec::new(),
            compact: Vec::new(),
            quads16: Vec::new(),
            quads32: Vec::new(),
            form: QuadForm::Compact,
            extent: UnormExtent::UNIT,
        }
    }

    /// Empties the mesh, keeping every buffer's capacity; the next quads start compact.
    pub fn clear(&mut self) {
        self.vertices.clear();
        self.compact.clear();
        self.quads16.clear();
        self.quads32.clear();
        self.form = QuadForm::Compact;
    }

    /// Starts a new mesh with positions over `extent`.
    pub(crate) fn reset(&mut self, extent: UnormExtent) {
        self.clear();
        self.extent = extent;
    }

    /// The packed vertices.
    #[inline]
    pub fn vertices(&self) -> &[BlockVertex] {
        &self.vertices
    }

    /// The vertex buffer's bytes (16 per vertex).
    pub fn vertex_bytes(&self) -> &[u8] {
        bytemuck::cast_slice(&self.vertices)
    }

    /// The quads, in the mesh's form (see the type docs).
    #[inline]
    pub fn quads(&self) -> SmoothQuads<'_> {
        match self.form {
            QuadForm::Compact => SmoothQuads::Compact(&self.compact),
            QuadForm::U16 => SmoothQuads::U16(&self.quads16),
            QuadForm::U32 => SmoothQuads::U32(&self.quads32),
        }
    }

    /// Number of quads.
    #[inline]
    pub fn quad_count(&self) -> usize {
        self.quads().len()
    }

    /// True when the mesh has no quads and no vertices.
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty() && self.quad_count() == 0
    }

    /// The extent positions are packed over: pass it to [`BlockVertex::decode`].
    #[inline]
    pub fn extent(&self) -> UnormExtent {
        self.extent
    }

    /// Vertex bytes plus quad bytes.
    pub fn byte_len(&self) -> usize {
        self.vertex_bytes().len() + self.quads().bytes().len()
    }

    /// [`byte_len`](Self::byte_len) divided by the quad count (0 for a mesh without quads).
    pub fn bytes_per_quad(&self) -> f64 {
        match self.quad_count() {
            0 => 0.0,
            n => self.byte_len() as f64 / n as f64,
        }
    }

    /// The two triangles of every quad, counter-clockwise from outside.
    pub fn triangles(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        let quads = self.quads();
        (0..quads.len())
            .filter_map(move |i| quads.get(i))
            .flat_map(|[a, b, c, d]| [[a, b, c], [a, c, d]])
    }

    #[inline]
    pub(crate) fn push_vertex(&mut self, v: BlockVertex) -> u32 {
        let i = self.vertices.len() as u32;
        self.vertices.push(v);
        i
    }

    /// Appends `vertices`; returns the index of the first.
    #[inline]
    pub(crate) fn extend_vertices(&mut self, vertices: &[BlockVertex]) -> u32 {
        let i = self.vertices.len() as u32;
        self.vertices.extend_from_slice(vertices);
        i
    }

    #[inline]
    pub(crate) fn vertex(&self, i: u32) -> Option<&BlockVertex> {
        self.vertices.get(i as usize)
    }

    /// Squared distance between the packed positions of vertices `a` and `b`, in codes (0 for
    /// an index past the end, which the meshers never pass).
    #[inline]
    pub(crate) fn dist2(&self, a: u32, b: u32) -> i64 {
        let pa = self.vertex(a).map_or([0; 3], |v| v.position);
        let pb = self.vertex(b).map_or([0; 3], |v| v.position);
        let d = |i: usize| {
            let d = i64::from(pa[i]) - i64::from(pb[i]);
            d * d
        };
        d(0) + d(1) + d(2)
    }

    /// Appends a quad; every index must be below the current vertex count.
    #[inline]
    pub(crate) fn push_quad(&mut self, q: [u32; 4]) {
        match self.form {
            QuadForm::Compact => {
                if let Some(r) = compact_quad_encode(q) {
                    self.compact.push(r);
                    return;
                }
            }
            QuadForm::U16 => {
                if self.vertices.len() <= U16_INDEX_LIMIT {
                    self.quads16.push(q.map(|i| i as u16));
                    return;
                }
            }
            QuadForm::U32 => {
                self.quads32.push(q);
                return;
            }
        }
        self.push_quad_wider(q);
    }

    /// Appends a quad with its compact record fields (see [`PairedQuad`]): the record when the
    /// mesh is compact and the deltas fit, else as [`push_quad`](Self::push_quad) would. This
    /// skips the general encoder's search on the hot path of SurfaceNets.
    #[inline(always)]
    pub(crate) fn push_paired_quad(&mut self, q: PairedQuad) {
        let fits = |d: u32| d.wrapping_sub(1) < COMPACT_QUAD_MAX_DELTA;
        if self.form == QuadForm::Compact
            && fits(q.da) & fits(q.db)
            && self.vertices.len() <= U16_INDEX_LIMIT
        {
            let record = [q.a, q.b, q.da | q.db << 6 | q.code << 12].map(|v| v as u16);
            debug_assert_eq!(compact_quad_decode(record), Ok(q.corners));
            self.compact.push(record);
        } else {
            self.push_quad(q.corners);
        }
    }

    /// Switches to the narrowest form wider than the current one that holds `q` (`u16` while
    /// the mesh has at most [`U16_INDEX_LIMIT`] vertices, else `u32`), converting the quads
    /// written so far, and appends `q`.
    #[cold]
    fn push_quad_wider(&mut self, q: [u32; 4]) {
        let decode = |r: [u16; 3]| compact_quad_decode(r).unwrap_or_default();
        if self.form == QuadForm::Compact && self.vertices.len() <= U16_INDEX_LIMIT {
            self.form = QuadForm::U16;
            self.quads16.clear();
            let compact = &self.compact;
            self.quads16
                .extend(compact.iter().map(|&r| decode(r).map(|i| i as u16)));
            self.compact.clear();
            self.quads16.push(q.map(|i| i as u16));
            return;
        }
        self.quads32.clear();
        match self.form {
            QuadForm::Compact => self.quads32.extend(self.compact.iter().map(|&r| decode(r))),
            QuadForm::U16 => self
                .quads32
                .extend(self.quads16.iter().map(|q| q.map(u32::from))),
            QuadForm::U32 => {}
        }
        self.compact.clear();
        self.quads16.clear();
        self.form = QuadForm::U32;
        self.quads32.push(q);
    }
}

/// An unquantized SurfaceNets mesh: `f32` positions and raw gradients, one vertex per surface
/// cell in cell order (z, then y, then x), and the quads. Vertices, their order and their
/// formulas are those of `fast-surface-nets`' `SurfaceNetsBuffer`, so the two can be compared
/// directly. The packed [`SmoothMesh`] has the same vertices in the same order except those no
/// quad uses, and the same quads (up to the diagonal, chosen there on quantized positions).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SmoothMeshF32 {
    /// Vertex positions in sample coordinates: the vertex of the cell with minimum corner
    /// `(x, y, z)` lies in `[x, x + 1] x [y, y + 1] x [z, z + 1]`.
    pub positions: Vec<[f32; 3]>,
    /// Density gradients at the vertices, not normalized (a zero gradient stays zero here; the
    /// packed mesh writes [`FALLBACK_NORMAL`](super::FALLBACK_NORMAL) for it).
    pub normals: Vec<[f32; 3]>,
    /// The minimum sample corner of each vertex's cell.
    pub cells: Vec<[u32; 3]>,
    /// Quads as in [`SmoothMesh`], always `u32`; the diagonal is chosen on the `f32` positions.
    pub quads: Vec<[u32; 4]>,
}

impl SmoothMeshF32 {
    /// Empties every buffer, keeping capacity.
    pub fn clear(&mut self) {
        self.positions.clear();
        self.normals.clear();
        self.cells.clear();
        self.quads.clear();
    }

    /// The two triangles of every quad.
    pub fn triangles(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        self.quads
            .iter()
            .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
    }
}

#[cfg(test)]
mod tests {
    use alloc::vec;
    use alloc::vec::Vec;

    use bytemuck::Zeroable;
    use voxel_core::formats::compact_quad::COMPACT_QUAD_FORMS;

    use super::*;

    fn with_vertices(n: usize) -> SmoothMesh {
        let mut mesh = SmoothMesh::new();
        mesh.vertices.resize(n, BlockVertex::zeroed());
        mesh
    }

    /// A quad of every compact form and rotation, with deltas 1 and 63.
    fn every_layout() -> Vec<[u32; 4]> {
        let mut quads = Vec::new();
        for (da, db) in [(1, 1), (1, 63), (63, 1), (63, 63)] {
            let values = [2000, 2000 - da, 1000, 1000 - db];
            for form in COMPACT_QUAD_FORMS {
                let cycle = form.map(|s| values[usize::from(s)]);
                for rotation in 0..4 {
                    quads.push(core::array::from_fn(|i| cycle[(i + rotation) % 4]));
                }
            }
        }
        quads
    }

    fn all(mesh: &SmoothMesh) -> Vec<[u32; 4]> {
        mesh.quads().iter().collect()
    }

    #[test]
    fn every_layout_stays_compact_until_the_first_misfit() {
        let mut mesh = with_vertices(3000);
        let mut expected = every_layout();
        for &q in &expected {
            mesh.push_quad(q);
        }
        assert!(matches!(mesh.quads(), SmoothQuads::Compact(r) if r.len() == 64));
        assert_eq!(all(&mesh), expected);
        assert_eq!(mesh.quads().bytes().len(), 6 * 64);
        assert_eq!(mesh.quads().quad_bytes(), 6);

        // A delta of 64 in the only pairing of neighbours that could fit: u16 from now on,
        // with the quads so far converted exactly.
        let misfit = [2000, 1936, 100, 99];
        assert_eq!(compact_quad_encode(misfit), None);
        mesh.push_quad(misfit);
        expected.push(misfit);
        mesh.push_quad(expected[0]);
        expected.push(expected[0]);
        assert!(matches!(mesh.quads(), SmoothQuads::U16(_)));
        assert_eq!(all(&mesh), expected);
        assert_eq!(mesh.byte_len(), 16 * 3000 + 8 * expected.len());
    }

    #[test]
    fn compact_switches_to_u32_past_65536_vertices() {
        let mut mesh = with_vertices(70_000);
        let mut expected = every_layout();
        for &q in &expected {
            mesh.push_quad(q);
        }
        // Fits the deltas, but not in u16.
        let wide = [69_999, 69_998, 68_000, 67_999];
        mesh.push_quad(wide);
        expected.push(wide);
        assert!(matches!(mesh.quads(), SmoothQuads::U32(_)));
        assert_eq!(all(&mesh), expected);
        assert_eq!(mesh.quads().bytes().len(), 16 * expected.len());
    }

    #[test]
    fn u16_switches_to_u32_when_the_mesh_grows() {
        let mut mesh = with_vertices(300);
        let mut expected = vec![[200, 100, 50, 20], [5, 4, 3, 2]];
        for &q in &expected {
            mesh.push_quad(q);
        }
        assert!(matches!(mesh.quads(), SmoothQuads::U16(_)));
        mesh.vertices
            .resize(U16_INDEX_LIMIT + 1, BlockVertex::zeroed());
        let q = [65_536, 65_535, 7, 6];
        mesh.push_quad(q);
        expected.push(q);
        assert!(matches!(mesh.quads(), SmoothQuads::U32(_)));
        assert_eq!(all(&mesh), expected);
    }

    #[test]
    fn clear_restarts_compact_and_keeps_capacity() {
        let mut mesh = with_vertices(70_000);
        for q in every_layout() {
            mesh.push_quad(q);
        }
        mesh.push_quad([200, 100, 50, 20]);
        mesh.push_quad([69_999, 69_998, 68_000, 67_999]);
        assert!(matches!(mesh.quads(), SmoothQuads::U32(_)));
        let capacity = (
            mesh.compact.capacity(),
            mesh.quads16.capacity(),
            mesh.quads32.capacity(),
        );
        mesh.clear();
        assert!(mesh.is_empty());
        assert!(matches!(mesh.quads(), SmoothQuads::Compact(r) if r.is_empty()));
        assert_eq!(
            (
                mesh.compact.capacity(),
                mesh.quads16.capacity(),
                mesh.quads32.capacity()
            ),
            capacity
        );
    }
}
