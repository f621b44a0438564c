// Shared by the renderer's shaders (the G-buffer, lighting, transparent and tonemap passes):
// the frame uniforms, the GPU material palette, and the lighting model. Twins in
// render-model: frame.rs (FrameUniforms), lighting/ (Lighting, shade, the sky and haze,
// neutral: the CPU twin of the formulas, same operation order), materials.rs (GpuMaterial).
// Layouts are checked with naga in unit tests.

struct Lighting {
    sun_direction: vec3<f32>,
    ambient_strength: f32,
    sun_colour: vec3<f32>,
    emissive_scale: f32,
    sky_colour: vec3<f32>,
    // 1 / haze distance; 0 = no haze.
    haze_inverse_distance: f32,
    ground_colour: vec3<f32>,
    ao_floor: f32,
    // Per-channel exposure (white balance included): Lighting::exposure_rgb.
    exposure: vec3<f32>,
    sun_disc_cos: f32,
    zenith_colour: vec3<f32>,
    sun_disc_brightness: f32,
    horizon_colour: vec3<f32>,
    sun_halo: f32,
}

struct FrameUniforms {
    // Camera-relative positions (eye at the origin, blocks) to clip space; reversed-Z.
    view_proj: mat4x4<f32>,
    // The eye inside its chunk, blocks.
    camera_offset: vec3<f32>,
    chunk_edge: f32,
    camera_chunk: vec3<i32>,
    material_count: u32,
    // BlockVertex positions decode over 0..=smooth_extent, then smooth_origin is subtracted.
    smooth_extent: f32,
    smooth_origin: f32,
    width: u32,
    height: u32,
    lighting: Lighting,
    // The camera's basis (world axes): the ray through pixel centre (x, y) is
    // forward + u * right + v * up, u = 2 (x + 0.5) / width - 1, v = 1 - 2 (y + 0.5) / height
    // (right and up are scaled by the half field of view's tangents), and its point at
    // parameter t lies t blocks in front of the eye (reversed-Z depth near / t).
    forward: vec3<f32>,
    near: f32,
    right: vec3<f32>,
    // FRAME_* bits.
    flags: u32,
    up: vec3<f32>,
    pad: u32,
}

// Far draws were splatted into the visibility buffers this frame (render::FRAME_SPLAT).
const FRAME_SPLAT: u32 = 1u;
// The shadow pass wrote this frame's visibility words (render::FRAME_SHADOWS).
const FRAME_SHADOWS: u32 = 2u;

// The ray direction through the centre of pixel p (unit component along forward).
fn pixel_ray(p: vec2<u32>) -> vec3<f32> {
    let u = 2.0 * (f32(p.x) + 0.5) / f32(frame.width) - 1.0;
    let v = 1.0 - 2.0 * (f32(p.y) + 0.5) / f32(frame.height);
    return frame.forward + u * frame.right + v * frame.up;
}

struct GpuMaterial {
    colour: u32,
    // Roughness 0..8, emission 8..16, class 16..20, volume bit 20, metalness 24..32.
    properties: u32,
}

// Material `id`, or entry 0 for an id past the palette (never an out-of-bounds read).
fn material_of(id: u32) -> GpuMaterial {
    return materials[select(0u, id, id < frame.material_count)];
}

// sRGB-encoded RGBA, each channel 0..=1.
fn material_srgba(m: GpuMaterial) -> vec4<f32> {
    return unpack4x8unorm(m.colour);
}

// Emission, 0..=1.
fn material_emission(m: GpuMaterial) -> f32 {
    return f32((m.properties >> 8u) & 0xffu) / 255.0;
}

// Perceptual roughness, 0..=1.
fn material_roughness(m: GpuMaterial) -> f32 {
    return f32(m.properties & 0xffu) / 255.0;
}

// Metalness, 0..=1.
fn material_metalness(m: GpuMaterial) -> f32 {
    return f32(m.properties >> 24u) / 255.0;
}

// A transparent volume (materials::VOLUME_BIT).
fn material_volume(m: GpuMaterial) -> bool {
    return (m.properties & 0x100000u) != 0u;
}

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    return select(pow((c + 0.055) / 1.055, vec3<f32>(2.4)), c / 12.92, c <= vec3<f32>(0.04045));
}

