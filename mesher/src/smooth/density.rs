//! Density sample types and the up-front pass that checks a grid and builds its inside masks.

use alloc::vec::Vec;

use glam::Vec4;

use super::GridShape;
use crate::MeshError;

/// The density one step of an `i8` sample stands for: sample `q` is the density
/// `q as f32 * I8_DENSITY_STEP`, so `-127..=127` covers `-1.0..=1.0` (and `-128` reads as
/// `-128 / 127`). See [`quantize_density`].
pub const I8_DENSITY_STEP: f32 = 1.0 / 127.0;

/// The `i8` sample nearest to `density` clamped to `-1.0..=1.0`: `round(clamp(d) * 127)`, ties
/// away from zero; NaN maps to 0 (outside).
///
/// The sign convention survives quantization except for densities in `(-0.5 / 127, 0)`, which
/// round to 0 and so read as outside: store signed distances scaled so that the band that
/// matters spans `-1..=1` (for example distance in voxels divided by 4).
pub fn quantize_density(density: f32) -> i8 {
    let d = density.clamp(-1.0, 1.0) * 127.0;
    let half = if d >= 0.0 { 0.5 } else { -0.5 };
    // NaN `as` i8 is 0; the clamp bounds the rest to -127..=127.
    (d + half) as i8
}

/// A density sample type: negative is inside, zero and positive are outside.
pub(crate) trait Density: Copy {
    /// The density as `f32` (the same value for equal samples, every time):
    /// `raw() * SCALE`.
    fn value(self) -> f32;

    /// Whether [`raw`](Self::raw) needs scaling by [`SCALE`](Self::SCALE).
    const SCALED: bool;
    /// The density of one unit of [`raw`](Self::raw).
    const SCALE: f32;
    /// The sample as `f32`, unscaled (exact).
    fn raw(self) -> f32;

    /// The inside mask of a row of at most 64 samples (bit `i` set iff `row[i]` is negative),
    /// or the offset of the first non-finite sample in the row.
    fn row_mask(row: &[Self]) -> Result<u64, usize>;
}

impl Density for f32 {
    const SCALED: bool = false;
    const SCALE: f32 = 1.0;

    #[inline]
    fn value(self) -> f32 {
        self
    }

    #[inline]
    fn raw(self) -> f32 {
        self
    }

    #[inline]
    fn row_mask(row: &[f32]) -> Result<u64, usize> {
        // 4 samples per step: the sign test is one compare and a `movmskps`. Non-finite values
        // are the ones whose product with zero is NaN, and one NaN poisons the running sum.
        let mut mask = 0u64;
        let mut poison = Vec4::ZERO;
        let quads = row.chunks_exact(4);
        let tail = quads.remainder();
        for (k, q) in quads.enumerate() {
            let v = Vec4::from_slice(q);
            mask |= u64::from(v.cmplt(Vec4::ZERO).bitmask()) << (4 * k);
            poison += v * 0.0;
        }
        let base = row.len() - tail.len();
        let mut tail_poison = 0.0f32;
        for (i, &v) in tail.iter().enumerate() {
            mask |= u64::from(v < 0.0) << (base + i);
            tail_poison += v * 0.0;
        }
        if poison.is_nan() || tail_poison.is_nan() {
            Err(row.iter().position(|v| !v.is_finite()).unwrap_or(0))
        } else {
            Ok(mask)
        }
    }
}

impl Density for i8 {
    const SCALED: bool = true;
    const SCALE: f32 = I8_DENSITY_STEP;

    #[inline]
    fn value(self) -> f32 {
        f32::from(self) * I8_DENSITY_STEP
    }

    #[inline]
    fn raw(self) -> f32 {
        f32::from(self)
    }

    #[inline]
    fn row_mask(row: &[i8]) -> Result<u64, usize> {
        // 8 samples per step: gather the 8 sign bits of a word with one multiplication (bit
        // `56 + i` of the product is the sign of byte `i`, and no two partial products overlap).
        let mut mask = 0u64;
        let bytes = row.chunks_exact(8);
        let tail = bytes.remainder();
        for (k, b) in bytes.enumerate() {
            let w = u64::from_le_bytes(core::array::from_fn(|i| b[i] as u8));
            let signs =
                ((w >> 7) & 0x0101_0101_0101_0101).wrapping_mul(0x0102_0408_1020_4080) >> 56;
            mask |= signs << (8 * k);
        }
        let base = row.len() - tail.len();
        for (i, &v) in tail.iter().enumerate() {
            mask |= u64::from((v as u8) >> 7) << (base + i);
        }
        Ok(mask)
    }
}

/// What the up-front pass found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Fill {
    /// No sample is inside: no surface.
    Empty,
    /// Every sample is inside: no surface.
    Full,
    /// Both: mesh it.
    Mixed,
}

/// Words per mask row for rows of `dx` samples.
#[inline]
pub(crate) fn words_per_row(dx: u32) -> usize {
    (dx as usize).div_ceil(64)
}

/// The bits `start..start + len` (`len <= 64`) of the bitset `bits`, as the low bits of a word.
#[inline]
fn extract(bits: &[u64], start: usize, len: usize) -> u64 {
    let (i, shift) = (start / 64, start % 64);
    let lo = bits[i] >> shift;
    let hi = match (shift, bits.get(i + 1)) {
        (1.., Some(&next)) => next << (64 - shift),
        _ => 0,
    };
    let keep = if len == 64 {
        u64::MAX
    } else {
        (1u64 << len) - 1
    };
    (lo | hi) & keep
}

