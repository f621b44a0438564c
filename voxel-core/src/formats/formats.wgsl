// Packed GPU formats of voxel-core: one struct per format and the functions that decode it.
//
// Twin of voxel-core/src/formats/*.rs; the bit layouts are documented there. Every struct uses
// scalar u32 / i32 / f32 members only (no vec3, whose 16-byte alignment would break the packed
// layout); pairs of Rust u16 fields share one u32, the first field in the low half.
// tests/wgsl_layout.rs checks every struct's size, stride, member names, offsets and types
// against the Rust `WGSL_LAYOUT` tables, and the constants below against the Rust ones.
//
// The decoders mirror the CPU decoders exactly: the same bit extraction, and the same f32
// formulas built from correctly rounded operations (+, -, *, abs, clamp, max, select). The one
// exception is the final normalization of octahedral normals (sqrt and 1/x), which a GPU may
// round differently in the last bits.
//
// Inputs that the CPU decoder rejects (face direction 6 or 7, reserved bits, ...) give
// unspecified but harmless results here.

// ---------------------------------------------------------------------------------------------
// Scalar quantization (quantize.rs, octahedral.rs)

// 1 / 65535, rounded to f32 (quantize::UNORM16_STEP).
const UNORM16_STEP: f32 = 0.000015259021893143654;
// 1 / 255, rounded to f32 (quantize::UNORM8_STEP).
const UNORM8_STEP: f32 = 0.003921568859368563;
// 1 / 127, rounded to f32 (octahedral::SNORM8_STEP).
const SNORM8_STEP: f32 = 0.007874015718698502;
// 1 / 32767, rounded to f32 (octahedral::SNORM16_STEP).
const SNORM16_STEP: f32 = 0.000030518509447574615;

// The value of the unorm16 code in the low 16 bits of `code`, over 0..=extent.
fn unorm16_decode(code: u32, extent: f32) -> f32 {
    return (f32(code & 0xffffu) * UNORM16_STEP) * extent;
}

// The value of the unorm8 code in the low 8 bits of `code`, over 0..=1.
fn unorm8_decode(code: u32) -> f32 {
    return f32(code & 0xffu) * UNORM8_STEP;
}

// Shared octahedral decode: square coordinates code * step, unfolded, normalized.
fn oct_decode(code_x: i32, code_y: i32, step: f32) -> vec3<f32> {
    let sx = clamp(f32(code_x) * step, -1.0, 1.0);
    let sy = clamp(f32(code_y) * step, -1.0, 1.0);
    let z = 1.0 - abs(sx) - abs(sy);
    let t = max(-z, 0.0);
    let x = select(sx + t, sx - t, sx >= 0.0);
    let y = select(sy + t, sy - t, sy >= 0.0);
    let v = vec3<f32>(x, y, z);
    return v * (1.0 / sqrt(dot(v, v)));
}

// Octahedral 8+8 normal in the low 16 bits of `code`: x = bits 0..8, y = bits 8..16, each i8.
fn oct16_decode(code: u32) -> vec3<f32> {
    let x = bitcast<i32>(code << 24u) >> 24u;
    let y = bitcast<i32>(code << 16u) >> 24u;
    return oct_decode(x, y, SNORM8_STEP);
}

// Octahedral 16+16 normal: x = bits 0..16, y = bits 16..32, each i16.
fn oct32_decode(code: u32) -> vec3<f32> {
    let x = bitcast<i32>(code << 16u) >> 16u;
    let y = bitcast<i32>(code) >> 16u;
    return oct_decode(x, y, SNORM16_STEP);
}

// ---------------------------------------------------------------------------------------------
// FaceDirection (face_direction.rs)

const FACE_POS_X: u32 = 0u;
const FACE_NEG_X: u32 = 1u;
const FACE_POS_Y: u32 = 2u;
const FACE_NEG_Y: u32 = 3u;
const FACE_POS_Z: u32 = 4u;
const FACE_NEG_Z: u32 = 5u;

// The axis (0 = x, 1 = y, 2 = z) as a unit vector; the zero vector for axis >= 3.
fn axis_unit(axis: u32) -> vec3<u32> {
    return vec3<u32>(u32(axis == 0u), u32(axis == 1u), u32(axis == 2u));
}

// The axis the face's normal runs along.
fn face_normal_axis(face: u32) -> u32 {
    return face / 2u;
}

