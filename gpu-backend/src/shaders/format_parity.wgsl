// Format parity: decode packed values with voxel-core's WGSL twins (FORMATS_WGSL, prepended by
// shaders.rs) and write every decoded field to `out`, so a test can compare them with the CPU
// decoders. One entry point per format; each reads only its own input binding and writes
// `*_STRIDE` words per element (integers as is, i32 and f32 as their bit patterns, bools as
// 0 / 1). The word order is mirrored by gpu-backend/tests/parity/expected.rs.

struct Params {
    // The unorm16 position extent of BlockVertex / ClutterUnit (and of decode_unorm).
    extent: f32,
}

@group(0) @binding(0) var<storage, read_write> out: array<u32>;
@group(0) @binding(1) var<uniform> params: Params;
@group(0) @binding(2) var<storage, read> draw_blocks: array<DrawBlock>;
@group(0) @binding(3) var<storage, read> quads: array<PackedQuad>;
@group(0) @binding(4) var<storage, read> vertices: array<BlockVertex>;
@group(0) @binding(5) var<storage, read> clutter: array<ClutterUnit>;
@group(0) @binding(6) var<storage, read> draw_infos: array<ChunkDrawInfo>;
@group(0) @binding(7) var<storage, read> meshed: array<MeshedChunkInfo>;
@group(0) @binding(8) var<storage, read> indirect: array<ChunkDrawIndirect>;
@group(0) @binding(9) var<storage, read> codes: array<u32>;

const DRAW_BLOCK_STRIDE: u32 = 5u;
const PACKED_QUAD_STRIDE: u32 = 30u;
const BLOCK_VERTEX_STRIDE: u32 = 10u;
const CLUTTER_UNIT_STRIDE: u32 = 17u;
const CHUNK_DRAW_INFO_STRIDE: u32 = 8u;
const MESHED_CHUNK_INFO_STRIDE: u32 = 43u;
const CHUNK_DRAW_INDIRECT_STRIDE: u32 = 8u;
const OCT_STRIDE: u32 = 3u;
const SMOOTH_QUAD_STRIDE: u32 = 4u;
const UNORM_STRIDE: u32 = 2u;
const SHELL_RUN_STRIDE: u32 = 86u;

fn put_u(at: u32, v: u32) {
    out[at] = v;
}

fn put_i(at: u32, v: i32) {
    out[at] = bitcast<u32>(v);
}

fn put_f(at: u32, v: f32) {
    out[at] = bitcast<u32>(v);
}

fn put_b(at: u32, v: bool) {
    out[at] = u32(v);
}

fn put_u3(at: u32, v: vec3<u32>) {
    put_u(at, v.x);
    put_u(at + 1u, v.y);
    put_u(at + 2u, v.z);
}

fn put_i3(at: u32, v: vec3<i32>) {
    put_i(at, v.x);
    put_i(at + 1u, v.y);
    put_i(at + 2u, v.z);
}

fn put_f3(at: u32, v: vec3<f32>) {
    put_f(at, v.x);
    put_f(at + 1u, v.y);
    put_f(at + 2u, v.z);
}

// flags, position x y z, block id.
@compute @workgroup_size(64)
fn decode_draw_block(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&draw_blocks) {
        return;
    }
    let b = draw_blocks[i];
    let o = i * DRAW_BLOCK_STRIDE;
    put_u(o, draw_block_flags(b));
    put_u3(o + 1u, draw_block_position(b));
    put_u(o + 4u, draw_block_id(b));
}

// position x y z, width, height, face, ao[0..4], block, corners[0..4] x y z, face normal
// x y z, normal axis, width axis, height axis, is positive.
@compute @workgroup_size(64)
fn decode_packed_quad(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&quads) {
        return;
    }
    let q = quads[i];
    let o = i * PACKED_QUAD_STRIDE;
    put_u3(o, packed_quad_position(q));
    put_u(o + 3u, packed_quad_width(q));
    put_u(o + 4u, packed_quad_height(q));
    let face = packed_quad_face(q);
    put_u(o + 5u, face);
    for (var c = 0u; c < 4u; c += 1u) {
        put_u(o + 6u + c, packed_quad_ao(q, c));
    }
    put_u(o + 10u, packed_quad_block(q));
    for (var c = 0u; c < 4u; c += 1u) {
        put_u3(o + 11u + 3u * c, packed_quad_corner(q, c));
    }
    put_i3(o + 23u, face_normal(face));
    put_u(o + 26u, face_normal_axis(face));
    put_u(o + 27u, face_width_axis(face));
    put_u(o + 28u, face_height_axis(face));
    put_b(o + 29u, face_is_positive(face));
}

