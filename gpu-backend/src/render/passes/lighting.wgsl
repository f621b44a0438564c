// The lighting pass, as a fragment pass (full-screen triangle) and as a compute pass (8 x 8
// pixels per workgroup), the same per-pixel function either way: the G-buffer and the
// visibility buffers to display-linear HDR (exposed, hazed, the sky where nothing drew). render_common.wgsl and fullscreen.wgsl come before this
// body.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<storage, read> materials: array<GpuMaterial>;

@group(1) @binding(0) var gbuffer_albedo: texture_2d<f32>;
@group(1) @binding(1) var gbuffer_normal: texture_2d<u32>;
@group(1) @binding(2) var gbuffer_depth: texture_depth_2d;

// The far draws' visibility buffers (render::far): per pixel, x = payload, y = reversed-Z
// depth bits (0 = nothing); read only when FRAME_SPLAT is set.
@group(1) @binding(4) var<storage, read> visibility: array<vec2<u32>>;
@group(1) @binding(5) var<storage, read> transparent: array<vec2<u32>>;

// The compute pass's output.
@group(1) @binding(6) var hdr_out: texture_storage_2d<rgba16float, write>;

// The shadow pass's per-pixel Visibility words (render::passes::shadow), read when
// FRAME_SHADOWS is set.
@group(1) @binding(7) var<storage, read> shadow_visibility: array<u32>;

// The sun and sky factors of pixel `at` (twin of shadow::Visibility's): 1 and 1 without
// shadows.
fn seen_light(at: u32) -> vec2<f32> {
    if (frame.flags & FRAME_SHADOWS) == 0u {
        return vec2<f32>(1.0);
    }
    let w = shadow_visibility[at];
    return vec2<f32>(f32(w & 1u), f32(min((w >> 1u) & 7u, 5u)) / 5.0);
}

// A splat payload (render::far): block id, face, AO in 255ths of 3.
struct Splat {
    block: u32,
    face: u32,
    ao: f32,
}

fn splat_of(payload: u32) -> Splat {
    return Splat(payload & 0xffffu, (payload >> 16u) & 7u, f32((payload >> 19u) & 0xffu) / 85.0);
}

// The shaded colour of a splatted surface seen along unit dir, its sun and sky scaled by
// `seen`.
fn shade_splat(s: Splat, dir: vec3<f32>, seen: vec2<f32>) -> vec3<f32> {
    let m = surface_material(material_of(s.block));
    return shade_surface_visible(m, vec3<f32>(face_normal(s.face)), s.ao, dir, seen);
}

// Display-linear colour of pixel p: the nearer of the G-buffer and the opaque far draws
// seen through the haze, the sky where neither drew, then the nearest transparent far draw
// (hazed at its own depth) blended over it when it is in front.
fn lit_pixel(p: vec2<u32>) -> vec3<f32> {
    let texel = vec2<i32>(p);
    var depth = textureLoad(gbuffer_depth, texel, 0);
    var surface = vec3<f32>(0.0);
    var splatted = false;
    let at = p.y * frame.width + p.x;
    let view_dir = normalize(pixel_ray(p));
    if (frame.flags & FRAME_SPLAT) != 0u {
        let v = visibility[at];
        let d = bitcast<f32>(v.y);
        // Reversed-Z: nearer is greater; 0 is the cleared far plane.
        if d > depth {
            depth = d;
            surface = shade_splat(splat_of(v.x), view_dir, seen_light(at));
            splatted = true;
        }
    }
    if !splatted && depth > 0.0 {
        let albedo_ao = textureLoad(gbuffer_albedo, texel, 0);
        let normal_material = textureLoad(gbuffer_normal, texel, 0);
        let n = oct32_decode(normal_material.x);
        // The G-buffer's albedo (a prop's texel, or the palette's), the material's lobe. A
        // material word with bit 31 set is an emissive prop's (render_model::props::emission):
        // its alpha is the emission word's low byte and its AO full.
        let y = normal_material.y;
        let glows = (y >> 31u) != 0u;
        var m = surface_material(material_of(y & 0xffffu));
        m.albedo = srgb_to_linear(albedo_ao.rgb);
        let ao = select(albedo_ao.a * 3.0, 3.0, glows);
        surface = shade_surface_visible(m, n, ao, view_dir, seen_light(at));
        if glows {
            let w = ((y >> 16u) << 8u) | u32(round(albedo_ao.a * 255.0));
            surface += prop_emission_decode(w) * frame.lighting.exposure;
        }
    }
    let ray = pixel_ray(p);
    var colour: vec3<f32>;
    if depth > 0.0 {
        let seen = eye_ray(p, depth);
        colour = apply_haze(surface, seen.dir, seen.distance);
    } else {
        colour = sky_background(normalize(ray));
    }
    if (frame.flags & FRAME_SPLAT) != 0u {
        let t = transparent[at];
        let d = bitcast<f32>(t.y);
        if d > depth {
            // A transparent far block, tinted by the distance to the opaque surface behind it
            // (lighting::surface; unbounded over the sky), as the transparent pass tints a
            // meshed layer.
            let over = splat_of(t.x);
            let seen = eye_ray(p, d);
            var inside = MAX_INSIDE;
            if depth > 0.0 {
                inside = eye_ray(p, depth).distance - seen.distance;
            }
            let m = surface_material(material_of(over.block));
            let n = vec3<f32>(face_normal(over.face));
            let layer = haze_layer(transparent_layer(m, n, over.ao, seen.dir, inside), seen.dir, seen.distance);
            colour = layer.rgb + colour * (1.0 - layer.a);
        }
    }
    return colour;
}

@fragment
fn fs_lighting(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(lit_pixel(vec2<u32>(position.xy)), 1.0);
}

@compute @workgroup_size(8, 8)
fn cs_lighting(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x < frame.width && id.y < frame.height {
        textureStore(hdr_out, id.xy, vec4<f32>(lit_pixel(id.xy), 1.0));
    }
}