// True for FACE_POS_X, FACE_POS_Y, FACE_POS_Z.
fn face_is_positive(face: u32) -> bool {
    return (face & 1u) == 0u;
}

// The outward unit normal (zero for an invalid face).
fn face_normal(face: u32) -> vec3<i32> {
    let sign = select(-1, 1, face_is_positive(face));
    return vec3<i32>(axis_unit(face_normal_axis(face))) * sign;
}

// The axis a quad's width runs along: z for +-X faces, x otherwise.
fn face_width_axis(face: u32) -> u32 {
    return select(0u, 2u, face_normal_axis(face) == 0u);
}

// The axis a quad's height runs along: z for +-Y faces, y otherwise.
fn face_height_axis(face: u32) -> u32 {
    return select(1u, 2u, face_normal_axis(face) == 1u);
}

// ---------------------------------------------------------------------------------------------
// DrawBlock (draw_block.rs)

struct DrawBlock {
    bits: u32,
}

const DRAW_BLOCK_TRANSPARENT: u32 = 1u;
const DRAW_BLOCK_EMISSIVE: u32 = 2u;
const DRAW_BLOCK_SMOOTH: u32 = 4u;
const DRAW_BLOCK_HAS_CLUTTER: u32 = 8u;

fn draw_block_flags(b: DrawBlock) -> u32 {
    return b.bits & 0xfu;
}

fn draw_block_position(b: DrawBlock) -> vec3<u32> {
    return vec3<u32>((b.bits >> 4u) & 0xfu, (b.bits >> 8u) & 0xfu, (b.bits >> 12u) & 0xfu);
}

fn draw_block_id(b: DrawBlock) -> u32 {
    return b.bits >> 16u;
}

// ---------------------------------------------------------------------------------------------
// PackedQuad (packed_quad.rs)

struct PackedQuad {
    position_size: u32,
    face_ao_block: u32,
}

fn packed_quad_position(q: PackedQuad) -> vec3<u32> {
    let w = q.position_size;
    return vec3<u32>(w & 63u, (w >> 6u) & 63u, (w >> 12u) & 63u);
}

// Width in voxels, 1..=64.
fn packed_quad_width(q: PackedQuad) -> u32 {
    return ((q.position_size >> 18u) & 63u) + 1u;
}

// Height in voxels, 1..=64.
fn packed_quad_height(q: PackedQuad) -> u32 {
    return ((q.position_size >> 24u) & 63u) + 1u;
}

fn packed_quad_face(q: PackedQuad) -> u32 {
    return q.face_ao_block & 7u;
}

// Ambient occlusion of corner `corner & 3`: 3 = unoccluded, 0 = most occluded.
fn packed_quad_ao(q: PackedQuad, corner: u32) -> u32 {
    return (q.face_ao_block >> (3u + 2u * (corner & 3u))) & 3u;
}

fn packed_quad_block(q: PackedQuad) -> u32 {
    return (q.face_ao_block >> 11u) & 0xffffu;
}

// Corner `corner & 3` in chunk-local voxel units, counter-clockwise seen from outside; the twin
// of PackedQuadFields::corners. Draw corners (0, 1, 2) and (0, 2, 3).
fn packed_quad_corner(q: PackedQuad, corner: u32) -> vec3<u32> {
    let face = packed_quad_face(q);
    let c = corner & 3u;
    // (a, b) = (0, 0), (1, 0), (1, 1), (0, 1) for corners 0..3.
    let a = u32(c == 1u || c == 2u);
    let b = u32(c >= 2u);
    // Faces whose width axis x height axis points against the normal walk (b, a) instead.
    let swap = face == FACE_POS_X || face == FACE_POS_Y || face == FACE_NEG_Z;
    let du = select(a, b, swap);
    let dv = select(b, a, swap);
    var p = packed_quad_position(q);
    p += axis_unit(face_normal_axis(face)) * u32(face_is_positive(face));
    p += axis_unit(face_width_axis(face)) * (du * packed_quad_width(q));
    p += axis_unit(face_height_axis(face)) * (dv * packed_quad_height(q));
    return p;
}

// ShellRun (shell_run.rs)

struct ShellRun {
    xzyh: u32,
    block_sides: u32,
}

// Chunk-local x, y, z of the run's lowest voxel.
fn shell_run_position(r: ShellRun) -> vec3<u32> {
    return vec3<u32>(r.xzyh & 0xffu, (r.xzyh >> 16u) & 0xffu, (r.xzyh >> 8u) & 0xffu);
}