// position x y z, normal x y z, uv u v, block, extra.
@compute @workgroup_size(64)
fn decode_block_vertex(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&vertices) {
        return;
    }
    let v = vertices[i];
    let o = i * BLOCK_VERTEX_STRIDE;
    put_f3(o, block_vertex_position(v, params.extent));
    put_f3(o + 3u, block_vertex_normal(v));
    let uv = block_vertex_uv(v);
    put_f(o + 6u, uv.x);
    put_f(o + 7u, uv.y);
    put_u(o + 8u, block_vertex_block(v));
    put_u(o + 9u, block_vertex_extra(v));
}

// position x y z, normal x y z, kind, scale step, seed, uv u v, uv size w h, tint r g b a.
@compute @workgroup_size(64)
fn decode_clutter_unit(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&clutter) {
        return;
    }
    let c = clutter[i];
    let o = i * CLUTTER_UNIT_STRIDE;
    put_f3(o, clutter_unit_position(c, params.extent));
    put_f3(o + 3u, clutter_unit_normal(c));
    put_u(o + 6u, clutter_unit_kind(c));
    put_u(o + 7u, clutter_unit_scale_step(c));
    put_u(o + 8u, clutter_unit_seed(c));
    let uv = clutter_unit_uv(c);
    put_f(o + 9u, uv.x);
    put_f(o + 10u, uv.y);
    let size = clutter_unit_uv_size(c);
    put_f(o + 11u, size.x);
    put_f(o + 12u, size.y);
    let tint = clutter_unit_tint(c);
    put_f(o + 13u, tint.x);
    put_f(o + 14u, tint.y);
    put_f(o + 15u, tint.z);
    put_f(o + 16u, tint.w);
}

// chunk x y z, kind, draw count, gigabuffer index, needs refresh, is resident.
@compute @workgroup_size(64)
fn decode_chunk_draw_info(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&draw_infos) {
        return;
    }
    let d = draw_infos[i];
    let o = i * CHUNK_DRAW_INFO_STRIDE;
    put_i3(o, chunk_draw_info_chunk(d));
    put_u(o + 3u, d.kind);
    put_i(o + 4u, d.draw_count);
    put_i(o + 5u, d.gigabuffer_index);
    put_b(o + 6u, chunk_draw_info_needs_refresh(d));
    put_b(o + 7u, chunk_draw_info_is_resident(d));
}

// offset, count per face (6), start per face (6), total.
fn put_face_layer_range(at: u32, r: FaceLayerRange) {
    put_u(at, r.offset);
    for (var f = 0u; f < 6u; f += 1u) {
        put_u(at + 1u + f, face_layer_range_count(r, f));
        put_u(at + 7u + f, face_layer_range_start(r, f));
    }
    put_u(at + 13u, face_layer_range_total(r));
}

// chunk x y z, lod, centre x y z, extent x y z, opaque quads (14), transparent quads (14),
// smooth vertices offset count, clutter units offset count, count of face 6 (invalid).
@compute @workgroup_size(64)
fn decode_meshed_chunk_info(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&meshed) {
        return;
    }
    let m = meshed[i];
    let o = i * MESHED_CHUNK_INFO_STRIDE;
    put_i3(o, meshed_chunk_info_chunk(m));
    put_u(o + 3u, m.lod);
    put_f3(o + 4u, meshed_chunk_info_centre(m));
    put_f3(o + 7u, meshed_chunk_info_extent(m));
    put_face_layer_range(o + 10u, m.opaque_quads);
    put_face_layer_range(o + 24u, m.transparent_quads);
    put_u(o + 38u, m.smooth_vertices.offset);
    put_u(o + 39u, m.smooth_vertices.count);
    put_u(o + 40u, m.clutter_units.offset);
    put_u(o + 41u, m.clutter_units.count);
    put_u(o + 42u, face_layer_range_count(m.opaque_quads, 6u));
}

