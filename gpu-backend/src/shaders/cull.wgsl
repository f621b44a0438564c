// Cull pass: frustum test per chunk, then per-face-direction culling (Lum), into one range of
// draw commands per gigabuffer page. The twin of gpu-backend/src/cull/reference.rs, which
// states the math, the rounding and the bounds; keep the two in the same order, operation by
// operation. FORMATS_WGSL (MeshedChunkInfo, FaceLayerRange, ChunkDrawIndirect) is prepended
// by shaders.rs.
//
// One invocation per table slot (0..slot_bound). Per workgroup, commands are counted per page
// in workgroup memory first, then each page with commands takes one global atomicAdd, so the
// global counters see one atomic per workgroup and page, not one per command.

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

var<workgroup> wg_count: array<atomic<u32>, CULL_MAX_PAGES>;
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

@compute @workgroup_size(64)
fn cull(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let slot = (wid.y * groups.x + wid.x) * CULL_WORKGROUP + lid;
    // Non-empty visible groups of this slot: bit f of `emit`, `n` of them, in page `page` from
    // in-page quad `start`.
    var emit = 0u;
    var n = 0u;
    var page = 0u;
    var start = 0u;
    var local = 0u;
    var range: FaceLayerRange;
    var rel = vec3<i32>(0);
    if slot < u.slot_bound {
        let info = table[slot];
        range = info.opaque_quads;
        if u.layer == 1u {
            range = info.transparent_quads;
        }
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
                rel = meshed_chunk_info_chunk(info) - u.camera_chunk;
                let c = relative_centre(info, rel);
                let e = meshed_chunk_info_extent(info);
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
    for (var p = lid; p < u.page_count; p += CULL_WORKGROUP) {
        let c = atomicLoad(&wg_count[p]);
        if c > 0u {
            wg_base[p] = atomicAdd(&counts[p], c);
        }
    }
    workgroupBarrier();
    if n == 0u {
        return;
    }
    var index = wg_base[page] + local;
    var first = start;
    for (var f = 0u; f < 6u; f += 1u) {
        let count = face_layer_range_count(range, f);
        if ((emit >> f) & 1u) != 0u {
            // Past the page's range: counted above, not written (the caller sees
            // counts[page] > commands_per_page).
            if index < u.commands_per_page {
                let at = page * u.commands_per_page + index;
                let a = DrawIndexedArgs(6u * count, 1u, 0u, i32(4u * first), at);
                args[at] = a;
                write_record(at, ChunkDrawIndirect(
                    a.index_count,
                    a.instance_count,
                    a.first_index,
                    a.base_vertex,
                    a.first_instance,
                    rel.x,
                    rel.y,
                    rel.z,
                ));
            }
            index += 1u;
        }
        first += count;
    }
}
