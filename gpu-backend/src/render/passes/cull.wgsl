// Cull pass: per table slot (a chunk, or a level-of-detail node), the LOD selection
// (lod.wgsl), the frustum, the per-face-direction culling (Lum), and the representation: meshed
// quads into one range of draw commands per gigabuffer page, smooth quads into one range per
// (vertex page, quad page) pair, or far-draw blocks into the far list. The twin of
// gpu-backend/src/cull/reference.rs, which states the math, the rounding and the bounds; keep
// the two in the same order, operation by operation. FORMATS_WGSL (MeshedChunkInfo,
// FaceLayerRange), node.wgsl and lod.wgsl are prepended by shaders.rs.
//
// One invocation per table slot (0..slot_bound). Entry points:
// - `cull`: commands in any order. Per workgroup, commands are counted per page (and far nodes,
//   smooth draws and statistics per counter) in workgroup memory first, then each counter with
//   something in it takes one global atomicAdd, so the global counters see one atomic per
//   workgroup and counter, not one per command.
// - `cull_count`, `order_prefix`, `cull_scatter`: the meshed commands of one layer, back to
//   front (a counting sort on a depth key, cull::order states the rule): count per (page, key),
//   prefix sums per page far keys first, then each chunk writes its commands at its key's
//   cursor. Used for the transparent layer; far nodes are skipped there (the far draw shades
//   their transparent blocks).

// wgpu's DrawIndexedIndirectArgs, 20 bytes, tightly packed (the stride of
// multi_draw_indexed_indirect(_count)). Twin of cull::DrawIndexedArgs.
struct DrawIndexedArgs {
    index_count: u32,
    instance_count: u32,
    first_index: u32,
    base_vertex: i32,
    first_instance: u32,
}

// Twin of cull::CullUniforms (a test checks the offsets with naga).
struct CullUniforms {
    // Camera-relative planes (eye at the origin): a point p is inside when
    // dot(xyz, p) + w >= 0.
    planes: array<vec4<f32>, 6>,
    camera_chunk: vec3<i32>,
    // 0 = opaque quads, 1 = transparent quads.
    layer: u32,
    // The eye inside its chunk, blocks.
    camera_offset: vec3<f32>,
    chunk_edge: f32,
    slot_bound: u32,
    page_count: u32,
    page_capacity: u32,
    last_page_capacity: u32,
    commands_per_page: u32,
    max_quads_per_draw: u32,
    // CULL_* bits.
    flags: u32,
    // Occlusion phase: 0 early (nodes visible last frame), 1 late (the rest, tested).
    phase: u32,
    // Nodes whose cells project to at most this many pixels are far-drawn.
    far_cell_px: f32,
    // Entries of the far list.
    far_capacity: u32,
    smooth_vertex_page_capacity: u32,
    smooth_quad_page_capacity: u32,
    smooth_quad_pages: u32,
    smooth_commands_per_pair: u32,
    smooth_pairs: u32,
    // Pixels per unit of tangent (as lod.focal_px; the far test measures from the camera).
    focal_px: f32,
    lod: LodParams,
    // Camera-relative view-projection (reversed-Z), output size and near plane: boxes are
    // projected to test them against the depth pyramid.
    view_proj: mat4x4<f32>,
    screen: vec2<f32>,
    near: f32,
    pad: u32,
}

// Select nodes by level of detail (else only level 0 is drawn: full detail).
const CULL_LOD: u32 = 1u;
// Far-draw nodes whose cells are small enough (else every node is meshed).
const CULL_FAR: u32 = 2u;
// Write the smooth layer's draws (opaque pass only).
const CULL_SMOOTH: u32 = 4u;
// Two-phase occlusion culling against the depth pyramid (phase: 0 early, 1 late, 2 test only).
const CULL_OCCLUSION: u32 = 8u;
// The opaque records list the slots of meshed nodes with transparent quads; an ordered record
// with this flag culls that list instead of the whole table.
const CULL_FROM_LIST: u32 = 16u;

