//! The shape of a depth pyramid: level sizes and which texels (or pixels) each texel covers.
//! Shared by the GPU pyramid ([`DepthPyramid`](super::DepthPyramid)) and the CPU references, so
//! both sides size and walk the levels the same way.

use super::error::ScreenError;

/// Largest screen edge a pyramid accepts on the CPU side (the GPU side is also bounded by the
/// device's `max_texture_dimension_2d`): keeps `W * H` and every pixel coordinate far from
/// `u32` overflow in the shaders.
pub const MAX_SCREEN_EDGE: u32 = 1 << 15;

/// Size of the level below a `size` texel (or pixel) edge: `max(1, size / 2)`, rounded down,
/// exactly like a wgpu mip chain.
pub const fn half(size: u32) -> u32 {
    if size > 1 { size / 2 } else { 1 }
}

/// `(width, height)` of every level of the pyramid of a `width x height` screen, level 0 first.
///
/// Level 0 is `max(1, W / 2) x max(1, H / 2)` and each level halves the one before it, rounding
/// down, down to 1 x 1: the mip chain wgpu gives a texture of level 0's size, so every level
/// is exactly one mip (see the [module docs](super) for why not `ceil`).
pub fn level_sizes(width: u32, height: u32) -> Result<Vec<(u32, u32)>, ScreenError> {
    check_screen(width, height, MAX_SCREEN_EDGE)?;
    let mut size = (half(width), half(height));
    let mut sizes = vec![size];
    while size != (1, 1) {
        size = (half(size.0), half(size.1));
        sizes.push(size);
    }
    Ok(sizes)
}

/// [`ScreenError::BadSize`] unless both edges are in `1..=max`.
pub fn check_screen(width: u32, height: u32, max: u32) -> Result<(), ScreenError> {
    let max = max.min(MAX_SCREEN_EDGE);
    if width == 0 || height == 0 || width > max || height > max {
        return Err(ScreenError::BadSize { width, height, max });
    }
    Ok(())
}

/// The inclusive range of source indices (pixels for level 0, texels of level `m - 1` for level
/// `m`) that index `i` of a level `dest` wide covers, along one axis of a source `source` wide:
/// `2i ..= 2i + 1`, except that the last index also takes the odd one left over, `2i ..=
/// source - 1` (2 or 3 wide; 1 wide when `source` is 1). The same rule as `hiz_footprint` in
/// `hiz_build.wgsl`.
pub const fn footprint(i: u32, dest: u32, source: u32) -> (u32, u32) {
    let lo = 2 * i;
    let hi = if i + 1 == dest {
        source - 1
    } else if lo + 1 < source {
        lo + 1
    } else {
        source - 1
    };
    (lo, hi)
}

/// The texel of a level `size` wide that covers pixel `x` at level `level`: `x >> (level + 1)`,
/// with pixels past the last texel's start taken by the last texel. The same rule as
/// `hiz_texel_of_pixel` in `hiz.wgsl`.
pub const fn texel_of_pixel(x: u32, level: u32, size: u32) -> u32 {
    let t = x >> (level + 1);
    if t < size { t } else { size - 1 }
}

/// The half-open pixel range `[start, end)` that texel `i` of a level `size` wide covers at
/// `level`, on a screen `screen` pixels wide: `[i * 2^(level+1), (i + 1) * 2^(level+1))`, the
/// last texel's range reaching to the screen edge.
pub const fn pixel_span(i: u32, level: u32, size: u32, screen: u32) -> (u32, u32) {
    let start = i << (level + 1);
    let end = if i + 1 == size {
        screen
    } else {
        (i + 1) << (level + 1)
    };
    (start, end)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_halve_down_to_one() {
        assert_eq!(
            level_sizes(37, 23).unwrap(),
            [(18, 11), (9, 5), (4, 2), (2, 1), (1, 1)]
        );
        assert_eq!(level_sizes(1, 1).unwrap(), [(1, 1)]);
        assert_eq!(level_sizes(3, 1).unwrap(), [(1, 1)]);
        assert_eq!(level_sizes(4, 1).unwrap(), [(2, 1), (1, 1)]);
        let hd = level_sizes(1920, 1080).unwrap();
        assert_eq!(hd.len(), 10);
        assert_eq!(hd[0], (960, 540));
        assert_eq!(hd[3], (120, 67));
        assert_eq!(hd[9], (1, 1));
    }

    #[test]
    fn bad_sizes_are_errors() {
        for (w, h) in [(0, 5), (5, 0), (MAX_SCREEN_EDGE + 1, 1)] {
            assert!(matches!(
                level_sizes(w, h),
                Err(ScreenError::BadSize { width, height, .. }) if (width, height) == (w, h)
            ));
        }
        assert!(level_sizes(MAX_SCREEN_EDGE, 1).is_ok());
    }

    #[test]
    fn footprints_tile_the_source() {
        for source in 1..70 {
            let dest = half(source);
            let mut next = 0;
            for i in 0..dest {
                let (lo, hi) = footprint(i, dest, source);
                assert_eq!(lo, next, "source {source} index {i}");
                assert!(hi >= lo && hi - lo <= 2 && hi < source);
                next = hi + 1;
            }
            assert_eq!(next, source, "source {source} fully covered");
        }
    }

    #[test]
    fn texel_of_pixel_inverts_pixel_span() {
        for screen in 1..80 {
            let mut size = half(screen);
            for level in 0..8 {
                for x in 0..screen {
                    let t = texel_of_pixel(x, level, size);
                    let (start, end) = pixel_span(t, level, size, screen);
                    assert!(start <= x && x < end, "screen {screen} level {level} x {x}");
                }
                size = half(size);
            }
        }
    }
}
