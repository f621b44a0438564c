//! The cull's rules, records and CPU reference: near chunks (`MeshedChunkInfo`) to
//! multi-draw-indirect commands. `gpu_backend::cull` runs them on the GPU (`cull.wgsl`); this
//! module says what it computes and computes the same on the CPU.
//!
//! ```text
//!  MeshedChunkTable ─┐                       per page p of the quad gigabuffer:
//!  CullView ─────────┼─► cull.wgsl (1 thread ─► args[p*C ..]     20 B DrawIndexedIndirect
//!  CullLayer ────────┘   per table slot)      records[p*C ..]  32 B ChunkDrawIndirect
//!                                             counts[p]        atomic command count
//!                                                  │
//!                            draw pass, per page: bind page p, multi_draw_indexed_indirect_count
//! ```
//!
//! **Per chunk** (one invocation per table slot `0..slot_bound`; vacant slots have all-zero
//! counts and emit nothing): the layer's range is checked (a face group larger than
//! `max_quads_per_draw`, a page past the last, or a range running off its page is *malformed*:
//! counted in `counts[page_count]`, never drawn); the chunk's box is tested against the six
//! frustum planes; then each of the six face-direction groups (Lum's per-face culling, the
//! counts of `FaceLayerRange`) is kept only if it can face the eye: `+X` only if the eye's x is
//! above the box's min x, `-X` only if below its max x, and so on (see [`face_mask`] for why
//! this is exact). Each kept, non-empty group becomes one command.
//!
//! **Paging: one command range per page, one dispatch for all.** A draw binds one page of the
//! quad gigabuffer, so commands are grouped by the page their chunk's quads live in (a chunk's
//! quads never straddle pages). Page `p` owns command slots `p*C .. (p+1)*C` with
//! `C = commands_per_page` (default `6 * table capacity`: a chunk emits at most 6 commands, so
//! no table that fits can overflow it), and `counts[p]` is its atomic count. The draw pass
//! issues one `multi_draw_indexed_indirect_count(args, p*C*20, counts, 4p, C)` per page
//! (`gpu_backend::cull::CullOutput::draw_page`); on NVIDIA (2 GiB bindings) the whole quad
//! gigabuffer is one page, so that is one call per layer. A smaller `C` saves memory on devices with many small
//! pages; commands past it are dropped and show as `counts[p] > C`. The alternative, one
//! dispatch per page, would re-read the table per page.
//!
//! **Command layout.** Each command is written twice at the same index `i`: the 20-byte
//! [`DrawIndexedArgs`] in a tight array (`multi_draw_indexed_indirect(_count)` has a fixed
//! 20-byte stride, so the 32-byte `ChunkDrawIndirect` cannot be its indirect buffer), and the
//! 32-byte `ChunkDrawIndirect` (the same args plus the camera-relative chunk coordinate) that
//! the vertex shader reads as `records[instance_index]`: `first_instance = i` and
//! `instance_count = 1`. A non-zero `first_instance` in an indirect draw needs wgpu's
//! `INDIRECT_FIRST_INSTANCE` (lavapipe and NVIDIA have it; `GpuCapabilities` records it).
//! Quads use one shared index buffer ([`quad_indices`]: `4q + (0,1,2, 0,2,3)`), read from its
//! start (`first_index = 0`) with `base_vertex = 4 * (in-page index of the group's first
//! quad)`, so `vertex_index = 4 * quad + corner` names the quad in the bound page directly and
//! the index buffer needs only `6 * max_quads_per_draw` entries (`edge^3` quads by default, the
//! most one face direction of a chunk can hold). `base_vertex` must fit `i32`: pages hold at
//! most 2^29 quads ([`MAX_PAGE_QUADS`]).
//!
//! **Fallback.** With `MultiDrawPath::ZeroedCommands` (no `MULTI_DRAW_INDIRECT_COUNT`) the
//! args buffer is cleared before the dispatch, so every slot past a page's count is a zero
//! command (`instance_count = 0`) and `multi_draw_indexed_indirect(args, p*C*20, C)` draws
//! nothing extra. Order is not deterministic either way: commands of a page come in the order
//! of the atomics (workgroups take their slots with one global `atomicAdd` per page).
//!
//! **Camera-relative math and its bound.** The GPU never sees a large coordinate as `f32`: a
//! chunk's box centre is `(f32(chunk - camera_chunk) * edge - camera_offset) + centre`, the
//! chunk difference in wrapping `i32` (exact for every pair of valid chunk coordinates: they
//! span at most `2^32 / edge < 2^31` chunks), the camera offset and the chunk-local centre
//! small. `f32(d) * edge` is exact while `|d| * edge < 2^24` blocks (16.7 M blocks, far beyond
//! any far plane); each later step rounds once, so a box within `D` blocks of the eye is placed
//! within about `2 * 2^-24 * D` blocks (under 0.01 blocks at 65,536 blocks). Chunks further than
//! `2^24` blocks are placed less exactly but still that far away, so any frustum with a far
//! plane culls them. Planes come from a camera-relative view-projection
//! ([`CullView::from_view_projection`]), so they too are small numbers.
//!
//! **CPU reference.** [`cull_reference`] makes the same decisions with the same `f32`
//! operations in the same order. GPUs may fuse a multiply and an add (`fma`) where the CPU
//! rounds twice, so a box whose frustum test lands within a few ulps of a plane may be decided
//! differently; everything else (face tests are additions only, placement is exact up to
//! `2^24` blocks) is identical. The parity tests keep random boxes a margin away from every
//! plane and compare the command lists exactly.
//!
//! **Back to front.** `gpu_backend::cull::CullPass` ordered requests writes the same commands sorted far to
//! near per page (a counting sort on a depth key; [`depth_key`] links the rule and its artefacts),
//! for blended layers.
//!
//! **Views.** The camera is an input: a shadow map or a second camera is another
//! [`CullView`] recorded into another output (or the same one, after the draws that
//! read it were recorded: uniforms are copied in encoder order).

mod layout;
pub mod lod;
mod node;
mod order;
mod reference;
mod stats;
mod view;

pub use layout::{
    CULL_FAR, CULL_FROM_LIST, CULL_LOD, CULL_OCCLUSION, CULL_SMOOTH, CullConfig, CullError,
    CullLayout, CullParams, CullUniforms, DrawIndexedArgs, MAX_PAGE_QUADS, MAX_PAGES,
    MAX_QUADS_PER_DRAW, MAX_SMOOTH_PAIRS, OcclusionView, PHASE_EARLY, PHASE_LATE, PHASE_TEST,
    SmoothPages, quad_indices,
};
pub use lod::{LodAnchor, LodParams, LodSettings};
pub use node::{
    DrawRecord, NODE_HAS_BLOCKS, NODE_TRANSPARENT_MASK, NodeRecord, SkirtTooLarge, skirt_count,
};
pub use order::{
    ORDER_KEY_BASE, ORDER_KEYS, cull_reference_ordered, cull_reference_ordered_with, depth_key,
};
pub use reference::{
    ChunkCull, Command, CullReference, SmoothCommand, cull_chunk, cull_node, cull_reference,
    cull_reference_with, face_draw_count, face_mask, in_frustum, layer_range, node_box, node_rel,
    relative_box, relative_chunk,
};
pub use stats::{CullStats, STAT_COUNT};
pub use view::{CullLayer, CullView, PLANE_KEEP_ALL};
