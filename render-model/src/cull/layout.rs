//! The numbers the cull pass and its CPU reference share: the command layout per page, the
//! 20-byte draw arguments, the uniform block, and the configuration they come from.

use std::fmt;
use std::ops::Range;

use bytemuck::{Pod, Zeroable};
use voxel_core::ChunkSize;

use super::lod::LodParams;
use super::view::{CullLayer, CullView};
use voxel_core::formats::DataKind;

use crate::pages::PageLayout;

/// Largest page count of the quad gigabuffer one cull handles (the shader's workgroup arrays).
/// 256 pages of 128 MiB (lavapipe's binding limit) are 32 GiB, the most 32-bit element offsets
/// of 8-byte quads can address.
pub const MAX_PAGES: u32 = 256;

/// Largest in-page quad count: `base_vertex = 4 * quad` must fit `i32` for every quad of a
/// page, so pages hold at most 2^29 quads (4 GiB).
pub const MAX_PAGE_QUADS: u32 = 1 << 29;

/// Largest `max_quads_per_draw`: keeps `6 * count` and the shader's sums far from `u32`
/// overflow.
pub const MAX_QUADS_PER_DRAW: u32 = 1 << 26;

/// Largest number of (smooth-vertex page, smooth-quad page) pairs one cull handles (the
/// shader's workgroup arrays): a smooth draw binds one page of each.
pub const MAX_SMOOTH_PAIRS: u32 = 64;

/// `CullUniforms::flags` bit: select nodes by level of detail (else only level 0 is drawn).
pub const CULL_LOD: u32 = 1;
/// `CullUniforms::flags` bit: far-draw nodes whose cells are small enough.
pub const CULL_FAR: u32 = 2;
/// `CullUniforms::flags` bit: write the smooth layer's draws.
pub const CULL_SMOOTH: u32 = 4;
/// `CullUniforms::flags` bit: two-phase occlusion culling against the depth pyramid.
pub const CULL_OCCLUSION: u32 = 8;
/// `CullUniforms::flags` bit: an ordered record culls the transparent list the opaque
/// records of the frame appended, not the whole table.
pub const CULL_FROM_LIST: u32 = 16;

/// Occlusion phase of a cull record: the nodes visible last frame.
pub const PHASE_EARLY: u32 = 0;
/// Occlusion phase: every node tested against the early phase's depth pyramid; the visible
/// ones not drawn early are drawn, and every tested node's visibility bit is updated.
pub const PHASE_LATE: u32 = 1;
/// Occlusion phase: tested against the depth pyramid, bits untouched (a second layer).
pub const PHASE_TEST: u32 = 2;

/// wgpu's `DrawIndexedIndirectArgs` (20 bytes, the stride `multi_draw_indexed_indirect(_count)`
/// reads), as the cull pass writes it.
///
/// | bytes  | field            | value written by the cull                          |
/// | ------ | ---------------- | -------------------------------------------------- |
/// | 0..4   | `index_count`    | `6 * quads` (two triangles per quad)               |
/// | 4..8   | `instance_count` | 1 (0 in a zeroed slot: draws nothing)              |
/// | 8..12  | `first_index`    | 0: the shared quad index buffer is read from its start |
/// | 12..16 | `base_vertex`    | `4 * first quad`, in-page: `vertex_index = 4 * quad + corner` |
/// | 16..20 | `first_instance` | the command's own index in the args buffer         |
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Pod, Zeroable)]
pub struct DrawIndexedArgs {
    /// Indices per instance.
    pub index_count: u32,
    /// Instances.
    pub instance_count: u32,
    /// First index in the index buffer.
    pub first_index: u32,
    /// Added to every index.
    pub base_vertex: i32,
    /// First instance.
    pub first_instance: u32,
}

const _: () = assert!(
    size_of::<DrawIndexedArgs>() == 20,
    "DrawIndexedArgs must be wgpu's 20-byte DrawIndexedIndirectArgs"
);

