// The prop draw: each batch's visible instances (the cull's list) into the G-buffer, vertex
// buffers of positions, normals and uvs, one indexed indirect draw per batch. The colour goes
// to the G-buffer's albedo as sRGB bytes like the palette's (lighting decodes it), AO full,
// material id 0; an emissive colour as its emission word (render_model::props::emission) in
// the albedo's alpha and the material word's upper half. BLEND materials are drawn by
// fs_prop_blend instead, into the lit colour (render::props). render_common.wgsl and
// prop_records.wgsl come before this body.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<storage, read> materials: array<GpuMaterial>;

@group(1) @binding(0) var<uniform> cull: PropCullUniforms;
@group(1) @binding(1) var<storage, read> instances: array<PropInstance>;
@group(1) @binding(2) var<storage, read> visible: array<u32>;

// One draw's material: base colour factor (linear), emissive colour (factor times strength,
// linear), alpha cutoff (MASK; 0 otherwise), and whether a base colour or an emissive texture
// is bound (1) or the white texture (0).
struct PropMaterial {
    base_colour: vec4<f32>,
    emissive: vec4<f32>,
    cutoff: f32,
    textured: u32,
    double_sided: u32,
    emissive_textured: u32,
}

@group(2) @binding(0) var<uniform> material: PropMaterial;
@group(2) @binding(1) var base_texture: texture_2d<f32>;
@group(2) @binding(2) var base_sampler: sampler;
@group(2) @binding(3) var emissive_texture: texture_2d<f32>;
@group(2) @binding(4) var emissive_sampler: sampler;

struct PropVaryings {
    @builtin(position) position: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) uv: vec2<f32>,
    // Camera-relative position (the blended draw's view ray and haze distance).
    @location(2) rel: vec3<f32>,
}

// The cofactor of the 3 x 3 part applied to n, sign of the determinant kept (local_normal).
fn prop_normal(r: PropInstance, n: vec3<f32>) -> vec3<f32> {
    let c0 = prop_column(r, 0u);
    let c1 = prop_column(r, 1u);
    let c2 = prop_column(r, 2u);
    let k0 = cross(c1, c2);
    let k1 = cross(c2, c0);
    let k2 = cross(c0, c1);
    let det = dot(c0, k0);
    let m = select(1.0, -1.0, det < 0.0) * ((k0 * n.x + k1 * n.y) + k2 * n.z);
    return m;
}

@vertex
fn vs_prop(
    @builtin(instance_index) instance: u32,
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
) -> PropVaryings {
    let r = instances[visible[instance]];
    let rel = prop_relative_origin(r, cull.eye_voxel, cull.eye_fraction) + prop_local_point(r, position);
    var out: PropVaryings;
    out.position = cull.view_proj * vec4<f32>(rel, 1.0);
    out.normal = prop_normal(r, normal);
    out.uv = uv;
    out.rel = rel;
    return out;
}

fn linear_to_srgb(c: vec3<f32>) -> vec3<f32> {
    let lo = c * 12.92;
    let hi = 1.055 * pow(max(c, vec3<f32>(0.0)), vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, lo, c <= vec3<f32>(0.0031308));
}

struct PropGBufferOut {
    @location(0) albedo_ao: vec4<f32>,
    @location(1) normal_material: vec2<u32>,
}

// A fragment's surface: colour (base colour factor times texel, linear, with alpha), emissive
// colour, and the normal turned towards the eye on a back face.
struct PropSurface {
    colour: vec4<f32>,
    emissive: vec3<f32>,
    normal: vec3<f32>,
}

fn prop_surface(in: PropVaryings, front: bool) -> PropSurface {
    var colour = material.base_colour;
    if material.textured != 0u {
        colour *= textureSample(base_texture, base_sampler, in.uv);
    }
    var emissive = material.emissive.rgb;
    if material.emissive_textured != 0u {
        emissive *= textureSample(emissive_texture, emissive_sampler, in.uv).rgb;
    }
    var n = in.normal;
    if !front {
        n = -n;
    }
    if dot(n, n) == 0.0 {
        n = vec3<f32>(0.0, 1.0, 0.0);
    }
    return PropSurface(colour, emissive, normalize(n));
}

@fragment
fn fs_prop(in: PropVaryings, @builtin(front_facing) front: bool) -> PropGBufferOut {
    let s = prop_surface(in, front);
    if s.colour.a < material.cutoff {
        discard;
    }
    // AO full, or the emission word's low byte (the lighting then reads AO as full).
    let w = prop_emission_encode(s.emissive);
    let ao = select(1.0, f32(w & 0xffu) / 255.0, w != 0u);
    var out: PropGBufferOut;
    out.albedo_ao = vec4<f32>(linear_to_srgb(clamp(s.colour.rgb, vec3<f32>(0.0), vec3<f32>(1.0))), ao);
    out.normal_material = vec2<u32>(oct32_encode(s.normal), (w >> 8u) << 16u);
    return out;
}

// A BLEND fragment (render::props): lit forward as the lighting pass lights a prop's G-buffer
// texel (palette material 0's lobe, AO full, the emission as the G-buffer would hold it; no
// shadows), premultiplied by its alpha and seen through the haze, for src + dst * (1 - a).
@fragment
fn fs_prop_blend(in: PropVaryings, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let s = prop_surface(in, front);
    let distance = length(in.rel);
    let dir = in.rel / max(distance, 1e-20);
    var m = surface_material(material_of(0u));
    m.albedo = clamp(s.colour.rgb, vec3<f32>(0.0), vec3<f32>(1.0));
    var lit = shade_surface_visible(m, s.normal, 3.0, dir, vec2<f32>(1.0));
    lit += prop_emission_decode(prop_emission_encode(s.emissive)) * frame.lighting.exposure;
    let a = clamp(s.colour.a, 0.0, 1.0);
    return haze_layer(vec4<f32>(lit * a, a), dir, distance);
}
