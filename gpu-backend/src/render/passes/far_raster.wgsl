// Far draws by rasterisation (render::far::raster): each far-list entry is one indirect draw
// (first_instance = its index in the far list, vertex_count = 6 or 18 per block), so
// instance_index names the entry and vertex_index / (6 or 18) the block. Two forms:
//
// - sprite (Majercik et al. 2018): one screen-space quad bounding the block's projection, at
//   the depth of its nearest corner; the fragment shader intersects its pixel's ray with the
//   cube, discards misses and writes the hit's depth (never nearer than the quad's, so the
//   early depth test stays valid where the device allows conservative depth);
// - cube: the block's faces that look at the eye (at most 3), drawn as the exact quads the
//   meshers would emit, with their ambient occlusion per corner and the meshers' diagonal.
//
// Both show what the splat shows: a face is drawn only where the meshers would emit one
// (towards a voxel that does not hide it; a transparent block's face towards a voxel that
// neither hides nor is transparent), shaded with the same palette and ambient occlusion.
// Blocks of the other layer (opaque in the transparent pipelines and the reverse) are thrown
// away in the vertex shader as degenerate triangles. render_common.wgsl, node.wgsl,
// far_blocks.wgsl, far_ao.wgsl and gbuffer.wgsl (whose fragment shaders the cube form reuses)
// come before this body.

@group(1) @binding(5) var<storage, read> far_table: array<MeshedChunkInfo>;
@group(1) @binding(6) var<storage, read> far_nodes: array<NodeRecord>;
@group(1) @binding(7) var<storage, read> far_list: array<vec2<u32>>;
// The draw-block gigabuffer (its one page): DrawBlocks, skirt blocks and hiding masks.
@group(1) @binding(8) var<storage, read> far_blocks: array<u32>;

// The hiding mask being read: set from the node before any `hides` (each invocation's own).
var<private> mask_offset: u32;
var<private> mask_words: u32;
var<private> mask_flags: u32;

// Bit `plane_words` + (the node's padded voxel p) of the node's masks.
fn node_mask_bit(p: vec3<i32>, edge: i32, plane_words: u32) -> bool {
    let q = edge + 2;
    if any(p < vec3<i32>(0)) || any(p >= vec3<i32>(q)) {
        return false;
    }
    let i = u32(p.x + q * (p.y + q * p.z));
    let word = min(i >> 5u, max(mask_words, 1u) - 1u);
    return ((far_blocks[mask_offset + plane_words + word] >> (i & 31u)) & 1u) != 0u;
}

fn hides(p: vec3<i32>, edge: i32) -> bool {
    return node_mask_bit(p, edge, 0u);
}

fn is_transparent(p: vec3<i32>, edge: i32) -> bool {
    if (mask_flags & NODE_TRANSPARENT_MASK) == 0u {
        return false;
    }
    return node_mask_bit(p, edge, mask_words);
}

// Whether face `face` of the block at padded cell `padded` is drawn: where the meshers would
// emit one (towards a voxel that does not hide it; a transparent block's, towards one that
// neither hides nor is transparent), and an opaque block's every face towards the node's
// border: the neighbour across it may be drawn at another level, whose cells need not cover
// the face (the splat and the sprite draw the whole cube, so they never hide it either).
fn face_shown(padded: vec3<i32>, face: u32, see_through: bool, edge: i32) -> bool {
    let beyond = padded + face_normal(face);
    if see_through {
        return !hides(beyond, edge) && !is_transparent(beyond, edge);
    }
    let across_border = any(beyond < vec3<i32>(1)) || any(beyond > vec3<i32>(edge));
    return across_border || !hides(beyond, edge);
}

// One block of a far-list entry, as the vertex shaders find it.
struct FarBlock {
    // DrawBlock bits.
    bits: u32,
    // Camera-relative corner with the least coordinates, and the edge, blocks.
    lo: vec3<f32>,
    scale: f32,
    // The entry's table slot.
    slot: u32,
    // The block exists and belongs to the layer drawn.
    drawn: bool,
}

// Block `b` of far-list entry `entry`; `transparent` selects the layer drawn.
fn far_block(entry: u32, b: u32, transparent: bool) -> FarBlock {
    let e = far_list[entry];
    let info = far_table[e.x];
    let node = far_nodes[e.x];
    var out: FarBlock;
    out.slot = e.x;
    if b >= far_block_total(node, e.y) {
        out.drawn = false;
        return out;
    }
    out.bits = far_blocks[block_index(node, e.y, b)];
    let level = min(info.lod, 15u);
    out.scale = f32(1u << level);
    let rel = (meshed_chunk_info_chunk(info) << vec3<u32>(level)) - frame.camera_chunk;
    let origin = vec3<f32>(rel) * frame.chunk_edge - frame.camera_offset;
    let cell = vec3<f32>(f32((out.bits >> 4u) & 15u), f32((out.bits >> 8u) & 15u), f32((out.bits >> 12u) & 15u));
    out.lo = origin + cell * out.scale;
    out.drawn = ((out.bits & DRAW_BLOCK_TRANSPARENT) != 0u) == transparent;
    return out;
}