/// The cull shader's uniform block (`CullUniforms` in `cull.wgsl`), 320 bytes; a unit test
/// checks every offset against naga's layout of the WGSL struct.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct CullUniforms {
    /// Camera-relative planes `[nx, ny, nz, d]`.
    pub planes: [[f32; 4]; 6],
    /// The eye's chunk.
    pub camera_chunk: [i32; 3],
    /// [`CullLayer::index`].
    pub layer: u32,
    /// The eye inside its chunk, blocks.
    pub camera_offset: [f32; 3],
    /// Chunk edge, blocks.
    pub chunk_edge: f32,
    /// Slots tested: `0..slot_bound`.
    pub slot_bound: u32,
    /// Pages of the quad gigabuffer.
    pub page_count: u32,
    /// Quads per full page.
    pub page_capacity: u32,
    /// Quads in the last page.
    pub last_page_capacity: u32,
    /// Command slots per page.
    pub commands_per_page: u32,
    /// Quads one command may draw at most.
    pub max_quads_per_draw: u32,
    /// `CULL_*` bits.
    pub flags: u32,
    /// Occlusion phase (0 early, 1 late).
    pub phase: u32,
    /// Nodes whose cells span at most this many pixels are far-drawn.
    pub far_cell_px: f32,
    /// Entries of the far list.
    pub far_capacity: u32,
    /// Smooth vertices per page.
    pub smooth_vertex_page_capacity: u32,
    /// Smooth-quad words per page.
    pub smooth_quad_page_capacity: u32,
    /// Smooth-quad pages.
    pub smooth_quad_pages: u32,
    /// Smooth draw slots per (vertex page, quad page) pair.
    pub smooth_commands_per_pair: u32,
    /// Pairs with draw slots (0: no smooth draws).
    pub smooth_pairs: u32,
    /// Pixels per unit of tangent (the far test).
    pub focal_px: f32,
    /// The level-of-detail selection.
    pub lod: LodParams,
    /// Camera-relative view-projection (reversed-Z), for the occlusion test.
    pub view_proj: [[f32; 4]; 4],
    /// Output size, pixels.
    pub screen: [f32; 2],
    /// Near plane, blocks.
    pub near: f32,
    /// Zero.
    pub pad: u32,
}

const _: () = assert!(
    size_of::<CullUniforms>() == 320,
    "CullUniforms is 320 bytes"
);

/// What the occlusion test projects boxes with.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OcclusionView {
    /// Camera-relative view-projection (reversed-Z, column-major).
    pub view_proj: [[f32; 4]; 4],
    /// Output width, pixels.
    pub width: u32,
    /// Output height, pixels.
    pub height: u32,
    /// Near plane, blocks.
    pub near: f32,
}

/// What one cull record selects and writes beyond its camera and layer.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CullParams {
    /// Select nodes by level of detail; `None` draws level 0 only (full detail).
    pub lod: Option<LodParams>,
    /// Far-draw nodes whose cells span at most this many pixels (needs `lod` for the focal
    /// length); `None` meshes every node.
    pub far_cell_px: Option<f32>,
    /// Write the smooth layer's draws (opaque layer).
    pub smooth: bool,
    /// Two-phase occlusion culling: the view the boxes are projected with (the record's
    /// inputs then bind the visibility bits and the depth pyramid); `None`: off.
    pub occlusion: Option<OcclusionView>,
    /// Occlusion phase ([`PHASE_EARLY`], [`PHASE_LATE`] or [`PHASE_TEST`]).
    pub phase: u32,
    /// An ordered record culls the frame's transparent list (the meshed nodes with
    /// transparent quads the opaque records drew) instead of every slot.
    pub from_list: bool,
}

