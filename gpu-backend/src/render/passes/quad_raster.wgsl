// Compute rasterisation of opaque greedy quads into the 64-bit visibility buffer that the far
// splat fills too (render::quad_raster states the contract, the cost and the bounds; its
// `reference` module is the CPU twin of every decision here, in the same f32 operations and
// order). render_common.wgsl and FORMATS_WGSL come before this body.
//
// qr_quads: one workgroup per drawn command of the bound quad page, 64 quads at a time. Each
// invocation sets its quad up (qr_setup: camera-relative plane and edges, the pixel box of its
// projection); quads whose box holds at most QR_LOCAL_MAX_PIXELS pixel centres are drawn by the
// whole workgroup, pixel by pixel over the concatenated boxes (a prefix sum and a binary
// search balance them); larger ones are appended to the big-quad list with one entry per
// QR_TILE x QR_TILE screen tile of their box, drawn by qr_tiles (one workgroup per tile). When
// the tile list is full, the workgroup draws the quads that did not fit itself (counted in
// QR_STAT_OVERFLOW): nothing is dropped.
//
// Per pixel (qr_sample): the ray through the pixel centre (render_common's pixel_ray, unit
// forward component, so its parameter t is the view depth) meets the quad's plane at
// t = plane / dir[normal axis]; it hits when the ray runs against the outward normal,
// near < t < QR_MAX_T, and the hit point lies in the quad's rectangle grown by
// eps = t * eps_scale + QR_EPS_MIN on every side (the G-buffer's T-junction hair: 1/64 pixel at
// the quad's distance, at least 1/4096 block). A hit writes
// atomicMax(visibility[y * width + x], bits(near / t) << 32 | payload), the far splat's payload:
// block id (0..16), face (16..19), AO in 255ths of 3 (19..27), the AO interpolated as the
// raster path does (corner values, the meshers' triangle split, barycentric in the plane).

// Twins of render::quad_raster's constants (a unit test compares them).
const QR_WORKGROUP: u32 = 64u;
const QR_TILE: u32 = 16u;
const QR_LOCAL_MAX_PIXELS: u32 = 256u;
const QR_EPS_PX: f32 = 0.015625;
const QR_EPS_MIN: f32 = 0.000244140625;
const QR_MAX_T: f32 = 1e30;
// The fraction of the near plane the setup clips at (a hair nearer than near, so the box is
// conservative where the ray parameter and the clip w differ by rounding).
const QR_NEAR_CLIP: f32 = 0.999;
// Pixels the box of a projection is padded by, for the rounding of the projection.
const QR_BOX_PAD: f32 = 0.125;
// Words of the state buffer (render::quad_raster::StateWord).
const QR_TILE_COUNT: u32 = 0u;
const QR_BIG_COUNT: u32 = 1u;
const QR_STAT_QUADS: u32 = 8u;
const QR_STAT_VISIBLE: u32 = 9u;
const QR_STAT_LOCAL_PIXELS: u32 = 10u;
const QR_STAT_BIG: u32 = 11u;
const QR_STAT_OVERFLOW: u32 = 12u;
const QR_STAT_TILE_PIXELS: u32 = 13u;
const QR_STAT_HITS: u32 = 14u;

// A quad set up for rasterisation (twin of render::quad_raster::RasterQuad, 32 bytes):
// camera-relative plane coordinate on the normal axis, the rectangle's bounds on the width and
// height axes (corner 0 and corner 2), the PackedQuad's face/AO/block word, and the inclusive
// box of pixel centres to test (x | y << 16; empty when lo > hi).
struct RasterQuad {
    plane: f32,
    lo_w: f32,
    lo_h: f32,
    hi_w: f32,
    hi_h: f32,
    face_ao_block: u32,
    box_lo: u32,
    box_hi: u32,
}

// Twin of cull::DrawRecord.
struct DrawRecord {
    chunk_x: i32,
    chunk_y: i32,
    chunk_z: i32,
    level: u32,
}