fn block_padded_cell(bits: u32) -> vec3<i32> {
    return vec3<i32>(i32((bits >> 4u) & 15u), i32((bits >> 8u) & 15u), i32((bits >> 12u) & 15u)) + vec3<i32>(1);
}

fn use_node_mask(slot: u32) {
    let node = far_nodes[slot];
    mask_offset = node.mask_offset;
    mask_words = node.mask_words;
    mask_flags = node.flags;
}

// Off screen and of zero area: a vertex of a block that is not drawn.
const NOT_DRAWN: vec4<f32> = vec4<f32>(-2.0, -2.0, 0.0, 1.0);

// ---- sprite ----

struct SpriteVaryings {
    @builtin(position) position: vec4<f32>,
    @location(0) @interpolate(flat) bits: u32,
    @location(1) @interpolate(flat) slot: u32,
    @location(2) @interpolate(flat) lo: vec3<f32>,
    @location(3) @interpolate(flat) scale: f32,
}

fn sprite_vertex(vertex: u32, entry: u32, transparent: bool) -> SpriteVaryings {
    let block = far_block(entry, vertex / 6u, transparent);
    var out: SpriteVaryings;
    out.position = NOT_DRAWN;
    if !block.drawn {
        return out;
    }
    var min_p = vec2<f32>(1e30);
    var max_p = vec2<f32>(-1e30);
    var nearest = 0.0;
    for (var c = 0u; c < 8u; c += 1u) {
        let corner = block.lo + vec3<f32>(f32(c & 1u), f32((c >> 1u) & 1u), f32((c >> 2u) & 1u)) * block.scale;
        let clip = frame.view_proj * vec4<f32>(corner, 1.0);
        if clip.w <= frame.near {
            // Reaches the near plane: far draws never should (the splat counts these).
            return out;
        }
        let ndc = clip.xyz / clip.w;
        min_p = min(min_p, ndc.xy);
        max_p = max(max_p, ndc.xy);
        nearest = max(nearest, ndc.z);
    }
    // Corner slots (0, 1, 2), (0, 2, 3) of the bounding rectangle.
    let slot = array<u32, 6>(0u, 1u, 2u, 0u, 2u, 3u)[vertex % 6u];
    let x = select(min_p.x, max_p.x, slot == 1u || slot == 2u);
    let y = select(min_p.y, max_p.y, slot >= 2u);
    // Reversed-Z: the nearest corner has the largest depth, so the quad's depth is an upper
    // bound of every hit's (what `@early_depth_test(less_equal)` promises).
    out.position = vec4<f32>(x, y, min(nearest, 1.0), 1.0);
    out.bits = block.bits;
    out.slot = block.slot;
    out.lo = block.lo;
    out.scale = block.scale;
    return out;
}

@vertex
fn vs_sprite(@builtin(vertex_index) vertex: u32, @builtin(instance_index) entry: u32) -> SpriteVaryings {
    return sprite_vertex(vertex, entry, false);
}

@vertex
fn vs_sprite_transparent(@builtin(vertex_index) vertex: u32, @builtin(instance_index) entry: u32) -> SpriteVaryings {
    return sprite_vertex(vertex, entry, true);
}

// A sprite pixel's hit: whether there is one, its depth, face and ambient occlusion.
struct SpriteHit {
    hit: bool,
    depth: f32,
    face: u32,
    ao: f32,
}

// The ray through this pixel's centre against the cube, as the splat does it.
fn sprite_hit(in: SpriteVaryings) -> SpriteHit {
    var out: SpriteHit;
    out.hit = false;
    let pixel = vec2<u32>(floor(in.position.xy));
    let d = pixel_ray(pixel);
    let hi = in.lo + vec3<f32>(in.scale);
    let safe = select(d, vec3<f32>(1e-30), abs(d) < vec3<f32>(1e-30));
    let t0 = in.lo / safe;
    let t1 = hi / safe;
    let near_t = min(t0, t1);
    let far_t = max(t0, t1);
    let t_in = max(near_t.x, max(near_t.y, near_t.z));
    let t_out = min(far_t.x, min(far_t.y, far_t.z));
    if t_in > t_out || t_in <= frame.near {
        return out;
    }
    var axis = 0u;
    if near_t.y >= near_t.x && near_t.y >= near_t.z {
        axis = 1u;
    } else if near_t.z >= near_t.x && near_t.z >= near_t.y {
        axis = 2u;
    }
    let face = axis * 2u + u32(d[axis] > 0.0);
    let edge = i32(frame.chunk_edge);
    let padded = block_padded_cell(in.bits);
    use_node_mask(in.slot);
    let see_through = (in.bits & DRAW_BLOCK_TRANSPARENT) != 0u;
    if see_through && !face_shown(padded, face, true, edge) {
        return out;
    }
    let local = clamp((d * t_in - in.lo) / in.scale, vec3<f32>(0.0), vec3<f32>(1.0));
    let uv = vec2<f32>(local[face_width_axis(face)], local[face_height_axis(face)]);
    out.hit = true;
    out.depth = frame.near / t_in;
    out.face = face;
    out.ao = face_ao(padded, face, uv, edge);
    return out;
}