impl CullUniforms {
    /// The uniforms of one record.
    pub fn new(
        layout: &CullLayout,
        camera: &CullView,
        layer: CullLayer,
        slot_bound: u32,
        params: &CullParams,
    ) -> Self {
        let mut flags = 0;
        if params.lod.is_some() {
            flags |= CULL_LOD;
        }
        if params.far_cell_px.is_some() && params.lod.is_some() {
            flags |= CULL_FAR;
        }
        if params.smooth && layout.smooth_pairs > 0 {
            flags |= CULL_SMOOTH;
        }
        if params.occlusion.is_some() {
            flags |= CULL_OCCLUSION;
        }
        if params.from_list {
            flags |= CULL_FROM_LIST;
        }
        let view = params.occlusion.unwrap_or_default();
        let lod = params.lod.unwrap_or(LodParams {
            chunk_edge: layout.chunk_edge as f32,
            ..LodParams::default()
        });
        CullUniforms {
            planes: camera.planes,
            camera_chunk: [camera.chunk.x, camera.chunk.y, camera.chunk.z],
            layer: layer.index(),
            camera_offset: camera.offset,
            chunk_edge: layout.chunk_edge as f32,
            slot_bound,
            page_count: layout.page_count,
            page_capacity: layout.page_capacity,
            last_page_capacity: layout.last_page_capacity,
            commands_per_page: layout.commands_per_page,
            max_quads_per_draw: layout.max_quads_per_draw,
            flags,
            phase: params.phase,
            far_cell_px: params.far_cell_px.unwrap_or(0.0),
            far_capacity: layout.far_capacity,
            smooth_vertex_page_capacity: layout.smooth.vertex_page_capacity.max(1),
            smooth_quad_page_capacity: layout.smooth.quad_page_capacity.max(1),
            smooth_quad_pages: layout.smooth.quad_pages,
            smooth_commands_per_pair: layout.smooth_commands_per_pair,
            smooth_pairs: layout.smooth_pairs,
            focal_px: lod.focal_px,
            lod,
            view_proj: view.view_proj,
            screen: [view.width as f32, view.height as f32],
            near: view.near,
            pad: 0,
        }
    }
}

/// The page split of the smooth layer's two gigabuffers, as the cull needs it to group smooth
/// draws by the pages they bind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SmoothPages {
    /// Smooth vertices per page.
    pub vertex_page_capacity: u32,
    /// Smooth-vertex pages.
    pub vertex_pages: u32,
    /// Smooth-quad words per page.
    pub quad_page_capacity: u32,
    /// Smooth-quad pages.
    pub quad_pages: u32,
}

impl SmoothPages {
    /// The split of `vertices` and `quads` (`Gigabuffer::layout` of the two smooth kinds).
    pub fn of(vertices: &PageLayout, quads: &PageLayout) -> SmoothPages {
        SmoothPages {
            vertex_page_capacity: vertices.page_capacity,
            vertex_pages: vertices.page_count,
            quad_page_capacity: quads.page_capacity,
            quad_pages: quads.page_count,
        }
    }

    /// (vertex page, quad page) pairs.
    pub fn pairs(&self) -> u32 {
        self.vertex_pages.saturating_mul(self.quad_pages)
    }
}

/// How a cull pass (`gpu_backend::cull::CullPass`) and its outputs are sized.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CullConfig {
    /// Chunk edge of the scene (places chunks; bounds face groups).
    pub chunk_size: ChunkSize,
    /// Slots of the chunk table the pass will cull.
    pub table_capacity: u32,
    /// Command slots per page; `None`: `6 * table_capacity`, which no table of that capacity
    /// can overflow (a chunk emits at most one command per face direction).
    pub commands_per_page: Option<u32>,
    /// Quads one command may draw (the draw pass's shared index buffer holds `6 *` this many
    /// indices); `None`: `edge^3`, the most quads one face direction of a chunk can have (one
    /// face per voxel; greedy merging only lowers it).
    pub max_quads_per_draw: Option<u32>,
    /// The smooth layer's pages; `None` (or no pages): no smooth draws.
    pub smooth: Option<SmoothPages>,
    /// Entries of the far list; `None`: the table capacity (never overflows).
    pub far_capacity: Option<u32>,
}

impl CullConfig {
    /// The exact (never overflowing) configuration for a table of `table_capacity` slots.
    pub fn new(chunk_size: ChunkSize, table_capacity: u32) -> CullConfig {
        CullConfig {
            chunk_size,
            table_capacity,
            commands_per_page: None,
            max_quads_per_draw: None,
            smooth: None,
            far_capacity: None,
        }
    }
}