// Statistics (twin of cull::CullStats), counted by the opaque-layer dispatch.
const STAT_SELECTED: u32 = 0u;
const STAT_FRUSTUM_CULLED: u32 = 1u;
const STAT_OCCLUDED: u32 = 2u;
const STAT_MESH_NODES: u32 = 3u;
const STAT_FAR_NODES: u32 = 4u;
const STAT_MESH_QUADS: u32 = 5u;
const STAT_FAR_BLOCKS: u32 = 6u;
const STAT_SMOOTH_QUADS: u32 = 7u;
const STAT_SKIRT_SIDES: u32 = 8u;
const STAT_FAR_LIST: u32 = 9u;
const STAT_TRANSPARENT_QUADS: u32 = 10u;
// Length of the transparent list (may exceed its capacity: the rest were dropped).
const STAT_TRANSPARENT_LIST: u32 = 13u;
// Selected nodes per level: STAT_LEVELS + level.
const STAT_LEVELS: u32 = 16u;
const STAT_COUNT: u32 = 32u;

const CULL_WORKGROUP: u32 = 64u;
// Largest page count one dispatch handles (cull::MAX_PAGES).
const CULL_MAX_PAGES: u32 = 256u;
// Largest (vertex page, quad page) pair count of the smooth layer (cull::MAX_SMOOTH_PAIRS).
const CULL_MAX_SMOOTH_PAIRS: u32 = 64u;

@group(0) @binding(0) var<uniform> u: CullUniforms;
@group(0) @binding(1) var<storage, read> table: array<MeshedChunkInfo>;
@group(0) @binding(2) var<storage, read_write> args: array<DrawIndexedArgs>;
// DrawRecords (cull::DrawRecord): level-0 chunk difference x, y, z and the level.
@group(0) @binding(3) var<storage, read_write> records: array<vec4<u32>>;
// counts[p]: commands page p wanted (those at or past commands_per_page were not written);
// counts[page_count]: malformed chunk layers skipped.
@group(0) @binding(4) var<storage, read_write> counts: array<atomic<u32>>;

// Depth keys of the ordered cull (cull::ORDER_KEYS): 256 per octave of squared distance,
// squared distances 1 .. 2^48 blocks^2.
const ORDER_KEYS: u32 = 12288u;
// bitcast<u32>(1.0) >> 15: the key of squared distance 1.
const ORDER_KEY_BASE: u32 = 32512u;
// Invocations of order_prefix (one workgroup per page).
const ORDER_PREFIX_WORKGROUP: u32 = 256u;

// Ordered cull only: commands per (page, key), then the cursor each key's next command goes to.
@group(0) @binding(5) var<storage, read_write> order_counts: array<atomic<u32>>;
@group(0) @binding(6) var<storage, read_write> order_cursors: array<atomic<u32>>;

@group(0) @binding(7) var<storage, read> nodes: array<NodeRecord>;
// Far nodes: (slot, skirt mask).
@group(0) @binding(8) var<storage, read_write> far_list: array<vec2<u32>>;
// Smooth draws per (vertex page, quad page) pair: DrawIndirectArgs (vertex count, instance
// count, first vertex, first instance) and SmoothDraw records (two words each), and counts.
@group(0) @binding(9) var<storage, read_write> smooth_args: array<vec4<u32>>;
@group(0) @binding(10) var<storage, read_write> smooth_records: array<vec4<u32>>;
@group(0) @binding(11) var<storage, read_write> smooth_counts: array<atomic<u32>>;
@group(0) @binding(12) var<storage, read_write> stats: array<atomic<u32>>;
// One bit per slot: the node passed the occlusion test in the last late phase.
@group(0) @binding(13) var<storage, read_write> visible: array<atomic<u32>>;
// The depth pyramid of the early phase (hiz.wgsl's contract).
@group(0) @binding(14) var hiz_texture: texture_2d<f32>;
// Slots of meshed nodes with transparent quads, appended by the opaque records.
@group(0) @binding(15) var<storage, read_write> transparent_list: array<u32>;

