// Shared by the far draws (splat.wgsl, far_raster.wgsl): the ambient occlusion the blocky
// meshers would give a point of a block's face. The including shader defines
// `hides(p, edge)`: whether the node's padded voxel p hides its neighbours (from its hiding
// mask, wherever that shader keeps it).

// The meshers' corner rule (mesher::blocky::ao::corner_ao).
fn corner_ao(side1: bool, side2: bool, corner: bool) -> f32 {
    if side1 && side2 {
        return 0.0;
    }
    return 3.0 - f32(u32(side1) + u32(side2) + u32(corner));
}

// (du, dv) of corner k of a face, in PackedQuad corner order (packed_quad_corner's walk).
fn corner_uv(face: u32, k: u32) -> vec2<f32> {
    let a = f32(u32(k == 1u || k == 2u));
    let b = f32(u32(k >= 2u));
    let swap = face == FACE_POS_X || face == FACE_POS_Y || face == FACE_NEG_Z;
    return select(vec2<f32>(a, b), vec2<f32>(b, a), swap);
}

// Barycentric weights of p in the triangle (a, b, c); all >= 0 inside.
fn barycentric(p: vec2<f32>, a: vec2<f32>, b: vec2<f32>, c: vec2<f32>) -> vec3<f32> {
    let v0 = b - a;
    let v1 = c - a;
    let v2 = p - a;
    let d = v0.x * v1.y - v1.x * v0.y;
    let wb = (v2.x * v1.y - v1.x * v2.y) / d;
    let wc = (v0.x * v2.y - v2.x * v0.y) / d;
    return vec3<f32>(1.0 - wb - wc, wb, wc);
}

// The ambient occlusion (0..=3) of the 4 corners (PackedQuad corner order) of face `face` of
// the block at padded cell `cell`, by the meshers' corner rule.
fn face_corner_aos(cell: vec3<i32>, face: u32, edge: i32) -> array<f32, 4> {
    let front = cell + face_normal(face);
    let w = vec3<i32>(axis_unit(face_width_axis(face)));
    let h = vec3<i32>(axis_unit(face_height_axis(face)));
    var ao: array<f32, 4>;
    for (var k = 0u; k < 4u; k += 1u) {
        let d = corner_uv(face, k) * 2.0 - vec2<f32>(1.0);
        let dw = w * i32(d.x);
        let dh = h * i32(d.y);
        ao[k] = corner_ao(hides(front + dh, edge), hides(front + dw, edge), hides(front + dw + dh, edge));
    }
    return ao;
}

// The AO diagonal flip of mesher::blocky::triangle_indices: 1 when the face splits along
// corners 1-3 (corner slot k is then corner (k + 1) & 3), else 0.
fn ao_flip(ao: array<f32, 4>) -> u32 {
    return u32(ao[1] + ao[3] > ao[0] + ao[2]);
}

// The ambient occlusion (0..=3) at point `uv` (0..1 along the face's width and height axes) of
// face `face` of the block at padded cell `cell`, as the blocky meshers' quad would shade it.
fn face_ao(cell: vec3<i32>, face: u32, uv: vec2<f32>, edge: i32) -> f32 {
    let ao = face_corner_aos(cell, face, edge);
    let flip = ao_flip(ao);
    let i0 = flip & 3u;
    let i1 = (1u + flip) & 3u;
    let i2 = (2u + flip) & 3u;
    let i3 = (3u + flip) & 3u;
    let p0 = corner_uv(face, i0);
    let p2 = corner_uv(face, i2);
    let first = barycentric(uv, p0, corner_uv(face, i1), p2);
    if min(first.x, min(first.y, first.z)) >= -1e-4 {
        return first.x * ao[i0] + first.y * ao[i1] + first.z * ao[i2];
    }
    let second = barycentric(uv, p0, p2, corner_uv(face, i3));
    return second.x * ao[i0] + second.y * ao[i2] + second.z * ao[i3];
}