// One quad page's dispatch, written by qr_page_args (twin of render::quad_raster::PageArgs).
struct PageArgs {
    groups_x: u32,
    groups_y: u32,
    groups_z: u32,
    first_command: u32,
    commands: u32,
    page: u32,
    pad0: u32,
    pad1: u32,
}

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
// Declared for render_common.wgsl's material helpers; never read here.
@group(0) @binding(1) var<storage, read> materials: array<GpuMaterial>;
@group(0) @binding(2) var<storage, read_write> visibility: array<atomic<u64>>;

@group(1) @binding(0) var<storage, read_write> state: array<atomic<u32>>;
@group(1) @binding(1) var<storage, read_write> bigs: array<RasterQuad>;
// (big-quad index, tile x | tile y << 16)
@group(1) @binding(2) var<storage, read_write> tiles: array<vec2<u32>>;

@group(2) @binding(0) var<storage, read> quads: array<PackedQuad>;
// The cull's DrawIndexedArgs, 5 words each.
@group(2) @binding(1) var<storage, read> commands: array<u32>;
@group(2) @binding(2) var<storage, read> records: array<DrawRecord>;
@group(2) @binding(3) var<storage, read> page_args: PageArgs;

var<workgroup> wg_quads: array<RasterQuad, 64>;
// Inclusive prefix sums over the batch: (local pixels, tiles, big quads).
var<workgroup> wg_scan: array<vec3<u32>, 64>;
// 1 where a big quad found no room in the tile list: drawn by this workgroup.
var<workgroup> wg_over: array<u32, 64>;
// (first tile entry, tile entries taken, first big-quad entry) of the batch.
var<workgroup> wg_fit: vec3<u32>;
var<workgroup> wg_local_pixels: atomic<u32>;
var<workgroup> wg_tile_pixels: atomic<u32>;
var<workgroup> wg_hits: atomic<u32>;
var<workgroup> wg_visible: atomic<u32>;
var<workgroup> wg_big: atomic<u32>;
var<workgroup> wg_overflow: atomic<u32>;

fn qr_empty() -> RasterQuad {
    return RasterQuad(0.0, 0.0, 0.0, 0.0, 0.0, 0u, 0xffffffffu, 0u);
}

// Pixel centres in the quad's box.
fn qr_box_area(q: RasterQuad) -> u32 {
    let lo = vec2<u32>(q.box_lo & 0xffffu, q.box_lo >> 16u);
    let hi = vec2<u32>(q.box_hi & 0xffffu, q.box_hi >> 16u);
    if any(hi < lo) {
        return 0u;
    }
    return (hi.x - lo.x + 1u) * (hi.y - lo.y + 1u);
}

// Screen tiles the quad's box touches: (first tile, tiles per row, rows).
fn qr_box_tiles(q: RasterQuad) -> vec4<u32> {
    let lo = vec2<u32>(q.box_lo & 0xffffu, q.box_lo >> 16u) / QR_TILE;
    let hi = vec2<u32>(q.box_hi & 0xffffu, q.box_hi >> 16u) / QR_TILE;
    return vec4<u32>(lo, hi - lo + vec2<u32>(1u));
}

// The pixel scale of the T-junction hair: blocks per unit of distance.
fn qr_eps_scale() -> f32 {
    return QR_EPS_PX * (2.0 * length(frame.up) / f32(frame.height));
}

// Camera-relative point with `n` on the normal axis `a` and (w, h) on its width and height
// axes.
fn qr_point(a: u32, wa: u32, ha: u32, n: f32, w: f32, h: f32) -> vec3<f32> {
    var p = vec3<f32>(0.0);
    p[a] = n;
    p[wa] = w;
    p[ha] = h;
    return p;
}

// Screen position (pixels, y down) of clip-space point c (c.w > 0).
fn qr_screen(c: vec4<f32>) -> vec2<f32> {
    let ndc = c.xy / c.w;
    return vec2<f32>((ndc.x * 0.5 + 0.5) * f32(frame.width), (0.5 - ndc.y * 0.5) * f32(frame.height));
}