/// Why a cull pass or output cannot be created, or a record cannot be prepared.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum CullError {
    /// The quad gigabuffer has no pages (the kind is disabled).
    NoQuadPages,
    /// The layout passed is not the quad gigabuffer's.
    NotQuads(DataKind),
    /// More pages than one cull handles ([`MAX_PAGES`]).
    TooManyPages {
        /// Pages of the quad gigabuffer.
        page_count: u32,
    },
    /// A page holds more quads than `base_vertex` can address ([`MAX_PAGE_QUADS`]); cap the
    /// gigabuffer's `max_page_bytes`.
    PageTooLarge {
        /// Quads per page.
        page_capacity: u32,
    },
    /// `max_quads_per_draw` is 0 or above [`MAX_QUADS_PER_DRAW`].
    BadMaxQuadsPerDraw(u32),
    /// An output buffer would exceed what the device can bind or allocate.
    OutputTooLarge {
        /// Which buffer.
        buffer: &'static str,
        /// Bytes it would take.
        bytes: u64,
        /// The device's limit.
        max_bytes: u64,
    },
    /// More command slots over all pages than 32-bit command indices address.
    TooManyCommands {
        /// `page_count * commands_per_page`.
        total: u64,
    },
    /// The smooth layer has more (vertex page, quad page) pairs than one cull handles
    /// ([`MAX_SMOOTH_PAIRS`]).
    TooManySmoothPairs {
        /// Pairs.
        pairs: u32,
    },
    /// An output created by a pass of another layout was given to `record`.
    OutputMismatch,
    /// A record asked for occlusion culling without the visibility bits and depth pyramid.
    OcclusionInputsMissing,
    /// The device refused one of the pass's buffers (out of memory, or past a limit), in
    /// its words.
    Gpu(String),
    /// Staged uniforms (`UniformSource::Staged`) that cannot be copied: the buffer lacks
    /// `COPY_SRC`, the offset is not a multiple of 4, or the uniforms run past its end.
    StagedUniformsUnusable {
        /// The offset given.
        offset: u64,
        /// The staging buffer's size.
        buffer_size: u64,
    },
}

impl fmt::Display for CullError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CullError::NoQuadPages => write!(f, "the quad gigabuffer has no pages (disabled)"),
            CullError::NotQuads(kind) => {
                write!(f, "the cull pass needs the quad page layout, not {kind}")
            }
            CullError::TooManyPages { page_count } => write!(
                f,
                "the quad gigabuffer has {page_count} pages; one cull handles at most {MAX_PAGES}"
            ),
            CullError::PageTooLarge { page_capacity } => write!(
                f,
                "quad pages of {page_count} quads exceed {MAX_PAGE_QUADS} (base_vertex = 4 * quad \
                 must fit i32); cap GigabufferConfig::max_page_bytes",
                page_count = page_capacity
            ),
            CullError::BadMaxQuadsPerDraw(n) => write!(
                f,
                "max_quads_per_draw {n} must be in 1..={MAX_QUADS_PER_DRAW}"
            ),
            CullError::OutputTooLarge {
                buffer,
                bytes,
                max_bytes,
            } => write!(
                f,
                "cull output {buffer} would take {bytes} bytes, above the device limit of \
                 {max_bytes}; lower CullConfig::commands_per_page or table_capacity"
            ),
            CullError::TooManyCommands { total } => write!(
                f,
                "{total} command slots over all pages; command indices are 32-bit"
            ),
            CullError::TooManySmoothPairs { pairs } => write!(
                f,
                "the smooth layer spans {pairs} (vertex page, quad page) pairs; one cull handles \
                 at most {MAX_SMOOTH_PAIRS}: raise the page size"
            ),
            CullError::OcclusionInputsMissing => write!(
                f,
                "occlusion culling needs the visibility bits and the depth pyramid in the \
                 record's inputs"
            ),
            CullError::StagedUniformsUnusable {
                offset,
                buffer_size,
            } => write!(
                f,
                "staged cull uniforms at offset {offset} of a {buffer_size}-byte buffer cannot \
                 be copied: the buffer needs COPY_SRC usage, the offset a multiple of 4, and \
                 {} bytes from it",
                size_of::<CullUniforms>()
            ),
            CullError::Gpu(message) => write!(f, "cull pass: {message}"),
            CullError::OutputMismatch => {
                write!(
                    f,
                    "this cull output was created for a pass of another layout"
                )
            }
        }
    }
}