var<workgroup> wg_count: array<atomic<u32>, CULL_MAX_PAGES>;
var<workgroup> wg_scan: array<u32, ORDER_PREFIX_WORKGROUP>;
var<workgroup> wg_base: array<u32, CULL_MAX_PAGES>;
var<workgroup> wg_smooth: array<atomic<u32>, CULL_MAX_SMOOTH_PAIRS>;
var<workgroup> wg_smooth_base: array<u32, CULL_MAX_SMOOTH_PAIRS>;
var<workgroup> wg_stats: array<atomic<u32>, STAT_COUNT>;
var<workgroup> wg_far: atomic<u32>;
var<workgroup> wg_far_base: u32;
var<workgroup> wg_transparent: atomic<u32>;
var<workgroup> wg_transparent_base: u32;

// Elements in page `page` of the quad gigabuffer.
fn page_capacity_of(page: u32) -> u32 {
    return select(u.page_capacity, u.last_page_capacity, page + 1u == u.page_count);
}

// False when the box (centre c, half size e) lies wholly outside one plane.
fn in_frustum(c: vec3<f32>, e: vec3<f32>) -> bool {
    var inside = true;
    for (var i = 0u; i < 6u; i += 1u) {
        let p = u.planes[i];
        let s = p.x * c.x + p.y * c.y + p.z * c.z + p.w;
        let r = abs(p.x) * e.x + abs(p.y) * e.y + abs(p.z) * e.z;
        if s + r < 0.0 {
            inside = false;
        }
    }
    return inside;
}

// Bit f set when face direction f can face the eye (at the origin): +X needs the eye's x above
// the box's min x, -X below its max x, and so on.
fn face_mask(c: vec3<f32>, e: vec3<f32>) -> u32 {
    var mask = 0u;
    mask |= u32(c.x - e.x < 0.0) << FACE_POS_X;
    mask |= u32(c.x + e.x > 0.0) << FACE_NEG_X;
    mask |= u32(c.y - e.y < 0.0) << FACE_POS_Y;
    mask |= u32(c.y + e.y > 0.0) << FACE_NEG_Y;
    mask |= u32(c.z - e.z < 0.0) << FACE_POS_Z;
    mask |= u32(c.z + e.z > 0.0) << FACE_NEG_Z;
    return mask;
}

// What one slot contributes to this dispatch.
struct SlotCull {
    // Meshed quads: bit f of `emit` for each visible face group with something to draw, `n` of
    // them, in page `page` from in-page quad `start`; `malformed` when the layer's range is bad.
    emit: u32,
    n: u32,
    page: u32,
    start: u32,
    malformed: bool,
    range: FaceLayerRange,
    // Sides whose skirt is drawn.
    skirts: u32,
    // Drawn as far-draw blocks (the far list), not as quads.
    far: bool,
    // A smooth draw in pair `smooth_pair`.
    smooth_draw: bool,
    smooth_pair: u32,
    // Level-0 chunk difference to the camera chunk, and the level.
    rel: vec3<i32>,
    level: u32,
    // Camera-relative box centre (the ordered cull's depth key comes from it).
    centre: vec3<f32>,
    // Selected at its level, outside the frustum, hidden by the depth pyramid.
    selected: bool,
    frustum_culled: bool,
    occluded: bool,
    // Opaque records: a meshed node with transparent quads, for the transparent list.
    transparent: bool,
}

// True unless the box (camera-relative centre c, half size e) is behind the depth pyramid:
// its 8 corners projected give the screen rectangle and the nearest depth (reversed-Z, depth
// is linear in view z over the box, so the nearest point is a corner); a box reaching the near
// plane is visible.
fn box_visible(c: vec3<f32>, e: vec3<f32>) -> bool {
    var lo = vec2<f32>(1e30);
    var hi = vec2<f32>(-1e30);
    var nearest = 0.0;
    for (var i = 0u; i < 8u; i += 1u) {
        let s = vec3<f32>(f32(i & 1u), f32((i >> 1u) & 1u), f32((i >> 2u) & 1u)) * 2.0 - 1.0;
        let clip = u.view_proj * vec4<f32>(c + e * s, 1.0);
        if clip.w <= u.near {
            return true;
        }
        let ndc = clip.xy / clip.w;
        let p = vec2<f32>((ndc.x * 0.5 + 0.5) * u.screen.x, (0.5 - ndc.y * 0.5) * u.screen.y);
        lo = min(lo, p);
        hi = max(hi, p);
        nearest = max(nearest, u.near / clip.w);
    }
    return hiz_rect_visible(lo, hi, nearest);
}

