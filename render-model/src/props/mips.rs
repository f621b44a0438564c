//! The mip levels of a prop's sRGB texture, made on the CPU when the texture is uploaded, and
//! the level of detail a sampler reads at: what the GPU samples and the CPU reference
//! (`voxel_reference::prop_raster`) samples alike.
//!
//! # Levels
//!
//! Level `k + 1` is level `k` halved, `max(1, w / 2) x max(1, h / 2)`, down to `1 x 1`. Each
//! texel is the mean of the 2 x 2 texels of level `k` it covers (`2x, 2x + 1` by `2y, 2y + 1`,
//! the second taken as the first where level `k` is 1 wide or tall): RGB averaged in linear
//! light (decoded from sRGB, the mean encoded again and rounded), alpha averaged as it is.
//! Where a side is odd, its last row or column is left out of the level above (a bias of at
//! most one texel in `w`, invisible at the sizes it is read at). Averaging the sRGB codes
//! instead would darken every minified edge between light and dark.
//!
//! # Why the CPU
//!
//! A model is uploaded once; its textures are at most a few megapixels
//! (`voxel_scene::props::PropLimits`), and a box filter over them costs a few milliseconds,
//! once. On the CPU the levels are exact and the same bytes the reference samples, with no
//! pipeline per texture format and no mip pass to record, and wgpu has no built-in
//! mipmap generation to lean on.
//!
//! # Level of detail
//!
//! [`mip_lod`] is the GPU's rule without its approximations: `lambda = log2(rho)`, `rho` the
//! larger of the lengths of the texel-space uv derivatives along screen x and y. Minified
//! (`lambda > 0`) the sampler's minification filter reads within a level, the mipmap filter
//! between levels (nearest: level `round(lambda)`; linear: the two levels around `lambda`,
//! mixed by its fraction); magnified, level 0 with the magnification filter. A GPU takes the
//! derivatives per 2 x 2 pixel quad by differences, so its `lambda` can differ from this one
//! along a triangle's edge or where the uv's rate changes fast.

use crate::lighting::{linear_to_srgb8, srgb_to_linear};

/// One mip level: `width x height` RGBA8 texels, sRGB colour, row by row.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MipLevel {
    /// Texels across.
    pub width: u32,
    /// Texels down.
    pub height: u32,
    /// RGBA8, `4 * width * height` bytes.
    pub rgba: Vec<u8>,
}

/// Why levels could not be made.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MipError {
    /// The pixels are not `4 * width * height` bytes, or a side is 0.
    Size {
        /// Texels across.
        width: u32,
        /// Texels down.
        height: u32,
        /// Bytes given.
        bytes: usize,
    },
}

impl std::fmt::Display for MipError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MipError::Size {
                width,
                height,
                bytes,
            } => write!(
                f,
                "a {width} x {height} texture needs 4 * {width} * {height} bytes of RGBA, not \
                 {bytes}"
            ),
        }
    }
}

impl std::error::Error for MipError {}

/// The number of levels of a `width x height` texture, level 0 included: `floor(log2(max
/// side)) + 1`.
pub fn mip_level_count(width: u32, height: u32) -> u32 {
    32 - width.max(height).max(1).leading_zeros()
}

