// Window presentation (see src/present.rs): the renderer's output copied into the swapchain
// image by one full-screen triangle. The output and the swapchain image have the same size, so
// every fragment loads exactly its own texel (no sampler, no filtering); the coordinate is
// clamped so that a size mismatch during a resize reads the edge instead of out of bounds.
//
// The output is Rgba8UnormSrgb: `textureLoad` returns linear colour. `fs_present` writes it to
// an sRGB swapchain format, whose hardware encode gives back the output's bytes; on a
// swapchain with only non-sRGB formats, `fs_present_encode` applies the sRGB transfer function
// itself.

@group(0) @binding(0) var present_source: texture_2d<f32>;

@vertex
fn vs_present(@builtin(vertex_index) vertex: u32) -> @builtin(position) vec4<f32> {
    // Vertices (-1,-1), (3,-1), (-1,3): one triangle covering the viewport.
    let x = f32((vertex << 1u) & 2u);
    let y = f32(vertex & 2u);
    return vec4<f32>(x * 2.0 - 1.0, y * 2.0 - 1.0, 0.0, 1.0);
}

fn present_load(position: vec4<f32>) -> vec4<f32> {
    let last = vec2<i32>(textureDimensions(present_source)) - vec2<i32>(1, 1);
    let p = clamp(vec2<i32>(position.xy), vec2<i32>(0, 0), max(last, vec2<i32>(0, 0)));
    return vec4<f32>(textureLoad(present_source, p, 0).rgb, 1.0);
}

// Linear to sRGB-encoded, per channel (IEC 61966-2-1).
fn present_srgb_encode(linear: vec3<f32>) -> vec3<f32> {
    let c = clamp(linear, vec3<f32>(0.0), vec3<f32>(1.0));
    let low = c * 12.92;
    let high = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(high, low, c <= vec3<f32>(0.0031308));
}

@fragment
fn fs_present(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    return present_load(position);
}

@fragment
fn fs_present_encode(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let linear = present_load(position);
    return vec4<f32>(present_srgb_encode(linear.rgb), 1.0);
}
