//! Anti-aliasing of geometric edges: FXAA (Lottes' fast approximate anti-aliasing, its
//! "quality" form with whole-pixel search steps) on the tonemapped, sRGB-encoded image; the
//! CPU twin of `gpu-backend`'s antialias pass, same operations.
//!
//! Why FXAA: one full-screen pass over the final image, with no history, motion vectors or
//! extra targets, so it applies unchanged to every geometry path the frame mixes (raster and
//! compute-rasterised quads, splatted and ray-cast far blocks) and to a camera that jumps.
//! SMAA looks sharper but takes three passes and lookup textures; temporal AA would need
//! sub-pixel jitter and velocities from all five geometry paths and ghosts on streamed-in
//! nodes.
//!
//! Per pixel: the luma (`0.299 r + 0.587 g + 0.114 b` of the encoded colour) of it and its
//! four neighbours; a pixel whose local contrast is below `max(EDGE_MIN, EDGE_RELATIVE *
//! brightest)` is kept. Otherwise the edge's orientation comes from the 3 x 3 lumas, the edge
//! line runs between the pixel and its steeper neighbour, and the edge is followed both ways
//! (whole-pixel steps [`STEPS`], the luma on the edge line the mean of the two rows) until
//! the luma leaves the local average by a quarter of the gradient. The pixel blends with its
//! neighbour across the edge by how near it is to the nearer end, or by the sub-pixel
//! estimate where that is larger (thin features).

/// Local contrast below which nothing is an edge.
pub const EDGE_MIN: f32 = 0.0312;
/// Local contrast below this share of the brightest luma is not an edge.
pub const EDGE_RELATIVE: f32 = 0.125;
/// Weight of the sub-pixel blend (thin features).
pub const SUBPIXEL: f32 = 0.75;
/// The search steps along an edge, pixels.
pub const STEPS: [i32; 10] = [1, 1, 1, 1, 1, 2, 2, 2, 4, 8];

fn luma(c: [f32; 3]) -> f32 {
    c[0] * 0.299 + c[1] * 0.587 + c[2] * 0.114
}

/// FXAA of an RGBA8 image (`width * height * 4` bytes, sRGB-encoded, alpha ignored and
/// written 255). Pixels past the border read the border.
///
/// # Panics
///
/// When `rgba` is not `width * height * 4` bytes.
pub fn fxaa(rgba: &[u8], width: u32, height: u32) -> Vec<u8> {
    assert_eq!(
        rgba.len(),
        width as usize * height as usize * 4,
        "image size"
    );
    let fetch = |x: i32, y: i32| -> [f32; 3] {
        let x = x.clamp(0, width as i32 - 1) as usize;
        let y = y.clamp(0, height as i32 - 1) as usize;
        let i = 4 * (y * width as usize + x);
        [rgba[i], rgba[i + 1], rgba[i + 2]].map(|c| f32::from(c) / 255.0)
    };
    let mut out = Vec::with_capacity(rgba.len());
    for y in 0..height as i32 {
        for x in 0..width as i32 {
            let c = pixel(&fetch, x, y);
            out.extend(c.map(|v| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8));
            out.push(255);
        }
    }
    out
}