// Voxels in the run, 1..=64 - y.
fn shell_run_height(r: ShellRun) -> u32 {
    return r.xzyh >> 24u;
}

// Columns in the box along x, 1..=64 - x (1 for a vertical shell).
fn shell_run_width(r: ShellRun) -> u32 {
    return ((r.block_sides >> 24u) & 0x3fu) + 1u;
}

// The feet, bits [+x, -x, +z, -z] (ShellRun::feet): sides that become visible at the box's
// lowest voxel, above a solid voxel in front of it.
fn shell_run_feet(r: ShellRun) -> u32 {
    return ((r.block_sides >> 22u) & 3u) | (((r.block_sides >> 30u) & 3u) << 2u);
}

// True if side `face` (a FACE_* index) has its foot at the box's lowest voxel; never for
// +y and -y.
fn shell_run_has_foot(r: ShellRun, face: u32) -> bool {
    let bit = array<u32, 6>(0u, 1u, 4u, 4u, 2u, 3u)[min(face, 5u)];
    return bit < 4u && ((shell_run_feet(r) >> bit) & 1u) != 0u;
}

fn shell_run_block(r: ShellRun) -> u32 {
    return r.block_sides & 0xffffu;
}

// True if box face `face` (a FACE_* index) is visible somewhere along the run.
fn shell_run_has_side(r: ShellRun, face: u32) -> bool {
    return ((r.block_sides >> (16u + face)) & 1u) != 0u;
}

// Corner `corner & 3` of box face `face` in chunk-local voxel units, counter-clockwise seen
// from outside, in the order of the greedy quad covering the same side; the twin of
// ShellRunFields::corners. Draw corners (0, 1, 2) and (0, 2, 3).
fn shell_run_corner(r: ShellRun, face: u32, corner: u32) -> vec3<u32> {
    let c = corner & 3u;
    let a = u32(c == 1u || c == 2u);
    let b = u32(c >= 2u);
    let swap = face == FACE_POS_X || face == FACE_POS_Y || face == FACE_NEG_Z;
    let du = select(a, b, swap);
    let dv = select(b, a, swap);
    let extent = vec3<u32>(shell_run_width(r), shell_run_height(r), 1u);
    let n = axis_unit(face_normal_axis(face));
    let w = axis_unit(face_width_axis(face));
    let h = axis_unit(face_height_axis(face));
    var p = shell_run_position(r);
    p += n * extent * u32(face_is_positive(face));
    p += w * extent * du;
    p += h * extent * dv;
    return p;
}

// Three unorm16 coordinates packed as BlockVertex and ClutterUnit pack them: x and y in the low
// and high halves of `xy`, z in the low half of `z_low` (the mirror of `unorm16x3_decode`).
fn unorm16x3_decode(xy: u32, z_low: u32, extent: f32) -> vec3<f32> {
    return vec3<f32>(
        unorm16_decode(xy, extent),
        unorm16_decode(xy >> 16u, extent),
        unorm16_decode(z_low, extent),
    );
}

// ---------------------------------------------------------------------------------------------
// BlockVertex (block_vertex.rs)

struct BlockVertex {
    position_xy: u32,
    position_z_normal: u32,
    uv: u32,
    block_extra: u32,
}

// Chunk-local position over 0..=extent (the extent the encoder used).
fn block_vertex_position(v: BlockVertex, extent: f32) -> vec3<f32> {
    return unorm16x3_decode(v.position_xy, v.position_z_normal, extent);
}

fn block_vertex_normal(v: BlockVertex) -> vec3<f32> {
    return oct16_decode(v.position_z_normal >> 16u);
}

fn block_vertex_uv(v: BlockVertex) -> vec2<f32> {
    return vec2<f32>(unorm16_decode(v.uv, 1.0), unorm16_decode(v.uv >> 16u, 1.0));
}

fn block_vertex_block(v: BlockVertex) -> u32 {
    return v.block_extra & 0xffffu;
}

fn block_vertex_extra(v: BlockVertex) -> u32 {
    return v.block_extra >> 16u;
}

// ---------------------------------------------------------------------------------------------
// ClutterUnit (clutter_unit.rs)

struct ClutterUnit {
    position_xy: u32,
    position_z_normal: u32,
    settings_uv_u: u32,
    uv_v_size: u32,
    tint: u32,
}

