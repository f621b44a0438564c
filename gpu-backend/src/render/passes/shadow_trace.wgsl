// The shadow trace: per pixel, the sun and sky visibility of the surface the lighting pass
// shades (the nearer of the G-buffer's and the opaque visibility buffer's), by the DDA march
// of render_model::lighting::shadow through the shadow grid (the same operations in the same
// order), written as a Visibility word (bit 0 sun, bits 1..4 open sky directions) for the
// lighting pass. 8 x 8 pixels per workgroup. render_common.wgsl and shadow_grid.wgsl (the
// grid's layout) come before this body.

// Twin of render_model::lighting::ShadowTraceUniforms.
struct ShadowTraceUniforms {
    fraction: vec3<f32>,
    flags: u32,
    max_steps: u32,
    max_distance: f32,
    normal_bias: f32,
    sky_distance: f32,
}

// Twins of render_model::lighting::{SHADOW_SUN, SHADOW_SKY, shadow::GRID_CELLS} (a test
// compares them).
const SHADOW_SUN: u32 = 1u;
const SHADOW_SKY: u32 = 2u;
const GRID_CELLS: i32 = 256;
// Stands for the CPU rule's infinity (no boundary is crossed along an axis the ray does not
// move on); far beyond every reachable distance.
const NEVER: f32 = 1e30;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<storage, read> materials: array<GpuMaterial>;

@group(1) @binding(0) var<uniform> t: ShadowTraceUniforms;
@group(1) @binding(1) var<storage, read> grid: array<u32>;
@group(1) @binding(2) var gbuffer_normal: texture_2d<u32>;
@group(1) @binding(3) var gbuffer_depth: texture_depth_2d;
// The opaque visibility buffer (render::far), read when FRAME_SPLAT is set.
@group(1) @binding(4) var<storage, read> visibility: array<vec2<u32>>;
@group(1) @binding(5) var<storage, read_write> shadow_out: array<u32>;

// The number of sky directions (shadow::SKY_DIRECTIONS; the directions are in
// surface_visibility).
const SKY_COUNT: u32 = 5u;

// Whether camera-relative block `cell` is marked in the grid (false outside it).
fn grid_solid(cell: vec3<i32>) -> bool {
    let g = cell + vec3<i32>(GRID_CELLS / 2);
    if any(g < vec3<i32>(0)) || any(g >= vec3<i32>(GRID_CELLS)) {
        return false;
    }
    return ((grid[grid_word(g)] >> grid_bit(g)) & 1u) != 0u;
}

// Twin of shadow::march_within with a cell size of 1, and one shortcut: a ray that leaves
// the grid is unoccluded (cells outside it are never solid, and a ray never comes back into
// the box it left), which is the CPU rule's answer without its remaining steps.
fn march(origin: vec3<f32>, normal: vec3<f32>, dir: vec3<f32>, max_distance: f32) -> bool {
    let bias = t.normal_bias * 1.0;
    let p = origin + normal * bias;
    var cell = vec3<i32>(floor(p));
    let step = select(vec3<i32>(-1), vec3<i32>(1), dir > vec3<f32>(0.0));
    var delta = vec3<f32>(NEVER);
    var next = vec3<f32>(NEVER);
    for (var i = 0u; i < 3u; i += 1u) {
        if dir[i] != 0.0 {
            delta[i] = 1.0 / abs(dir[i]);
            if dir[i] > 0.0 {
                next[i] = (f32(cell[i]) + 1.0 - p[i]) * delta[i];
            } else {
                next[i] = (p[i] - f32(cell[i])) * delta[i];
            }
        }
    }
    let half = GRID_CELLS / 2;
    for (var s = 0u; s < t.max_steps; s += 1u) {
        let g = cell + vec3<i32>(half);
        if any(g < vec3<i32>(0)) || any(g >= vec3<i32>(GRID_CELLS)) {
            // Outside the grid: leaving it for good when the ray points away from it.
            let away = (g < vec3<i32>(0) & step < vec3<i32>(0))
                | (g >= vec3<i32>(GRID_CELLS) & step > vec3<i32>(0));
            if any(away) {
                return false;
            }
        } else if grid_solid(cell) {
            return true;
        }
        var axis = 2u;
        if next.x <= next.y && next.x <= next.z {
            axis = 0u;
        } else if next.y <= next.z {
            axis = 1u;
        }
        if next[axis] > max_distance {
            return false;
        }
        cell[axis] += step[axis];
        next[axis] += delta[axis];
    }
    return false;
}

// Twin of shadow::surface_visibility, packed as Visibility::pack.
fn surface_visibility(origin: vec3<f32>, n: vec3<f32>) -> u32 {
    let g = vec3<i32>(floor(origin)) + vec3<i32>(GRID_CELLS / 2);
    if any(g < vec3<i32>(0)) || any(g >= vec3<i32>(GRID_CELLS)) {
        return 1u | (SKY_COUNT << 1u);
    }
    let l = frame.lighting.sun_direction;
    let facing = n.x * l.x + n.y * l.y + n.z * l.z > 0.0;
    var sun = true;
    if (t.flags & SHADOW_SUN) != 0u {
        sun = facing && !march(origin, n, l, t.max_distance);
    }
    var open = SKY_COUNT;
    if (t.flags & SHADOW_SKY) != 0u {
        // Twin of shadow::SKY_DIRECTIONS: straight up and four at 45 degrees from it.
        let h = 0.70710677;
        var sky = array<vec3<f32>, 5>(
            vec3<f32>(0.0, 1.0, 0.0),
            vec3<f32>(h, h, 0.0),
            vec3<f32>(-h, h, 0.0),
            vec3<f32>(0.0, h, h),
            vec3<f32>(0.0, h, -h),
        );
        open = 0u;
        for (var i = 0u; i < SKY_COUNT; i += 1u) {
            if !march(origin, n, sky[i], t.sky_distance) {
                open += 1u;
            }
        }
    }
    return u32(sun) | (open << 1u);
}

@compute @workgroup_size(8, 8)
fn shadow_trace(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= frame.width || id.y >= frame.height {
        return;
    }
    let p = id.xy;
    let at = p.y * frame.width + p.x;
    var depth = textureLoad(gbuffer_depth, vec2<i32>(p), 0);
    var n = vec3<f32>(0.0);
    var splatted = false;
    if (frame.flags & FRAME_SPLAT) != 0u {
        let v = visibility[at];
        let d = bitcast<f32>(v.y);
        // Reversed-Z: nearer is greater; 0 is the cleared far plane.
        if d > depth {
            depth = d;
            n = vec3<f32>(face_normal((v.x >> 16u) & 7u));
            splatted = true;
        }
    }
    if depth <= 0.0 {
        // The sky: nothing to shade.
        shadow_out[at] = 1u | (SKY_COUNT << 1u);
        return;
    }
    if !splatted {
        n = oct32_decode(textureLoad(gbuffer_normal, vec2<i32>(p), 0).x);
    }
    let seen = eye_ray(p, depth);
    let origin = t.fraction + seen.dir * seen.distance;
    shadow_out[at] = surface_visibility(origin, n);
}
