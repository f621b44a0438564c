// The transparent pass: transparent greedy quads forward-shaded and blended over the lit
// opaque image. render_common.wgsl and surface.wgsl come before this body.

// Transparent quads are not grown: overlapping seams would be blended twice.
@vertex
fn vs_quad_transparent(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> SurfaceVaryings {
    return quad_vertex(vertex, instance, false);
}

// Transparent quads: lit here and blended over the lit opaque image with the palette alpha.
@fragment
fn fs_transparent(in: SurfaceVaryings) -> @location(0) vec4<f32> {
    return transparent_colour(in.block, in.ao, in.normal, in.position);
}

// fs_transparent for the meshed quads, which also hides them behind the opaque visibility
// buffer (splatted far blocks and compute-rasterised quads are not in the depth attachment).
@fragment
fn fs_transparent_over_visibility(in: SurfaceVaryings) -> @location(0) vec4<f32> {
    if (frame.flags & FRAME_SPLAT) != 0u {
        let pixel = vec2<u32>(floor(in.position.xy));
        let word = opaque_visibility[pixel.y * frame.width + pixel.x];
        // Reversed-Z: the opaque surface is nearer when its depth is greater.
        if word.y != 0u && bitcast<f32>(word.y) > in.position.z {
            discard;
        }
    }
    return transparent_colour(in.block, in.ao, in.normal, in.position);
}