// Chunk-local position over 0..=extent (the extent the encoder used).
fn clutter_unit_position(c: ClutterUnit, extent: f32) -> vec3<f32> {
    return unorm16x3_decode(c.position_xy, c.position_z_normal, extent);
}

fn clutter_unit_normal(c: ClutterUnit) -> vec3<f32> {
    return oct16_decode(c.position_z_normal >> 16u);
}

fn clutter_unit_kind(c: ClutterUnit) -> u32 {
    return c.settings_uv_u & 0xffu;
}

fn clutter_unit_scale_step(c: ClutterUnit) -> u32 {
    return (c.settings_uv_u >> 8u) & 0xfu;
}

fn clutter_unit_seed(c: ClutterUnit) -> u32 {
    return (c.settings_uv_u >> 12u) & 0xfu;
}

fn clutter_unit_uv(c: ClutterUnit) -> vec2<f32> {
    return vec2<f32>(unorm16_decode(c.settings_uv_u >> 16u, 1.0), unorm16_decode(c.uv_v_size, 1.0));
}

fn clutter_unit_uv_size(c: ClutterUnit) -> vec2<f32> {
    return vec2<f32>(unorm8_decode(c.uv_v_size >> 16u), unorm8_decode(c.uv_v_size >> 24u));
}

// RGBA tint, each channel over 0..=1 (red from the lowest byte).
fn clutter_unit_tint(c: ClutterUnit) -> vec4<f32> {
    return vec4<f32>(
        unorm8_decode(c.tint),
        unorm8_decode(c.tint >> 8u),
        unorm8_decode(c.tint >> 16u),
        unorm8_decode(c.tint >> 24u),
    );
}

// ---------------------------------------------------------------------------------------------
// ChunkDrawInfo (chunk_draw_info.rs)

struct ChunkDrawInfo {
    chunk_x: i32,
    chunk_y: i32,
    chunk_z: i32,
    kind: u32,
    draw_count: i32,
    gigabuffer_index: i32,
}

const CHUNK_KIND_EMPTY: u32 = 0u;
const CHUNK_KIND_MESH: u32 = 1u;
const CHUNK_KIND_SPRITE: u32 = 2u;

fn chunk_draw_info_chunk(i: ChunkDrawInfo) -> vec3<i32> {
    return vec3<i32>(i.chunk_x, i.chunk_y, i.chunk_z);
}

// draw_count == -1.
fn chunk_draw_info_needs_refresh(i: ChunkDrawInfo) -> bool {
    return i.draw_count == -1;
}

// gigabuffer_index != -1 (and valid, i.e. >= 0).
fn chunk_draw_info_is_resident(i: ChunkDrawInfo) -> bool {
    return i.gigabuffer_index >= 0;
}

// ---------------------------------------------------------------------------------------------
// FaceLayerRange, LayerRange, MeshedChunkInfo (layer_range.rs, meshed_chunk_info.rs)

struct FaceLayerRange {
    offset: u32,
    count_pos_x: u32,
    count_neg_x: u32,
    count_pos_y: u32,
    count_neg_y: u32,
    count_pos_z: u32,
    count_neg_z: u32,
}

struct LayerRange {
    offset: u32,
    count: u32,
}

struct MeshedChunkInfo {
    chunk_x: i32,
    chunk_y: i32,
    chunk_z: i32,
    lod: u32,
    centre_x: f32,
    centre_y: f32,
    centre_z: f32,
    extent_x: f32,
    extent_y: f32,
    extent_z: f32,
    opaque_quads: FaceLayerRange,
    transparent_quads: FaceLayerRange,
    smooth_vertices: LayerRange,
    clutter_units: LayerRange,
}

// Elements facing `face` (0 for an invalid face).
fn face_layer_range_count(r: FaceLayerRange, face: u32) -> u32 {
    switch face {
        case 0u: { return r.count_pos_x; }
        case 1u: { return r.count_neg_x; }
        case 2u: { return r.count_pos_y; }
        case 3u: { return r.count_neg_y; }
        case 4u: { return r.count_pos_z; }
        case 5u: { return r.count_neg_z; }
        default: { return 0u; }
    }
}

// The first element facing `face`: offset + the counts of every lower direction.
fn face_layer_range_start(r: FaceLayerRange, face: u32) -> u32 {
    var start = r.offset;
    for (var i = 0u; i < min(face, 6u); i += 1u) {
        start += face_layer_range_count(r, i);
    }
    return start;
}

