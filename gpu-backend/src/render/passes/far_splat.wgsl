// Far draws by compute splatting: each far-listed node's surface blocks (DrawBlocks, with the
// skirt blocks of the sides its entry names) are rasterised as exact cubes into 64-bit
// visibility buffers, one workgroup per node. Per block: project the cube's corners, then for
// every pixel centre inside their bounds intersect the pixel's ray with the cube (slab test);
// a hit takes the face it entered, the ambient occlusion the blocky meshers would give that
// point (read from the node's hiding mask: the same corner rule and the same triangle split of
// the face, interpolated barycentrically), and writes atomicMax(depth << 32 | payload):
// reversed-Z, so the nearest surface wins, and equal depths keep the larger payload (the
// result does not depend on the order). Transparent blocks go to their own buffer; the lighting
// pass blends the nearest one over the opaque surface. render::far states the format and the
// bounds. render_common.wgsl, node.wgsl, far_blocks.wgsl, far_ao.wgsl and FORMATS_WGSL come before
// this body.

// Twin of render::far::SPLAT_WORKGROUP.
const SPLAT_WORKGROUP: u32 = 64u;
// The hiding mask of a 16^3 node: 18^3 bits in 183 words; the transparent mask, when the node
// has one, is loaded at TRANSPARENT_PLANE.
const MASK_WORDS: u32 = 192u;
const TRANSPARENT_PLANE: u32 = 192u;
// Pixels one block may cover before it is skipped and counted (a far block that large means
// the far threshold is wrong for this view): 32 x 32.
const MAX_BLOCK_PIXELS: u32 = 1024u;
// The statistics word counting the far list (cull::CullStats::FAR_LIST_WORD) and the words
// this pass adds (render::far::SplatStats).
const STAT_FAR_LIST: u32 = 9u;
const STAT_SPLAT_PIXELS: u32 = 11u;
const STAT_SPLAT_SKIPPED: u32 = 12u;

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
// Declared for render_common.wgsl's material helpers; the splat does not read it.
@group(0) @binding(1) var<storage, read> materials: array<GpuMaterial>;

@group(1) @binding(0) var<storage, read> table: array<MeshedChunkInfo>;
@group(1) @binding(1) var<storage, read> nodes: array<NodeRecord>;
@group(1) @binding(2) var<storage, read> far_list: array<vec2<u32>>;
// The draw-block gigabuffer (its one page): DrawBlocks, skirt blocks and hiding masks.
@group(1) @binding(3) var<storage, read> blocks: array<u32>;
@group(1) @binding(4) var<storage, read_write> visibility: array<atomic<u64>>;
@group(1) @binding(5) var<storage, read_write> transparent: array<atomic<u64>>;
// [x, y, z workgroups, first entry, end entry]: written by far_args, read by splat.
@group(1) @binding(6) var<storage, read> range: array<u32>;
@group(1) @binding(7) var<storage, read_write> stats: array<atomic<u32>>;

var<workgroup> wg_mask: array<u32, 384>;
var<workgroup> wg_pixels: atomic<u32>;
var<workgroup> wg_skipped: atomic<u32>;

// Bit `plane` + (the node's padded voxel p, each axis 0..edge + 2) of the loaded masks.
fn mask_bit(p: vec3<i32>, edge: i32, plane: u32) -> bool {
    let q = edge + 2;
    if any(p < vec3<i32>(0)) || any(p >= vec3<i32>(q)) {
        return false;
    }
    let i = u32(p.x + q * (p.y + q * p.z));
    return ((wg_mask[plane + min(i >> 5u, MASK_WORDS - 1u)] >> (i & 31u)) & 1u) != 0u;
}

// The node's padded voxel p hides its neighbours.
fn hides(p: vec3<i32>, edge: i32) -> bool {
    return mask_bit(p, edge, 0u);
}

// The node's padded voxel p is transparent (false when the node has no transparent mask).
fn is_transparent(p: vec3<i32>, edge: i32) -> bool {
    return mask_bit(p, edge, TRANSPARENT_PLANE);
}