/// Checks `samples` against `shape` and every sample for NaN / infinity, and fills `masks` with
/// one inside mask per row (`words_per_row` words each, row `y + dy * z`, bit `x % 64` of word
/// `x / 64`). Errors name the first bad sample in storage order.
///
/// The samples are read as one flat array, 64 at a time, into the bitset `flat` (bit `i` = sample
/// `i` is inside); the row masks are then cut out of it.
pub(crate) fn build_masks<D: Density>(
    samples: &[D],
    shape: GridShape,
    flat: &mut Vec<u64>,
    masks: &mut Vec<u64>,
) -> Result<Fill, MeshError> {
    if samples.len() != shape.sample_count() {
        return Err(MeshError::BadShape {
            reason: "density sample count does not match the grid shape",
            value: samples.len(),
        });
    }
    flat.clear();
    let (mut any, mut all) = (0u64, u64::MAX);
    for (k, block) in samples.chunks(64).enumerate() {
        let m = D::row_mask(block).map_err(|offset| MeshError::NonFiniteDensity {
            index: 64 * k + offset,
            value: block[offset].value(),
        })?;
        flat.push(m);
        any |= m;
        all &= if block.len() == 64 {
            m
        } else {
            m | (u64::MAX << block.len())
        };
    }
    if any == 0 {
        return Ok(Fill::Empty);
    }
    if all == u64::MAX {
        return Ok(Fill::Full);
    }

    let dx = shape.dims()[0] as usize;
    let wpr = words_per_row(dx as u32);
    let rows = samples.len() / dx;
    masks.clear();
    masks.reserve(rows * wpr);
    for r in 0..rows {
        for w in 0..wpr {
            let len = (dx - 64 * w).min(64);
            masks.push(extract(flat, r * dx + 64 * w, len));
        }
    }
    Ok(Fill::Mixed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantize_density_rounds_and_clamps() {
        assert_eq!(quantize_density(0.0), 0);
        assert_eq!(quantize_density(-1.0), -127);
        assert_eq!(quantize_density(5.0), 127);
        assert_eq!(quantize_density(-0.003), 0);
        assert_eq!(quantize_density(-0.004), -1);
        assert_eq!(quantize_density(f32::NAN), 0);
        for q in -127..=127i8 {
            assert_eq!(quantize_density(q.value()), q);
        }
    }

    #[test]
    fn row_masks_match_a_plain_loop() {
        let f: Vec<f32> = (0..64)
            .map(|i| {
                if (i * 7) % 5 < 2 {
                    -1.0
                } else {
                    (i % 3) as f32
                }
            })
            .collect();
        let q: Vec<i8> = (0..64).map(|i| ((i * 37) % 256) as u8 as i8).collect();
        for len in [0, 1, 3, 4, 5, 8, 9, 34, 63, 64] {
            let plain = |neg: &dyn Fn(usize) -> bool| {
                (0..len).fold(0u64, |m, i| m | u64::from(neg(i)) << i)
            };
            assert_eq!(f32::row_mask(&f[..len]), Ok(plain(&|i| f[i] < 0.0)));
            assert_eq!(i8::row_mask(&q[..len]), Ok(plain(&|i| q[i] < 0)));
        }
        let mut g = f.clone();
        g[41] = f32::NAN;
        g[50] = f32::INFINITY;
        assert_eq!(
            f32::row_mask(&g[..34]),
            Ok(f32::row_mask(&f[..34]).unwrap())
        );
        assert_eq!(f32::row_mask(&g[..42]), Err(41));
        assert_eq!(f32::row_mask(&g[42..]), Err(8));
    }

    #[test]
    fn masks_and_fill() {
        let shape = GridShape::new([70, 3, 3]).unwrap();
        let mut s = alloc::vec![1.0f32; shape.sample_count()];
        let (mut flat, mut masks) = (Vec::new(), Vec::new());
        let mut build = |s: &[f32]| build_masks(s, shape, &mut flat, &mut masks);
        assert_eq!(build(&s), Ok(Fill::Empty));
        s[shape.index([65, 1, 2])] = -0.5;
        s[shape.index([3, 2, 1])] = -0.5;
        assert_eq!(build(&s), Ok(Fill::Mixed));
        assert_eq!(masks[2 * (1 + 3 * 2) + 1], 1 << 1);
        assert_eq!(masks[2 * (2 + 3)], 1 << 3);
        assert_eq!(masks.iter().map(|m| m.count_ones()).sum::<u32>(), 2);
        let mut build = |s: &[f32]| build_masks(s, shape, &mut flat, &mut masks);
        s.fill(-1.0);
        assert_eq!(build(&s), Ok(Fill::Full));
        s[shape.index([66, 2, 1])] = f32::NEG_INFINITY;
        assert_eq!(
            build(&s),
            Err(MeshError::NonFiniteDensity {
                index: shape.index([66, 2, 1]),
                value: f32::NEG_INFINITY
            })
        );
        assert!(matches!(build(&s[1..]), Err(MeshError::BadShape { .. })));
    }
}