// The occlusion phases for a selected node in the frustum: true when this dispatch draws it.
// Early: the nodes visible last frame. Late: every node is tested; its bit records the result,
// and it is drawn if visible and not drawn early. Test only (the transparent layer): visible.
fn occlusion_draws(slot: u32, c: vec3<f32>, e: vec3<f32>, out: ptr<function, SlotCull>) -> bool {
    if (u.flags & CULL_OCCLUSION) == 0u {
        return true;
    }
    let word = slot >> 5u;
    let bit = 1u << (slot & 31u);
    if u.phase == 0u {
        return (atomicLoad(&visible[word]) & bit) != 0u;
    }
    let seen = box_visible(c, e);
    (*out).occluded = !seen;
    if u.phase == 1u {
        var was = 0u;
        if seen {
            was = atomicOr(&visible[word], bit);
        } else {
            was = atomicAnd(&visible[word], ~bit);
        }
        return seen && (was & bit) == 0u;
    }
    return seen;
}

// The quads group f draws: its quads without the skirt, plus the skirt when that side's bit is
// set (opaque layer; the transparent layer has no skirts).
fn face_draw_count(s: SlotCull, node: NodeRecord, f: u32) -> u32 {
    let count = face_layer_range_count(s.range, f);
    if u.layer != 0u {
        return count;
    }
    let skirt = min(skirt_count(node.opaque_skirts, f), count);
    return count - skirt + select(0u, skirt, ((s.skirts >> f) & 1u) != 0u);
}

fn cull_slot(slot: u32) -> SlotCull {
    var out: SlotCull;
    if slot >= u.slot_bound {
        return out;
    }
    let occlusion = (u.flags & CULL_OCCLUSION) != 0u;
    // The early phase draws only last frame's visible nodes: one bit read rejects the rest.
    if occlusion && u.phase == 0u
        && (atomicLoad(&visible[slot >> 5u]) & (1u << (slot & 31u))) == 0u {
        return out;
    }
    // The selection reads the record's first 16 bytes only; most nodes stop here.
    let coord = vec3<i32>(table[slot].chunk_x, table[slot].chunk_y, table[slot].chunk_z);
    out.level = min(table[slot].lod, 15u);
    if (u.flags & CULL_LOD) != 0u {
        out.selected = lod_selected(u.lod, coord, out.level);
    } else {
        out.selected = out.level == 0u;
    }
    if !out.selected {
        return out;
    }
    let info = table[slot];
    let node = nodes[slot];
    out.range = info.opaque_quads;
    if u.layer == 1u {
        out.range = info.transparent_quads;
    }
    var any = false;
    var oversized = false;
    for (var f = 0u; f < 6u; f += 1u) {
        let count = face_layer_range_count(out.range, f);
        any = any || count > 0u;
        oversized = oversized || count > u.max_quads_per_draw;
    }
    let has_smooth = u.layer == 0u && node.smooth_quad_count > 0u;
    let has_blocks = (node.flags & NODE_HAS_BLOCKS) != 0u;
    let has_transparent = u.layer == 0u && face_layer_range_total(info.transparent_quads) > 0u;
    // Shell runs draw in the shell pass, which reads the visibility bit this cull sets.
    let has_shells = u.layer == 0u && node.shell_count > 0u;
    // Far-draw blocks belong to the opaque pass (it shades their transparent blocks too), and so
    // does listing the nodes whose transparent quads the transparent records draw.
    if !any && !has_smooth && !has_shells && !(u.layer == 0u && (has_blocks || has_transparent)) {
        return out;
    }
    if any {
        out.page = out.range.offset / u.page_capacity;
        out.start = out.range.offset % u.page_capacity;
        // Counts are <= max_quads_per_draw < 2^26 here, so no sum overflows.
        out.malformed = oversized || out.page >= u.page_count
            || out.start + face_layer_range_total(out.range) > page_capacity_of(out.page);
        if out.malformed {
            return out;
        }
    }
    let scale = f32(1u << out.level);
    out.rel = (coord << vec3<u32>(out.level)) - u.camera_chunk;
    out.centre = (vec3<f32>(out.rel) * u.chunk_edge - u.camera_offset)
        + meshed_chunk_info_centre(info) * scale;
    let e = meshed_chunk_info_extent(info) * scale;
    if !in_frustum(out.centre, e) {
        out.frustum_culled = true;
        // Out of the frustum is not visible: the late phase clears the bit, so no bit outlives
        // the view that set it (or the node that held the slot before) and the passes that
        // read it (grass, shells) see this frame's visibility only.
        if occlusion && u.phase == 1u {
            atomicAnd(&visible[slot >> 5u], ~(1u << (slot & 31u)));
        }
        return out;
    }
    if !occlusion_draws(slot, out.centre, e, &out) {
        return out;
    }
    if (u.flags & CULL_LOD) != 0u {
        out.skirts = lod_skirt_mask(u.lod, coord, out.level);
    }
    // Far-drawn when the node's cells, seen from the camera at the box's nearest point, are at
    // most far_cell_px pixels: scale * focal / distance <= far_cell_px, without a division.
    let distance = length(max(abs(out.centre) - e, vec3<f32>(0.0)));
    out.far = (u.flags & CULL_FAR) != 0u && has_blocks
        && scale * u.focal_px <= u.far_cell_px * distance;
    if out.far {
        return out;
    }
    out.transparent = has_transparent;
    if any {
        let mask = face_mask(out.centre, e);
        for (var f = 0u; f < 6u; f += 1u) {
            if ((mask >> f) & 1u) != 0u && face_draw_count(out, node, f) > 0u {
                out.emit |= 1u << f;
                out.n += 1u;
            }
        }
    }
    if has_smooth && (u.flags & CULL_SMOOTH) != 0u {
        let vp = info.smooth_vertices.offset / u.smooth_vertex_page_capacity;
        let qp = node.smooth_quad_offset / u.smooth_quad_page_capacity;
        out.smooth_pair = vp * u.smooth_quad_pages + qp;
        out.smooth_draw = out.smooth_pair < u.smooth_pairs;
    }
    return out;
}