// Splats one block (DrawBlock bits) of a node whose cell (0, 0, 0) starts at camera-relative
// `origin` and whose cells are `scale` blocks wide.
fn splat_block(bits: u32, origin: vec3<f32>, scale: f32, edge: i32) {
    let cell = vec3<u32>((bits >> 4u) & 15u, (bits >> 8u) & 15u, (bits >> 12u) & 15u);
    let lo = origin + vec3<f32>(cell) * scale;
    let hi = lo + vec3<f32>(scale);
    let size = vec2<f32>(f32(frame.width), f32(frame.height));
    var min_p = vec2<f32>(1e30);
    var max_p = vec2<f32>(-1e30);
    // Clip space is linear in the corner: one matrix product for `lo`, then the edge vectors.
    let clip_lo = frame.view_proj * vec4<f32>(lo, 1.0);
    let ex = frame.view_proj[0] * scale;
    let ey = frame.view_proj[1] * scale;
    let ez = frame.view_proj[2] * scale;
    for (var c = 0u; c < 8u; c += 1u) {
        let clip = clip_lo + select(vec4<f32>(0.0), ex, (c & 1u) != 0u)
            + select(vec4<f32>(0.0), ey, (c & 2u) != 0u)
            + select(vec4<f32>(0.0), ez, (c & 4u) != 0u);
        if clip.w <= frame.near {
            // Reaches the near plane: far draws never should; skip and count it.
            atomicAdd(&wg_skipped, 1u);
            return;
        }
        let ndc = clip.xy / clip.w;
        let p = vec2<f32>((ndc.x * 0.5 + 0.5) * size.x, (0.5 - ndc.y * 0.5) * size.y);
        min_p = min(min_p, p);
        max_p = max(max_p, p);
    }
    // Pixel centres (x + 0.5) inside the projected bounds, on screen.
    let x0 = max(i32(ceil(min_p.x - 0.5)), 0);
    let y0 = max(i32(ceil(min_p.y - 0.5)), 0);
    let x1 = min(i32(floor(max_p.x - 0.5)), i32(frame.width) - 1);
    let y1 = min(i32(floor(max_p.y - 0.5)), i32(frame.height) - 1);
    if x0 > x1 || y0 > y1 {
        return;
    }
    if u32(x1 - x0 + 1) * u32(y1 - y0 + 1) > MAX_BLOCK_PIXELS {
        atomicAdd(&wg_skipped, 1u);
        return;
    }
    atomicAdd(&wg_pixels, u32(x1 - x0 + 1) * u32(y1 - y0 + 1));
    let id = bits >> 16u;
    let see_through = (bits & DRAW_BLOCK_TRANSPARENT) != 0u;
    let padded = vec3<i32>(cell) + vec3<i32>(1);
    for (var y = y0; y <= y1; y += 1) {
        for (var x = x0; x <= x1; x += 1) {
            let d = pixel_ray(vec2<u32>(u32(x), u32(y)));
            // Slab test from the eye (the origin); zero components become tiny ones.
            let safe = select(d, vec3<f32>(1e-30), abs(d) < vec3<f32>(1e-30));
            let t0 = lo / safe;
            let t1 = hi / safe;
            let near_t = min(t0, t1);
            let far_t = max(t0, t1);
            let t_in = max(near_t.x, max(near_t.y, near_t.z));
            let t_out = min(far_t.x, min(far_t.y, far_t.z));
            if t_in > t_out || t_in <= frame.near {
                continue;
            }
            // The face entered: the axis whose slab was entered last, against the ray.
            var axis = 0u;
            if near_t.y >= near_t.x && near_t.y >= near_t.z {
                axis = 1u;
            } else if near_t.z >= near_t.x && near_t.z >= near_t.y {
                axis = 2u;
            }
            let face = axis * 2u + u32(d[axis] > 0.0);
            // A transparent block shows a face only where the meshers would: towards a voxel
            // that neither hides nor is transparent. Entering through any other face, the ray
            // is inside the transparent volume already: no surface here.
            let beyond = padded + face_normal(face);
            if see_through && (hides(beyond, edge) || is_transparent(beyond, edge)) {
                continue;
            }
            // A nearer surface already written wins whatever this payload is: skip its AO
            // and its atomic (the write would change nothing; equal depths still compete).
            let depth = frame.near / t_in;
            let at = u32(y) * frame.width + u32(x);
            var written = 0lu;
            if see_through {
                written = atomicLoad(&transparent[at]);
            } else {
                written = atomicLoad(&visibility[at]);
            }
            if u32(written >> 32u) > bitcast<u32>(depth) {
                continue;
            }
            let local = clamp((d * t_in - lo) / scale, vec3<f32>(0.0), vec3<f32>(1.0));
            let uv = vec2<f32>(local[face_width_axis(face)], local[face_height_axis(face)]);
            let ao = face_ao(padded, face, uv, edge);
            let ao8 = u32(round(clamp(ao / 3.0, 0.0, 1.0) * 255.0));
            let payload = id | (face << 16u) | (ao8 << 19u);
            let value = (u64(bitcast<u32>(depth)) << 32u) | u64(payload);
            if see_through {
                atomicMax(&transparent[at], value);
            } else {
                atomicMax(&visibility[at], value);
            }
        }
    }
}

// One workgroup per far-list entry in range[3] .. range[4].
@compute @workgroup_size(64)
fn splat(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let entry_index = range[3] + wid.y * groups.x + wid.x;
    let valid = entry_index < range[4];
    var entry = vec2<u32>(0u);
    if valid {
        entry = far_list[entry_index];
    }
    let info = table[entry.x];
    let node = nodes[entry.x];
    let words = select(0u, min(node.mask_words, MASK_WORDS), valid);
    let with_transparent = (node.flags & NODE_TRANSPARENT_MASK) != 0u;
    for (var i = lid; i < words; i += SPLAT_WORKGROUP) {
        wg_mask[i] = blocks[node.mask_offset + i];
        var t = 0u;
        if with_transparent {
            t = blocks[node.mask_offset + node.mask_words + i];
        }
        // Cleared every time: a workgroup's memory starts zeroed only once per dispatch slot.
        wg_mask[TRANSPARENT_PLANE + i] = t;
    }
    workgroupBarrier();
    let level = min(info.lod, 15u);
    let scale = f32(1u << level);
    let rel = (meshed_chunk_info_chunk(info) << vec3<u32>(level)) - frame.camera_chunk;
    let origin = vec3<f32>(rel) * frame.chunk_edge - frame.camera_offset;
    let edge = i32(frame.chunk_edge);
    let total = select(0u, far_block_total(node, entry.y), valid);
    for (var b = lid; b < total; b += SPLAT_WORKGROUP) {
        splat_block(blocks[block_index(node, entry.y, b)], origin, scale, edge);
    }
    workgroupBarrier();
    if lid == 0u {
        atomicAdd(&stats[STAT_SPLAT_PIXELS], atomicLoad(&wg_pixels));
        atomicAdd(&stats[STAT_SPLAT_SKIPPED], atomicLoad(&wg_skipped));
    }
}
