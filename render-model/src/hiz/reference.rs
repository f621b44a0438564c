//! The CPU twin of the pyramid build (`hiz_build.wgsl`): the same footprints, the same `min` and
//! `max` in the same order, so a GPU pyramid equals it exactly.

use super::error::ScreenError;
use super::levels::{footprint, level_sizes};

/// The nearer of the depth image and the visibility buffer per pixel: `max(depth, f32 of the
/// high word)`, what `hiz_level0` reads for each pixel when a visibility buffer is bound.
///
/// `visibility` holds the splatting pass's `u64` words (high 32 bits: the `f32` bits of a
/// reversed-Z depth, 0 = nothing; low 32 bits: payload), one per pixel, row-major.
pub fn merge_visibility_reference(
    depth: &[f32],
    visibility: &[u64],
) -> Result<Vec<f32>, ScreenError> {
    if visibility.len() != depth.len() {
        return Err(ScreenError::VisibilityLength {
            expected: depth.len(),
            found: visibility.len(),
        });
    }
    Ok(depth
        .iter()
        .zip(visibility)
        .map(|(&d, &v)| d.max(f32::from_bits((v >> 32) as u32)))
        .collect())
}

/// Every level of the depth pyramid of `depth` (`width x height` reversed-Z values, row-major),
/// level 0 first, each row-major: texel `(i, j)` of a level is the minimum (farthest) of the
/// source values in its [`footprint`] on each axis.
///
/// Errors: [`ScreenError::BadSize`] for an empty or oversized screen, [`ScreenError::DepthLength`]
/// when `depth` is not `width * height` values long.
pub fn pyramid_reference(
    depth: &[f32],
    width: u32,
    height: u32,
) -> Result<Vec<Vec<f32>>, ScreenError> {
    let sizes = level_sizes(width, height)?;
    let expected = width as usize * height as usize;
    if depth.len() != expected {
        return Err(ScreenError::DepthLength {
            expected,
            found: depth.len(),
        });
    }
    let mut levels: Vec<Vec<f32>> = Vec::with_capacity(sizes.len());
    let mut source = (depth, width, height);
    for &(w, h) in &sizes {
        let level = reduce(source.0, source.1, source.2, w, h);
        levels.push(level);
        let last = levels.last().map_or(&[][..], Vec::as_slice);
        source = (last, w, h);
    }
    Ok(levels)
}

