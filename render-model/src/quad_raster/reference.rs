//! The CPU twin of the rasteriser: the quad setup (`qr_setup`), the per-pixel decision
//! (`qr_sample`: hit, depth bits, payload) and a whole reference image, with the same `f32`
//! operations in the same order as `quad_raster.wgsl`.
//!
//! A GPU may fuse a multiply and an add where the CPU rounds twice, and its `length` and
//! divisions may round differently in the last bit, so a GPU and this twin can disagree where a
//! decision is within rounding of its threshold: a pixel centre within a hair of a quad's
//! (grown) edge or of the near plane. [`PixelSample::ambiguous`] flags those pixels, with a
//! margin of [`AMBIGUITY`] of the magnitudes involved (see [`sample_reference`]); the depth and
//! AO of a hit may differ by the same rounding (a few units in the last place of the depth, one
//! 255th of the AO where it rounds at a half).

use voxel_core::formats::{FaceDirection, PackedQuad};

use super::layout::{BOX_PAD, EMPTY_BOX, EPS_MIN, EPS_PX, MAX_T, NEAR_CLIP, RasterQuad};
use crate::cull::DrawRecord;
use crate::frame::FrameUniforms;

/// Relative margin of [`PixelSample::ambiguous`]: `2^-16` (about 500 units in the last place
/// of an `f32`, far above the rounding of the few operations involved, and about 1/100 pixel
/// for coordinates of the magnitude of the quad's distance at a 60 degree field of view and
/// 1080 rows).
pub const AMBIGUITY: f32 = 1.0 / 65536.0;

/// What one quad gives one pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PixelSample {
    /// The visibility word the quad writes there (`depth bits << 32 | payload`), 0 for none.
    pub value: u64,
    /// The word it would write if its coverage decision flipped (the same as `value` on a hit;
    /// 0 where the ray does not reach the plane in front of the eye).
    pub candidate: u64,
    /// The coverage decision is within rounding of its threshold (see the module docs).
    pub ambiguous: bool,
}

/// `face_width_axis` / `face_height_axis` / `face_normal_axis` of FORMATS_WGSL.
fn axes(face: u32) -> (usize, usize, usize) {
    let a = (face / 2) as usize;
    let wa = if a == 0 { 2 } else { 0 };
    let ha = if a == 1 { 2 } else { 1 };
    (a, wa, ha)
}

/// `face_is_positive`.
fn positive(face: u32) -> bool {
    face & 1 == 0
}

/// `pixel_ray` of `render_common.wgsl`.
pub fn pixel_ray(frame: &FrameUniforms, x: u32, y: u32) -> [f32; 3] {
    let u = 2.0 * (x as f32 + 0.5) / frame.width as f32 - 1.0;
    let v = 1.0 - 2.0 * (y as f32 + 0.5) / frame.height as f32;
    std::array::from_fn(|i| frame.forward[i] + u * frame.right[i] + v * frame.up[i])
}

/// `qr_eps_scale`: blocks of hair per block of distance.
pub fn eps_scale(frame: &FrameUniforms) -> f32 {
    let up = frame.up;
    let length = (up[0] * up[0] + up[1] * up[1] + up[2] * up[2]).sqrt();
    EPS_PX * (2.0 * length / frame.height as f32)
}

/// `frame.view_proj * (p, 1)`, column-major, summed in the order naga emits it.
fn clip(frame: &FrameUniforms, p: [f32; 3]) -> [f32; 4] {
    let m = &frame.view_proj;
    std::array::from_fn(|r| m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + m[3][r])
}

fn point(a: usize, wa: usize, ha: usize, n: f32, w: f32, h: f32) -> [f32; 3] {
    let mut p = [0.0; 3];
    p[a] = n;
    p[wa] = w;
    p[ha] = h;
    p
}

fn screen(frame: &FrameUniforms, c: [f32; 4]) -> [f32; 2] {
    let (nx, ny) = (c[0] / c[3], c[1] / c[3]);
    [
        (nx * 0.5 + 0.5) * frame.width as f32,
        (0.5 - ny * 0.5) * frame.height as f32,
    ]
}