/// The anti-aliased colour of pixel `(x, y)` (the [module docs](self)).
fn pixel(fetch: &impl Fn(i32, i32) -> [f32; 3], x: i32, y: i32) -> [f32; 3] {
    let l = |dx: i32, dy: i32| luma(fetch(x + dx, y + dy));
    let centre = fetch(x, y);
    let m = luma(centre);
    let (n, s, e, w) = (l(0, -1), l(0, 1), l(1, 0), l(-1, 0));
    let lo = m.min(n).min(s).min(e).min(w);
    let hi = m.max(n).max(s).max(e).max(w);
    let range = hi - lo;
    if range < EDGE_MIN.max(hi * EDGE_RELATIVE) {
        return centre;
    }
    let (nw, ne, sw, se) = (l(-1, -1), l(1, -1), l(-1, 1), l(1, 1));
    let (ns, we) = (n + s, w + e);
    let edge_h =
        (-2.0 * w + nw + sw).abs() + 2.0 * (-2.0 * m + ns).abs() + (-2.0 * e + ne + se).abs();
    let edge_v =
        (-2.0 * n + nw + ne).abs() + 2.0 * (-2.0 * m + we).abs() + (-2.0 * s + sw + se).abs();
    let horizontal = edge_h >= edge_v;
    let (l1, l2) = if horizontal { (n, s) } else { (w, e) };
    let (g1, g2) = (l1 - m, l2 - m);
    let steep1 = g1.abs() >= g2.abs();
    let scaled = 0.25 * g1.abs().max(g2.abs());
    let side = if steep1 { -1 } else { 1 };
    let local = 0.5 * (m + if steep1 { l1 } else { l2 });
    // Along the edge (`along`) and across it towards the steeper neighbour (`across`).
    let (along, across) = if horizontal {
        ((1, 0), (0, side))
    } else {
        ((0, 1), (side, 0))
    };
    let edge_luma = |k: i32| {
        let (px, py) = (x + k * along.0, y + k * along.1);
        0.5 * (luma(fetch(px, py)) + luma(fetch(px + across.0, py + across.1)))
    };
    let (mut k1, mut k2) = (0, 0);
    let (mut end1, mut end2) = (0.0f32, 0.0f32);
    let (mut done1, mut done2) = (false, false);
    for step in STEPS {
        if !done1 {
            k1 -= step;
            end1 = edge_luma(k1) - local;
            done1 = end1.abs() >= scaled;
        }
        if !done2 {
            k2 += step;
            end2 = edge_luma(k2) - local;
            done2 = end2.abs() >= scaled;
        }
        if done1 && done2 {
            break;
        }
    }
    let (d1, d2) = ((-k1) as f32, k2 as f32);
    let nearer1 = d1 < d2;
    let nearest = d1.min(d2);
    let edge_offset = -nearest / (d1 + d2) + 0.5;
    let centre_darker = m < local;
    let end = if nearer1 { end1 } else { end2 };
    let mut offset = if (end < 0.0) != centre_darker {
        edge_offset
    } else {
        0.0
    };
    let average = (1.0 / 12.0) * (2.0 * (ns + we) + nw + ne + sw + se);
    let s1 = ((average - m).abs() / range).clamp(0.0, 1.0);
    let s2 = (-2.0 * s1 + 3.0) * s1 * s1;
    offset = offset.max(s2 * s2 * SUBPIXEL);
    let other = fetch(x + across.0, y + across.1);
    core::array::from_fn(|i| centre[i] + (other[i] - centre[i]) * offset)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(width: u32, height: u32, f: impl Fn(u32, u32) -> u8) -> Vec<u8> {
        (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .flat_map(|(x, y)| {
                let v = f(x, y);
                [v, v, v, 255]
            })
            .collect()
    }

    #[test]
    fn flat_and_low_contrast_images_pass_unchanged() {
        let flat = image(16, 16, |_, _| 90);
        assert_eq!(fxaa(&flat, 16, 16), flat);
        let gentle = image(16, 16, |x, _| 100 + x as u8 / 4);
        assert_eq!(fxaa(&gentle, 16, 16), gentle);
    }

    #[test]
    fn a_staircase_edge_gets_intermediate_values() {
        // A dark half-plane below a line of slope 1/4: a staircase of steps 4 pixels long.
        let (w, h) = (32u32, 16u32);
        let stairs = image(w, h, |x, y| if 4 * y > x + 16 { 20 } else { 230 });
        let smoothed = fxaa(&stairs, w, h);
        let between = smoothed
            .chunks(4)
            .filter(|p| p[0] > 40 && p[0] < 210)
            .count();
        assert!(between >= 16, "{between} blended pixels");
        // Far from the edge nothing changes.
        assert_eq!(&smoothed[..4], &stairs[..4]);
        assert_eq!(&smoothed[smoothed.len() - 4..], &stairs[stairs.len() - 4..]);
    }
}
