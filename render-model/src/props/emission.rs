//! A prop's emission in the G-buffer: the glTF emissive colour (`emissiveFactor *
//! emissiveTexture * KHR_materials_emissive_strength`, linear) packed into bits the voxel
//! path leaves free, and added by the lighting pass after shading, as the voxels' palette
//! emission is (`render_common.wgsl`'s `prop_emission_*` twin these functions).
//!
//! # Where it lives
//!
//! The G-buffer's normal target holds `(oct32 normal, material)`, and block ids take the
//! material word's low 16 bits only; its albedo target holds sRGB colour and AO in alpha, and
//! a prop's AO is always full. So an emissive prop pixel writes a 24-bit emission word `w`
//! ([`encode_emission`]) as
//!
//! ```text
//! albedo.a = (w & 0xff) / 255                 (AO is full: 3)
//! material = (w >> 8) << 16 | 0               (bit 31 = w's bit 23, set for every w != 0)
//! ```
//!
//! and the lighting pass reads a pixel whose material word has bit 31 set as an emissive
//! prop: AO 3, palette material 0, emission [`decode_emission`]`(w)`. Every other pixel
//! (voxels, grass, props that do not glow) has bit 31 clear and reads as before.
//!
//! # The word
//!
//! A shared-exponent colour, like `RGB9E5` with 6-bit mantissas (low bits first):
//!
//! ```text
//! bits  0..6   red mantissa   m_r
//! bits  6..12  green mantissa m_g
//! bits 12..18  blue mantissa  m_b
//! bits 18..23  exponent       e        c = m_c * 2^(e - EMISSION_BIAS - 6)
//! bit  23      1 (emissive)
//! ```
//!
//! The exponent is the brightest channel's: `e = floor(log2(max)) + 1 + EMISSION_BIAS`, read
//! from the `f32` bits, so the brightest channel's mantissa is 32..=63 (6 significant bits)
//! and every channel is within half a step, at most 1/63 of the brightest; below `2^-EMISSION_BIAS`
//! (far dimmer than anything the eye sees glow) the exponent stays 0 and every channel is a
//! multiple of `2^(-EMISSION_BIAS - 6)`, within half of it. Channels run from
//! [`EMISSION_MIN`] (below it a channel is 0; a colour whose brightest is below it is no
//! emission, word 0) to [`EMISSION_MAX`]; the prop store refuses a material whose emissive
//! colour exceeds it, by name.

/// Added to the exponent: the smallest exponent field (0) stands for `2^-EMISSION_BIAS`.
pub const EMISSION_BIAS: i32 = 15;

/// The largest channel an emission word holds: `63 * 2^(31 - EMISSION_BIAS - 6)`.
pub const EMISSION_MAX: f32 = 63.0 * 1024.0;

/// The smallest brightest channel that is emission: half the finest step,
/// `2^(-EMISSION_BIAS - 7)`.
pub const EMISSION_MIN: f32 = 1.0 / (1u32 << 22) as f32;

/// The emission word's flag bit (set in every non-zero word).
pub const EMISSION_FLAG: u32 = 1 << 23;

/// The emission word of linear colour `rgb` (see the [module docs](self)): 0 when its
/// brightest channel is below [`EMISSION_MIN`] or not a number; channels are taken as at most
/// [`EMISSION_MAX`] and at least 0 (the store checks materials against the maximum first).
pub fn encode_emission(rgb: [f32; 3]) -> u32 {
    let c = rgb.map(|v| {
        if v.is_nan() {
            0.0
        } else {
            v.clamp(0.0, EMISSION_MAX)
        }
    });
    let max = c[0].max(c[1]).max(c[2]);
    if max < EMISSION_MIN {
        return 0;
    }
    // floor(log2(max)) from the f32 bits: exact, as on the GPU (max is normal here).
    let floor_log2 = ((max.to_bits() >> 23) & 0xff) as i32 - 127;
    let mut e = (floor_log2 + 1 + EMISSION_BIAS).clamp(0, 31);
    // Times the step's inverse, a power of two: exact, where a GPU division need not be.
    let mut inv_step = exp2i(EMISSION_BIAS + 6 - e);
    if (max * inv_step + 0.5).floor() >= 64.0 {
        e += 1;
        inv_step *= 0.5;
    }
    let m = c.map(|v| ((v * inv_step + 0.5).floor() as u32).min(63));
    m[0] | m[1] << 6 | m[2] << 12 | (e as u32) << 18 | EMISSION_FLAG
}