// A prop's emission word (twin of render_model::props::emission, its constants compared by a
// test): a shared-exponent colour, 6-bit mantissas, 5-bit exponent, flag bit 23.
const EMISSION_BIAS: i32 = 15;
const EMISSION_MAX: f32 = 64512.0;
const EMISSION_MIN: f32 = 2.3841858e-7;
const EMISSION_FLAG: u32 = 0x800000u;

// Twin of render_model::props::encode_emission (multiplications by powers of two: exact).
fn prop_emission_encode(rgb: vec3<f32>) -> u32 {
    // NaN channels to 0 (a NaN fails every comparison), then at most EMISSION_MAX.
    let c = min(select(vec3<f32>(0.0), rgb, rgb > vec3<f32>(0.0)), vec3<f32>(EMISSION_MAX));
    let m = max(max(c.x, c.y), c.z);
    if !(m >= EMISSION_MIN) {
        return 0u;
    }
    let floor_log2 = i32((bitcast<u32>(m) >> 23u) & 0xffu) - 127;
    var e = clamp(floor_log2 + 1 + EMISSION_BIAS, 0, 31);
    var inv_step = ldexp(1.0, EMISSION_BIAS + 6 - e);
    if floor(m * inv_step + 0.5) >= 64.0 {
        e += 1;
        inv_step *= 0.5;
    }
    let q = min(vec3<u32>(floor(c * inv_step + 0.5)), vec3<u32>(63u));
    return q.x | (q.y << 6u) | (q.z << 12u) | (u32(e) << 18u) | EMISSION_FLAG;
}

// Twin of render_model::props::decode_emission.
fn prop_emission_decode(w: u32) -> vec3<f32> {
    if (w & EMISSION_FLAG) == 0u {
        return vec3<f32>(0.0);
    }
    let step = ldexp(1.0, i32((w >> 18u) & 31u) - EMISSION_BIAS - 6);
    return vec3<f32>(f32(w & 63u), f32((w >> 6u) & 63u), f32((w >> 12u) & 63u)) * step;
}

// Exposed (display-linear) colour of a surface point: hemisphere ambient scaled by AO
// (0..=3), Lambert sun, emission, times the exposure. The twin of lighting::shade.
fn shade(albedo: vec3<f32>, n: vec3<f32>, ao: f32, emission: f32) -> vec3<f32> {
    return shade_visible(albedo, n, ao, emission, 1.0, 1.0);
}

// shade with the sun term scaled by `sun` and the hemisphere ambient by `sky` (the shadow
// pass's visibility); the twin of lighting::shade_visible.
fn shade_visible(albedo: vec3<f32>, n: vec3<f32>, ao: f32, emission: f32, sun: f32, sky: f32) -> vec3<f32> {
    let l = frame.lighting;
    let hemisphere = 0.5 + 0.5 * n.y;
    let ambient = l.ground_colour + (l.sky_colour - l.ground_colour) * hemisphere;
    let occlusion = (l.ao_floor + (1.0 - l.ao_floor) * (ao / 3.0)) * l.ambient_strength * sky;
    let n_dot_l = max(n.x * l.sun_direction.x + n.y * l.sun_direction.y + n.z * l.sun_direction.z, 0.0) * sun;
    let light = ambient * occlusion + l.sun_colour * n_dot_l;
    return (albedo * light + albedo * (emission * l.emissive_scale)) * l.exposure;
}

// lighting::surface: a surface's material as the shading rule reads it.
struct SurfaceMaterial {
    albedo: vec3<f32>,
    alpha: f32,
    emission: f32,
    roughness: f32,
    metalness: f32,
    volume: bool,
}

fn surface_material(m: GpuMaterial) -> SurfaceMaterial {
    let srgba = material_srgba(m);
    return SurfaceMaterial(srgb_to_linear(srgba.rgb), srgba.a, material_emission(m), material_roughness(m), material_metalness(m), material_volume(m));
}

// lighting::surface::{DIELECTRIC_F0, MIN_GGX_ALPHA, MAX_INSIDE}.
const DIELECTRIC_F0: f32 = 0.04;
const MIN_GGX_ALPHA: f32 = 0.02;
const MAX_INSIDE: f32 = 1.0e6;
const PI: f32 = 3.14159265358979;

fn schlick(f0: vec3<f32>, c: f32) -> vec3<f32> {
    let x = 1.0 - c;
    let x2 = x * x;
    return f0 + (1.0 - f0) * (x2 * x2 * x);
}

