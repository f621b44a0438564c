// The prop cull (render-model/src/props/cull.rs is its CPU twin, operation for operation):
// `prop_zero` zeroes every batch's instance count, then `prop_cull` tests one instance slot
// per thread and appends the visible ones to their batch's range of the visible list.
// prop_records.wgsl and hiz_test.wgsl come before this body.

@group(0) @binding(0) var<uniform> u: PropCullUniforms;
@group(0) @binding(1) var<storage, read> instances: array<PropInstance>;
@group(0) @binding(2) var<storage, read_write> batches: array<PropBatch>;
@group(0) @binding(3) var<storage, read_write> visible: array<u32>;
@group(0) @binding(4) var hiz_texture: texture_2d<f32>;

@compute @workgroup_size(64)
fn prop_zero(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x < u.batch_count {
        atomicStore(&batches[id.x].instance_count, 0u);
    }
}

// False when the sphere lies wholly outside one plane (NaN keeps it).
fn sphere_in_frustum(c: vec3<f32>, radius: f32) -> bool {
    var inside = true;
    for (var i = 0u; i < 6u; i += 1u) {
        let p = u.planes[i];
        let d = ((p.x * c.x + p.y * c.y) + p.z * c.z) + p.w;
        if d < -radius {
            inside = false;
        }
    }
    return inside;
}

// The sphere's bounding cube's corners projected, as the chunk cull projects a box.
fn sphere_visible_hiz(c: vec3<f32>, radius: f32) -> bool {
    var lo = vec2<f32>(1e30);
    var hi = vec2<f32>(-1e30);
    var nearest = 0.0;
    let m = u.view_proj;
    for (var i = 0u; i < 8u; i += 1u) {
        let s = vec3<f32>(f32(i & 1u), f32((i >> 1u) & 1u), f32((i >> 2u) & 1u)) * 2.0 - 1.0;
        let p = c + radius * s;
        let clip = ((m[0] * p.x + m[1] * p.y) + m[2] * p.z) + m[3];
        if clip.w <= u.near {
            return true;
        }
        let ndc = vec2<f32>(clip.x / clip.w, clip.y / clip.w);
        let px = vec2<f32>((ndc.x * 0.5 + 0.5) * u.screen.x, (0.5 - ndc.y * 0.5) * u.screen.y);
        lo = min(lo, px);
        hi = max(hi, px);
        nearest = max(nearest, u.near / clip.w);
    }
    return hiz_rect_visible(lo, hi, nearest);
}

fn column_length(c: vec3<f32>) -> f32 {
    return sqrt(c.x * c.x + c.y * c.y + c.z * c.z);
}

@compute @workgroup_size(64)
fn prop_cull(@builtin(global_invocation_id) id: vec3<u32>) {
    let slot = id.x;
    if slot >= u.slot_count {
        return;
    }
    let r = instances[slot];
    if r.batch == PROP_NO_BATCH || r.batch >= u.batch_count {
        return;
    }
    let start = batches[r.batch].first_instance;
    let shown = batches[r.batch].visible_count;
    if slot < start || slot - start >= shown {
        return;
    }
    let centre = prop_relative_origin(r, u.eye_voxel, u.eye_fraction)
        + prop_local_point(r, vec3<f32>(batches[r.batch].sphere_x, batches[r.batch].sphere_y, batches[r.batch].sphere_z));
    let scale = max(max(column_length(prop_column(r, 0u)), column_length(prop_column(r, 1u))), column_length(prop_column(r, 2u)));
    let radius = batches[r.batch].sphere_radius * scale;
    if (u.flags & PROP_CULL_FRUSTUM) != 0u && !sphere_in_frustum(centre, radius) {
        return;
    }
    if (u.flags & PROP_CULL_OCCLUSION) != 0u && !sphere_visible_hiz(centre, radius) {
        return;
    }
    let k = atomicAdd(&batches[r.batch].instance_count, 1u);
    visible[start + k] = slot;
}