/// The linear colour of emission word `w` (0 when its flag is clear; bits above 23 ignored).
pub fn decode_emission(w: u32) -> [f32; 3] {
    if w & EMISSION_FLAG == 0 {
        return [0.0; 3];
    }
    let e = ((w >> 18) & 31) as i32;
    let step = exp2i(e - EMISSION_BIAS - 6);
    [w & 63, (w >> 6) & 63, (w >> 12) & 63].map(|m| m as f32 * step)
}

/// `2^k` for the exponents the word uses (exact).
fn exp2i(k: i32) -> f32 {
    f32::from_bits(((k + 127).clamp(1, 254) as u32) << 23)
}

/// The G-buffer halves of emission word `w`: the albedo alpha byte and the material word's
/// upper 16 bits (already shifted), so `material | high` is what a prop pixel writes.
pub fn split_emission(w: u32) -> (u8, u32) {
    ((w & 0xff) as u8, (w >> 8) << 16)
}

/// The emission word of a G-buffer pixel: its albedo alpha byte and material word (0 when
/// the material word's bit 31 is clear: no emission, the alpha is AO).
pub fn join_emission(alpha: u8, material: u32) -> u32 {
    if material & (1 << 31) == 0 {
        return 0;
    }
    (material >> 16) << 8 | u32::from(alpha)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_word_keeps_six_bits_of_the_brightest_channel() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u32 << 24) as f32
        };
        for _ in 0..20_000 {
            let scale = exp2i((next() * 40.0) as i32 - 20);
            let rgb = [next() * scale, next() * scale, next() * scale];
            let max = rgb[0].max(rgb[1]).max(rgb[2]);
            if max > EMISSION_MAX {
                continue;
            }
            let back = decode_emission(encode_emission(rgb));
            if max < EMISSION_MIN {
                assert_eq!(back, [0.0; 3]);
                continue;
            }
            let bound = (max / 63.0).max(EMISSION_MIN);
            for i in 0..3 {
                assert!(
                    (back[i] - rgb[i]).abs() <= bound,
                    "{rgb:?} came back as {back:?}"
                );
            }
            let bmax = back[0].max(back[1]).max(back[2]);
            let bound = (max / 63.0).max(EMISSION_MIN);
            assert!((bmax - max).abs() <= bound, "{rgb:?} -> {back:?}");
        }
    }

    #[test]
    fn extremes_and_the_gbuffer_halves() {
        assert_eq!(encode_emission([0.0; 3]), 0);
        assert_eq!(encode_emission([f32::NAN, -1.0, 0.0]), 0);
        assert_eq!(
            decode_emission(encode_emission([EMISSION_MAX; 3])),
            [EMISSION_MAX; 3]
        );
        assert_eq!(
            decode_emission(encode_emission([1.0, 0.5, 0.25])),
            [1.0, 0.5, 0.25]
        );
        // A power of two rounds up into the next exponent rather than past 63.
        let just_below = decode_emission(encode_emission([0.999_9, 0.0, 0.0]));
        assert_eq!(just_below, [1.0, 0.0, 0.0]);
        let w = encode_emission([3.0, 0.2, 0.7]);
        assert_ne!(w & EMISSION_FLAG, 0);
        let (alpha, high) = split_emission(w);
        assert_eq!(
            join_emission(alpha, high | 7),
            w,
            "a palette id below does not matter"
        );
        assert_ne!(high & 1 << 31, 0, "the flag lands on bit 31");
        assert_eq!(
            join_emission(255, 0xffff),
            0,
            "a block id alone is no emission"
        );
        assert_eq!(decode_emission(0xff_ffff & !EMISSION_FLAG), [0.0; 3]);
    }
}
