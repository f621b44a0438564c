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
    roughness_emission_class: u32,
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
    return f32((m.roughness_emission_class >> 8u) & 0xffu) / 255.0;
}

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    return select(pow((c + 0.055) / 1.055, vec3<f32>(2.4)), c / 12.92, c <= vec3<f32>(0.04045));
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
