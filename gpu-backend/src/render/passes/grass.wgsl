// The grass pass: clutter units as two crossed quads into the G-buffer (the rule, constants
// and CPU twin: render_model::grass). render_common.wgsl comes before this body.
//
// No vertex or index buffers: vertex v of a draw is unit v / 12 of the bound clutter page
// (first_vertex = 12 * the chunk's first unit), quad (v % 12) / 6, corner
// [0, 1, 2, 0, 2, 3][v % 6]; instance_index is the chunk table slot (first_instance).
//
// No clutter atlas exists: the unit's uv region is interpolated across the quad, and the
// fragment takes the point's place within that region (0..1, y up the blade) for a
// procedural sprite: a tapering blade shaded by the tint, darker at its base, or (kind % 4 ==
// 3) a flower: a green stem under a round head of the tint. Outside the sprite it discards.
// A blade's sprite is the triangle from the quad's bottom corners to the middle of its top
// edge, and the quad is a parallelogram (both top corners sway alike), so a blade is drawn
// as that triangle (the quad's other three vertices collapse to one point): the same pixels,
// half the fragments, and none discarded.
// The albedo is written as sRGB like the voxels' (lighting linearises it), AO full, the normal
// the unit's up direction (grass is lit like the ground it grows on), material 0 (no
// emission).

struct GrassUniforms {
    wind_phase: f32,
    wind_strength: f32,
    focal_px: f32,
    budget_px: f32,
}

// Twins of render_model::grass constants (a test compares them).
const BLADE_HEIGHT: f32 = 0.45;
const BLADE_WIDTH_RATIO: f32 = 0.8;
const WIND_SWAY: f32 = 0.25;
const WIND_SPACE: f32 = 0.35;
const WIND_SEED: f32 = 0.4;
const WIND_DIRECTION: vec3<f32> = vec3<f32>(0.8, 0.0, 0.6);
const FADE_FULL: f32 = 8.0;
const FADE_DROP: f32 = 4.0;
const VERTICES_PER_UNIT: u32 = 12u;
const FLOWER_HEAD_RADIUS: f32 = 0.2;
const FLOWER_STEM_HALF_WIDTH: f32 = 0.06;
const FLOWER_STEM: vec3<f32> = vec3<f32>(0.25, 0.5, 0.15);
const BLADE_BASE_SHADE: f32 = 0.55;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<storage, read> materials: array<GpuMaterial>;
@group(1) @binding(0) var<storage, read> clutter: array<ClutterUnit>;
@group(1) @binding(1) var<storage, read> chunks: array<MeshedChunkInfo>;
@group(1) @binding(2) var<uniform> grass: GrassUniforms;

struct GrassVaryings {
    @builtin(position) position: vec4<f32>,
    // The atlas uv, interpolated; the unit's region (corner, size) flat.
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) region: vec4<f32>,
    @location(2) @interpolate(flat) tint: vec3<f32>,
    @location(3) @interpolate(flat) kind: u32,
    @location(4) @interpolate(flat) normal: vec3<f32>,
}

// Twin of render_model::grass::blade_fade.
fn blade_fade(height: f32, distance: f32) -> f32 {
    if grass.budget_px <= 0.0 {
        return 1.0;
    }
    let px = height * grass.focal_px / max(distance, 1e-6);
    return clamp((px - FADE_DROP * grass.budget_px) / ((FADE_FULL - FADE_DROP) * grass.budget_px), 0.0, 1.0);
}

// Twin of render_model::grass::quad_direction.
fn quad_direction(n: vec3<f32>, seed: u32, quad: u32) -> vec3<f32> {
    var a = vec3<f32>(0.0, 0.0, 1.0);
    if abs(n.y) < 0.9 {
        a = vec3<f32>(0.0, 1.0, 0.0);
    }
    let t = normalize(cross(a, n));
    let b = cross(n, t);
    let angle = f32(seed) * (3.14159265 / 16.0) + f32(quad) * (3.14159265 / 2.0);
    return t * cos(angle) + b * sin(angle);
}