/// One level of `w x h` from a `sw x sh` source: the twin of `hiz_level0` / `hiz_reduce`
/// (first value of the footprint, then `min` over it row by row).
fn reduce(source: &[f32], sw: u32, sh: u32, w: u32, h: u32) -> Vec<f32> {
    let at = |x: u32, y: u32| source[y as usize * sw as usize + x as usize];
    let mut out = Vec::with_capacity(w as usize * h as usize);
    for j in 0..h {
        let (y0, y1) = footprint(j, h, sh);
        for i in 0..w {
            let (x0, x1) = footprint(i, w, sw);
            let mut m = at(x0, y0);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    m = m.min(at(x, y));
                }
            }
            out.push(m);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hiz::levels::pixel_span;
    use crate::hiz::test_rng::{TestRng, seed};

    #[test]
    fn a_hand_made_5x3_image() {
        // Level 0 is 2 x 1: texel 0 covers x 0..=1, texel 1 covers x 2..=4 (the odd column
        // joins the last texel), both cover y 0..=2.
        #[rustfmt::skip]
        let depth = [
            0.9, 0.8, 0.7, 0.6, 0.5,
            0.9, 0.4, 0.9, 0.9, 0.9,
            0.9, 0.9, 0.9, 0.9, 0.2,
        ];
        let levels = pyramid_reference(&depth, 5, 3).unwrap();
        assert_eq!(levels, [vec![0.4, 0.2], vec![0.2]]);
    }

    #[test]
    fn a_single_pixel_and_a_single_row() {
        assert_eq!(pyramid_reference(&[0.25], 1, 1).unwrap(), [vec![0.25]]);
        let row = [0.5, 0.1, 0.7, 0.3, 0.9, 0.6, 0.8];
        // 7 x 1: level 0 is 3 x 1 ({0,1}, {2,3}, {4,5,6}), level 1 is 1 x 1 (all three).
        assert_eq!(
            pyramid_reference(&row, 7, 1).unwrap(),
            [vec![0.1, 0.3, 0.6], vec![0.1]]
        );
        // The same values as a column.
        assert_eq!(
            pyramid_reference(&row, 1, 7).unwrap(),
            [vec![0.1, 0.3, 0.6], vec![0.1]]
        );
    }

    #[test]
    fn sky_is_the_minimum_and_one_far_pixel_reaches_the_top() {
        // 1920 x 1080 of near depth, one pixel of sky at the bottom-right corner (an odd row and
        // column of the last texels at several levels).
        let (w, h) = (1920u32, 1080u32);
        let mut depth = vec![0.75f32; (w * h) as usize];
        depth[(w * h - 1) as usize] = 0.0;
        let levels = pyramid_reference(&depth, w, h).unwrap();
        let sizes = level_sizes(w, h).unwrap();
        for (m, (level, &(lw, lh))) in levels.iter().zip(&sizes).enumerate() {
            for j in 0..lh {
                for i in 0..lw {
                    let v = level[(j * lw + i) as usize];
                    let corner = i + 1 == lw && j + 1 == lh;
                    assert_eq!(v, if corner { 0.0 } else { 0.75 }, "level {m} ({i}, {j})");
                }
            }
        }
        assert_eq!(levels.last().unwrap(), &[0.0]);
    }

    #[test]
    fn the_visibility_buffer_wins_where_nearer() {
        let depth = [0.5, 0.5, 0.0, 0.25];
        let word = |d: f32, payload: u32| (u64::from(d.to_bits()) << 32) | u64::from(payload);
        let vis = [0, word(0.75, 7), word(0.125, u32::MAX), word(0.25, 1)];
        assert_eq!(
            merge_visibility_reference(&depth, &vis).unwrap(),
            [0.5, 0.75, 0.125, 0.25]
        );
        assert_eq!(
            merge_visibility_reference(&depth, &vis[..3]),
            Err(ScreenError::VisibilityLength {
                expected: 4,
                found: 3
            })
        );
    }

    #[test]
    fn bad_input_is_an_error() {
        assert_eq!(
            pyramid_reference(&[0.0; 5], 2, 3),
            Err(ScreenError::DepthLength {
                expected: 6,
                found: 5
            })
        );
        assert!(matches!(
            pyramid_reference(&[], 0, 3),
            Err(ScreenError::BadSize { .. })
        ));
    }

    /// Random sizes and images: every texel of every level is the minimum of the screen pixels
    /// its pixel span covers (so it bounds each of them from below, conservatively), and the
    /// spans of a level tile the screen.
    #[test]
    fn every_texel_is_the_minimum_of_its_pixel_span() {
        let seed = seed(0x417a_5eed);
        let mut rng = TestRng::new(seed);
        for case in 0..300 {
            let (w, h) = if case % 10 == 0 {
                (1 + rng.below(3), 1 + rng.below(400))
            } else {
                (1 + rng.below(300), 1 + rng.below(300))
            };
            let depth: Vec<f32> = (0..w * h).map(|_| rng.depth()).collect();
            let levels = pyramid_reference(&depth, w, h).unwrap();
            let sizes = level_sizes(w, h).unwrap();
            assert_eq!(levels.len(), sizes.len());
            for (m, (level, &(lw, lh))) in levels.iter().zip(&sizes).enumerate() {
                assert_eq!(level.len(), (lw * lh) as usize);
                let mut covered = vec![0u8; depth.len()];
                for j in 0..lh {
                    let (y0, y1) = pixel_span(j, m as u32, lh, h);
                    for i in 0..lw {
                        let (x0, x1) = pixel_span(i, m as u32, lw, w);
                        let mut min = f32::INFINITY;
                        for y in y0..y1 {
                            for x in x0..x1 {
                                let p = (y * w + x) as usize;
                                covered[p] += 1;
                                min = min.min(depth[p]);
                            }
                        }
                        let texel = level[(j * lw + i) as usize];
                        assert_eq!(
                            texel, min,
                            "seed {seed}: {w}x{h} level {m} texel ({i}, {j})"
                        );
                    }
                }
                assert!(
                    covered.iter().all(|&c| c == 1),
                    "seed {seed}: {w}x{h} level {m}: spans do not tile the screen"
                );
            }
        }
    }
}
