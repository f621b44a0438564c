// The transparent pass: transparent greedy quads forward-shaded and blended (premultiplied)
// over the lit opaque image. render_common.wgsl and surface.wgsl come before this body.

// The opaque depth behind the transparent quads (the G-buffer's, bound read-only while it is
// also the pass's read-only depth attachment): a volume is tinted by the distance to it.
// Only fs_transparent_over_visibility reads it, so the far raster's cubes (which include this
// body for fs_transparent) do not bind it.
@group(2) @binding(0) var opaque_depth: texture_depth_2d;

// Transparent quads are not grown: overlapping seams would be blended twice.
@vertex
fn vs_quad_transparent(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> SurfaceVaryings {
    return quad_vertex(vertex, instance, false);
}

// Transparent far cubes: lit here and blended over the lit opaque image, tinted as one block
// deep (the far raster does not bind the depth behind them).
@fragment
fn fs_transparent(in: SurfaceVaryings) -> @location(0) vec4<f32> {
    return transparent_colour(in.block, in.ao, in.normal, in.position, 1.0);
}

// The meshed transparent quads, hidden behind the opaque visibility buffer too (splatted far
// blocks and compute-rasterised quads are not in the depth attachment), and tinted by the
// distance to the nearest opaque surface behind them: the depth attachment's or the
// visibility buffer's, MAX_INSIDE where neither drew (the sky).
@fragment
fn fs_transparent_over_visibility(in: SurfaceVaryings) -> @location(0) vec4<f32> {
    let pixel = vec2<u32>(floor(in.position.xy));
    var behind = textureLoad(opaque_depth, vec2<i32>(pixel), 0);
    if (frame.flags & FRAME_SPLAT) != 0u {
        let word = opaque_visibility[pixel.y * frame.width + pixel.x];
        // Reversed-Z: the opaque surface is nearer when its depth is greater.
        let splat = bitcast<f32>(word.y);
        if word.y != 0u && splat > in.position.z {
            discard;
        }
        if word.y != 0u {
            behind = max(behind, splat);
        }
    }
    var inside = MAX_INSIDE;
    if behind > 0.0 {
        inside = eye_ray(pixel, behind).distance - eye_ray(pixel, in.position.z).distance;
    }
    return transparent_colour(in.block, in.ao, in.normal, in.position, inside);
}