// The specular lobe (sky reflection scaled by the sky visibility seen.y plus sun highlight
// scaled by the sun visibility seen.x, display-linear) in xyz and the mean Fresnel reflectance
// towards the eye in w, both before gloss; the twin of lighting::surface::lobe. dir: unit,
// eye to point.
fn specular_lobe(m: SurfaceMaterial, n: vec3<f32>, dir: vec3<f32>, seen: vec2<f32>) -> vec4<f32> {
    let l = frame.lighting;
    let f0 = DIELECTRIC_F0 + (m.albedo - DIELECTRIC_F0) * m.metalness;
    let v = -dir;
    let n_dot_v = max(dot(n, v), 0.0);
    let r = dir - 2.0 * dot(dir, n) * n;
    let sky = haze_colour(r);
    let n_dot_l = max(dot(n, l.sun_direction), 0.0);
    let h_raw = l.sun_direction + v;
    let h = h_raw / max(length(h_raw), 1e-6);
    let n_dot_h = max(dot(n, h), 0.0);
    let v_dot_h = max(dot(v, h), 0.0);
    let a = max(m.roughness * m.roughness, MIN_GGX_ALPHA);
    let a2 = a * a;
    let k = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    let d = a2 / (PI * k * k);
    let f_view = schlick(f0, n_dot_v);
    let sun = d * schlick(f0, v_dot_h) * 0.25 * n_dot_l * l.sun_colour;
    let light = f_view * sky * seen.y + sun * l.exposure * seen.x;
    return vec4<f32>(light, (f_view.x + f_view.y + f_view.z) * (1.0 / 3.0));
}

// The diffuse colour, the specular light times gloss, and gloss times the mean Fresnel
// (lighting::surface::parts).
struct SurfaceParts {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
    fresnel: f32,
}

// seen: the sun (x) and sky (y) visibility of the shadow rule; (1, 1) unshadowed.
fn surface_parts(m: SurfaceMaterial, n: vec3<f32>, ao: f32, dir: vec3<f32>, seen: vec2<f32>) -> SurfaceParts {
    let gloss = 1.0 - m.roughness;
    let kd = 1.0 - m.metalness * gloss;
    let diffuse = shade_visible(m.albedo * kd, n, ao, m.emission, seen.x, seen.y);
    if gloss <= 0.0 {
        return SurfaceParts(diffuse, vec3<f32>(0.0), 0.0);
    }
    let lobe = specular_lobe(m, n, dir, seen);
    return SurfaceParts(diffuse, lobe.xyz * gloss, lobe.w * gloss);
}

// Exposed colour of an opaque surface point seen along unit dir: Lambert (shade) plus the
// specular lobe; exactly shade() for a fully rough material. The twin of
// lighting::surface::shade_surface.
fn shade_surface(m: SurfaceMaterial, n: vec3<f32>, ao: f32, dir: vec3<f32>) -> vec3<f32> {
    return shade_surface_visible(m, n, ao, dir, vec2<f32>(1.0));
}

// shade_surface with the sun and sky scaled by the visibility seen (x sun, y sky); the twin
// of lighting::surface::shade_surface_visible.
fn shade_surface_visible(m: SurfaceMaterial, n: vec3<f32>, ao: f32, dir: vec3<f32>, seen: vec2<f32>) -> vec3<f32> {
    let p = surface_parts(m, n, ao, dir, seen);
    return p.diffuse + p.specular;
}

// The opacity of a layer over `inside` blocks (lighting::surface::layer_opacity).
fn layer_opacity(m: SurfaceMaterial, inside: f32) -> f32 {
    if !m.volume || m.alpha <= 0.0 {
        return m.alpha;
    }
    if m.alpha >= 1.0 {
        return 1.0;
    }
    let d = clamp(inside, 0.0, MAX_INSIDE);
    return 1.0 - exp2(d * log2(1.0 - m.alpha));
}

// A transparent surface point as premultiplied colour (rgb) and coverage (a), the opaque
// surface `inside` blocks behind it. The twin of lighting::surface::transparent_layer.
fn transparent_layer(m: SurfaceMaterial, n: vec3<f32>, ao: f32, dir: vec3<f32>, inside: f32) -> vec4<f32> {
    let p = surface_parts(m, n, ao, dir, vec2<f32>(1.0));
    let o = layer_opacity(m, inside);
    let through = (1.0 - p.fresnel) * o;
    return vec4<f32>(through * p.diffuse + p.specular, o + p.fresnel * (1.0 - o));
}

