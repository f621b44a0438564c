//! Retained glTF prop instances, the records the GPU prop pass reads, and the CPU twin of
//! its per-instance cull.
//!
//! ```text
//!  PropRegistry ──► instance records  [batch 0: shown.. hidden.. free..][batch 1: ...]   64 B each
//!   (handles)   ──► batch records     [args | visible | live | material | sphere]        48 B each
//!                          │
//!   prop cull (1 thread per slot): record.batch → batch; slot in the shown range?
//!       sphere placed camera-relative → frustum planes → Hi-Z → visible[first_instance +
//!       atomicAdd(&batch.args.instance_count, 1)] = slot
//!                          │
//!   draw: draw_indexed_indirect(batches, 48 * b) per batch (or the args copied tight for one
//!         multi_draw_indexed_indirect); vertex shader: instances[visible[instance_index]]
//! ```
//!
//! **Batches.** Instances are grouped by (primitive, material): each batch owns a contiguous
//! range of instance slots, `first_instance .. first_instance + capacity`, its shown instances
//! first (`visible_count` of them), then its hidden ones (to `live_count`), then free slots
//! (record batch [`NO_BATCH`]). Creating, deleting, showing and hiding move at most two
//! instances within their batch (swaps with the boundary), so ranges stay contiguous and only
//! the slots touched are re-uploaded. A batch that fills doubles its capacity and the layout
//! is rebuilt: [`PropUpload::full`] then asks for everything (amortized: capacities double).
//! The visible list (one `u32` per slot) shares the instance slots' indexing, so a batch's
//! visible instances land in its own range of it and `first_instance` needs no other offset.
//!
//! **Dirty tracking.** [`PropRegistry::take_upload`] returns the merged slot and batch ranges
//! changed since the last call; copying those ranges of [`PropRegistry::instance_records`] and
//! [`PropRegistry::batch_records`] makes the GPU's copy equal to the registry's (a property
//! test checks it on random sequences). Each frame the pass also zeroes every batch's
//! `args.instance_count` before the cull (the CPU records keep it 0).
//!
//! **Camera-relative rule.** An instance is a world voxel `anchor` (`i32`, exact anywhere in
//! the world) plus a small `f32` affine map `local` ([`PropPlacement`]). The GPU never sees a
//! large coordinate: with the eye at voxel `e` plus fraction `f` ([`PropEye`]), a mesh point
//! `p` is at
//!
//! ```text
//! o   = f32(anchor - e) - f                                  wrapping i32 difference, per axis
//! q   = ((c0 * p.x + c1 * p.y) + c2 * p.z) + c3               local's columns, f32
//! rel = o + q                                                then view_proj * (rel, 1)
//! ```
//!
//! The difference is exact in `i32` for any two voxels of the world, and its `f32` conversion
//! is exact below `2^24` blocks; nothing else depends on where the scene is. So a prop at
//! `2^30` from the origin, seen from a camera at the same offset, gives the same `rel` bit for
//! bit as at the origin, hence the same image (tests here and in `voxel-reference` check it).
//! Keep `local`'s translation small ([`PropPlacement::at_world`] takes an `f64` position and
//! keeps only its fraction there). Normals go through the cofactor of `local`'s 3 x 3
//! ([`local_normal`]).
//!
//! **The cull twin.** [`cull_slot`] / [`cull_props_reference`], in this order and in these
//! `f32` operations (a WGSL shader writes them one for one):
//!
//! 1. `record.batch` must be a batch (`< batch_count`, not [`NO_BATCH`]) whose shown range
//!    holds the slot;
//! 2. sphere ([`instance_sphere`]): centre `o + q(batch centre)`, radius `batch radius *
//!    max(max(|c0|, |c1|), |c2|)` with `|c| = sqrt(x * x + y * y + z * z)`;
//! 3. frustum ([`sphere_in_frustum`]): per plane `d = ((n.x c.x + n.y c.y) + n.z c.z) + w`,
//!    culled when `d < -radius` (NaN keeps);
//! 4. Hi-Z ([`sphere_visible_hiz`]): the sphere's bounding cube's 8 corners projected as the
//!    chunk cull projects a box (any corner with `clip.w <= near` keeps it), the rectangle and
//!    nearest depth tested by [`rect_visible_reference`](crate::hiz::rect_visible_reference).
//!
//! A GPU may fuse a multiply and an add where the CPU rounds twice, so a sphere within a few
//! ulps of a plane or of a pyramid texel's depth may be decided differently; parity tests
//! keep their inputs a margin away from both.

pub mod blend;
mod cull;
pub mod emission;
pub mod mips;
mod placement;
mod records;
mod registry;
#[cfg(test)]
mod tests;

pub use blend::blend_order;
pub use cull::{
    PropHiz, SlotCull, cull_props_reference, cull_slot, instance_sphere, sphere_in_frustum,
    sphere_visible_hiz,
};
pub use emission::{
    EMISSION_BIAS, EMISSION_FLAG, EMISSION_MAX, EMISSION_MIN, decode_emission, encode_emission,
    join_emission, split_emission,
};
pub use mips::{MipError, MipLevel, mip_chain, mip_level_count, mip_lod};
pub use placement::{
    PlacementError, PropEye, PropPlacement, local_normal, local_point, relative_origin,
    relative_point,
};
pub use records::{
    NO_BATCH, PROP_CULL_FRUSTUM, PROP_CULL_OCCLUSION, PropBatchRecord, PropCullUniforms,
    PropInstanceRecord,
};
pub use registry::{
    PrimitiveId, PropHandle, PropPrimitiveDesc, PropRegistry, PropRegistryError, PropUpload,
};