impl std::error::Error for CullError {}

/// The resolved sizes both the GPU pass and the CPU reference use.
///
/// Commands live in one range per quad page: page `p` owns command slots
/// `p * commands_per_page .. (p + 1) * commands_per_page` of the args and records buffers, and
/// `counts[p]` says how many of them this cull filled (more than `commands_per_page` means some
/// did not fit and were dropped). `counts[page_count]` counts malformed chunk layers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CullLayout {
    /// Chunk edge, blocks.
    pub chunk_edge: u32,
    /// Quad pages.
    pub page_count: u32,
    /// Quads per full page.
    pub page_capacity: u32,
    /// Quads in the last page.
    pub last_page_capacity: u32,
    /// Command slots per page.
    pub commands_per_page: u32,
    /// Quads one command may draw.
    pub max_quads_per_draw: u32,
    /// The smooth layer's pages (all zero without one).
    pub smooth: SmoothPages,
    /// (vertex page, quad page) pairs with draw slots.
    pub smooth_pairs: u32,
    /// Smooth draw slots per pair.
    pub smooth_commands_per_pair: u32,
    /// Entries of the far list.
    pub far_capacity: u32,
}

impl CullLayout {
    /// The layout for the quad gigabuffer `quads` (`Gigabuffer::layout(DataKind::Quads)`).
    pub fn new(quads: &PageLayout, config: &CullConfig) -> Result<CullLayout, CullError> {
        if quads.kind != DataKind::Quads {
            return Err(CullError::NotQuads(quads.kind));
        }
        if quads.page_count == 0 {
            return Err(CullError::NoQuadPages);
        }
        if quads.page_count > MAX_PAGES {
            return Err(CullError::TooManyPages {
                page_count: quads.page_count,
            });
        }
        if quads.page_capacity > MAX_PAGE_QUADS {
            return Err(CullError::PageTooLarge {
                page_capacity: quads.page_capacity,
            });
        }
        let edge = config.chunk_size.edge();
        let max_quads = config.max_quads_per_draw.unwrap_or(edge * edge * edge);
        if max_quads == 0 || max_quads > MAX_QUADS_PER_DRAW {
            return Err(CullError::BadMaxQuadsPerDraw(max_quads));
        }
        let commands_per_page = config
            .commands_per_page
            .unwrap_or_else(|| config.table_capacity.saturating_mul(6))
            .max(1);
        let total = u64::from(quads.page_count) * u64::from(commands_per_page);
        if total > u64::from(u32::MAX) {
            return Err(CullError::TooManyCommands { total });
        }
        let smooth = config.smooth.unwrap_or_default();
        let smooth_pairs = smooth.pairs();
        if smooth_pairs > MAX_SMOOTH_PAIRS {
            return Err(CullError::TooManySmoothPairs {
                pairs: smooth_pairs,
            });
        }
        Ok(CullLayout {
            chunk_edge: edge,
            page_count: quads.page_count,
            page_capacity: quads.page_capacity,
            last_page_capacity: quads.last_page_capacity,
            commands_per_page,
            max_quads_per_draw: max_quads,
            smooth,
            smooth_pairs,
            smooth_commands_per_pair: config.table_capacity.max(1),
            far_capacity: config.far_capacity.unwrap_or(config.table_capacity).max(1),
        })
    }

    /// Command slots over all pages.
    pub fn total_commands(&self) -> u64 {
        u64::from(self.page_count) * u64::from(self.commands_per_page)
    }

    /// The command slots of page `page`.
    pub fn page_commands(&self, page: u32) -> Range<u64> {
        let start = u64::from(page) * u64::from(self.commands_per_page);
        start..start + u64::from(self.commands_per_page)
    }

