// The transparent pass: transparent greedy quads forward-shaded and blended (premultiplied)
// over the lit opaque image. render_common.wgsl and surface.wgsl come before this body.

// The opaque depth behind the transparent quads and raster far blocks (the G-buffer's, bound
// read-only while it is also the pass's read-only depth attachment): a volume is tinted by the
// distance to it.
@group(2) @binding(0) var opaque_depth: texture_depth_2d;

// The distance along the view ray through `pixel` from the transparent surface at depth `z`
// to the opaque surface at depth `behind` (reversed-Z; 0 where nothing opaque drew: the sky,
// MAX_INSIDE then).
fn inside_to(pixel: vec2<u32>, z: f32, behind: f32) -> f32 {
    if behind > 0.0 {
        return eye_ray(pixel, behind).distance - eye_ray(pixel, z).distance;
    }
    return MAX_INSIDE;
}

// inside_to the depth attachment's opaque surface: the raster far blocks' depth behind (the
// far blocks behind them are rasterised into it).
fn inside_to_opaque_depth(position: vec4<f32>) -> f32 {
    let pixel = vec2<u32>(floor(position.xy));
    return inside_to(pixel, position.z, textureLoad(opaque_depth, vec2<i32>(pixel), 0));
}

// Transparent quads are not grown: overlapping seams would be blended twice.
@vertex
fn vs_quad_transparent(@builtin(vertex_index) vertex: u32, @builtin(instance_index) instance: u32) -> SurfaceVaryings {
    return quad_vertex(vertex, instance, false);
}

// Transparent far cubes: lit here and blended over the lit opaque image, tinted by the depth
// behind them.
@fragment
fn fs_transparent(in: SurfaceVaryings) -> @location(0) vec4<f32> {
    return transparent_colour(in.block, in.ao, in.normal, in.position, inside_to_opaque_depth(in.position));
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
    return transparent_colour(in.block, in.ao, in.normal, in.position, inside_to(pixel, in.position.z, behind));
}