// Writes the slot's commands from page-local command index `index` on; those at or past
// commands_per_page are dropped (the caller sees counts[page] > commands_per_page). Returns the
// quads drawn.
fn write_commands(s: SlotCull, node: NodeRecord, first_index: u32) -> u32 {
    var index = first_index;
    var first = s.start;
    var quads = 0u;
    for (var f = 0u; f < 6u; f += 1u) {
        let count = face_layer_range_count(s.range, f);
        if ((s.emit >> f) & 1u) != 0u {
            let drawn = face_draw_count(s, node, f);
            if index < u.commands_per_page {
                let at = s.page * u.commands_per_page + index;
                args[at] = DrawIndexedArgs(6u * drawn, 1u, 0u, i32(4u * first), at);
                records[at] = vec4<u32>(bitcast<vec3<u32>>(s.rel), s.level);
                quads += drawn;
            }
            index += 1u;
        }
        first += count;
    }
    return quads;
}

// The smooth draw of slot `slot` at pair-local index `index` (dropped past the pair's range).
fn write_smooth(s: SlotCull, slot: u32, index: u32) {
    if index >= u.smooth_commands_per_pair {
        return;
    }
    let info = table[slot];
    let node = nodes[slot];
    let at = s.smooth_pair * u.smooth_commands_per_pair + index;
    smooth_args[at] = vec4<u32>(6u * node.smooth_quad_count, 1u, 0u, at);
    // SmoothDraw (render::SmoothDraw): chunk difference, vertex offset; quad offset, count,
    // form, level.
    smooth_records[2u * at] = vec4<u32>(
        bitcast<vec3<u32>>(s.rel),
        info.smooth_vertices.offset % u.smooth_vertex_page_capacity,
    );
    smooth_records[2u * at + 1u] = vec4<u32>(
        node.smooth_quad_offset % u.smooth_quad_page_capacity,
        node.smooth_quad_count,
        node.smooth_quad_form,
        s.level,
    );
}

