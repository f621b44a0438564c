//! Octahedral unit-vector encoding in 8+8 bits ([`oct16_encode`]) and 16+16 bits
//! ([`oct32_encode`]).
//!
//! A direction `n` is projected onto the octahedron `|x| + |y| + |z| = 1`; the upper half
//! (`z >= 0`) maps straight onto the square `[-1, 1]^2` by `(x, y)`, the lower half is folded
//! over the square's diagonals into its corners. Each square coordinate is stored as a signed
//! normalized integer (two's complement, like `snorm8` / `snorm16`): code `c` stands for
//! `clamp(c * (1 / M), -1, 1)` with `M = 127` (8 bits) or `M = 32767` (16 bits), so `0` and
//! `±1` are exact and the six axis directions decode exactly. The most negative code
//! (`-128` / `-32768`) decodes like `-M`.
//!
//! Bit layout (low bits first):
//!
//! | format  | bits     | field                          |
//! | ------- | -------- | ------------------------------ |
//! | `oct16` | 0..8     | x code, `i8` two's complement  |
//! | `oct16` | 8..16    | y code, `i8` two's complement  |
//! | `oct32` | 0..16    | x code, `i16` two's complement |
//! | `oct32` | 16..32   | y code, `i16` two's complement |
//!
//! **Encoding** accepts any finite, non-zero vector; its length is ignored (the projection
//! divides by the L1 norm, after dividing by the largest component so that huge and tiny
//! vectors work too). NaN, infinite and zero-length input is a [`FormatError::InvalidNormal`].
//! It uses the "precise" variant: of the 4 codes around the projected point (floor and
//! floor + 1 on each axis) it keeps the one whose *decoded* vector is closest in angle to the
//! input. That lowers the worst-case error by a third compared with rounding each coordinate
//! (measured over the same 1,000,026 directions: 8+8 bits, 0.942 degrees rounded vs 0.638
//! precise; 16+16 bits, 0.00368 vs 0.00247 degrees).
//!
//! **Decoding** accepts every code and always returns a unit vector (length within a few ulps
//! of 1): unfold `z = 1 - |x| - |y|`, `t = max(-z, 0)`, `x -= sign(x) * t`, `y -= sign(y) * t`
//! (with `sign(0) = +1`), then normalize as `v * (1 / sqrt(dot(v, v)))`. The WGSL twins
//! `oct16_decode` / `oct32_decode` compute the same formula in `f32`; everything up to the
//! normalization is exact in both; the normalization (dot product, square root, reciprocal) may
//! differ in the last bits on a GPU.
//!
//! **Error bounds** ([`OCT16_MAX_ERROR_DEGREES`], [`OCT32_MAX_ERROR_DEGREES`]): measured as
//! the largest angle between a unit input and its decoded code over a Fibonacci sphere of
//! 1,000,000 points plus the 6 axes, 12 edge diagonals and 8 corner diagonals (the test
//! `tests/formats_octahedral.rs` repeats this measurement), then confirmed by 20 million random
//! directions with a hill-climbing search from the worst 50 (the ignored test
//! `search_for_worse_directions` there), and rounded up. The worst cases
//! lie near the corner diagonals `(±1, ±1, ±1) / sqrt(3)`, where the octahedral map stretches
//! most.

use glam::Vec3;

use super::FormatError;

/// Largest angle, in degrees, between a direction and `oct16_decode(oct16_encode(direction))`.
///
/// Measured maximum: 0.63799 degrees (1,000,026 sampled directions: 0.637991, at the corner
/// diagonals; a hill-climbing search found nothing above 0.637994).
pub const OCT16_MAX_ERROR_DEGREES: f32 = 0.64;

/// Largest angle, in degrees, between a direction and `oct32_decode(oct32_encode(direction))`.
///
/// Measured maximum: 0.00247 degrees (1,000,026 sampled directions: 0.0024705; a
/// hill-climbing search found 0.0024747).
pub const OCT32_MAX_ERROR_DEGREES: f32 = 0.0025;

/// The value of one step of an 8-bit code: `1 / 127`, rounded to `f32`.
pub const SNORM8_STEP: f32 = 1.0 / 127.0;

/// The value of one step of a 16-bit code: `1 / 32767`, rounded to `f32`.
pub const SNORM16_STEP: f32 = 1.0 / 32767.0;

/// Encodes a direction into 8+8 bits (layout in the [module docs](self)).
///
/// Fails with [`FormatError::InvalidNormal`] (field `"oct16"`) for a NaN, infinite or zero
/// vector. The input need not be unit length.
pub fn oct16_encode(direction: Vec3) -> Result<u16, FormatError> {
    oct16_encode_field(direction, "oct16")
}

