// Depth pyramid (Hi-Z) build, one dispatch per level (gpu-backend/src/hiz). Twin of
// gpu-backend/src/hiz/reference.rs (same footprints, same min/max order): keep them in step.
//
// - `hiz_level0`: the screen's depth (Depth32Float, reversed-Z, 0 = sky), raised per pixel to
//   the visibility buffer's depth where that is nearer, reduced to level 0 (min over each
//   texel's 2 x 2 pixels, 3 wide on the last row / column of an odd screen).
// - `hiz_reduce`: level m - 1 to level m, the same footprint one level up.
//
// One invocation per destination texel, 8 x 8 per workgroup; sizes come from
// textureDimensions, so there are no uniforms.

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
