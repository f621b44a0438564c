//! The CPU twin of the Hi-Z rectangle test (`hiz_rect_level`, `hiz_rect_farthest` and
//! `hiz_rect_visible` in `hiz.wgsl`): the same clamping, the same level choice, the same four
//! texels and the same `min` order, so the GPU decides every rectangle as this does.

use std::cmp::Ordering;

use super::error::ScreenError;
use super::levels::{level_sizes, texel_of_pixel};

/// What the Hi-Z test decided for one rectangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RectTest {
    /// The inclusive pixel range tested, after ordering and clamping: `[x0, y0]` to `[x1, y1]`.
    pub pixels: [[u32; 2]; 2],
    /// The level read: the finest whose texels split that range at most 2 x 2.
    pub level: u32,
    /// The texels read at `level`: `[x0, y0]` to `[x1, y1]` (each axis 1 or 2 wide).
    pub texels: [[u32; 2]; 2],
    /// The minimum (farthest) depth of those texels: a lower bound of every pixel's depth.
    pub farthest: f32,
    /// `!(nearest_depth < farthest)`: false only when the object is behind everything drawn
    /// there.
    pub visible: bool,
}

/// Smallest shift `s` with `(hi >> s) - (lo >> s) <= 1` (`lo <= hi`): the twin of
/// `hiz_min_shift`. With `2^(g-1) <= hi - lo < 2^g` the answer is `g - 1` or `g`.
pub(crate) const fn min_shift(lo: u32, hi: u32) -> u32 {
    let e = hi - lo;
    if e == 0 {
        return 0;
    }
    let g = 32 - e.leading_zeros();
    let s = g - 1;
    if (hi >> s) - (lo >> s) <= 1 { s } else { g }
}

/// The pixel range of a rectangle on a pyramid whose level 0 is `size0`: the twin of
/// `hiz_rect_pixels`. Corners are ordered per axis, floored, and clamped to
/// `0 ..= 2 * size0 - 1` (texel for texel the same as clamping to the screen: the last texel
/// of every level takes the pixels past it).
fn rect_pixels(rect_min: [f32; 2], rect_max: [f32; 2], size0: (u32, u32)) -> [[u32; 2]; 2] {
    let bound = [2 * size0.0 - 1, 2 * size0.1 - 1];
    let pixel = |v: f32, axis: usize| {
        let clamped = v.floor().max(0.0).min(bound[axis] as f32);
        (clamped as u32).min(bound[axis])
    };
    let lo = [0, 1].map(|a| pixel(rect_min[a].min(rect_max[a]), a));
    let hi = [0, 1].map(|a| pixel(rect_min[a].max(rect_max[a]), a));
    [lo, hi]
}

/// The Hi-Z test of the screen rectangle `rect_min ..= rect_max` (pixels, x right, y down) of
/// an object whose largest (nearest) reversed-Z depth is `nearest_depth`, against `levels`,
/// the pyramid of a `width x height` screen (as [`pyramid_reference`](super::pyramid_reference)
/// or `gpu_backend`'s `DepthPyramid::read_levels` gives it).
///
/// Errors when `levels` is not that screen's pyramid ([`ScreenError::LevelCount`],
/// [`ScreenError::LevelLength`]) or the screen is invalid ([`ScreenError::BadSize`]). See the
/// [module docs](super) for the rules on empty, inverted and off-screen rectangles.
pub fn rect_test_reference(
    levels: &[Vec<f32>],
    width: u32,
    height: u32,
    rect_min: [f32; 2],
    rect_max: [f32; 2],
    nearest_depth: f32,
) -> Result<RectTest, ScreenError> {
    let sizes = level_sizes(width, height)?;
    if levels.len() != sizes.len() {
        return Err(ScreenError::LevelCount {
            expected: sizes.len(),
            found: levels.len(),
        });
    }
    for (level, (values, &(w, h))) in levels.iter().zip(&sizes).enumerate() {
        let expected = w as usize * h as usize;
        if values.len() != expected {
            return Err(ScreenError::LevelLength {
                level,
                expected,
                found: values.len(),
            });
        }
    }
    let [lo, hi] = rect_pixels(rect_min, rect_max, sizes[0]);
    let shift = min_shift(lo[0], hi[0]).max(min_shift(lo[1], hi[1])).max(1);
    let level = (shift - 1).min(sizes.len() as u32 - 1);
    let (w, h) = sizes[level as usize];
    let t0 = [
        texel_of_pixel(lo[0], level, w),
        texel_of_pixel(lo[1], level, h),
    ];
    let t1 = [
        texel_of_pixel(hi[0], level, w),
        texel_of_pixel(hi[1], level, h),
    ];
    let values = &levels[level as usize];
    let at = |x: u32, y: u32| values[y as usize * w as usize + x as usize];
    let a = at(t0[0], t0[1]);
    let b = at(t1[0], t0[1]);
    let c = at(t0[0], t1[1]);
    let d = at(t1[0], t1[1]);
    let farthest = a.min(b).min(c.min(d));
    Ok(RectTest {
        pixels: [lo, hi],
        level,
        texels: [t0, t1],
        farthest,
        // `!(nearest_depth < farthest)` in hiz.wgsl: a NaN depth is visible.
        visible: nearest_depth.partial_cmp(&farthest) != Some(Ordering::Less),
    })
}