/// Decodes 8+8 bits into a unit vector. Every code is valid.
pub fn oct16_decode(code: u16) -> Vec3 {
    let [x, y] = code.to_le_bytes();
    oct_decode(i32::from(x as i8), i32::from(y as i8), SNORM8_STEP)
}

/// Encodes a direction into 16+16 bits (layout in the [module docs](self)).
///
/// Fails with [`FormatError::InvalidNormal`] (field `"oct32"`) for a NaN, infinite or zero
/// vector. The input need not be unit length.
pub fn oct32_encode(direction: Vec3) -> Result<u32, FormatError> {
    let [x, y] = oct_encode(direction, 32767, SNORM16_STEP, "oct32")?;
    Ok(u32::from(x as i16 as u16) | u32::from(y as i16 as u16) << 16)
}

/// Decodes 16+16 bits into a unit vector. Every code is valid.
pub fn oct32_decode(code: u32) -> Vec3 {
    let x = code as u16 as i16;
    let y = (code >> 16) as u16 as i16;
    oct_decode(i32::from(x), i32::from(y), SNORM16_STEP)
}

/// [`oct16_encode`] with the field name to put in the error.
pub(crate) fn oct16_encode_field(direction: Vec3, field: &'static str) -> Result<u16, FormatError> {
    let [x, y] = oct_encode(direction, 127, SNORM8_STEP, field)?;
    Ok(u16::from_le_bytes([x as i8 as u8, y as i8 as u8]))
}

/// The shared decode formula (see the module docs); `step` is `1 / M`.
fn oct_decode(code_x: i32, code_y: i32, step: f32) -> Vec3 {
    let x = (code_x as f32 * step).clamp(-1.0, 1.0);
    let y = (code_y as f32 * step).clamp(-1.0, 1.0);
    let z = 1.0 - x.abs() - y.abs();
    let t = (-z).max(0.0);
    let x = if x >= 0.0 { x - t } else { x + t };
    let y = if y >= 0.0 { y - t } else { y + t };
    // Never zero: the unfolded vector has L1 norm 1 (up to rounding).
    Vec3::new(x, y, z).normalize()
}

/// The shared precise encoder: returns the two codes, each in `-max_code..=max_code`.
fn oct_encode(
    direction: Vec3,
    max_code: i32,
    step: f32,
    field: &'static str,
) -> Result<[i32; 2], FormatError> {
    let invalid = FormatError::InvalidNormal {
        field,
        value: direction.to_array(),
    };
    let largest = direction.abs().max_element();
    if !direction.is_finite() || largest == 0.0 {
        return Err(invalid);
    }
    // f64 from here on: exact enough that the 4 candidates always surround the true point.
    let n = to_f64(direction).map(|c| c / f64::from(largest));
    let l1 = n[0].abs() + n[1].abs() + n[2].abs();
    let (mut px, mut py) = (n[0] / l1, n[1] / l1);
    if n[2] < 0.0 {
        let (ax, ay) = (px.abs(), py.abs());
        px = (1.0 - ay) * sign_not_zero(px);
        py = (1.0 - ax) * sign_not_zero(py);
    }
    let scale = f64::from(max_code);
    let (fx, fy) = (floor_i32(px * scale), floor_i32(py * scale));

    let mut best = [0; 2];
    let mut best_score = f64::NEG_INFINITY;
    for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
        let cx = (fx + dx).clamp(-max_code, max_code);
        let cy = (fy + dy).clamp(-max_code, max_code);
        let d = to_f64(oct_decode(cx, cy, step));
        // cos^2 of the angle, signed: larger is closer. No square root needed, and exact
        // enough in f64 to rank codes 0.001 degrees apart.
        let dot = dot_f64(n, d);
        let score = dot * dot.abs() / (dot_f64(d, d) * dot_f64(n, n));
        if score > best_score {
            best_score = score;
            best = [cx, cy];
        }
    }
    Ok(best)
}

/// `+1` for `x >= 0` (including `-0.0`), else `-1`.
fn sign_not_zero(x: f64) -> f64 {
    if x >= 0.0 { 1.0 } else { -1.0 }
}

/// `floor(x)` for `|x| < 2^31` without `std`.
fn floor_i32(x: f64) -> i32 {
    let t = x as i32;
    if f64::from(t) > x { t - 1 } else { t }
}

fn to_f64(v: Vec3) -> [f64; 3] {
    v.to_array().map(f64::from)
}

fn dot_f64(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
