// Runs the Hi-Z test (hiz.wgsl, prepended by shaders.rs) on a list of rectangles: the GPU
// test's way of comparing it with hiz::rect_test_reference, and an example of including
// hiz.wgsl. One invocation per query.

struct HizQuery {
    rect_min: vec2<f32>,
    rect_max: vec2<f32>,
    nearest_depth: f32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

// What hiz_rect_visible decided and the steps that led there.
struct HizAnswer {
    visible: u32,
    level: u32,
    farthest_bits: u32,
    pixels_lo: u32,
    pixels_hi: u32,
    pad0: u32,
    pad1: u32,
    pad2: u32,
}

// The contract of hiz.wgsl: the includer declares hiz_texture where it likes.
@group(0) @binding(0) var hiz_texture: texture_2d<f32>;
@group(0) @binding(1) var<storage, read> queries: array<HizQuery>;
@group(0) @binding(2) var<storage, read_write> answers: array<HizAnswer>;

@compute @workgroup_size(64)
fn hiz_probe(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= arrayLength(&queries) {
        return;
    }
    let q = queries[i];
    let pixels = hiz_rect_pixels(q.rect_min, q.rect_max);
    var a: HizAnswer;
    a.visible = u32(hiz_rect_visible(q.rect_min, q.rect_max, q.nearest_depth));
    a.level = hiz_rect_level(pixels);
    a.farthest_bits = bitcast<u32>(hiz_rect_farthest(q.rect_min, q.rect_max));
    a.pixels_lo = pixels.lo.x | (pixels.lo.y << 16u);
    a.pixels_hi = pixels.hi.x | (pixels.hi.y << 16u);
    answers[i] = a;
}