// Quad `q` of a node whose cell (0, 0, 0) is at camera-relative `origin`, cells `scale` blocks
// wide, set up: its plane and edges, and the pixel box of its rectangle grown by the largest
// hair it can use, clipped at the near plane. Back-facing quads, quads with an invalid face
// and quads wholly before the near plane get an empty box.
fn qr_setup(q: PackedQuad, origin: vec3<f32>, scale: f32, eps_scale: f32) -> RasterQuad {
    var r = qr_empty();
    let face = packed_quad_face(q);
    if face > FACE_NEG_Z {
        return r;
    }
    let a = face_normal_axis(face);
    let wa = face_width_axis(face);
    let ha = face_height_axis(face);
    // As gbuffer.wgsl's quad_vertex places corners: origin + cell * scale.
    let c0 = origin + vec3<f32>(packed_quad_corner(q, 0u)) * scale;
    let c2 = origin + vec3<f32>(packed_quad_corner(q, 2u)) * scale;
    r.plane = c0[a];
    r.lo_w = c0[wa];
    r.lo_h = c0[ha];
    r.hi_w = c2[wa];
    r.hi_h = c2[ha];
    r.face_ao_block = q.face_ao_block;
    // Front-facing only: the eye (the origin) strictly in front of the plane.
    let facing = select(r.plane > 0.0, r.plane < 0.0, face_is_positive(face));
    if !facing {
        return r;
    }
    // The deepest corner bounds the hair; the grown rectangle bounds every hit.
    var corners: array<vec4<f32>, 4>;
    var t_max = 0.0;
    for (var k = 0u; k < 4u; k += 1u) {
        let w = select(r.lo_w, r.hi_w, k == 1u || k == 2u);
        let h = select(r.lo_h, r.hi_h, k >= 2u);
        t_max = max(t_max, (frame.view_proj * vec4<f32>(qr_point(a, wa, ha, r.plane, w, h), 1.0)).w);
    }
    let near_w = frame.near * QR_NEAR_CLIP;
    if !(t_max > near_w) {
        return r;
    }
    let grow = 2.0 * (t_max * eps_scale + QR_EPS_MIN);
    for (var k = 0u; k < 4u; k += 1u) {
        let w = select(r.lo_w - grow, r.hi_w + grow, k == 1u || k == 2u);
        let h = select(r.lo_h - grow, r.hi_h + grow, k >= 2u);
        corners[k] = frame.view_proj * vec4<f32>(qr_point(a, wa, ha, r.plane, w, h), 1.0);
    }
    // The polygon clipped at w >= near_w, projected: its bounds.
    var lo = vec2<f32>(1e30);
    var hi = vec2<f32>(-1e30);
    for (var k = 0u; k < 4u; k += 1u) {
        let c = corners[k];
        let n = corners[(k + 1u) & 3u];
        if c.w >= near_w {
            let s = qr_screen(c);
            lo = min(lo, s);
            hi = max(hi, s);
        }
        if (c.w < near_w) != (n.w < near_w) {
            let f = (near_w - c.w) / (n.w - c.w);
            let m = c + (n - c) * f;
            let s = qr_screen(vec4<f32>(m.xyz, near_w));
            lo = min(lo, s);
            hi = max(hi, s);
        }
    }
    let size = vec2<f32>(f32(frame.width), f32(frame.height));
    // Clamped before the conversion; NaN compares false and leaves the box empty.
    let lo_c = clamp(lo, vec2<f32>(-2.0), size + vec2<f32>(2.0));
    let hi_c = clamp(hi, vec2<f32>(-2.0), size + vec2<f32>(2.0));
    if !(all(lo_c <= hi_c)) {
        return r;
    }
    let first = max(vec2<i32>(ceil(lo_c - vec2<f32>(0.5 + QR_BOX_PAD))), vec2<i32>(0));
    let last = min(vec2<i32>(floor(hi_c - vec2<f32>(0.5 - QR_BOX_PAD))), vec2<i32>(size) - vec2<i32>(1));
    if any(last < first) {
        return r;
    }
    r.box_lo = u32(first.x) | (u32(first.y) << 16u);
    r.box_hi = u32(last.x) | (u32(last.y) << 16u);
    return r;
}

