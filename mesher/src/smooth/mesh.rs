//! The outputs of the smooth meshers: [`SmoothMesh`] (packed, for the GPU) and [`SmoothMeshF32`]
//! (unquantized, for tests and tools).

use alloc::vec::Vec;

use voxel_core::formats::BlockVertex;
use voxel_core::formats::quantize::UnormExtent;

/// Vertex count up to which quads use `u16` indices.
pub const U16_INDEX_LIMIT: usize = 1 << 16;

/// A packed smooth mesh: [`BlockVertex`]es and quads of 4 vertex indices.
///
/// Each quad `[a, b, c, d]` lists its corners counter-clockwise seen from outside (the side the
/// normals point to) and stands for the triangles `(a, b, c)` and `(a, c, d)`: the mesher
/// rotates the corners so that `a`-`c` is the shorter diagonal. A renderer either expands the
/// quads on the GPU (vertex pulling: vertex `i` of the draw reads quad `i / 6`, corner
/// `[0, 1, 2, 0, 2, 3][i % 6]`) or calls [`triangles`](Self::triangles).
///
/// **Index width.** Quads are `u16` while the mesh has at most [`U16_INDEX_LIMIT`] (65,536)
/// vertices when they are written, the common case (a 62^3 terrain chunk has about 10^4). A
/// denser mesh switches to `u32` quads ([`SmoothQuads::U32`]): the quads written so far are
/// widened once and the rest are written wide. That costs 8 more bytes per quad (16 instead of
/// 8); the vertex buffer is unchanged and the mesh is never split.
///
/// **Bytes.** 16 per vertex plus 8 per quad (16 past the limit). On a closed surface there is
/// about one vertex per quad, so about 24 bytes per quad; [`bytes_per_quad`](Self::bytes_per_quad)
/// reports the exact figure of a mesh.
///
/// Positions are packed over [`extent`](Self::extent) (decode with
/// [`BlockVertex::decode`]). [`clear`](Self::clear) keeps every buffer's capacity.
#[derive(Clone, Debug, PartialEq)]
pub struct SmoothMesh {
    vertices: Vec<BlockVertex>,
    quads16: Vec<[u16; 4]>,
    quads32: Vec<[u32; 4]>,
    wide: bool,
    extent: UnormExtent,
}

impl Default for SmoothMesh {
    fn default() -> Self {
        SmoothMesh::new()
    }
}

/// The quads of a [`SmoothMesh`], in the width the mesh uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SmoothQuads<'a> {
    /// At most 65,536 vertices: 8 bytes per quad.
    U16(&'a [[u16; 4]]),
    /// More vertices: 16 bytes per quad.
    U32(&'a [[u32; 4]]),
}

impl SmoothQuads<'_> {
    /// Number of quads.
    pub fn len(&self) -> usize {
        match self {
            SmoothQuads::U16(q) => q.len(),
            SmoothQuads::U32(q) => q.len(),
        }
    }

    /// True when there are no quads.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Quad `i` widened to `u32`, or `None` past the end.
    pub fn get(&self, i: usize) -> Option<[u32; 4]> {
        match self {
            SmoothQuads::U16(q) => q.get(i).map(|q| q.map(u32::from)),
            SmoothQuads::U32(q) => q.get(i).copied(),
        }
    }

    /// Every quad widened to `u32`.
    pub fn iter(&self) -> impl Iterator<Item = [u32; 4]> + '_ {
        (0..self.len()).filter_map(|i| self.get(i))
    }

    /// The index buffer's bytes, little-endian, 4 indices per quad.
    pub fn bytes(&self) -> &[u8] {
        match self {
            SmoothQuads::U16(q) => bytemuck::cast_slice(q),
            SmoothQuads::U32(q) => bytemuck::cast_slice(q),
        }
    }
}

impl SmoothMesh {
    /// An empty mesh.
    pub const fn new() -> Self {
        SmoothMesh {
            vertices: Vec::new(),
            quads16: Vec::new(),
            quads32: Vec::new(),
            wide: false,
            extent: UnormExtent::UNIT,
        }
    }

    /// Empties the mesh, keeping every buffer's capacity.
    pub fn clear(&mut self) {
        self.vertices.clear();
        self.quads16.clear();
        self.quads32.clear();
        self.wide = false;
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

    /// The quads, `u16` or `u32` (see the type docs).
    #[inline]
    pub fn quads(&self) -> SmoothQuads<'_> {
        if self.wide {
            SmoothQuads::U32(&self.quads32)
        } else {
            SmoothQuads::U16(&self.quads16)
        }
    }

    /// Number of quads.
    #[inline]
    pub fn quad_count(&self) -> usize {
        if self.wide {
            self.quads32.len()
        } else {
            self.quads16.len()
        }
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

    /// Vertex bytes plus index bytes.
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
        if !self.wide && self.vertices.len() <= U16_INDEX_LIMIT {
            self.quads16.push(q.map(|i| i as u16));
        } else {
            self.push_quad_wide(q);
        }
    }

    #[cold]
    fn push_quad_wide(&mut self, q: [u32; 4]) {
        if !self.wide {
            self.wide = true;
            self.quads32.clear();
            self.quads32
                .extend(self.quads16.drain(..).map(|q| q.map(u32::from)));
        }
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
