// The prop records (render-model/src/props/records.rs; layouts checked with naga in
// gpu-backend/src/twins.rs): one instance slot, one batch, the cull's uniforms.

struct PropInstance {
    anchor_x: i32,
    anchor_y: i32,
    anchor_z: i32,
    // Its batch, or PROP_NO_BATCH for an empty slot.
    batch: u32,
    // The mesh-to-anchor affine map: columns x, y, z, translation, 3 floats each.
    local: array<f32, 12>,
}

struct PropBatch {
    // DrawIndexedIndirect: index_count, instance_count, first_index, base_vertex,
    // first_instance. The cull adds one to instance_count per visible instance.
    index_count: u32,
    instance_count: atomic<u32>,
    first_index: u32,
    base_vertex: i32,
    first_instance: u32,
    visible_count: u32,
    live_count: u32,
    material: u32,
    sphere_x: f32,
    sphere_y: f32,
    sphere_z: f32,
    sphere_radius: f32,
}

struct PropCullUniforms {
    view_proj: mat4x4<f32>,
    planes: array<vec4<f32>, 6>,
    eye_voxel: vec3<i32>,
    slot_count: u32,
    eye_fraction: vec3<f32>,
    near: f32,
    screen: vec2<f32>,
    flags: u32,
    batch_count: u32,
}

const PROP_NO_BATCH: u32 = 0xffffffffu;
const PROP_CULL_FRUSTUM: u32 = 1u;
const PROP_CULL_OCCLUSION: u32 = 2u;

// f32(anchor - eye voxel) - eye fraction: the wrapping i32 difference (exact anywhere).
fn prop_relative_origin(r: PropInstance, eye_voxel: vec3<i32>, eye_fraction: vec3<f32>) -> vec3<f32> {
    let d = vec3<i32>(r.anchor_x, r.anchor_y, r.anchor_z) - eye_voxel;
    return vec3<f32>(d) - eye_fraction;
}

fn prop_column(r: PropInstance, c: u32) -> vec3<f32> {
    return vec3<f32>(r.local[3u * c], r.local[3u * c + 1u], r.local[3u * c + 2u]);
}

// ((c0 * p.x + c1 * p.y) + c2 * p.z) + c3.
fn prop_local_point(r: PropInstance, p: vec3<f32>) -> vec3<f32> {
    return ((prop_column(r, 0u) * p.x + prop_column(r, 1u) * p.y) + prop_column(r, 2u) * p.z) + prop_column(r, 3u);
}