/// The camera-relative position of cell (0, 0, 0) of the record's node, and its cell size:
/// `f32(record.chunk) * chunk_edge - camera_offset`, `2^min(level, 15)`.
pub fn node_origin(frame: &FrameUniforms, record: &DrawRecord) -> ([f32; 3], f32) {
    let origin =
        std::array::from_fn(|i| record.chunk[i] as f32 * frame.chunk_edge - frame.camera_offset[i]);
    (origin, (1u32 << record.level.min(15)) as f32)
}

/// `qr_setup`: quad `quad` of the node of `record`, set up for `frame` (its plane, its edges
/// and the box of pixel centres its grown rectangle may cover).
pub fn setup_reference(frame: &FrameUniforms, quad: PackedQuad, record: &DrawRecord) -> RasterQuad {
    let (origin, scale) = node_origin(frame, record);
    let mut r = RasterQuad {
        box_lo: EMPTY_BOX.0,
        box_hi: EMPTY_BOX.1,
        ..RasterQuad::default()
    };
    let face = quad.face_ao_block & 7;
    if face > 5 {
        return r;
    }
    let (a, wa, ha) = axes(face);
    let corner = |k: u32| -> [f32; 3] {
        let cell = corner_cell(quad, k);
        std::array::from_fn(|i| origin[i] + cell[i] as f32 * scale)
    };
    let (c0, c2) = (corner(0), corner(2));
    r.plane = c0[a];
    r.lo_w = c0[wa];
    r.lo_h = c0[ha];
    r.hi_w = c2[wa];
    r.hi_h = c2[ha];
    r.face_ao_block = quad.face_ao_block;
    let facing = if positive(face) {
        r.plane < 0.0
    } else {
        r.plane > 0.0
    };
    if !facing {
        return r;
    }
    let mut t_max = 0.0f32;
    for k in 0..4 {
        let w = if k == 1 || k == 2 { r.hi_w } else { r.lo_w };
        let h = if k >= 2 { r.hi_h } else { r.lo_h };
        t_max = t_max.max(clip(frame, point(a, wa, ha, r.plane, w, h))[3]);
    }
    let near_w = frame.near * NEAR_CLIP;
    if t_max.is_nan() || t_max <= near_w {
        return r;
    }
    let grow = 2.0 * (t_max * eps_scale(frame) + EPS_MIN);
    let corners: [[f32; 4]; 4] = std::array::from_fn(|k| {
        let w = if k == 1 || k == 2 {
            r.hi_w + grow
        } else {
            r.lo_w - grow
        };
        let h = if k >= 2 { r.hi_h + grow } else { r.lo_h - grow };
        clip(frame, point(a, wa, ha, r.plane, w, h))
    });
    let mut lo = [1e30f32; 2];
    let mut hi = [-1e30f32; 2];
    let mut take = |s: [f32; 2]| {
        for i in 0..2 {
            lo[i] = lo[i].min(s[i]);
            hi[i] = hi[i].max(s[i]);
        }
    };
    for k in 0..4 {
        let c = corners[k];
        let n = corners[(k + 1) & 3];
        if c[3] >= near_w {
            take(screen(frame, c));
        }
        if (c[3] < near_w) != (n[3] < near_w) {
            let f = (near_w - c[3]) / (n[3] - c[3]);
            let m: [f32; 4] = std::array::from_fn(|i| c[i] + (n[i] - c[i]) * f);
            take(screen(frame, [m[0], m[1], m[2], near_w]));
        }
    }
    let size = [frame.width as f32, frame.height as f32];
    let lo_c: [f32; 2] = std::array::from_fn(|i| lo[i].clamp(-2.0, size[i] + 2.0));
    let hi_c: [f32; 2] = std::array::from_fn(|i| hi[i].clamp(-2.0, size[i] + 2.0));
    if !(lo_c[0] <= hi_c[0] && lo_c[1] <= hi_c[1]) {
        return r;
    }
    let first: [i32; 2] =
        std::array::from_fn(|i| ((lo_c[i] - (0.5 + BOX_PAD)).ceil() as i32).max(0));
    let last: [i32; 2] = std::array::from_fn(|i| {
        ((hi_c[i] - (0.5 - BOX_PAD)).floor() as i32).min(size[i] as i32 - 1)
    });
    if last[0] < first[0] || last[1] < first[1] {
        return r;
    }
    r.box_lo = first[0] as u32 | (first[1] as u32) << 16;
    r.box_hi = last[0] as u32 | (last[1] as u32) << 16;
    r
}

