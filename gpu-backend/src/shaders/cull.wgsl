// Cull pass: frustum test per chunk, then per-face-direction culling (Lum), into one range of
// draw commands per gigabuffer page. The twin of gpu-backend/src/cull/reference.rs, which
// states the math, the rounding and the bounds; keep the two in the same order, operation by
// operation. FORMATS_WGSL (MeshedChunkInfo, FaceLayerRange, ChunkDrawIndirect) is prepended
// by shaders.rs.
//
// One invocation per table slot (0..slot_bound). Entry points:
// - `cull`: commands in any order. Per workgroup, commands are counted per page in workgroup
//   memory first, then each page with commands takes one global atomicAdd, so the global
//   counters see one atomic per workgroup and page, not one per command.
// - `cull_count`, `order_prefix`, `cull_scatter`: the same commands, back to front (a counting
//   sort on a depth key, cull::order states the rule): count per (page, key), prefix sums per
//   page far keys first, then each chunk writes its commands at its key's cursor.

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
    pad0: u32,
    pad1: u32,
}

const CULL_WORKGROUP: u32 = 64u;
// Largest page count one dispatch handles (cull::MAX_PAGES).
const CULL_MAX_PAGES: u32 = 256u;

@group(0) @binding(0) var<uniform> u: CullUniforms;
@group(0) @binding(1) var<storage, read> table: array<MeshedChunkInfo>;
@group(0) @binding(2) var<storage, read_write> args: array<DrawIndexedArgs>;
// ChunkDrawIndirect records, two 16-byte words each (see write_record).
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

var<workgroup> wg_count: array<atomic<u32>, CULL_MAX_PAGES>;
var<workgroup> wg_scan: array<u32, ORDER_PREFIX_WORKGROUP>;
var<workgroup> wg_base: array<u32, CULL_MAX_PAGES>;

// Elements in page `page` of the quad gigabuffer.
fn page_capacity_of(page: u32) -> u32 {
    return select(u.page_capacity, u.last_page_capacity, page + 1u == u.page_count);
}

// The chunk's box centre in camera-relative space: (chunk - camera chunk) * edge - offset +
// centre. The chunk difference wraps (i32), as in the CPU reference.
fn relative_centre(info: MeshedChunkInfo, rel: vec3<i32>) -> vec3<f32> {
    let origin = vec3<f32>(rel) * u.chunk_edge - u.camera_offset;
    return origin + meshed_chunk_info_centre(info);
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

// Stores record `at` as two 16-byte vector stores. Writing the struct member by member took
// eight scalar stores, and the stores are what this pass spends its time on: on an H200 the
// whole pass went from 78 to 46 us at 400,000 chunks (BENCHMARKS.md). The word order is the
// struct's (a unit test pins ChunkDrawIndirect's offsets).
fn write_record(at: u32, r: ChunkDrawIndirect) {
    records[2u * at] = vec4<u32>(
        r.index_count,
        r.instance_count,
        r.first_index,
        bitcast<u32>(r.base_vertex),
    );
    records[2u * at + 1u] = vec4<u32>(
        r.first_instance,
        bitcast<u32>(r.chunk_x),
        bitcast<u32>(r.chunk_y),
        bitcast<u32>(r.chunk_z),
    );
}

// What one slot contributes: bit f of `emit` for each non-empty visible face group, `n` of
// them, in page `page` from in-page quad `start`; `malformed` when the layer's range is bad.
struct SlotCull {
    emit: u32,
    n: u32,
    page: u32,
    start: u32,
    malformed: bool,
    range: FaceLayerRange,
    rel: vec3<i32>,
    // Camera-relative box centre (the ordered cull's depth key comes from it).
    centre: vec3<f32>,
}

fn cull_slot(slot: u32) -> SlotCull {
    var out: SlotCull;
    if slot >= u.slot_bound {
        return out;
    }
    let info = table[slot];
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
    if !any {
        return out;
    }
    out.page = out.range.offset / u.page_capacity;
    out.start = out.range.offset % u.page_capacity;
    // Counts are <= max_quads_per_draw < 2^26 here, so no sum overflows.
    out.malformed = oversized || out.page >= u.page_count
        || out.start + face_layer_range_total(out.range) > page_capacity_of(out.page);
    if out.malformed {
        return out;
    }
    out.rel = meshed_chunk_info_chunk(info) - u.camera_chunk;
    out.centre = relative_centre(info, out.rel);
    let e = meshed_chunk_info_extent(info);
    if in_frustum(out.centre, e) {
        let mask = face_mask(out.centre, e);
        for (var f = 0u; f < 6u; f += 1u) {
            if ((mask >> f) & 1u) != 0u && face_layer_range_count(out.range, f) > 0u {
                out.emit |= 1u << f;
                out.n += 1u;
            }
        }
    }
    return out;
}

// Writes the slot's commands from page-local command index `index` on; those at or past
// commands_per_page are dropped (the caller sees counts[page] > commands_per_page).
fn write_commands(s: SlotCull, first_index: u32) {
    var index = first_index;
    var first = s.start;
    for (var f = 0u; f < 6u; f += 1u) {
        let count = face_layer_range_count(s.range, f);
        if ((s.emit >> f) & 1u) != 0u {
            if index < u.commands_per_page {
                let at = s.page * u.commands_per_page + index;
                let a = DrawIndexedArgs(6u * count, 1u, 0u, i32(4u * first), at);
                args[at] = a;
                write_record(at, ChunkDrawIndirect(
                    a.index_count,
                    a.instance_count,
                    a.first_index,
                    a.base_vertex,
                    a.first_instance,
                    s.rel.x,
                    s.rel.y,
                    s.rel.z,
                ));
            }
            index += 1u;
        }
        first += count;
    }
}

fn slot_of(wid: vec3<u32>, groups: vec3<u32>, lid: u32) -> u32 {
    return (wid.y * groups.x + wid.x) * CULL_WORKGROUP + lid;
}

@compute @workgroup_size(64)
fn cull(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let s = cull_slot(slot_of(wid, groups, lid));
    if s.malformed {
        atomicAdd(&counts[u.page_count], 1u);
    }
    var local = 0u;
    if s.n > 0u {
        local = atomicAdd(&wg_count[s.page], s.n);
    }
    workgroupBarrier();
    for (var p = lid; p < u.page_count; p += CULL_WORKGROUP) {
        let c = atomicLoad(&wg_count[p]);
        if c > 0u {
            wg_base[p] = atomicAdd(&counts[p], c);
        }
    }
    workgroupBarrier();
    if s.n > 0u {
        write_commands(s, wg_base[s.page] + local);
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
    let s = cull_slot(slot_of(wid, groups, lid));
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
    let s = cull_slot(slot_of(wid, groups, lid));
    if s.n > 0u {
        let at = atomicAdd(&order_cursors[s.page * ORDER_KEYS + depth_key(s.centre)], s.n);
        write_commands(s, at);
    }
}
