// Drawing into a host's targets (see src/render/external.rs): one full-screen triangle that
// writes the renderer's output colour and, where a host depth target is given, the depth of
// the same surface in the host's depth convention, depth-tested against what the host drew.
//
// The renderer's depth is reversed-Z `near / view_z` (0 = nothing drawn: the fragment is
// discarded, the host's pixel stays). The host's depth of view distance `z` comes from its
// projection's z and w rows: `(a * -z + b) / (c * -z + d)`.

struct HostDepthUniforms {
    // The renderer camera's near plane, blocks.
    near: f32,
    // P[2][2], P[3][2], P[2][3], P[3][3] of the host's column-major projection.
    a: f32,
    b: f32,
    c: f32,
    d: f32,
    _pad0: f32,
    _pad1: f32,
    _pad2: f32,
}

@group(0) @binding(0) var host_colour: texture_2d<f32>;
@group(0) @binding(1) var host_depth_source: texture_depth_2d;
@group(0) @binding(2) var<uniform> host_u: HostDepthUniforms;

@vertex
fn vs_host(@builtin(vertex_index) vertex: u32) -> @builtin(position) vec4<f32> {
    let x = f32((vertex << 1u) & 2u);
    let y = f32(vertex & 2u);
    return vec4<f32>(x * 2.0 - 1.0, y * 2.0 - 1.0, 0.0, 1.0);
}

struct HostFragment {
    @location(0) colour: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

// The renderer's depth at the fragment's pixel; discards where nothing was drawn.
fn host_source_depth(position: vec4<f32>) -> f32 {
    let d = textureLoad(host_depth_source, vec2<i32>(position.xy), 0);
    if d <= 0.0 {
        discard;
    }
    return d;
}

fn host_source_colour(position: vec4<f32>) -> vec4<f32> {
    return vec4<f32>(textureLoad(host_colour, vec2<i32>(position.xy), 0).rgb, 1.0);
}

@fragment
fn fs_host_depth(@builtin(position) position: vec4<f32>) -> HostFragment {
    let d = host_source_depth(position);
    let view_z = host_u.near / d;
    let depth = (host_u.a * -view_z + host_u.b) / (host_u.c * -view_z + host_u.d);
    return HostFragment(host_source_colour(position), clamp(depth, 0.0, 1.0));
}

@fragment
fn fs_host_colour(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    _ = host_source_depth(position);
    return host_source_colour(position);
}