struct SpriteGBufferOut {
    @location(0) albedo_ao: vec4<f32>,
    @location(1) normal_material: vec2<u32>,
    @builtin(frag_depth) depth: f32,
}

fn sprite_gbuffer(in: SpriteVaryings) -> SpriteGBufferOut {
    let hit = sprite_hit(in);
    if !hit.hit {
        discard;
    }
    let g = gbuffer_texels(in.bits >> 16u, hit.ao, vec3<f32>(face_normal(hit.face)));
    var out: SpriteGBufferOut;
    out.albedo_ao = g.albedo_ao;
    out.normal_material = g.normal_material;
    // Never nearer than the rasterised quad (rounding aside): clamp keeps the promise exact.
    out.depth = min(hit.depth, in.position.z);
    return out;
}

// Without conservative depth (the device lacks SHADER_EARLY_DEPTH_TEST): the depth test runs
// after this shader.
@fragment
fn fs_sprite(in: SpriteVaryings) -> SpriteGBufferOut {
    return sprite_gbuffer(in);
}

struct SpriteTransparentOut {
    @location(0) colour: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn fs_sprite_transparent(in: SpriteVaryings) -> SpriteTransparentOut {
    let hit = sprite_hit(in);
    if !hit.hit {
        discard;
    }
    var out: SpriteTransparentOut;
    out.depth = min(hit.depth, in.position.z);
    let at = vec4<f32>(in.position.xy, out.depth, 1.0);
    out.colour = transparent_colour(in.bits >> 16u, hit.ao, vec3<f32>(face_normal(hit.face)), at, inside_to_opaque_depth(at));
    return out;
}

// ---- cube ----

// Vertex `vertex` of block vertex / 18: face slot (vertex % 18) / 6 is the face of axis slot
// that looks at the eye (none when the eye is between the block's two planes of that axis),
// corner slots (0, 1, 2), (0, 2, 3) after the AO diagonal flip, as the meshers index a quad.
fn cube_vertex(vertex: u32, entry: u32, transparent: bool) -> SurfaceVaryings {
    let block = far_block(entry, vertex / 18u, transparent);
    var out: SurfaceVaryings;
    out.position = NOT_DRAWN;
    if !block.drawn {
        return out;
    }
    let axis = (vertex % 18u) / 6u;
    let lo = block.lo[axis];
    let hi = lo + block.scale;
    // The eye is at the origin: the face towards it is the negative one when the block lies
    // on the positive side.
    if lo < 0.0 && hi > 0.0 {
        return out;
    }
    let face = axis * 2u + u32(lo >= 0.0);
    let edge = i32(frame.chunk_edge);
    let padded = block_padded_cell(block.bits);
    use_node_mask(block.slot);
    let see_through = (block.bits & DRAW_BLOCK_TRANSPARENT) != 0u;
    if !face_shown(padded, face, see_through, edge) {
        return out;
    }
    let ao = face_corner_aos(padded, face, edge);
    let slot = array<u32, 6>(0u, 1u, 2u, 0u, 2u, 3u)[vertex % 6u];
    let corner = (slot + ao_flip(ao)) & 3u;
    let uv = corner_uv(face, corner);
    var local = vec3<f32>(axis_unit(face_normal_axis(face))) * f32(face_is_positive(face));
    local += vec3<f32>(axis_unit(face_width_axis(face))) * uv.x;
    local += vec3<f32>(axis_unit(face_height_axis(face))) * uv.y;
    out.position = frame.view_proj * vec4<f32>(block.lo + local * block.scale, 1.0);
    out.block = block.bits >> 16u;
    out.ao = ao[corner];
    out.normal = vec3<f32>(face_normal(face));
    return out;
}

@vertex
fn vs_cube(@builtin(vertex_index) vertex: u32, @builtin(instance_index) entry: u32) -> SurfaceVaryings {
    return cube_vertex(vertex, entry, false);
}

@vertex
fn vs_cube_transparent(@builtin(vertex_index) vertex: u32, @builtin(instance_index) entry: u32) -> SurfaceVaryings {
    return cube_vertex(vertex, entry, true);
}