// The ambient occlusion (0..=3) at (a, b) in the quad's corner walk (corner 0 at (0, 0),
// 1 at (1, 0), 2 at (1, 1), 3 at (0, 1)): the raster path's triangles (0, 1, 2), (0, 2, 3), or
// (1, 2, 3), (1, 3, 0) when ao1 + ao3 > ao0 + ao2 (mesher::blocky::triangle_indices),
// interpolated barycentrically.
fn qr_ao(word: u32, a: f32, b: f32) -> f32 {
    let q = PackedQuad(0u, word);
    let i0 = packed_quad_ao(q, 0u);
    let i1 = packed_quad_ao(q, 1u);
    let i2 = packed_quad_ao(q, 2u);
    let i3 = packed_quad_ao(q, 3u);
    let ao0 = f32(i0);
    let ao1 = f32(i1);
    let ao2 = f32(i2);
    let ao3 = f32(i3);
    if i1 + i3 > i0 + i2 {
        if a + b >= 1.0 {
            return (1.0 - b) * ao1 + (a + b - 1.0) * ao2 + (1.0 - a) * ao3;
        }
        return (1.0 - a - b) * ao0 + a * ao1 + b * ao3;
    }
    if a >= b {
        return (1.0 - a) * ao0 + (a - b) * ao1 + b * ao2;
    }
    return (1.0 - b) * ao0 + a * ao2 + (b - a) * ao3;
}

// The visibility word quad `q` writes at pixel `p`, or 0 where its pixel centre misses.
fn qr_sample(q: RasterQuad, p: vec2<u32>, eps_scale: f32) -> u64 {
    let face = q.face_ao_block & 7u;
    let a = face_normal_axis(face);
    let d = pixel_ray(p);
    let da = d[a];
    let against = select(da > 0.0, da < 0.0, face_is_positive(face));
    if !against {
        return 0lu;
    }
    let t = q.plane / da;
    if !(t > frame.near && t < QR_MAX_T) {
        return 0lu;
    }
    let uw = t * d[face_width_axis(face)] - q.lo_w;
    let uh = t * d[face_height_axis(face)] - q.lo_h;
    let eps = t * eps_scale + QR_EPS_MIN;
    let sw = q.hi_w - q.lo_w;
    let sh = q.hi_h - q.lo_h;
    if !(uw >= -eps && uw <= sw + eps && uh >= -eps && uh <= sh + eps) {
        return 0lu;
    }
    let du = clamp(uw / sw, 0.0, 1.0);
    let dv = clamp(uh / sh, 0.0, 1.0);
    // packed_quad_corner's walk: (du, dv) = (a, b), or (b, a) on the swapped faces.
    let swap = face == FACE_POS_X || face == FACE_POS_Y || face == FACE_NEG_Z;
    let ao = qr_ao(q.face_ao_block, select(du, dv, swap), select(dv, du, swap));
    let ao8 = u32(round(clamp(ao / 3.0, 0.0, 1.0) * 255.0));
    let payload = ((q.face_ao_block >> 11u) & 0xffffu) | (face << 16u) | (ao8 << 19u);
    let depth = frame.near / t;
    return (u64(bitcast<u32>(depth)) << 32u) | u64(payload);
}

// Tests pixel `p` against `q`; true when it hit (and was written).
fn qr_draw(q: RasterQuad, p: vec2<u32>, eps_scale: f32) -> bool {
    let v = qr_sample(q, p, eps_scale);
    if v == 0lu {
        return false;
    }
    atomicMax(&visibility[p.y * frame.width + p.x], v);
    return true;
}

// Pixel `i` (row-major) of the quad's box.
fn qr_box_pixel(q: RasterQuad, i: u32) -> vec2<u32> {
    let lo = vec2<u32>(q.box_lo & 0xffffu, q.box_lo >> 16u);
    let width = (q.box_hi & 0xffffu) - lo.x + 1u;
    return lo + vec2<u32>(i % width, i / width);
}

