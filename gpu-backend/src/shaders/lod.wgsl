// Level-of-detail selection by screen-space error: the twin of cull::lod (same operations in
// the same order; that module states the rule, its hysteresis and its bound).
//
// A node of level k covers 2^k x 2^k x 2^k chunks of level 0 and errs by at most
// sqrt(3) (2^k - 1) blocks. It *refines* (its children are drawn instead) when that error,
// seen from the anchor at the node's nearest point less the hysteresis distance, exceeds the
// budget; it is *selected* when it does not refine and its parent does (or it is at the top
// level).

struct LodParams {
    // The anchor: level-0 chunk and the offset inside it, blocks.
    anchor_chunk: vec3<i32>,
    top_level: u32,
    anchor_offset: vec3<f32>,
    budget_px: f32,
    // Pixels per unit of tangent: (height / 2) / tan(fov_y / 2).
    focal_px: f32,
    // Blocks the camera may move from the anchor before the selection must change.
    hysteresis: f32,
    chunk_edge: f32,
    pad: u32,
}

// Twin of cull::lod::SQRT_3.
const LOD_SQRT_3: f32 = 1.7320508;

// Distance from the origin to the box [lo, lo + size] (0 inside).
fn lod_cube_distance(lo: vec3<f32>, size: f32) -> f32 {
    let d = max(max(lo, -(lo + vec3<f32>(size))), vec3<f32>(0.0));
    return length(d);
}

// The anchor-relative minimum corner of node `coord` of level `level`, blocks. The chunk
// difference is taken in i32 (wrapping), then made small before it becomes an f32.
fn lod_node_lo(p: LodParams, coord: vec3<i32>, level: u32) -> vec3<f32> {
    let rel = (coord << vec3<u32>(level)) - p.anchor_chunk;
    return vec3<f32>(rel) * p.chunk_edge - p.anchor_offset;
}

fn lod_refines(p: LodParams, coord: vec3<i32>, level: u32) -> bool {
    if level == 0u {
        return false;
    }
    let scale = f32(1u << level);
    let distance = lod_cube_distance(lod_node_lo(p, coord, level), p.chunk_edge * scale);
    let d = max(distance - p.hysteresis, 0.0);
    return (scale - 1.0) * LOD_SQRT_3 * p.focal_px > p.budget_px * d;
}

fn lod_selected(p: LodParams, coord: vec3<i32>, level: u32) -> bool {
    if lod_refines(p, coord, level) {
        return false;
    }
    if level >= p.top_level {
        return true;
    }
    return lod_refines(p, coord >> vec3<u32>(1u), level + 1u);
}

// Bit f set when the neighbour across side f (same level) is not selected: it is drawn at
// another level, and this node must draw that side's skirt.
fn lod_skirt_mask(p: LodParams, coord: vec3<i32>, level: u32) -> u32 {
    var mask = 0u;
    for (var f = 0u; f < 6u; f += 1u) {
        if !lod_selected(p, coord + face_normal(f), level) {
            mask |= 1u << f;
        }
    }
    return mask;
}
