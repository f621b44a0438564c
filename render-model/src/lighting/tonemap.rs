//! The sRGB transfer functions and the hue-preserving tonemap (the rule is in the
//! [module docs](super)).

/// Largest channel below which [`neutral`] passes a colour unchanged.
pub const COMPRESSION_START: f32 = 0.85;

/// How fast compressed highlights turn white (Khronos PBR Neutral's value).
pub const DESATURATION: f32 = 0.15;

/// The sRGB transfer function's inverse: an 8-bit sRGB code to linear `0..=1`.
pub fn srgb_to_linear(code: u8) -> f32 {
    let c = f32::from(code) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear `0..=1` to an 8-bit sRGB code, rounded to nearest (what an `Rgba8UnormSrgb` render
/// target stores, up to one code of rounding). The tonemap's output is in `0..=1` already;
/// the clamp only guards rounding.
pub fn linear_to_srgb8(c: f32) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

/// The hue-preserving highlight compression of the display-linear colour `c` (non-negative
/// channels): unchanged while its largest channel is below [`COMPRESSION_START`], above it
/// scaled so the largest channel approaches 1, and desaturated towards white. Twin of the
/// WGSL `neutral`, same operations.
pub fn neutral(c: [f32; 3]) -> [f32; 3] {
    let c = c.map(|v| v.max(0.0));
    let peak = c[0].max(c[1]).max(c[2]);
    if peak < COMPRESSION_START {
        return c;
    }
    let d = 1.0 - COMPRESSION_START;
    let new_peak = 1.0 - d * d / (peak + d - COMPRESSION_START);
    let scale = new_peak / peak;
    let g = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
    c.map(|v| {
        let scaled = v * scale;
        scaled + (new_peak - scaled) * g
    })
}

/// What the output target stores for a display-linear colour: [`neutral`] then sRGB, alpha
/// 255.
pub fn output_rgba8(colour: [f32; 3]) -> [u8; 4] {
    let [r, g, b] = neutral(colour).map(linear_to_srgb8);
    [r, g, b, 255]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips_every_code() {
        for code in 0..=255u8 {
            assert_eq!(linear_to_srgb8(srgb_to_linear(code)), code);
        }
    }

    #[test]
    fn colours_below_the_knee_pass_unchanged() {
        for c in [[0.0, 0.0, 0.0], [0.84, 0.2, 0.01], [0.3, 0.3, 0.3]] {
            assert_eq!(neutral(c), c);
        }
    }

    #[test]
    fn compression_is_monotonic_bounded_and_keeps_channel_order() {
        let mut last = -1.0;
        for i in 0..2000 {
            let x = i as f32 * 0.01;
            let [r, g, b] = neutral([x, 0.5 * x, 0.25 * x]);
            assert!((0.0..=1.0).contains(&r) && r >= last, "{x}: {r}");
            assert!(r >= g && g >= b, "{x}: {r} {g} {b}");
            last = r;
        }
    }

    #[test]
    fn hue_is_kept_until_highlights_whiten() {
        // Just above the knee the ratios of the channels are kept to within the desaturation.
        let [r, g, b] = neutral([0.95, 0.475, 0.095]);
        assert!((g / r - 0.5).abs() < 0.01 && (b / r - 0.1).abs() < 0.01);
    }
}