// Blocks a far node draws: its blocks plus the skirt blocks of the sides in its mask.
fn far_block_count(node: NodeRecord, skirts: u32) -> u32 {
    var n = node.block_count;
    for (var f = 0u; f < 6u; f += 1u) {
        if ((skirts >> f) & 1u) != 0u {
            n += skirt_count(node.block_skirts, f);
        }
    }
    return n;
}

fn slot_of(wid: vec3<u32>, groups: vec3<u32>, lid: u32) -> u32 {
    return (wid.y * groups.x + wid.x) * CULL_WORKGROUP + lid;
}

// The slot an ordered record's invocation culls: its index, or with CULL_FROM_LIST the
// transparent list's entry at that index (u32 max past the list: no slot).
fn ordered_slot(wid: vec3<u32>, groups: vec3<u32>, lid: u32) -> u32 {
    let index = slot_of(wid, groups, lid);
    if (u.flags & CULL_FROM_LIST) == 0u {
        return index;
    }
    let listed = min(atomicLoad(&stats[STAT_TRANSPARENT_LIST]), arrayLength(&transparent_list));
    return select(0xffffffffu, transparent_list[min(index, arrayLength(&transparent_list) - 1u)], index < listed);
}

fn add_stat(index: u32, value: u32) {
    if value > 0u {
        atomicAdd(&wg_stats[index], value);
    }
}

@compute @workgroup_size(64)
fn cull(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let slot = slot_of(wid, groups, lid);
    let s = cull_slot(slot);
    if s.malformed {
        atomicAdd(&counts[u.page_count], 1u);
    }
    var local = 0u;
    if s.n > 0u {
        local = atomicAdd(&wg_count[s.page], s.n);
    }
    let listed = s.far && u.layer == 0u;
    var far_local = 0u;
    if listed {
        far_local = atomicAdd(&wg_far, 1u);
    }
    let listed_transparent = s.transparent && u.layer == 0u;
    var transparent_local = 0u;
    if listed_transparent {
        transparent_local = atomicAdd(&wg_transparent, 1u);
    }
    var smooth_local = 0u;
    if s.smooth_draw {
        smooth_local = atomicAdd(&wg_smooth[s.smooth_pair], 1u);
    }
    workgroupBarrier();
    for (var p = lid; p < u.page_count; p += CULL_WORKGROUP) {
        let c = atomicLoad(&wg_count[p]);
        if c > 0u {
            wg_base[p] = atomicAdd(&counts[p], c);
        }
    }
    for (var p = lid; p < u.smooth_pairs; p += CULL_WORKGROUP) {
        let c = atomicLoad(&wg_smooth[p]);
        if c > 0u {
            wg_smooth_base[p] = atomicAdd(&smooth_counts[p], c);
        }
    }
    if lid == 0u {
        let c = atomicLoad(&wg_far);
        if c > 0u {
            wg_far_base = atomicAdd(&stats[STAT_FAR_LIST], c);
        }
        let t = atomicLoad(&wg_transparent);
        if t > 0u {
            wg_transparent_base = atomicAdd(&stats[STAT_TRANSPARENT_LIST], t);
        }
    }
    workgroupBarrier();
    var node: NodeRecord;
    if slot < u.slot_bound {
        node = nodes[slot];
    }
    if s.n > 0u {
        let quads = write_commands(s, node, wg_base[s.page] + local);
        add_stat(select(STAT_MESH_QUADS, STAT_TRANSPARENT_QUADS, u.layer == 1u), quads);
    }
    if s.smooth_draw {
        write_smooth(s, slot, wg_smooth_base[s.smooth_pair] + smooth_local);
        add_stat(STAT_SMOOTH_QUADS, node.smooth_quad_count);
    }
    if listed_transparent {
        let at = wg_transparent_base + transparent_local;
        if at < arrayLength(&transparent_list) {
            transparent_list[at] = slot;
        }
    }
    if listed {
        let at = wg_far_base + far_local;
        if at < u.far_capacity {
            far_list[at] = vec2<u32>(slot, s.skirts);
        }
        add_stat(STAT_FAR_NODES, 1u);
        add_stat(STAT_FAR_BLOCKS, far_block_count(node, s.skirts));
    }
    // The selection counts once per frame: in the late phase when there are two.
    let counting = (u.flags & CULL_OCCLUSION) == 0u || u.phase == 1u;
    if u.layer == 0u && counting {
        if s.selected {
            add_stat(STAT_SELECTED, 1u);
            add_stat(STAT_LEVELS + s.level, 1u);
        }
        add_stat(STAT_FRUSTUM_CULLED, u32(s.frustum_culled));
        add_stat(STAT_OCCLUDED, u32(s.occluded));
    }
    if u.layer == 0u {
        add_stat(STAT_MESH_NODES, u32(s.n > 0u || s.smooth_draw));
        add_stat(STAT_SKIRT_SIDES, countOneBits(select(0u, s.skirts, s.n > 0u || listed)));
    }
    workgroupBarrier();
    if lid < STAT_COUNT && lid != STAT_FAR_LIST && lid != STAT_TRANSPARENT_LIST {
        let c = atomicLoad(&wg_stats[lid]);
        if c > 0u {
            atomicAdd(&stats[lid], c);
        }
    }
}