/// [`rect_test_reference`]'s decision alone: `false` (occluded) only when `nearest_depth` is
/// below (farther than) the minimum of the texels read. The twin of `hiz_rect_visible`.
pub fn rect_visible_reference(
    levels: &[Vec<f32>],
    width: u32,
    height: u32,
    rect_min: [f32; 2],
    rect_max: [f32; 2],
    nearest_depth: f32,
) -> Result<bool, ScreenError> {
    rect_test_reference(levels, width, height, rect_min, rect_max, nearest_depth).map(|t| t.visible)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hiz::reference::pyramid_reference;
    use crate::hiz::test_rng::{TestRng, seed};

    #[test]
    fn min_shift_is_the_smallest_that_splits_at_most_twice() {
        for lo in 0..300u32 {
            for hi in lo..lo + 300 {
                let s = min_shift(lo, hi);
                assert!((hi >> s) - (lo >> s) <= 1, "{lo}..={hi}");
                if s > 0 {
                    assert!((hi >> (s - 1)) - (lo >> (s - 1)) > 1, "{lo}..={hi}");
                }
            }
        }
    }

    /// 8 x 4 screen, level 0 is 4 x 2, level 1 2 x 1, level 2 1 x 1.
    fn small() -> Vec<Vec<f32>> {
        #[rustfmt::skip]
        let depth = [
            0.5, 0.5, 0.5, 0.5, 0.9, 0.9, 0.1, 0.1,
            0.5, 0.5, 0.5, 0.5, 0.9, 0.9, 0.1, 0.1,
            0.5, 0.5, 0.5, 0.5, 0.9, 0.9, 0.9, 0.9,
            0.5, 0.5, 0.5, 0.5, 0.9, 0.9, 0.9, 0.9,
        ];
        pyramid_reference(&depth, 8, 4).unwrap()
    }

    #[test]
    fn hand_checked_rectangles() {
        let levels = small();
        let test = |min: [f32; 2], max: [f32; 2], nearest: f32| {
            rect_test_reference(&levels, 8, 4, min, max, nearest).unwrap()
        };
        // Inside the 0.9 block (pixels 4..=5 x 0..=3): level 0 texels (2, 0) and (2, 1).
        let t = test([4.2, 0.5], [5.9, 3.5], 0.8);
        assert_eq!(t.pixels, [[4, 0], [5, 3]]);
        assert_eq!((t.level, t.texels), (0, [[2, 0], [2, 1]]));
        assert_eq!(t.farthest, 0.9);
        assert!(!t.visible, "0.8 is behind 0.9");
        assert!(
            test([4.2, 0.5], [5.9, 3.5], 0.9).visible,
            "a tie is visible"
        );
        // Pixels 3..=4 span level 0 texels 1 and 2: still level 0, min 0.5.
        let t = test([3.0, 0.0], [4.5, 1.0], 0.6);
        assert_eq!((t.level, t.farthest, t.visible), (0, 0.5, true));
        // Pixels 1..=6: 6 >> 1 - 1 >> 1 = 3 texels at level 0; level 1 splits 0..=1 twice.
        let t = test([1.0, 0.0], [6.0, 0.0], 0.05);
        assert_eq!((t.level, t.texels), (1, [[0, 0], [1, 0]]));
        assert_eq!((t.farthest, t.visible), (0.1, false));
        // The whole screen and far beyond it: clamped, level 1 covers it 2 x 1.
        let t = test([-1e9, -5.0], [1e9, f32::INFINITY], 0.0);
        assert_eq!(t.pixels, [[0, 0], [7, 3]]);
        assert_eq!((t.level, t.farthest, t.visible), (1, 0.1, false));
        assert!(test([-1e9, -5.0], [1e9, f32::INFINITY], 0.2).visible);
        // Inverted corners test the rectangle between them.
        assert_eq!(
            test([5.9, 3.5], [4.2, 0.5], 0.8),
            test([4.2, 0.5], [5.9, 3.5], 0.8)
        );
        // Off screen to the right: the last column of pixels is tested.
        let t = test([100.0, 0.0], [120.0, 1.0], 0.05);
        assert_eq!(t.pixels, [[7, 0], [7, 1]]);
        assert_eq!((t.farthest, t.visible), (0.1, false));
    }

    #[test]
    fn levels_of_another_screen_are_an_error() {
        let levels = small();
        assert_eq!(
            rect_visible_reference(&levels, 16, 4, [0.0; 2], [1.0; 2], 0.5),
            Err(ScreenError::LevelCount {
                expected: 4,
                found: 3
            })
        );
        assert!(
            rect_visible_reference(&levels, 9, 4, [0.0; 2], [1.0; 2], 0.5).is_ok(),
            "9 x 4 has the pyramid shape of 8 x 4"
        );
        let mut short = levels.clone();
        short[1].pop();
        assert_eq!(
            rect_visible_reference(&short, 8, 4, [0.0; 2], [1.0; 2], 0.5),
            Err(ScreenError::LevelLength {
                level: 1,
                expected: 2,
                found: 1
            })
        );
    }

    /// Random screens, images and rectangles: an occluded verdict is always right (every
    /// pixel of the clamped rectangle is strictly farther than the object), the level is the
    /// finest that reads at most 2 x 2 texels, and both verdicts occur.
    #[test]
    fn occluded_means_behind_every_pixel_and_the_level_is_the_finest() {
        let seed = seed(0x0cc1_0de5);
        let mut rng = TestRng::new(seed);
        let (mut occluded, mut visible) = (0, 0);
        for _ in 0..60 {
            let (w, h) = (1 + rng.below(200), 1 + rng.below(200));
            // Blocky images (runs of equal depth) so that whole rectangles can be behind.
            let tile = 1 + rng.below(16);
            let tiles: Vec<f32> = (0..(w / tile + 1) * (h / tile + 1))
                .map(|_| rng.depth())
                .collect();
            let depth: Vec<f32> = (0..w * h)
                .map(|p| tiles[((p / w / tile) * (w / tile + 1) + p % w / tile) as usize])
                .collect();
            let levels = pyramid_reference(&depth, w, h).unwrap();
            let sizes = level_sizes(w, h).unwrap();
            for _ in 0..200 {
                let corner = |rng: &mut TestRng| {
                    [
                        rng.range(-20.0, w as f32 + 20.0),
                        rng.range(-20.0, h as f32 + 20.0),
                    ]
                };
                let (a, mut b) = (corner(&mut rng), corner(&mut rng));
                if rng.below(2) == 0 {
                    // Small rectangles are the common case.
                    b = [a[0] + rng.range(0.0, 12.0), a[1] + rng.range(0.0, 12.0)];
                }
                let nearest = rng.depth();
                let t = rect_test_reference(&levels, w, h, a, b, nearest).unwrap();
                let [lo, hi] = t.pixels;
                let (lo, hi) = (
                    [lo[0].min(w - 1), lo[1].min(h - 1)],
                    [hi[0].min(w - 1), hi[1].min(h - 1)],
                );
                let mut min = f32::INFINITY;
                for y in lo[1]..=hi[1] {
                    for x in lo[0]..=hi[0] {
                        min = min.min(depth[(y * w + x) as usize]);
                    }
                }
                assert!(t.farthest <= min, "seed {seed}: {w}x{h} {a:?} {b:?}: {t:?}");
                if t.visible {
                    visible += 1;
                } else {
                    occluded += 1;
                    assert!(nearest < min, "seed {seed}: {w}x{h} {a:?} {b:?}: {t:?}");
                }
                assert!(t.texels[1][0] - t.texels[0][0] <= 1);
                assert!(t.texels[1][1] - t.texels[0][1] <= 1);
                let top = sizes.len() as u32 - 1;
                if t.level > 0 && t.level < top {
                    // At the level below, the texel grid (before the last texel takes the
                    // pixels past it) splits the range more than twice on some axis.
                    let shift = t.level;
                    let [lo, hi] = t.pixels;
                    assert!(
                        (hi[0] >> shift) - (lo[0] >> shift) > 1
                            || (hi[1] >> shift) - (lo[1] >> shift) > 1,
                        "seed {seed}: {w}x{h} {a:?} {b:?}: level {} is not the finest",
                        t.level
                    );
                }
            }
        }
        assert!(
            occluded > 1000 && visible > 1000,
            "seed {seed}: {occluded} occluded, {visible} visible: the test exercises too little"
        );
    }
}
