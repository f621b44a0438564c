// Cull pass: frustum test per chunk, then per-face-direction culling (Lum), into one range of
// draw commands per gigabuffer page. The twin of gpu-backend/src/cull/reference.rs, which
// states the math, the rounding and the bounds; keep the two in the same order, operation by
// operation. FORMATS_WGSL (FaceLayerRange, ChunkDrawIndirect, ...) is prepended by shaders.rs.
//
// One invocation per table slot (0..slot_bound), 64 per workgroup, in four phases:
// 1. the workgroup copies its 64 table entries into workgroup memory word by word (adjacent
//    invocations read adjacent words: coalesced, where one 112-byte struct per invocation
//    would make every load instruction touch 32 scattered cache sectors);
// 2. each invocation culls its chunk and counts its commands per page in workgroup memory;
// 3. each page with commands takes one global atomicAdd per workgroup; the workgroup's
//    commands are staged in page order (a compact description each);
// 4. the workgroup writes the staged commands' args and records word by word, again so that
//    adjacent invocations write adjacent words.
// The table is read as words at offsets the Rust side derives from MeshedChunkInfo's layout
// (CullUniforms::info_*), so this file never restates that layout.

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
    // MeshedChunkInfo in 32-bit words: its size, and the first word of its chunk coordinate,
    // box centre, box half size and of the culled layer's FaceLayerRange.
    info_words: u32,
    info_chunk: u32,
    info_centre: u32,
    info_extent: u32,
    info_range: u32,
    pad0: u32,
}

const CULL_WORKGROUP: u32 = 64u;
// Largest page count one dispatch handles (cull::MAX_PAGES).
const CULL_MAX_PAGES: u32 = 256u;
// Largest MeshedChunkInfo in words the staging holds (cull::MAX_INFO_WORDS).
const CULL_MAX_INFO_WORDS: u32 = 32u;
// Commands one workgroup can emit: six face groups per invocation.
const CULL_MAX_COMMANDS: u32 = 384u;
// A staged command whose page range is full: counted, not written.
const CULL_DROPPED: u32 = 0xffffffffu;

@group(0) @binding(0) var<uniform> u: CullUniforms;
// The MeshedChunkInfo table as words (u.info_words per slot).
@group(0) @binding(1) var<storage, read> table: array<u32>;
// DrawIndexedArgs (5 words) and ChunkDrawIndirect (8 words) per command slot, as words.
@group(0) @binding(2) var<storage, read_write> args: array<u32>;
@group(0) @binding(3) var<storage, read_write> records: array<u32>;
// counts[p]: commands page p wanted (those at or past commands_per_page were not written);
// counts[page_count]: malformed chunk layers skipped.
@group(0) @binding(4) var<storage, read_write> counts: array<atomic<u32>>;

var<workgroup> wg_info: array<u32, 2048>; // CULL_WORKGROUP * CULL_MAX_INFO_WORDS
var<workgroup> wg_count: array<atomic<u32>, CULL_MAX_PAGES>;
var<workgroup> wg_base: array<u32, CULL_MAX_PAGES>;
var<workgroup> wg_stage_base: array<u32, CULL_MAX_PAGES>;
var<workgroup> wg_total: u32;
// Staged commands, in page order: destination slot (or CULL_DROPPED), quads, first in-page
// quad, and the staging invocation (whose wg_rel holds the chunk).
var<workgroup> wg_cmd_at: array<u32, CULL_MAX_COMMANDS>;
var<workgroup> wg_cmd_quads: array<u32, CULL_MAX_COMMANDS>;
var<workgroup> wg_cmd_first: array<u32, CULL_MAX_COMMANDS>;
var<workgroup> wg_cmd_owner: array<u32, CULL_MAX_COMMANDS>;
var<workgroup> wg_rel: array<vec3<i32>, CULL_WORKGROUP>;

// Elements in page `page` of the quad gigabuffer.
fn page_capacity_of(page: u32) -> u32 {
    return select(u.page_capacity, u.last_page_capacity, page + 1u == u.page_count);
}

// Word `w` of this workgroup's table entry `lid`.
fn info_word(lid: u32, w: u32) -> u32 {
    return wg_info[lid * u.info_words + w];
}

fn info_vec3_u32(lid: u32, w: u32) -> vec3<u32> {
    return vec3<u32>(info_word(lid, w), info_word(lid, w + 1u), info_word(lid, w + 2u));
}

// The culled layer's range of entry `lid`.
fn info_range(lid: u32) -> FaceLayerRange {
    let w = u.info_range;
    return FaceLayerRange(
        info_word(lid, w),
        info_word(lid, w + 1u),
        info_word(lid, w + 2u),
        info_word(lid, w + 3u),
        info_word(lid, w + 4u),
        info_word(lid, w + 5u),
        info_word(lid, w + 6u),
    );
}

