// Depth pyramid (Hi-Z) build (gpu-backend/src/hiz): one dispatch per level down to the fifth
// level from the end, then one workgroup for the last four. Twin of
// gpu-backend/src/hiz/reference.rs (same footprints, same min/max order): keep them in step.
//
// - `hiz_level0`: the screen's depth (Depth32Float, reversed-Z, 0 = sky), raised per pixel to
//   the visibility buffer's depth where that is nearer, reduced to level 0 (min over each
//   texel's 2 x 2 pixels, 3 wide on the last row / column of an odd screen).
// - `hiz_reduce`: level m - 1 to level m, the same footprint one level up.
// - `hiz_tail`: the (at most 4) levels below a level four halvings from 1 x 1 (so at most 31
//   texels on each side) in one workgroup: each level is kept in workgroup memory for the
//   next, so the small levels, too small to fill a GPU, cost one dispatch instead of one each
//   (every dispatch also costs the CPU a barrier and a driver call). Four because WebGPU's
//   default limit is four storage textures per shader stage.
//
// `hiz_level0` and `hiz_reduce`: one invocation per destination texel, 8 x 8 per workgroup.
// Sizes come from textureDimensions, so there are no uniforms.

const HIZ_BUILD_WORKGROUP: u32 = 8u;

// hiz_level0's bindings (hiz::bindings::LEVEL0_*).
@group(0) @binding(0) var hiz_depth: texture_depth_2d;
// The splatting pass's 64-bit words, one per pixel, row-major, as (low, high) u32 pairs: high
// = f32 bits of a reversed-Z depth (0 = nothing), low = payload. When the frame has no
// visibility buffer a one-word dummy (zero) is bound: arrayLength below W * H turns it off.
@group(0) @binding(1) var<storage, read> hiz_visibility: array<vec2<u32>>;
@group(0) @binding(2) var hiz_level0_out: texture_storage_2d<r32float, write>;

// hiz_reduce's bindings (hiz::bindings::REDUCE_*): one mip each.
@group(0) @binding(3) var hiz_source: texture_2d<f32>;
@group(0) @binding(4) var hiz_reduce_out: texture_storage_2d<r32float, write>;

// hiz_tail's bindings (hiz::bindings::TAIL_*): the source level, then the levels below it in
// order (where the pyramid has fewer, 1 x 1 stand-ins that are never written).
@group(0) @binding(5) var hiz_tail_source: texture_2d<f32>;
@group(0) @binding(6) var hiz_tail_out0: texture_storage_2d<r32float, write>;
@group(0) @binding(7) var hiz_tail_out1: texture_storage_2d<r32float, write>;
@group(0) @binding(8) var hiz_tail_out2: texture_storage_2d<r32float, write>;
@group(0) @binding(9) var hiz_tail_out3: texture_storage_2d<r32float, write>;

const HIZ_TAIL_WORKGROUP: u32 = 256u;
// Levels hiz_tail writes at most.
const HIZ_TAIL_LEVELS: u32 = 4u;
// The tail's levels in workgroup memory, alternating: the first and third below the source
// (at most 15 x 15 texels) in `a`, the others (at most 7 x 7) in `b`.
var<workgroup> hiz_tail_a: array<f32, 225>;
var<workgroup> hiz_tail_b: array<f32, 49>;

// The inclusive source range that destination texel `id` covers, per axis: 2i ..= 2i + 1,
// the last texel reaching to the source's last index. Twin of levels::footprint.
struct HizFootprint {
    lo: vec2<u32>,
    hi: vec2<u32>,
}

fn hiz_footprint(id: vec2<u32>, dest: vec2<u32>, source: vec2<u32>) -> HizFootprint {
    let lo = 2u * id;
    let hi = select(min(lo + 1u, source - 1u), source - 1u, id + 1u == dest);
    return HizFootprint(lo, hi);
}

// The nearer of the depth buffer and the visibility buffer at pixel `p`.
fn hiz_pixel_depth(p: vec2<u32>, width: u32, use_visibility: bool) -> f32 {
    let depth = textureLoad(hiz_depth, p, 0);
    if use_visibility {
        return max(depth, bitcast<f32>(hiz_visibility[p.y * width + p.x].y));
    }
    return depth;
}