@vertex
fn vs_grass(@builtin(vertex_index) vertex: u32, @builtin(instance_index) slot: u32) -> GrassVaryings {
    let unit = clutter[vertex / VERTICES_PER_UNIT];
    let quad = (vertex % VERTICES_PER_UNIT) / 6u;
    let corner = array<u32, 6>(0u, 1u, 2u, 0u, 2u, 3u)[vertex % 6u];
    let info = chunks[slot];
    let rel = vec3<i32>(info.chunk_x, info.chunk_y, info.chunk_z) - frame.camera_chunk;
    let origin = vec3<f32>(rel) * frame.chunk_edge - frame.camera_offset;
    let p = clutter_unit_position(unit, frame.chunk_edge);
    var n = clutter_unit_normal(unit);
    n = select(vec3<f32>(0.0, 1.0, 0.0), normalize(n), length(n) > 0.0);
    let seed = clutter_unit_seed(unit);
    let full = BLADE_HEIGHT * (1.0 + f32(clutter_unit_scale_step(unit)) / 15.0);
    let height = full * blade_fade(full, length(origin + p));
    let half = 0.5 * BLADE_WIDTH_RATIO * height;
    let d = quad_direction(n, seed, quad) * half;
    var s = array<vec2<f32>, 4>(vec2(0.0, 0.0), vec2(1.0, 0.0), vec2(1.0, 1.0), vec2(0.0, 1.0))[corner];
    let kind = clutter_unit_kind(unit);
    if kind % 4u != 3u {
        // A blade: its triangle, then a zero-area one (nothing rasterised).
        s = array<vec2<f32>, 6>(vec2(0.0, 0.0), vec2(1.0, 0.0), vec2(0.5, 1.0), vec2(0.0, 0.0), vec2(0.0, 0.0), vec2(0.0, 0.0))[vertex % 6u];
    }
    var local = p + d * (2.0 * s.x - 1.0);
    if s.y > 0.5 {
        // Only the top corners sway (render_model::grass::wind_offset).
        let phase = grass.wind_phase + WIND_SPACE * (p.x + p.z) + WIND_SEED * f32(seed);
        let sway = grass.wind_strength * WIND_SWAY * height * sin(phase);
        local += n * height + WIND_DIRECTION * sway;
    }
    let uv0 = clutter_unit_uv(unit);
    let size = clutter_unit_uv_size(unit);
    var out: GrassVaryings;
    out.position = frame.view_proj * vec4<f32>(origin + local, 1.0);
    out.uv = uv0 + s * size;
    out.region = vec4<f32>(uv0, size);
    out.tint = clutter_unit_tint(unit).rgb;
    out.kind = kind;
    out.normal = n;
    return out;
}

struct GrassOut {
    @location(0) albedo_ao: vec4<f32>,
    @location(1) normal_material: vec2<u32>,
}

// Twin of render_model::grass::sprite_colour; a negative red is "not covered".
fn sprite_colour(kind: u32, s: vec2<f32>, tint: vec3<f32>) -> vec3<f32> {
    let dx = abs(s.x - 0.5);
    if kind % 4u == 3u {
        if length(s - vec2<f32>(0.5, 0.78)) < FLOWER_HEAD_RADIUS {
            return tint;
        }
        if dx < FLOWER_STEM_HALF_WIDTH && s.y < 0.78 {
            return FLOWER_STEM;
        }
        return vec3<f32>(-1.0);
    }
    // The blade's coverage test (dx > 0.5 * (1 - s.y): not covered) is its triangle's edges.
    return tint * (BLADE_BASE_SHADE + (1.0 - BLADE_BASE_SHADE) * s.y);
}

@fragment
fn fs_grass(in: GrassVaryings) -> GrassOut {
    let s = (in.uv - in.region.xy) / max(in.region.zw, vec2<f32>(1e-6));
    let colour = sprite_colour(in.kind, s, in.tint);
    if colour.r < 0.0 {
        discard;
    }
    var out: GrassOut;
    out.albedo_ao = vec4<f32>(colour, 1.0);
    out.normal_material = vec2<u32>(oct32_encode(in.normal), 0u);
    return out;
}
