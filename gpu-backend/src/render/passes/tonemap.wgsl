// The tonemap pass, as a fragment pass (full-screen triangle, into the *Srgb output) and as
// a compute pass (8 x 8 pixels per workgroup, into its storage view): HDR to the sRGB output.
// render_common.wgsl and fullscreen.wgsl come before this body.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<storage, read> materials: array<GpuMaterial>;

@group(1) @binding(3) var hdr: texture_2d<f32>;

// The compute pass's output.
@group(1) @binding(7) var output_out: texture_storage_2d<rgba8unorm, write>;

// The hue-preserving tonemap of the display-linear HDR colour (linear, 0..=1 out).
fn tonemapped(p: vec2<u32>) -> vec3<f32> {
    return neutral(textureLoad(hdr, vec2<i32>(p), 0).rgb);
}

// The sRGB transfer function, linear 0..=1 to encoded 0..=1 (what an *Srgb target does).
fn linear_to_srgb(c: vec3<f32>) -> vec3<f32> {
    return select(1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055, c * 12.92, c <= vec3<f32>(0.0031308));
}

@fragment
fn fs_tonemap(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    // The output target is *Srgb: the hardware encodes.
    return vec4<f32>(tonemapped(vec2<u32>(position.xy)), 1.0);
}

@compute @workgroup_size(8, 8)
fn cs_tonemap(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x < frame.width && id.y < frame.height {
        // A storage texture cannot be *Srgb: encode here.
        textureStore(output_out, id.xy, vec4<f32>(linear_to_srgb(tonemapped(id.xy)), 1.0));
    }
}
