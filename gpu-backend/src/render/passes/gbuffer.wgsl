// The G-buffer pass: opaque greedy quads and smooth quads into the G-buffer, and their
// wireframe view. render_common.wgsl and surface.wgsl come before this body.

// Opaque quads. Greedy quads meet at T-junctions, where rasterization can leave pinholes: each
// quad is grown in its own plane by a hair (DILATION_PX of a pixel at its distance, at least
// MIN_DILATION blocks), so neighbours overlap instead.
@vertex
fn vs_quad(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> SurfaceVaryings {
    return quad_vertex(vertex, instance, true);
}

// The wireframe view: a surface point and where it lies in its quad (0..1 on both axes).
struct WireVaryings {
    @builtin(position) position: vec4<f32>,
    @location(0) @interpolate(flat) block: u32,
    @location(1) ao: f32,
    @location(2) normal: vec3<f32>,
    @location(3) in_quad: vec2<f32>,
}

// Corner k of a quad, in the quad's own 0..1 coordinates (corners run around the quad).
fn corner_in_quad(k: u32) -> vec2<f32> {
    return array<vec2<f32>, 4>(vec2(0.0, 0.0), vec2(1.0, 0.0), vec2(1.0, 1.0), vec2(0.0, 1.0))[k & 3u];
}

fn wire(surface: SurfaceVaryings, corner: u32) -> WireVaryings {
    var out: WireVaryings;
    out.position = surface.position;
    out.block = surface.block;
    out.ao = surface.ao;
    out.normal = surface.normal;
    out.in_quad = corner_in_quad(corner);
    return out;
}

@vertex
fn vs_quad_wire(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> WireVaryings {
    return wire(quad_vertex(vertex, instance, false), quad_corner(vertex));
}

@vertex
fn vs_smooth_wire(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> WireVaryings {
    let slot = array<u32, 6>(0u, 1u, 2u, 0u, 2u, 3u)[vertex % 6u];
    return wire(smooth_vertex(vertex, instance), slot);
}

@vertex
fn vs_smooth(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> SurfaceVaryings {
    return smooth_vertex(vertex, instance);
}

@fragment
fn fs_gbuffer(in: SurfaceVaryings) -> GBufferOut {
    return gbuffer_texels(in.block, in.ao, in.normal);
}

// The wireframe view: only the pixels within about one pixel of the quad's edges are drawn.
@fragment
fn fs_gbuffer_wire(in: WireVaryings) -> GBufferOut {
    let pixels = min(in.in_quad, 1.0 - in.in_quad) / max(fwidth(in.in_quad), vec2<f32>(1e-6));
    if min(pixels.x, pixels.y) > 1.0 {
        discard;
    }
    return gbuffer_texels(in.block, in.ao, in.normal);
}