/// `packed_quad_corner` (the twin of `PackedQuadFields::corners`), for any bit pattern.
fn corner_cell(q: PackedQuad, corner: u32) -> [u32; 3] {
    let face = q.face_ao_block & 7;
    let c = corner & 3;
    let a = u32::from(c == 1 || c == 2);
    let b = u32::from(c >= 2);
    let swap = face == 0 || face == 2 || face == 5;
    let (du, dv) = if swap { (b, a) } else { (a, b) };
    let w = q.position_size;
    let mut p = [w & 63, (w >> 6) & 63, (w >> 12) & 63];
    let width = ((w >> 18) & 63) + 1;
    let height = ((w >> 24) & 63) + 1;
    let (n, wa, ha) = axes(face.min(5));
    if positive(face) {
        p[n] += 1;
    }
    p[wa] += du * width;
    p[ha] += dv * height;
    p
}

/// `qr_ao`: the AO (0..=3) at `(a, b)` of the corner walk, by the raster path's triangles.
pub fn ao_reference(face_ao_block: u32, a: f32, b: f32) -> f32 {
    let i: [u32; 4] = std::array::from_fn(|k| (face_ao_block >> (3 + 2 * k)) & 3);
    let ao = i.map(|v| v as f32);
    if i[1] + i[3] > i[0] + i[2] {
        if a + b >= 1.0 {
            return (1.0 - b) * ao[1] + (a + b - 1.0) * ao[2] + (1.0 - a) * ao[3];
        }
        return (1.0 - a - b) * ao[0] + a * ao[1] + b * ao[3];
    }
    if a >= b {
        return (1.0 - a) * ao[0] + (a - b) * ao[1] + b * ao[2];
    }
    (1.0 - b) * ao[0] + a * ao[2] + (b - a) * ao[3]
}

/// `qr_sample`: what quad `q` gives pixel `(x, y)`.
///
/// `ambiguous` is set where the decision is within rounding of flipping: the hit point's
/// in-plane coordinates within `AMBIGUITY * m` of the grown rectangle's edges (`m` the largest
/// magnitude among the hit point's coordinates, the quad's bounds and the hair), or `t` within
/// `AMBIGUITY * t` of the near plane.
pub fn sample_reference(frame: &FrameUniforms, q: &RasterQuad, x: u32, y: u32) -> PixelSample {
    let none = PixelSample::default();
    let face = q.face_ao_block & 7;
    if face > 5 {
        return none;
    }
    let (a, wa, ha) = axes(face);
    let d = pixel_ray(frame, x, y);
    let da = d[a];
    let against = if positive(face) { da < 0.0 } else { da > 0.0 };
    if !against {
        return none;
    }
    let t = q.plane / da;
    if !(t > 0.0 && t < MAX_T) {
        return none;
    }
    let hw = t * d[wa];
    let hh = t * d[ha];
    let uw = hw - q.lo_w;
    let uh = hh - q.lo_h;
    let eps = t * eps_scale(frame) + EPS_MIN;
    let sw = q.hi_w - q.lo_w;
    let sh = q.hi_h - q.lo_h;
    let inside = uw >= -eps && uw <= sw + eps && uh >= -eps && uh <= sh + eps;
    let hit = inside && t > frame.near;
    let m = [hw, hh, q.lo_w, q.hi_w, q.lo_h, q.hi_h, eps]
        .iter()
        .fold(0.0f32, |m, v| m.max(v.abs()));
    let margin = AMBIGUITY * m;
    let edges = [uw + eps, sw + eps - uw, uh + eps, sh + eps - uh];
    let ambiguous = edges.iter().all(|e| *e > -margin)
        && (edges.iter().any(|e| e.abs() <= margin) || (t - frame.near).abs() <= AMBIGUITY * t);
    let du = (uw / sw).clamp(0.0, 1.0);
    let dv = (uh / sh).clamp(0.0, 1.0);
    let swap = face == 0 || face == 2 || face == 5;
    let (ca, cb) = if swap { (dv, du) } else { (du, dv) };
    let ao = ao_reference(q.face_ao_block, ca, cb);
    let ao8 = ((ao / 3.0).clamp(0.0, 1.0) * 255.0).round_ties_even() as u32;
    let payload = ((q.face_ao_block >> 11) & 0xffff) | face << 16 | ao8 << 19;
    let depth = frame.near / t;
    let candidate = u64::from(depth.to_bits()) << 32 | u64::from(payload);
    PixelSample {
        value: if hit { candidate } else { 0 },
        candidate,
        ambiguous,
    }
}

