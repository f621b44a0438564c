// The shadow trace: per pixel, the sun and sky visibility of the surface the lighting pass
// shades (the nearer of the G-buffer's and the opaque visibility buffer's), by the DDA march
// of render_model::lighting::shadow through the shadow grid (the same cells in the same
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

// One bit per 8^3 brick of the grid, set when the brick holds a marked cell (shadow_bricks
// in shadow_fill.wgsl): the march jumps the bricks it calls empty.
@group(1) @binding(6) var<storage, read> bricks: array<u32>;

// Twin of shadow::BRICK.
const BRICK: i32 = 8;

// Whether the brick holding grid cell g (each component in 0..GRID_CELLS) has no marked cell.
fn brick_empty(g: vec3<i32>) -> bool {
    let per_axis = u32(GRID_CELLS / BRICK);
    let b = vec3<u32>(g) / u32(BRICK);
    let i = b.x + (b.y + b.z * per_axis) * per_axis;
    return ((bricks[i >> 5u] >> (i & 31u)) & 1u) == 0u;
}

// The axis of the earliest of three times, ties to the lower axis (shadow::first_axis).
fn first_axis(t: vec3<f32>) -> u32 {
    if t.x <= t.y && t.x <= t.z {
        return 0u;
    }
    if t.y <= t.z {
        return 1u;
    }
    return 2u;
}

// Twin of shadow::march_within with a cell size of 1: crossing j along axis a is at
// first[a] + j * delta[a], and a brick with no marked cell is jumped, its crossings counted
// in the cell-by-cell order (the same cells, steps and answer). One shortcut: a ray that
// leaves the grid is unoccluded (cells outside it are never solid, and a ray never comes
// back into the box it left), which is the CPU rule's answer without its remaining steps.
fn march(origin: vec3<f32>, normal: vec3<f32>, dir: vec3<f32>, max_distance: f32) -> bool {
    let bias = t.normal_bias * 1.0;
    let p = origin + normal * bias;
    var cell = vec3<i32>(floor(p));
    let step = select(vec3<i32>(-1), vec3<i32>(1), dir > vec3<f32>(0.0));
    let moves = dir != vec3<f32>(0.0);
    var delta = vec3<f32>(NEVER);
    var first = vec3<f32>(NEVER);
    for (var i = 0u; i < 3u; i += 1u) {
        if moves[i] {
            delta[i] = 1.0 / abs(dir[i]);
            if dir[i] > 0.0 {
                first[i] = (f32(cell[i]) + 1.0 - p[i]) * delta[i];
            } else {
                first[i] = (p[i] - f32(cell[i])) * delta[i];
            }
        }
    }
    let half = GRID_CELLS / 2;
    var crossed = vec3<u32>(0u);
    var steps = 0u;
    while steps < t.max_steps {
        let g = cell + vec3<i32>(half);
        if any(g < vec3<i32>(0)) || any(g >= vec3<i32>(GRID_CELLS)) {
            // Outside the grid: leaving it for good when the ray points away from it.
            let away = (g < vec3<i32>(0) & step < vec3<i32>(0))
                | (g >= vec3<i32>(GRID_CELLS) & step > vec3<i32>(0));
            if any(away) {
                return false;
            }
        } else if brick_empty(g) {
            // Crossings along each axis until the ray leaves the brick that way.
            let lo = (g / BRICK) * BRICK;
            let to_leave = vec3<u32>(select(g - lo + 1, lo + BRICK - g, step > vec3<i32>(0)));
            let leave = select(vec3<f32>(NEVER), first + vec3<f32>(crossed + to_leave - 1u) * delta, moves);
            let exit = first_axis(leave);
            let t_exit = leave[exit];
            if t_exit > max_distance {
                return false;
            }
            var made = vec3<u32>(0u);
            for (var a = 0u; a < 3u; a += 1u) {
                if a == exit {
                    made[a] = to_leave[a];
                } else if moves[a] {
                    // The crossings before the exit's: earlier, or as early on a lower
                    // axis. An estimate by division, then corrected by the rule itself.
                    let limit = to_leave[a] - 1u;
                    let estimate = floor((t_exit - first[a]) / delta[a]) + 1.0 - f32(crossed[a]);
                    var m = u32(clamp(estimate, 0.0, f32(limit)));
                    let tm = first[a] + f32(crossed[a] + m) * delta[a];
                    if m < limit && (tm < t_exit || (tm == t_exit && a < exit)) {
                        m += 1u;
                    }
                    if m > 0u {
                        let tb = first[a] + f32(crossed[a] + m - 1u) * delta[a];
                        if !(tb < t_exit || (tb == t_exit && a < exit)) {
                            m -= 1u;
                        }
                    }
                    made[a] = m;
                }
            }
            cell += step * vec3<i32>(made);
            crossed += made;
            steps += made.x + made.y + made.z;
            continue;
        } else if ((grid[grid_word(g)] >> grid_bit(g)) & 1u) != 0u {
            return true;
        }
        let next = select(vec3<f32>(NEVER), first + vec3<f32>(crossed) * delta, moves);
        let axis = first_axis(next);
        if next[axis] > max_distance {
            return false;
        }
        cell[axis] += step[axis];
        crossed[axis] += 1u;
        steps += 1u;
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