// The chunk's box centre in camera-relative space: (chunk - camera chunk) * edge - offset +
// centre. The chunk difference wraps (i32), as in the CPU reference.
fn relative_centre(centre: vec3<f32>, rel: vec3<i32>) -> vec3<f32> {
    let origin = vec3<f32>(rel) * u.chunk_edge - u.camera_offset;
    return origin + centre;
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

// The draw arguments of staged command `c`.
fn staged_args(c: u32) -> DrawIndexedArgs {
    return DrawIndexedArgs(6u * wg_cmd_quads[c], 1u, 0u, i32(4u * wg_cmd_first[c]), wg_cmd_at[c]);
}

// Word `w` (0..8) of staged command `c` as a ChunkDrawIndirect; words 0..5 are its
// DrawIndexedArgs.
fn staged_word(c: u32, w: u32) -> u32 {
    let a = staged_args(c);
    let rel = wg_rel[wg_cmd_owner[c]];
    let r = ChunkDrawIndirect(
        a.index_count,
        a.instance_count,
        a.first_index,
        a.base_vertex,
        a.first_instance,
        rel.x,
        rel.y,
        rel.z,
    );
    switch w {
        case 0u: { return r.index_count; }
        case 1u: { return r.instance_count; }
        case 2u: { return r.first_index; }
        case 3u: { return bitcast<u32>(r.base_vertex); }
        case 4u: { return r.first_instance; }
        case 5u: { return bitcast<u32>(r.chunk_x); }
        case 6u: { return bitcast<u32>(r.chunk_y); }
        default: { return bitcast<u32>(r.chunk_z); }
    }
}

@compute @workgroup_size(64)
fn cull(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let first_slot = (wid.y * groups.x + wid.x) * CULL_WORKGROUP;
    let slot = first_slot + lid;

    // Phase 1: this workgroup's table entries, word by word.
    if first_slot < u.slot_bound {
        let words = min(CULL_WORKGROUP, u.slot_bound - first_slot) * u.info_words;
        let first_word = first_slot * u.info_words;
        for (var i = lid; i < words; i += CULL_WORKGROUP) {
            wg_info[i] = table[first_word + i];
        }
    }
    workgroupBarrier();

    // Phase 2: non-empty visible groups of this slot: bit f of `emit`, `n` of them, in page
    // `page` from in-page quad `start`, at `local` among the workgroup's commands of that page.
    var emit = 0u;
    var n = 0u;
    var page = 0u;
    var start = 0u;
    var local = 0u;
    var range: FaceLayerRange;
    if slot < u.slot_bound {
        range = info_range(lid);
        var any = false;
        var oversized = false;
        for (var f = 0u; f < 6u; f += 1u) {
            let count = face_layer_range_count(range, f);
            any = any || count > 0u;
            oversized = oversized || count > u.max_quads_per_draw;
        }
        if any {
            page = range.offset / u.page_capacity;
            start = range.offset % u.page_capacity;
            // Counts are <= max_quads_per_draw < 2^26 here, so no sum overflows.
            let malformed = oversized || page >= u.page_count
                || start + face_layer_range_total(range) > page_capacity_of(page);
            if malformed {
                atomicAdd(&counts[u.page_count], 1u);
            } else {
                let rel = bitcast<vec3<i32>>(info_vec3_u32(lid, u.info_chunk)) - u.camera_chunk;
                wg_rel[lid] = rel;
                let c = relative_centre(bitcast<vec3<f32>>(info_vec3_u32(lid, u.info_centre)), rel);
                let e = bitcast<vec3<f32>>(info_vec3_u32(lid, u.info_extent));
                if in_frustum(c, e) {
                    let mask = face_mask(c, e);
                    for (var f = 0u; f < 6u; f += 1u) {
                        if ((mask >> f) & 1u) != 0u && face_layer_range_count(range, f) > 0u {
                            emit |= 1u << f;
                            n += 1u;
                        }
                    }
                }
            }
        }
        if n > 0u {
            local = atomicAdd(&wg_count[page], n);
        }
    }
    workgroupBarrier();

    // Phase 3: one global atomic per page with commands; staging offsets in page order.
    for (var p = lid; p < u.page_count; p += CULL_WORKGROUP) {
        let c = atomicLoad(&wg_count[p]);
        if c > 0u {
            wg_base[p] = atomicAdd(&counts[p], c);
        }
    }
    if lid == 0u {
        var total = 0u;
        for (var p = 0u; p < u.page_count; p += 1u) {
            wg_stage_base[p] = total;
            total += atomicLoad(&wg_count[p]);
        }
        wg_total = total;
    }
    workgroupBarrier();
    if n > 0u {
        var staged = wg_stage_base[page] + local;
        var index = wg_base[page] + local;
        var first = start;
        for (var f = 0u; f < 6u; f += 1u) {
            let count = face_layer_range_count(range, f);
            if ((emit >> f) & 1u) != 0u {
                // Past the page's range: counted above, not written (the caller sees
                // counts[page] > commands_per_page).
                wg_cmd_at[staged] = select(
                    CULL_DROPPED,
                    page * u.commands_per_page + index,
                    index < u.commands_per_page,
                );
                wg_cmd_quads[staged] = count;
                wg_cmd_first[staged] = first;
                wg_cmd_owner[staged] = lid;
                staged += 1u;
                index += 1u;
            }
            first += count;
        }
    }
    workgroupBarrier();

    // Phase 4: the staged commands, word by word. A page's commands are consecutive slots,
    // so adjacent invocations write adjacent words.
    let total = wg_total;
    for (var k = lid; k < total * 5u; k += CULL_WORKGROUP) {
        let c = k / 5u;
        let at = wg_cmd_at[c];
        if at != CULL_DROPPED {
            let w = k - 5u * c;
            args[5u * at + w] = staged_word(c, w);
        }
    }
    for (var k = lid; k < total * 8u; k += CULL_WORKGROUP) {
        let c = k / 8u;
        let at = wg_cmd_at[c];
        if at != CULL_DROPPED {
            records[8u * at + (k % 8u)] = staged_word(c, k % 8u);
        }
    }
}