// The ordered cull's depth key of a camera-relative box centre (twin of cull::depth_key):
// the top 8 mantissa bits and the exponent of the squared distance, clamped to 1 .. 2^48.
fn depth_key(c: vec3<f32>) -> u32 {
    let d2 = max(c.x * c.x + c.y * c.y + c.z * c.z, 1.0);
    return min((bitcast<u32>(d2) >> 15u) - ORDER_KEY_BASE, ORDER_KEYS - 1u);
}

// Ordered cull, pass 1: commands per (page, depth key), and the malformed count.
@compute @workgroup_size(64)
fn cull_count(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let s = cull_slot(ordered_slot(wid, groups, lid));
    if s.malformed {
        atomicAdd(&counts[u.page_count], 1u);
    }
    if s.n > 0u {
        atomicAdd(&order_counts[s.page * ORDER_KEYS + depth_key(s.centre)], s.n);
    }
}

// Ordered cull, pass 2 (one workgroup per page): each key's first command index, farthest key
// first, into order_cursors; the page's total into counts[page].
@compute @workgroup_size(256)
fn order_prefix(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let page = wid.x;
    let base = page * ORDER_KEYS;
    // Thread t owns keys in far-first position t * per .. (t + 1) * per, position i being key
    // ORDER_KEYS - 1 - i.
    let per = ORDER_KEYS / ORDER_PREFIX_WORKGROUP;
    var sum = 0u;
    for (var i = lid * per; i < (lid + 1u) * per; i += 1u) {
        sum += atomicLoad(&order_counts[base + ORDER_KEYS - 1u - i]);
    }
    wg_scan[lid] = sum;
    workgroupBarrier();
    // Inclusive Hillis-Steele scan of the per-thread sums.
    for (var step = 1u; step < ORDER_PREFIX_WORKGROUP; step <<= 1u) {
        var add = 0u;
        if lid >= step {
            add = wg_scan[lid - step];
        }
        workgroupBarrier();
        wg_scan[lid] += add;
        workgroupBarrier();
    }
    var cursor = wg_scan[lid] - sum;
    for (var i = lid * per; i < (lid + 1u) * per; i += 1u) {
        let key = base + ORDER_KEYS - 1u - i;
        let c = atomicLoad(&order_counts[key]);
        atomicStore(&order_cursors[key], cursor);
        cursor += c;
    }
    if lid == ORDER_PREFIX_WORKGROUP - 1u {
        atomicStore(&counts[page], wg_scan[lid]);
    }
}

// Ordered cull, pass 3: each chunk's commands at its key's cursor (chunks of one key in any
// order, the faces of one chunk in face order).
@compute @workgroup_size(64)
fn cull_scatter(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let slot = ordered_slot(wid, groups, lid);
    let s = cull_slot(slot);
    if s.n > 0u {
        let at = atomicAdd(&order_cursors[s.page * ORDER_KEYS + depth_key(s.centre)], s.n);
        let quads = write_commands(s, nodes[slot], at);
        atomicAdd(&stats[STAT_TRANSPARENT_QUADS], quads);
    }
}