// The batch entry whose range of local pixels holds `e` (< the batch's total): the number of
// entries whose inclusive sum is <= e.
fn qr_find_pixel(e: u32) -> u32 {
    var k = 0u;
    for (var step = 32u; step > 0u; step >>= 1u) {
        if wg_scan[k + step - 1u].x <= e {
            k += step;
        }
    }
    return k;
}

// The same over the tile entries.
fn qr_find_tile(e: u32) -> u32 {
    var k = 0u;
    for (var step = 32u; step > 0u; step >>= 1u) {
        if wg_scan[k + step - 1u].y <= e {
            k += step;
        }
    }
    return k;
}

// Inclusive prefix sums of wg_scan (Hillis-Steele, 6 steps).
fn qr_scan(lid: u32) {
    for (var offset = 1u; offset < QR_WORKGROUP; offset <<= 1u) {
        var v = wg_scan[lid];
        if lid >= offset {
            v += wg_scan[lid - offset];
        }
        workgroupBarrier();
        wg_scan[lid] = v;
        workgroupBarrier();
    }
}

// Thread 0: takes room in the tile list for the longest run of the batch's big quads (in
// batch order) that fits, and their big-quad entries. A big quad touches at least 2 tiles,
// so big-quad entries never run out before tile entries (QuadRasterConfig sizes them so).
fn qr_reserve() {
    var fit = vec3<u32>(0u);
    let capacity = arrayLength(&tiles);
    var taken = atomicLoad(&state[QR_TILE_COUNT]);
    loop {
        let room = capacity - min(taken, capacity);
        var k = 0u;
        for (var step = 32u; step > 0u; step >>= 1u) {
            if wg_scan[k + step - 1u].y <= room {
                k += step;
            }
        }
        if k == 0u || wg_scan[k - 1u].y == 0u {
            break;
        }
        let want = wg_scan[k - 1u];
        let swap = atomicCompareExchangeWeak(&state[QR_TILE_COUNT], taken, taken + want.y);
        if swap.exchanged {
            fit = vec3<u32>(taken, want.y, atomicAdd(&state[QR_BIG_COUNT], want.z));
            break;
        }
        taken = swap.old_value;
    }
    wg_fit = fit;
}

