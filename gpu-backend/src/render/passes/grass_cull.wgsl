// The grass cull: one indirect draw appended per chunk table slot that draws its clutter
// (non-indexed, 12 vertices per clutter unit, first_instance = slot; compacted: the draw's
// index is the count of chunks drawn, stats[0], the draw count). A slot draws its clutter when the voxel cull draws its chunk:
// a level-0 chunk selected by the same level-of-detail rule (lod.wgsl), inside the frustum
// (its cube grown by the tallest swaying blade), and, with occlusion culling, visible in this
// frame's late phase (its bit). A chunk whose nearest point is so far that its tallest blade
// fades out (render_model::grass::chunk_fades_out) is skipped. FORMATS_WGSL, node.wgsl and
// lod.wgsl come before this body.

struct GrassCullUniforms {
    planes: array<vec4<f32>, 6>,
    camera_chunk: vec3<i32>,
    slot_bound: u32,
    camera_offset: vec3<f32>,
    chunk_edge: f32,
    lod: LodParams,
    flags: u32,
    focal_px: f32,
    budget_px: f32,
    pad: u32,
}

// Twins of render_model::grass constants (a test compares them).
const GRASS_CULL_LOD: u32 = 1u;
const GRASS_CULL_OCCLUSION: u32 = 2u;
const MAX_BLADE_HEIGHT: f32 = 0.9;
const WIND_SWAY: f32 = 0.25;
const FADE_FULL: f32 = 8.0;
const FADE_DROP: f32 = 4.0;
const VERTICES_PER_UNIT: u32 = 12u;

@group(0) @binding(0) var<uniform> g: GrassCullUniforms;
@group(0) @binding(1) var<storage, read> table: array<MeshedChunkInfo>;
// (vertex_count, instance_count, first_vertex, first_instance) per drawn chunk, compacted.
@group(0) @binding(2) var<storage, read_write> args: array<vec4<u32>>;
// The voxel cull's visibility bits (a bit per slot; one zero word without occlusion).
@group(0) @binding(3) var<storage, read> visible: array<u32>;
// 0: chunks drawn (the draw count), 1: units drawn (before the per-blade fade).
@group(0) @binding(4) var<storage, read_write> stats: array<atomic<u32>>;

fn grass_in_frustum(c: vec3<f32>, e: vec3<f32>) -> bool {
    for (var i = 0u; i < 6u; i += 1u) {
        let p = g.planes[i];
        let s = dot(p.xyz, c) + p.w;
        let r = dot(abs(p.xyz), e);
        if s + r < 0.0 {
            return false;
        }
    }
    return true;
}

// The fade of a blade `height` tall at `distance` (twin of render_model::grass::blade_fade).
fn grass_fade(height: f32, distance: f32, focal_px: f32, budget_px: f32) -> f32 {
    if budget_px <= 0.0 {
        return 1.0;
    }
    let px = height * focal_px / max(distance, 1e-6);
    return clamp((px - FADE_DROP * budget_px) / ((FADE_FULL - FADE_DROP) * budget_px), 0.0, 1.0);
}

fn grass_slot_draws(slot: u32) -> bool {
    let info = table[slot];
    if info.lod != 0u || info.clutter_units.count == 0u {
        return false;
    }
    let coord = vec3<i32>(info.chunk_x, info.chunk_y, info.chunk_z);
    if (g.flags & GRASS_CULL_LOD) != 0u && !lod_selected(g.lod, coord, 0u) {
        return false;
    }
    let rel = coord - g.camera_chunk;
    let grow = MAX_BLADE_HEIGHT * (1.0 + WIND_SWAY);
    // The whole chunk cube: clutter lies on top faces inside it, and the mesh's box need not
    // hold a unit's base (a chunk may carry clutter and no quads).
    let half = 0.5 * g.chunk_edge;
    let c = vec3<f32>(rel) * g.chunk_edge - g.camera_offset + vec3<f32>(half);
    let e = vec3<f32>(half + grow);
    if !grass_in_frustum(c, e) {
        return false;
    }
    if (g.flags & GRASS_CULL_OCCLUSION) != 0u
        && (visible[slot >> 5u] & (1u << (slot & 31u))) == 0u {
        return false;
    }
    let nearest = length(max(abs(c) - e, vec3<f32>(0.0)));
    return grass_fade(MAX_BLADE_HEIGHT, nearest, g.focal_px, g.budget_px) > 0.0;
}

@compute @workgroup_size(64)
fn grass_cull(@builtin(global_invocation_id) id: vec3<u32>) {
    let slot = id.x;
    if slot >= g.slot_bound {
        return;
    }
    if grass_slot_draws(slot) {
        let units = table[slot].clutter_units;
        let draw = atomicAdd(&stats[0], 1u);
        atomicAdd(&stats[1], units.count);
        args[draw] = vec4<u32>(units.count * VERTICES_PER_UNIT, 1u, units.offset * VERTICES_PER_UNIT, slot);
    }
}