// index count, instance count, first index, base vertex, first instance, chunk x y z.
@compute @workgroup_size(64)
fn decode_chunk_draw_indirect(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&indirect) {
        return;
    }
    let d = indirect[i];
    let o = i * CHUNK_DRAW_INDIRECT_STRIDE;
    put_u(o, d.index_count);
    put_u(o + 1u, d.instance_count);
    put_u(o + 2u, d.first_index);
    put_i(o + 3u, d.base_vertex);
    put_u(o + 4u, d.first_instance);
    put_i3(o + 5u, chunk_draw_indirect_chunk(d));
}

// oct16_decode of the low 16 bits: x y z.
@compute @workgroup_size(64)
fn decode_oct16(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&codes) {
        return;
    }
    put_f3(i * OCT_STRIDE, oct16_decode(codes[i]));
}

// oct32_decode: x y z.
@compute @workgroup_size(64)
fn decode_oct32(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&codes) {
        return;
    }
    put_f3(i * OCT_STRIDE, oct32_decode(codes[i]));
}

// unorm16_decode(code, extent), unorm8_decode(code).
@compute @workgroup_size(64)
fn decode_unorm(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&codes) {
        return;
    }
    put_f(i * UNORM_STRIDE, unorm16_decode(codes[i], params.extent));
    put_f(i * UNORM_STRIDE + 1u, unorm8_decode(codes[i]));
}

// Shell runs (`codes` holds their two words each): position x y z, height, block, the six
// side bits, then the 4 corners of each of the 6 faces (face order, 3 words each), then the
// width, the feet, and shell_run_has_foot of each face (bit f).
@compute @workgroup_size(64)
fn decode_shell_run(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&codes) / 2u {
        return;
    }
    let r = ShellRun(codes[2u * i], codes[2u * i + 1u]);
    let o = i * SHELL_RUN_STRIDE;
    put_u3(o, shell_run_position(r));
    put_u(o + 3u, shell_run_height(r));
    put_u(o + 4u, shell_run_block(r));
    for (var f = 0u; f < 6u; f += 1u) {
        put_b(o + 5u + f, shell_run_has_side(r, f));
        for (var c = 0u; c < 4u; c += 1u) {
            put_u3(o + 11u + 12u * f + 3u * c, shell_run_corner(r, f, c));
        }
    }
    put_u(o + 83u, shell_run_width(r));
    put_u(o + 84u, shell_run_feet(r));
    var feet = 0u;
    for (var f = 0u; f < 6u; f += 1u) {
        feet |= u32(shell_run_has_foot(r, f)) << f;
    }
    put_u(o + 85u, feet);
}

// Smooth quads in `form` (`codes` holds the words): corners 0..4 of quad i, read with
// smooth_quad_word / smooth_quad_corner as the smooth draw reads them.
fn put_smooth_quad(form: u32, i: u32) {
    if i >= arrayLength(&out) / SMOOTH_QUAD_STRIDE {
        return;
    }
    for (var c = 0u; c < 4u; c++) {
        let w = smooth_quad_word(form, i, c);
        let next = min(w + 1u, arrayLength(&codes) - 1u);
        put_u(i * SMOOTH_QUAD_STRIDE + c, smooth_quad_corner(form, i, c, codes[w], codes[next]));
    }
}

@compute @workgroup_size(64)
fn decode_compact_quads(@builtin(global_invocation_id) id: vec3<u32>) {
    put_smooth_quad(SMOOTH_QUADS_COMPACT, id.x);
}

@compute @workgroup_size(64)
fn decode_u16_quads(@builtin(global_invocation_id) id: vec3<u32>) {
    put_smooth_quad(SMOOTH_QUADS_U16, id.x);
}

@compute @workgroup_size(64)
fn decode_u32_quads(@builtin(global_invocation_id) id: vec3<u32>) {
    put_smooth_quad(SMOOTH_QUADS_U32, id.x);
}
