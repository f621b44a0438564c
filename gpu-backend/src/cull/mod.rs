//! The cull pass on the GPU: near chunks (`MeshedChunkInfo`) to multi-draw-indirect commands.
//! What it decides (frustum, face directions, level of detail, far draws, occlusion), the
//! command layout per page and the CPU reference that makes the same decisions are in
//! [`render_model::cull`]; this module holds the pipelines ([`CullPass`]), the buffers a record
//! writes ([`CullOutput`], [`CullFrame`]) and their reads.
//!
//! **Fallback.** With [`MultiDrawPath::ZeroedCommands`] (no `MULTI_DRAW_INDIRECT_COUNT`) the
//! args buffer is cleared before the dispatch, so every slot past a page's count is a zero
//! command (`instance_count = 0`) and `multi_draw_indexed_indirect(args, p*C*20, C)` draws
//! nothing extra. Order is not deterministic either way: commands of a page come in the order
//! of the atomics (workgroups take their slots with one global `atomicAdd` per page).

mod output;
mod pass;

pub use output::{CullFrame, CullOutput, CullReadback};
pub use pass::{CullInputs, CullPass, OcclusionInputs, PreparedCull, UniformSource};

#[cfg(doc)]
use crate::device::MultiDrawPath;