// Elements of every direction.
fn face_layer_range_total(r: FaceLayerRange) -> u32 {
    return r.count_pos_x + r.count_neg_x + r.count_pos_y + r.count_neg_y + r.count_pos_z
        + r.count_neg_z;
}

fn meshed_chunk_info_chunk(m: MeshedChunkInfo) -> vec3<i32> {
    return vec3<i32>(m.chunk_x, m.chunk_y, m.chunk_z);
}

// Bounding box centre, chunk-local units.
fn meshed_chunk_info_centre(m: MeshedChunkInfo) -> vec3<f32> {
    return vec3<f32>(m.centre_x, m.centre_y, m.centre_z);
}

// Bounding box half size, chunk-local units.
fn meshed_chunk_info_extent(m: MeshedChunkInfo) -> vec3<f32> {
    return vec3<f32>(m.extent_x, m.extent_y, m.extent_z);
}

// ---------------------------------------------------------------------------------------------
// ChunkDrawIndirect (chunk_draw_indirect.rs)

struct ChunkDrawIndirect {
    index_count: u32,
    instance_count: u32,
    first_index: u32,
    base_vertex: i32,
    first_instance: u32,
    chunk_x: i32,
    chunk_y: i32,
    chunk_z: i32,
}

fn chunk_draw_indirect_chunk(d: ChunkDrawIndirect) -> vec3<i32> {
    return vec3<i32>(d.chunk_x, d.chunk_y, d.chunk_z);
}

// ---------------------------------------------------------------------------------------------
// Smooth-mesh quads (smooth_quads.rs, compact_quad.rs)
//
// A chunk's smooth quads are an array<u32> of words (the CPU bytes, zero-padded to a multiple
// of 4) in one of three forms, tagged SMOOTH_QUADS_*: compact 6-byte records, 4 x u16 or
// 4 x u32 vertex indices per quad. Corner `corner` of quad `q`: read the word at index
// `smooth_quad_word(form, q, corner)` (relative to the chunk's first word) and the word after
// it, and pass both to `smooth_quad_corner`. The second word is read only for compact records;
// clamp its index to the buffer when the chunk may end the buffer.

const SMOOTH_QUADS_COMPACT: u32 = 0u;
const SMOOTH_QUADS_U16: u32 = 1u;
const SMOOTH_QUADS_U32: u32 = 2u;
// compact_quad::COMPACT_QUAD_SELECTORS: 2 bits per (form, position), selector 0 = a,
// 1 = a - da, 2 = b, 3 = b - db.
const COMPACT_QUAD_SELECTORS: u32 = 0x6ce4b478u;

// Corner `corner` of the compact record (a, b, info): compact_quad_decode, without its checks.
fn compact_quad_corner(a: u32, b: u32, info: u32, corner: u32) -> u32 {
    let form = (info >> 12u) & 3u;
    let p = (corner + (info >> 14u)) & 3u;
    let s = (COMPACT_QUAD_SELECTORS >> (2u * (4u * form + p))) & 3u;
    let second = s >= 2u;
    let base = select(a, b, second);
    let delta = select(info & 63u, (info >> 6u) & 63u, second);
    return base - select(0u, delta, (s & 1u) == 1u);
}

// The index of the first word quad `q`'s corner `corner` is read from.
fn smooth_quad_word(form: u32, q: u32, corner: u32) -> u32 {
    if form == SMOOTH_QUADS_COMPACT {
        return (3u * q) >> 1u;
    }
    if form == SMOOTH_QUADS_U16 {
        return 2u * q + (corner >> 1u);
    }
    return 4u * q + corner;
}

// Corner `corner` of quad `q` from the word at smooth_quad_word(form, q, corner) and the next.
fn smooth_quad_corner(form: u32, q: u32, corner: u32, word: u32, next: u32) -> u32 {
    if form == SMOOTH_QUADS_COMPACT {
        // The record's u16s start in the low half of `word` for even q, in the high half
        // for odd q: `ab` holds a and b, `info` is the next u16.
        let odd = (q & 1u) == 1u;
        let ab = select(word, (word >> 16u) | (next << 16u), odd);
        let info = select(next & 0xffffu, next >> 16u, odd);
        return compact_quad_corner(ab & 0xffffu, ab >> 16u, info, corner);
    }
    if form == SMOOTH_QUADS_U16 {
        return (word >> (16u * (corner & 1u))) & 0xffffu;
    }
    return word;
}
