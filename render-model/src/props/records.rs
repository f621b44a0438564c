//! The records the prop pass reads on the GPU: one per instance slot, one per batch, one
//! uniform block per cull. Each is `#[repr(C)]`, `Pod`, scalar fields only (no `vec3`
//! padding: the WGSL twins declare the same scalars), its size pinned below.

use bytemuck::{Pod, Zeroable};

use crate::cull::DrawIndexedArgs;

/// [`PropInstanceRecord::batch`] of a slot that holds no instance.
pub const NO_BATCH: u32 = u32::MAX;

/// One instance slot, 64 bytes:
///
/// | bytes | field | WGSL |
/// | --- | --- | --- |
/// | 0..12 | `anchor`: world voxel the instance is placed from, 3 x `i32` | `anchor_x, anchor_y, anchor_z: i32` (or `vec3<i32>`, align 16, at 0) |
/// | 12..16 | `batch`: index of its batch record, [`NO_BATCH`] for an empty slot | `batch: u32` |
/// | 16..64 | `local`: the affine map from mesh space to anchor-relative space, 4 columns of 3 x `f32` (x, y, z axes, then translation) | `local: array<f32, 12>` (not `mat4x3`, whose columns are 16 bytes apart) |
///
/// A vertex at mesh position `p` lands, camera-relative, at
/// `relative_origin(anchor) + (((c0 * p.x + c1 * p.y) + c2 * p.z) + c3)` (see the
/// [module docs](super) for the rule and its exactness).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PropInstanceRecord {
    /// World voxel of the instance's origin.
    pub anchor: [i32; 3],
    /// Its batch, or [`NO_BATCH`].
    pub batch: u32,
    /// Columns of the mesh-to-anchor affine map: x axis, y axis, z axis, translation.
    pub local: [[f32; 3]; 4],
}

const _: () = assert!(
    size_of::<PropInstanceRecord>() == 64,
    "PropInstanceRecord is 64 bytes: anchor, batch, 12 floats"
);

impl PropInstanceRecord {
    /// The record of an empty slot: zeros, batch [`NO_BATCH`].
    pub const EMPTY: PropInstanceRecord = PropInstanceRecord {
        anchor: [0; 3],
        batch: NO_BATCH,
        local: [[0.0; 3]; 4],
    };
}

/// One batch (a mesh primitive with a material), 48 bytes:
///
/// | bytes | field | |
/// | --- | --- | --- |
/// | 0..20 | `args`: wgpu's `DrawIndexedIndirect`: `index_count`, `instance_count`, `first_index`, `base_vertex`, `first_instance` | the CPU writes `instance_count = 0`; the cull adds one per visible instance; `first_instance` is the batch's first slot |
/// | 20..24 | `visible_count`: instances shown, slots `first_instance ..` | `u32` |
/// | 24..28 | `live_count`: instances shown or hidden (hidden ones follow the shown) | `u32` |
/// | 28..32 | `material`: the caller's material index | `u32` |
/// | 32..44 | `sphere_centre`: bounding sphere centre, mesh space, 3 x `f32` | scalars |
/// | 44..48 | `sphere_radius`: its radius, mesh space | `f32` |
///
/// `args` sits at the start so that `draw_indexed_indirect(batches, 48 * b)` draws batch `b`
/// straight from this buffer; `multi_draw_indexed_indirect` needs a 20-byte stride, so a pass
/// that draws every batch in one call copies the args into a tight array first.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PropBatchRecord {
    /// The indexed indirect draw of the batch.
    pub args: DrawIndexedArgs,
    /// Shown instances (the first slots of the range).
    pub visible_count: u32,
    /// Shown and hidden instances.
    pub live_count: u32,
    /// Material index.
    pub material: u32,
    /// Bounding sphere centre, mesh space.
    pub sphere_centre: [f32; 3],
    /// Bounding sphere radius, mesh space.
    pub sphere_radius: f32,
}

const _: () = assert!(
    size_of::<PropBatchRecord>() == 48,
    "PropBatchRecord is 48 bytes: 20 of args, 28 of batch data"
);

/// [`PropCullUniforms::flags`]: test the six frustum planes.
pub const PROP_CULL_FRUSTUM: u32 = 1;
/// [`PropCullUniforms::flags`]: test the depth pyramid (Hi-Z).
pub const PROP_CULL_OCCLUSION: u32 = 2;

/// The prop cull's uniform block, 208 bytes (WGSL uniform layout: each field at its natural
/// alignment, no padding):
///
/// | bytes | field | WGSL |
/// | --- | --- | --- |
/// | 0..64 | `view_proj`: camera-relative view-projection, column-major, reversed-Z | `mat4x4<f32>` |
/// | 64..160 | `planes`: six frustum planes `(n, d)`, inside when `dot(n, p) + d >= 0` | `array<vec4<f32>, 6>` |
/// | 160..172 | `eye_voxel`: the camera's voxel | `vec3<i32>` |
/// | 172..176 | `slot_count`: instance slots to test | `u32` |
/// | 176..188 | `eye_fraction`: the camera's fraction inside its voxel | `vec3<f32>` |
/// | 188..192 | `near`: near plane, blocks | `f32` |
/// | 192..200 | `screen`: width, height, pixels | `vec2<f32>` |
/// | 200..204 | `flags`: [`PROP_CULL_FRUSTUM`], [`PROP_CULL_OCCLUSION`] | `u32` |
/// | 204..208 | `batch_count`: batch records | `u32` |
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct PropCullUniforms {
    /// Camera-relative view-projection (column-major).
    pub view_proj: [[f32; 4]; 4],
    /// Frustum planes, camera-relative.
    pub planes: [[f32; 4]; 6],
    /// The eye's voxel.
    pub eye_voxel: [i32; 3],
    /// Instance slots to test (`0..slot_count`).
    pub slot_count: u32,
    /// The eye's fraction in its voxel, each axis `0..1`.
    pub eye_fraction: [f32; 3],
    /// Near plane, blocks.
    pub near: f32,
    /// Output size, pixels.
    pub screen: [f32; 2],
    /// Which tests run.
    pub flags: u32,
    /// Batch records.
    pub batch_count: u32,
}

const _: () = assert!(
    size_of::<PropCullUniforms>() == 208,
    "PropCullUniforms is 208 bytes in WGSL's uniform layout"
);