    /// Quads in page `page` (0 past the last).
    pub fn page_quads(&self, page: u32) -> u32 {
        if page + 1 < self.page_count {
            self.page_capacity
        } else if page + 1 == self.page_count {
            self.last_page_capacity
        } else {
            0
        }
    }
}

/// The shared quad index buffer of the draw passes: `6 * quads` indices, quad `q` as the two
/// triangles `4q + (0, 1, 2)` and `4q + (0, 2, 3)` (`packed_quad_corner`'s winding). With the
/// cull's `base_vertex = 4 * first quad`, the vertex shader sees `vertex_index = 4 * quad +
/// corner` with `quad` the in-page index of the quad. Size it for
/// [`CullLayout::max_quads_per_draw`].
pub fn quad_indices(quads: u32) -> Vec<u32> {
    (0..quads)
        .flat_map(|q| {
            let v = 4 * q;
            [v, v + 1, v + 2, v, v + 2, v + 3]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const MIB: u64 = 1 << 20;

    #[test]
    fn layout_follows_the_quad_pages() {
        let quads = PageLayout::plan(DataKind::Quads, 300 * MIB, 128 * MIB).unwrap();
        let layout = CullLayout::new(&quads, &CullConfig::new(ChunkSize::S32, 1000)).unwrap();
        assert_eq!(layout.page_count, 3);
        assert_eq!(layout.commands_per_page, 6000);
        assert_eq!(layout.max_quads_per_draw, 32 * 32 * 32);
        assert_eq!(layout.total_commands(), 18_000);
        assert_eq!(layout.page_commands(2), 12_000..18_000);
        assert_eq!(layout.page_quads(0), (128 * MIB / 8) as u32);
        assert_eq!(layout.page_quads(2), quads.last_page_capacity);
        assert_eq!(layout.page_quads(3), 0);
    }

    #[test]
    fn layout_errors() {
        let config = CullConfig::new(ChunkSize::S16, 10);
        let empty = PageLayout::plan(DataKind::Quads, 0, 128 * MIB).unwrap();
        assert_eq!(
            CullLayout::new(&empty, &config),
            Err(CullError::NoQuadPages)
        );
        let clutter = PageLayout::plan(DataKind::Clutter, MIB, MIB).unwrap();
        assert_eq!(
            CullLayout::new(&clutter, &config),
            Err(CullError::NotQuads(DataKind::Clutter))
        );
        let many = PageLayout::plan(DataKind::Quads, 257 * 8, 8).unwrap();
        assert!(matches!(
            CullLayout::new(&many, &config),
            Err(CullError::TooManyPages { page_count: 257 })
        ));
        let huge = PageLayout::plan(DataKind::Quads, 8 << 30, 8 << 30).unwrap();
        let e = CullLayout::new(&huge, &config).unwrap_err();
        assert!(matches!(e, CullError::PageTooLarge { .. }));
        assert!(e.to_string().contains("max_page_bytes"));
        let ok = PageLayout::plan(DataKind::Quads, 4 << 30, 4 << 30).unwrap();
        assert_eq!(ok.page_capacity, MAX_PAGE_QUADS);
        assert!(
            CullLayout::new(&ok, &config).is_ok(),
            "2^29 quads per page fit"
        );
        let too_many = CullConfig {
            commands_per_page: Some(u32::MAX),
            ..config
        };
        let two_pages = PageLayout::plan(DataKind::Quads, 16, 8).unwrap();
        assert!(matches!(
            CullLayout::new(&two_pages, &too_many),
            Err(CullError::TooManyCommands { .. })
        ));
        let zero = CullConfig {
            max_quads_per_draw: Some(0),
            ..config
        };
        assert_eq!(
            CullLayout::new(&ok, &zero),
            Err(CullError::BadMaxQuadsPerDraw(0))
        );
    }

    #[test]
    fn quad_indices_follow_the_winding() {
        assert_eq!(quad_indices(2), vec![0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7]);
        assert!(quad_indices(0).is_empty());
    }
}