@compute @workgroup_size(HIZ_BUILD_WORKGROUP, HIZ_BUILD_WORKGROUP)
fn hiz_level0(@builtin(global_invocation_id) gid: vec3<u32>) {
    let dest = textureDimensions(hiz_level0_out);
    let id = gid.xy;
    if any(id >= dest) {
        return;
    }
    let screen = textureDimensions(hiz_depth);
    let use_visibility = arrayLength(&hiz_visibility) >= screen.x * screen.y;
    let f = hiz_footprint(id, dest, screen);
    var m = hiz_pixel_depth(f.lo, screen.x, use_visibility);
    for (var y = f.lo.y; y <= f.hi.y; y++) {
        for (var x = f.lo.x; x <= f.hi.x; x++) {
            m = min(m, hiz_pixel_depth(vec2<u32>(x, y), screen.x, use_visibility));
        }
    }
    textureStore(hiz_level0_out, id, vec4<f32>(m, 0.0, 0.0, 0.0));
}

@compute @workgroup_size(HIZ_BUILD_WORKGROUP, HIZ_BUILD_WORKGROUP)
fn hiz_reduce(@builtin(global_invocation_id) gid: vec3<u32>) {
    let dest = textureDimensions(hiz_reduce_out);
    let id = gid.xy;
    if any(id >= dest) {
        return;
    }
    let source = textureDimensions(hiz_source);
    let f = hiz_footprint(id, dest, source);
    var m = textureLoad(hiz_source, f.lo, 0).x;
    for (var y = f.lo.y; y <= f.hi.y; y++) {
        for (var x = f.lo.x; x <= f.hi.x; x++) {
            m = min(m, textureLoad(hiz_source, vec2<u32>(x, y), 0).x);
        }
    }
    textureStore(hiz_reduce_out, id, vec4<f32>(m, 0.0, 0.0, 0.0));
}

// Writes texel `id` of the tail's level `step` (0 = the level below the source).
fn hiz_tail_store(step: u32, id: vec2<u32>, m: f32) {
    let texel = vec4<f32>(m, 0.0, 0.0, 0.0);
    switch step {
        case 0u: { textureStore(hiz_tail_out0, id, texel); }
        case 1u: { textureStore(hiz_tail_out1, id, texel); }
        case 2u: { textureStore(hiz_tail_out2, id, texel); }
        default: { textureStore(hiz_tail_out3, id, texel); }
    }
}

// Texel `p` of the tail's level `step - 1`, `width` wide, from workgroup memory.
fn hiz_tail_load(step: u32, p: vec2<u32>, width: u32) -> f32 {
    let i = p.y * width + p.x;
    if step % 2u == 1u {
        return hiz_tail_a[i];
    }
    return hiz_tail_b[i];
}

@compute @workgroup_size(HIZ_TAIL_WORKGROUP)
fn hiz_tail(@builtin(local_invocation_index) t: u32) {
    var source = textureDimensions(hiz_tail_source);
    var dest = max(source / 2u, vec2<u32>(1u));
    // The first level below the source, from the texture.
    for (var i = t; i < dest.x * dest.y; i += HIZ_TAIL_WORKGROUP) {
        let id = vec2<u32>(i % dest.x, i / dest.x);
        let f = hiz_footprint(id, dest, source);
        var m = textureLoad(hiz_tail_source, f.lo, 0).x;
        for (var y = f.lo.y; y <= f.hi.y; y++) {
            for (var x = f.lo.x; x <= f.hi.x; x++) {
                m = min(m, textureLoad(hiz_tail_source, vec2<u32>(x, y), 0).x);
            }
        }
        hiz_tail_a[i] = m;
        hiz_tail_store(0u, id, m);
    }
    workgroupBarrier();
    // The rest, each from the one before in workgroup memory, down to 1 x 1.
    for (var step = 1u; step < HIZ_TAIL_LEVELS; step++) {
        source = dest;
        if all(source == vec2<u32>(1u)) {
            break;
        }
        dest = max(source / 2u, vec2<u32>(1u));
        for (var i = t; i < dest.x * dest.y; i += HIZ_TAIL_WORKGROUP) {
            let id = vec2<u32>(i % dest.x, i / dest.x);
            let f = hiz_footprint(id, dest, source);
            var m = hiz_tail_load(step, f.lo, source.x);
            for (var y = f.lo.y; y <= f.hi.y; y++) {
                for (var x = f.lo.x; x <= f.hi.x; x++) {
                    m = min(m, hiz_tail_load(step, vec2<u32>(x, y), source.x));
                }
            }
            if step % 2u == 0u {
                hiz_tail_a[i] = m;
            } else {
                hiz_tail_b[i] = m;
            }
            hiz_tail_store(step, id, m);
        }
        workgroupBarrier();
    }
}
