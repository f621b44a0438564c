// The antialias pass: FXAA of the tonemapped, sRGB-encoded image (ldr) into the output, as a
// fragment pass (full-screen triangle into the output's plain view: the bytes are already
// encoded) or a compute pass (8 x 8 pixels per workgroup, into its storage view). The twin of
// render_model::antialias, same operations. render_common.wgsl and fullscreen.wgsl come
// before this body.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<storage, read> materials: array<GpuMaterial>;

@group(1) @binding(3) var ldr: texture_2d<f32>;

// The compute pass's output.
@group(1) @binding(7) var output_out: texture_storage_2d<rgba8unorm, write>;

const EDGE_MIN: f32 = 0.0312;
const EDGE_RELATIVE: f32 = 0.125;
const SUBPIXEL: f32 = 0.75;
const STEP_COUNT: u32 = 10u;
const STEPS: array<i32, 10> = array<i32, 10>(1, 1, 1, 1, 1, 2, 2, 2, 4, 8);

fn fetch(p: vec2<i32>) -> vec3<f32> {
    let q = clamp(p, vec2<i32>(0), vec2<i32>(i32(frame.width) - 1, i32(frame.height) - 1));
    return textureLoad(ldr, q, 0).rgb;
}

fn luma(c: vec3<f32>) -> f32 {
    return c.r * 0.299 + c.g * 0.587 + c.b * 0.114;
}

fn luma_at(p: vec2<i32>) -> f32 {
    return luma(fetch(p));
}

fn antialiased(pixel: vec2<u32>) -> vec3<f32> {
    let p = vec2<i32>(pixel);
    let centre = fetch(p);
    let m = luma(centre);
    let n = luma_at(p + vec2<i32>(0, -1));
    let s = luma_at(p + vec2<i32>(0, 1));
    let e = luma_at(p + vec2<i32>(1, 0));
    let w = luma_at(p + vec2<i32>(-1, 0));
    let lo = min(min(min(min(m, n), s), e), w);
    let hi = max(max(max(max(m, n), s), e), w);
    let range = hi - lo;
    if range < max(EDGE_MIN, hi * EDGE_RELATIVE) {
        return centre;
    }
    let nw = luma_at(p + vec2<i32>(-1, -1));
    let ne = luma_at(p + vec2<i32>(1, -1));
    let sw = luma_at(p + vec2<i32>(-1, 1));
    let se = luma_at(p + vec2<i32>(1, 1));
    let ns = n + s;
    let we = w + e;
    let edge_h = abs(-2.0 * w + nw + sw) + 2.0 * abs(-2.0 * m + ns) + abs(-2.0 * e + ne + se);
    let edge_v = abs(-2.0 * n + nw + ne) + 2.0 * abs(-2.0 * m + we) + abs(-2.0 * s + sw + se);
    let horizontal = edge_h >= edge_v;
    let l1 = select(w, n, horizontal);
    let l2 = select(e, s, horizontal);
    let g1 = l1 - m;
    let g2 = l2 - m;
    let steep1 = abs(g1) >= abs(g2);
    let scaled = 0.25 * max(abs(g1), abs(g2));
    let side = select(1, -1, steep1);
    let local = 0.5 * (m + select(l2, l1, steep1));
    let along = select(vec2<i32>(0, 1), vec2<i32>(1, 0), horizontal);
    let across = select(vec2<i32>(side, 0), vec2<i32>(0, side), horizontal);
    var k1 = 0;
    var k2 = 0;
    var end1 = 0.0;
    var end2 = 0.0;
    var done1 = false;
    var done2 = false;
    for (var i = 0u; i < STEP_COUNT; i++) {
        let step = STEPS[i];
        if !done1 {
            k1 -= step;
            let q = p + k1 * along;
            end1 = 0.5 * (luma_at(q) + luma_at(q + across)) - local;
            done1 = abs(end1) >= scaled;
        }
        if !done2 {
            k2 += step;
            let q = p + k2 * along;
            end2 = 0.5 * (luma_at(q) + luma_at(q + across)) - local;
            done2 = abs(end2) >= scaled;
        }
        if done1 && done2 {
            break;
        }
    }
    let d1 = f32(-k1);
    let d2 = f32(k2);
    let nearer1 = d1 < d2;
    let nearest = min(d1, d2);
    let edge_offset = -nearest / (d1 + d2) + 0.5;
    let centre_darker = m < local;
    let end = select(end2, end1, nearer1);
    var offset = select(0.0, edge_offset, (end < 0.0) != centre_darker);
    let average = (1.0 / 12.0) * (2.0 * (ns + we) + nw + ne + sw + se);
    let s1 = clamp(abs(average - m) / range, 0.0, 1.0);
    let s2 = (-2.0 * s1 + 3.0) * s1 * s1;
    offset = max(offset, s2 * s2 * SUBPIXEL);
    let other = fetch(p + across);
    return centre + (other - centre) * offset;
}

@fragment
fn fs_antialias(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(antialiased(vec2<u32>(position.xy)), 1.0);
}

@compute @workgroup_size(8, 8)
fn cs_antialias(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x < frame.width && id.y < frame.height {
        textureStore(output_out, id.xy, vec4<f32>(antialiased(id.xy), 1.0));
    }
}