/// The visibility buffer (`width * height` words, row-major) that drawing `quads` (each with
/// its command's record) into an empty buffer gives: per pixel the largest word any quad
/// writes. Every pixel of the screen is tested against every quad (not only the quad's box), so
/// the GPU's boxes are checked too.
pub fn rasterise_reference(frame: &FrameUniforms, quads: &[(PackedQuad, DrawRecord)]) -> Vec<u64> {
    let (w, h) = (frame.width, frame.height);
    let mut out = vec![0u64; (w as usize) * (h as usize)];
    for (quad, record) in quads {
        let q = setup_reference(frame, *quad, record);
        for y in 0..h {
            for x in 0..w {
                let s = sample_reference(frame, &q, x, y);
                let at = (y * w + x) as usize;
                out[at] = out[at].max(s.value);
            }
        }
    }
    out
}

/// The face of a visibility word's payload.
pub fn payload_face(value: u64) -> Option<FaceDirection> {
    FaceDirection::from_index(((value >> 16) & 7) as u8).ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Camera;
    use crate::frame::FrameShape;
    use crate::lighting::Lighting;
    use glam::DVec3;
    use voxel_core::formats::PackedQuadFields;
    use voxel_core::{BlockId, ChunkSize, WorldPos};

    fn frame(yaw: f64, pitch: f64, offset: [f32; 3], w: u32, h: u32) -> FrameUniforms {
        let camera = Camera::new(WorldPos::new(0, 0, 0), DVec3::ZERO, yaw, pitch, 1.0);
        let shape = FrameShape {
            width: w,
            height: h,
            chunk_size: ChunkSize::S16,
            material_count: 1,
            smooth_extent: 1.0,
            smooth_origin: 0.0,
            flags: 0,
        };
        // The eye may lie outside chunk 0: the records below are relative to chunk 0.
        FrameUniforms {
            camera_offset: offset,
            camera_chunk: [0; 3],
            ..FrameUniforms::new(&camera, &Lighting::default(), &shape)
        }
    }

    fn quad(position: [u32; 3], size: (u32, u32), face: FaceDirection, ao: [u8; 4]) -> PackedQuad {
        PackedQuad::encode(&PackedQuadFields {
            position,
            width: size.0,
            height: size.1,
            face,
            ao,
            block: BlockId(7),
        })
        .unwrap()
    }

    #[test]
    fn corners_match_the_format() {
        for face in FaceDirection::ALL {
            let fields = PackedQuadFields {
                position: [3, 5, 9],
                width: 4,
                height: 2,
                face,
                ao: [0; 4],
                block: BlockId(1),
            };
            let q = PackedQuad::encode(&fields).unwrap();
            for (k, want) in fields.corners().iter().enumerate() {
                assert_eq!(corner_cell(q, k as u32), *want, "{face:?} corner {k}");
            }
        }
    }

    /// AO equals the corner values at the corners, is linear along every edge, and takes the
    /// meshers' diagonal: the centre is the average of the two corners of the split diagonal.
    #[test]
    fn ao_follows_the_triangle_split() {
        let walk = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        for bits in 0..256u32 {
            let word = bits << 3;
            let ao: [f32; 4] = std::array::from_fn(|k| ((bits >> (2 * k)) & 3) as f32);
            for (k, &(a, b)) in walk.iter().enumerate() {
                assert_eq!(ao_reference(word, a, b), ao[k]);
            }
            for k in 0..4 {
                let (a0, b0) = walk[k];
                let (a1, b1) = walk[(k + 1) % 4];
                let mid = ao_reference(word, (a0 + a1) / 2.0, (b0 + b1) / 2.0);
                assert_eq!(
                    mid,
                    (ao[k] + ao[(k + 1) % 4]) / 2.0,
                    "edge {k} of {bits:#x}"
                );
            }
            let flip = ao[1] + ao[3] > ao[0] + ao[2];
            let centre = ao_reference(word, 0.5, 0.5);
            let want = if flip {
                (ao[1] + ao[3]) / 2.0
            } else {
                (ao[0] + ao[2]) / 2.0
            };
            assert_eq!(centre, want, "{bits:#x}");
        }
    }

    /// A quad seen head-on covers exactly the pixel centres inside its projection, with the
    /// near depth `near / distance` and the block and face of the quad.
    #[test]
    fn a_head_on_quad_covers_its_projection() {
        // Eye at (8, 8, 30) looking along -z at a +Z quad 0..16 x 0..16 at z = 1 (cells 0).
        let f = frame(0.0, 0.0, [8.0, 8.0, 30.0], 64, 64);
        let q = quad([0, 0, 0], (16, 16), FaceDirection::PosZ, [3; 4]);
        let record = DrawRecord {
            chunk: [0; 3],
            level: 0,
        };
        let image = rasterise_reference(&f, &[(q, record)]);
        let setup = setup_reference(&f, q, &record);
        let half = 8.0 / (29.0 * (0.5f32).tan()) * 32.0;
        let mut covered = 0;
        for y in 0..64 {
            for x in 0..64 {
                let v = image[(y * 64 + x) as usize];
                let px = (x as f32 + 0.5 - 32.0).abs();
                let py = (y as f32 + 0.5 - 32.0).abs();
                if px < half - 0.05 && py < half - 0.05 {
                    assert_ne!(v, 0, "({x}, {y}) inside");
                    assert_eq!(v as u32 & 0xffff, 7);
                    assert_eq!(payload_face(v), Some(FaceDirection::PosZ));
                    assert_eq!((v as u32 >> 19) & 0xff, 255, "unoccluded");
                    let t = 29.0 * (pixel_ray(&f, x, y)[2] / -1.0).recip();
                    let depth = f32::from_bits((v >> 32) as u32);
                    assert!((depth - f.near / t).abs() < 1e-6 * depth);
                    covered += 1;
                } else if px > half + 0.05 || py > half + 0.05 {
                    assert_eq!(v, 0, "({x}, {y}) outside");
                }
            }
        }
        assert!(covered > 100, "{covered}");
        let (lo, hi) = setup.pixel_box().unwrap();
        for y in 0..64 {
            for x in 0..64 {
                let inside = (lo[0]..=hi[0]).contains(&x) && (lo[1]..=hi[1]).contains(&y);
                if image[(y * 64 + x) as usize] != 0 {
                    assert!(inside, "hit ({x}, {y}) outside the box {lo:?}..{hi:?}");
                }
            }
        }
        // Seen from behind, nothing.
        let back = frame(std::f64::consts::PI, 0.0, [8.0, 8.0, -30.0], 64, 64);
        assert!(
            rasterise_reference(&back, &[(q, record)])
                .iter()
                .all(|&v| v == 0)
        );
        assert_eq!(setup_reference(&back, q, &record).box_area(), 0);
    }

    /// For random quads and cameras (near the eye, behind it, crossing the screen edge and the
    /// near plane), every pixel a quad hits lies inside its box.
    #[test]
    fn boxes_hold_every_hit() {
        let mut state = 0x51u64;
        let mut next = move |n: u32| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 33) % u64::from(n)) as u32
        };
        let mut hits = 0;
        for _ in 0..1000 {
            let f = frame(
                next(628) as f64 / 100.0,
                next(280) as f64 / 100.0 - 1.4,
                [
                    next(160) as f32 / 10.0,
                    next(160) as f32 / 10.0,
                    next(160) as f32 / 10.0,
                ],
                40 + next(40),
                30 + next(40),
            );
            let face = FaceDirection::ALL[next(6) as usize];
            let q = quad(
                [next(16), next(16), next(16)],
                (1 + next(16), 1 + next(16)),
                face,
                [0, 1, 2, 3].map(|_| next(4) as u8),
            );
            let record = DrawRecord {
                chunk: [next(3) as i32 - 1, next(3) as i32 - 1, next(3) as i32 - 1],
                level: next(3),
            };
            let setup = setup_reference(&f, q, &record);
            let image = rasterise_reference(&f, &[(q, record)]);
            for y in 0..f.height {
                for x in 0..f.width {
                    if image[(y * f.width + x) as usize] != 0 {
                        hits += 1;
                        let (lo, hi) = setup.pixel_box().expect("a hit needs a box");
                        assert!(
                            (lo[0]..=hi[0]).contains(&x) && (lo[1]..=hi[1]).contains(&y),
                            "({x}, {y}) outside {lo:?}..{hi:?} for {q:?} {record:?}"
                        );
                    }
                }
            }
        }
        assert!(hits > 12_000, "{hits}");
    }
}