/// Levels 1 and up of the sRGB texture `rgba` (`width x height`, level 0 itself), smallest
/// last (see the [module docs](self)).
pub fn mip_chain(width: u32, height: u32, rgba: &[u8]) -> Result<Vec<MipLevel>, MipError> {
    let bytes = 4 * width as usize * height as usize;
    if width == 0 || height == 0 || rgba.len() != bytes {
        return Err(MipError::Size {
            width,
            height,
            bytes: rgba.len(),
        });
    }
    let mut out: Vec<MipLevel> = Vec::new();
    let (mut w, mut h) = (width, height);
    let mut linear: Vec<[f32; 4]> = rgba
        .chunks_exact(4)
        .map(|p| {
            [
                srgb_to_linear(p[0]),
                srgb_to_linear(p[1]),
                srgb_to_linear(p[2]),
                f32::from(p[3]) / 255.0,
            ]
        })
        .collect();
    while w > 1 || h > 1 {
        let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
        let at = |x: u32, y: u32| linear[(y.min(h - 1) * w + x.min(w - 1)) as usize];
        let mut next = Vec::with_capacity((nw * nh) as usize);
        for y in 0..nh {
            for x in 0..nw {
                let (x0, y0) = (2 * x, 2 * y);
                let (x1, y1) = (
                    if w > 1 { x0 + 1 } else { x0 },
                    if h > 1 { y0 + 1 } else { y0 },
                );
                let q = [at(x0, y0), at(x1, y0), at(x0, y1), at(x1, y1)];
                next.push(std::array::from_fn(|c| {
                    0.25 * (q[0][c] + q[1][c] + q[2][c] + q[3][c])
                }));
            }
        }
        let bytes = next
            .iter()
            .flat_map(|t: &[f32; 4]| {
                [
                    linear_to_srgb8(t[0]),
                    linear_to_srgb8(t[1]),
                    linear_to_srgb8(t[2]),
                    (t[3] * 255.0).round().clamp(0.0, 255.0) as u8,
                ]
            })
            .collect();
        out.push(MipLevel {
            width: nw,
            height: nh,
            rgba: bytes,
        });
        // The next level averages the rounded bytes, as a GPU reading this level would.
        linear = out
            .last()
            .map(|l| {
                l.rgba
                    .chunks_exact(4)
                    .map(|p| {
                        [
                            srgb_to_linear(p[0]),
                            srgb_to_linear(p[1]),
                            srgb_to_linear(p[2]),
                            f32::from(p[3]) / 255.0,
                        ]
                    })
                    .collect()
            })
            .unwrap_or_default();
        (w, h) = (nw, nh);
    }
    Ok(out)
}

/// The level of detail of a texture `size` texels wide and tall sampled with uv derivatives
/// `du_dx`, `du_dy` (uv per pixel along screen x and y): `log2` of the larger texel-space
/// derivative length (see the [module docs](self)); `-inf` for no change.
pub fn mip_lod(size: [u32; 2], du_dx: [f32; 2], du_dy: [f32; 2]) -> f32 {
    let s = size.map(|v| v as f32);
    let len = |d: [f32; 2]| ((d[0] * s[0]).powi(2) + (d[1] * s[1]).powi(2)).sqrt();
    len(du_dx).max(len(du_dy)).log2()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_checkerboard_averages_to_mid_grey_in_linear_light() {
        // 1-texel black and white checks, 8 x 4.
        let (w, h) = (8, 4);
        let rgba: Vec<u8> = (0..w * h)
            .flat_map(|i| {
                let v = if (i % w + i / w) % 2 == 0 { 255 } else { 0 };
                [v, v, v, 255]
            })
            .collect();
        let chain = mip_chain(w, h, &rgba).unwrap();
        assert_eq!(chain.len() as u32 + 1, mip_level_count(w, h));
        let sizes: Vec<(u32, u32)> = chain.iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, [(4, 2), (2, 1), (1, 1)]);
        // Linear 0.5 is sRGB 188, not the codes' mean 128.
        let grey = linear_to_srgb8(0.5);
        assert_eq!(grey, 188);
        for level in &chain {
            assert!(level.rgba.chunks(4).all(|p| p == [grey, grey, grey, 255]));
        }
    }

    #[test]
    fn sizes_are_checked_and_odd_sides_shrink() {
        assert!(matches!(
            mip_chain(3, 3, &[0; 10]),
            Err(MipError::Size { bytes: 10, .. })
        ));
        assert!(mip_chain(0, 4, &[]).is_err());
        assert!(mip_chain(1, 1, &[1, 2, 3, 4]).unwrap().is_empty());
        let chain = mip_chain(5, 1, &[200; 20]).unwrap();
        let sizes: Vec<(u32, u32)> = chain.iter().map(|l| (l.width, l.height)).collect();
        assert_eq!(sizes, [(2, 1), (1, 1)]);
        assert!(
            chain.iter().all(|l| l.rgba.iter().all(|&b| b == 200)),
            "flat stays flat"
        );
        assert_eq!(mip_level_count(256, 100), 9);
        assert_eq!(
            mip_lod([256, 256], [1.0 / 64.0, 0.0], [0.0, 1.0 / 256.0]),
            2.0
        );
    }
}