// The sky's colour towards unit direction dir without the sun disc (the haze's colour):
// horizon-to-zenith gradient plus the sun's halo. The twin of lighting::sky::haze_colour.
fn haze_colour(dir: vec3<f32>) -> vec3<f32> {
    let l = frame.lighting;
    let up = clamp(dir.y, 0.0, 1.0);
    let t = 1.0 - (1.0 - up) * (1.0 - up);
    let c = max(dot(dir, l.sun_direction), 0.0);
    let c2 = c * c;
    let c4 = c2 * c2;
    let c8 = c4 * c4;
    let halo = l.sun_halo * (c8 * c8);
    let sun = l.sun_colour * l.exposure;
    return l.horizon_colour + (l.zenith_colour - l.horizon_colour) * t + sun * halo;
}

// The background towards unit direction dir: haze_colour plus the sun disc. The twin of
// lighting::sky::sky_background.
fn sky_background(dir: vec3<f32>) -> vec3<f32> {
    let l = frame.lighting;
    let sky = haze_colour(dir);
    if dot(dir, l.sun_direction) < l.sun_disc_cos {
        return sky;
    }
    return sky + (l.sun_colour * l.exposure) * l.sun_disc_brightness;
}

// ln(255): the haze's transmittance at its distance is 1/255 (lighting::sky::HAZE_DENSITY).
const HAZE_DENSITY: f32 = 5.541264;

// colour seen through the haze from distance blocks along unit direction dir. The twin of
// lighting::sky::apply_haze.
fn apply_haze(colour: vec3<f32>, dir: vec3<f32>, distance: f32) -> vec3<f32> {
    let x = distance * frame.lighting.haze_inverse_distance;
    let x2 = x * x;
    let t = exp(-HAZE_DENSITY * (x2 * x2));
    let haze = haze_colour(dir);
    return haze + (colour - haze) * t;
}

// A premultiplied layer seen through the haze (lighting::surface::haze_layer).
fn haze_layer(layer: vec4<f32>, dir: vec3<f32>, distance: f32) -> vec4<f32> {
    let x = distance * frame.lighting.haze_inverse_distance;
    let x2 = x * x;
    let t = exp(-HAZE_DENSITY * (x2 * x2));
    let h = haze_colour(dir) * layer.a;
    return vec4<f32>(h + (layer.rgb - h) * t, layer.a);
}

// Reversed-Z depth (near / view_z, > 0) at pixel centre p to the distance from the eye and
// the unit ray direction: pixel_ray has a unit component along forward, so the point lies
// view_z * |ray| blocks away.
struct EyeRay {
    dir: vec3<f32>,
    distance: f32,
}

fn eye_ray(p: vec2<u32>, depth: f32) -> EyeRay {
    let ray = pixel_ray(p);
    let len = length(ray);
    return EyeRay(ray / len, frame.near / depth * len);
}

// Khronos PBR Neutral's highlight compression without its toe; the twin of
// lighting::neutral (COMPRESSION_START, DESATURATION).
fn neutral(colour: vec3<f32>) -> vec3<f32> {
    let c = max(colour, vec3<f32>(0.0));
    let peak = max(c.r, max(c.g, c.b));
    if peak < 0.85 {
        return c;
    }
    let d = 1.0 - 0.85;
    let new_peak = 1.0 - d * d / (peak + d - 0.85);
    let scale = new_peak / peak;
    let g = 1.0 - 1.0 / (0.15 * (peak - new_peak) + 1.0);
    let scaled = c * scale;
    return scaled + (vec3<f32>(new_peak) - scaled) * g;
}

// Octahedral 16+16 encoding of a unit vector, rounded to nearest; oct32_decode (formats) is
// its inverse. Axis-aligned normals round-trip exactly.
fn oct32_encode(n: vec3<f32>) -> u32 {
    let l1 = abs(n.x) + abs(n.y) + abs(n.z);
    var p = n.xy / l1;
    if n.z < 0.0 {
        let s = select(vec2<f32>(-1.0), vec2<f32>(1.0), p >= vec2<f32>(0.0));
        p = (1.0 - abs(p.yx)) * s;
    }
    let c = vec2<i32>(round(clamp(p, vec2<f32>(-1.0), vec2<f32>(1.0)) * 32767.0));
    return (bitcast<u32>(c.x) & 0xffffu) | (bitcast<u32>(c.y) << 16u);
}
