// Full-screen passes of the deferred renderer: lighting (G-buffer to linear HDR) and tonemap
// (HDR to the sRGB output). render_common.wgsl comes before this body.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<storage, read> materials: array<GpuMaterial>;

@group(1) @binding(0) var gbuffer_albedo: texture_2d<f32>;
@group(1) @binding(1) var gbuffer_normal: texture_2d<u32>;
@group(1) @binding(2) var gbuffer_depth: texture_depth_2d;

@group(1) @binding(3) var hdr: texture_2d<f32>;

// One triangle covering the screen.
@vertex
fn vs_fullscreen(@builtin(vertex_index) vertex: u32) -> @builtin(position) vec4<f32> {
    let x = f32((vertex << 1u) & 2u);
    let y = f32(vertex & 2u);
    return vec4<f32>(x * 2.0 - 1.0, y * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs_lighting(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(position.xy);
    // Reversed-Z: 0 is the cleared far plane, i.e. sky.
    if textureLoad(gbuffer_depth, p, 0) <= 0.0 {
        return vec4<f32>(frame.lighting.sky_colour, 1.0);
    }
    let albedo_ao = textureLoad(gbuffer_albedo, p, 0);
    let normal_material = textureLoad(gbuffer_normal, p, 0);
    let n = oct32_decode(normal_material.x);
    let m = material_of(normal_material.y);
    let colour = shade(srgb_to_linear(albedo_ao.rgb), n, albedo_ao.a * 3.0, material_emission(m));
    return vec4<f32>(colour, 1.0);
}

@fragment
fn fs_tonemap(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let c = textureLoad(hdr, vec2<i32>(position.xy), 0).rgb;
    // The output target is *Srgb: the hardware encodes.
    return vec4<f32>(aces(c * frame.lighting.exposure), 1.0);
}