// One workgroup per drawn command of the bound page (page_args: written by qr_page_args).
@compute @workgroup_size(64)
fn qr_quads(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let j = wid.y * groups.x + wid.x;
    if j >= page_args.commands {
        return;
    }
    let command = (page_args.first_command + j) * 5u;
    let quad_count = commands[command] / 6u;
    let first = bitcast<u32>(max(bitcast<i32>(commands[command + 3u]), 0)) / 4u;
    let record = records[commands[command + 4u]];
    let scale = f32(1u << min(record.level, 15u));
    let rel = vec3<i32>(record.chunk_x, record.chunk_y, record.chunk_z);
    let origin = vec3<f32>(rel) * frame.chunk_edge - frame.camera_offset;
    let eps_scale = qr_eps_scale();
    var hits = 0u;
    var tested = 0u;
    for (var batch = 0u; batch < quad_count; batch += QR_WORKGROUP) {
        let i = batch + lid;
        var rq = qr_empty();
        var entry = vec3<u32>(0u);
        if i < quad_count {
            rq = qr_setup(quads[first + i], origin, scale, eps_scale);
            let area = qr_box_area(rq);
            if area > QR_LOCAL_MAX_PIXELS {
                let t = qr_box_tiles(rq);
                entry = vec3<u32>(0u, t.z * t.w, 1u);
            } else {
                entry = vec3<u32>(area, 0u, 0u);
            }
            if area > 0u {
                atomicAdd(&wg_visible, 1u);
            }
        }
        wg_quads[lid] = rq;
        wg_scan[lid] = entry;
        workgroupBarrier();
        qr_scan(lid);
        if lid == 0u {
            qr_reserve();
        }
        workgroupBarrier();
        let fit = wg_fit;
        let mine = wg_scan[lid];
        var over = 0u;
        if entry.z == 1u {
            if mine.y <= fit.y {
                bigs[fit.z + mine.z - 1u] = rq;
                atomicAdd(&wg_big, 1u);
            } else {
                over = 1u;
                atomicAdd(&wg_overflow, 1u);
            }
        }
        wg_over[lid] = over;
        workgroupBarrier();
        // The tile entries of the big quads that fit, spread over the workgroup.
        for (var e = lid; e < fit.y; e += QR_WORKGROUP) {
            let k = qr_find_tile(e);
            let t = qr_box_tiles(wg_quads[k]);
            let n = e - (wg_scan[k].y - t.z * t.w);
            let tile = t.xy + vec2<u32>(n % t.z, n / t.z);
            tiles[fit.x + e] = vec2<u32>(fit.z + wg_scan[k].z - 1u, tile.x | (tile.y << 16u));
        }
        // The small quads' pixels, spread over the workgroup.
        let total = wg_scan[QR_WORKGROUP - 1u].x;
        for (var e = lid; e < total; e += QR_WORKGROUP) {
            let k = qr_find_pixel(e);
            let q = wg_quads[k];
            let p = qr_box_pixel(q, e - (wg_scan[k].x - qr_box_area(q)));
            hits += u32(qr_draw(q, p, eps_scale));
        }
        tested += total;
        // Big quads the tile list had no room for, each by the whole workgroup.
        for (var k = 0u; k < QR_WORKGROUP; k += 1u) {
            if wg_over[k] != 0u {
                let q = wg_quads[k];
                let area = qr_box_area(q);
                for (var e = lid; e < area; e += QR_WORKGROUP) {
                    hits += u32(qr_draw(q, qr_box_pixel(q, e), eps_scale));
                }
                tested += area;
            }
        }
        workgroupBarrier();
    }
    atomicAdd(&wg_hits, hits);
    workgroupBarrier();
    if lid == 0u {
        atomicAdd(&state[QR_STAT_QUADS], quad_count);
        atomicAdd(&state[QR_STAT_VISIBLE], atomicLoad(&wg_visible));
        atomicAdd(&state[QR_STAT_LOCAL_PIXELS], tested);
        atomicAdd(&state[QR_STAT_BIG], atomicLoad(&wg_big));
        atomicAdd(&state[QR_STAT_OVERFLOW], atomicLoad(&wg_overflow));
        atomicAdd(&state[QR_STAT_HITS], atomicLoad(&wg_hits));
    }
}

// One workgroup per tile entry (dispatched by qr_tile_args): the tile's pixels inside the big
// quad's box, 4 per invocation.
@compute @workgroup_size(64)
fn qr_tiles(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let e = wid.y * groups.x + wid.x;
    let count = min(atomicLoad(&state[QR_TILE_COUNT]), arrayLength(&tiles));
    var hits = 0u;
    var tested = 0u;
    if e < count {
        let entry = tiles[e];
        let q = bigs[min(entry.x, arrayLength(&bigs) - 1u)];
        let eps_scale = qr_eps_scale();
        let tile = vec2<u32>(entry.y & 0xffffu, entry.y >> 16u) * QR_TILE;
        let lo = max(tile, vec2<u32>(q.box_lo & 0xffffu, q.box_lo >> 16u));
        let hi = min(tile + vec2<u32>(QR_TILE - 1u), vec2<u32>(q.box_hi & 0xffffu, q.box_hi >> 16u));
        for (var row = 0u; row < QR_TILE; row += QR_WORKGROUP / QR_TILE) {
            let p = tile + vec2<u32>(lid % QR_TILE, row + lid / QR_TILE);
            if all(p >= lo) && all(p <= hi) {
                tested += 1u;
                hits += u32(qr_draw(q, p, eps_scale));
            }
        }
    }
    atomicAdd(&wg_hits, hits);
    atomicAdd(&wg_tile_pixels, tested);
    workgroupBarrier();
    if lid == 0u && e < count {
        atomicAdd(&state[QR_STAT_TILE_PIXELS], atomicLoad(&wg_tile_pixels));
        atomicAdd(&state[QR_STAT_HITS], atomicLoad(&wg_hits));
    }
}
