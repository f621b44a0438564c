//! The lighting model of the deferred renderer, and its CPU twin: one [`Lighting`] for every
//! renderer of the stack (the GPU passes, the CPU raycasters, the viewer).
//!
//! One formula, written twice: in WGSL (`gpu-backend`'s `render_common.wgsl`, used by the
//! lighting pass and the transparent pass) and here in Rust, operation for operation, so a CPU
//! renderer (the viewer's reference raycaster) can shade exactly like the GPU and images can
//! be compared.
//!
//! ```text
//! ambient  = mix(ground, sky, 0.5 + 0.5 * n.y) * ambient_strength      hemisphere light
//! occluded = ambient * (AO_FLOOR + (1 - AO_FLOOR) * ao / 3)            per-vertex AO (0..=3)
//! colour   = albedo * (occluded + sun * max(dot(n, l), 0))             Lambert sun, no shadows
//!          + albedo * emission * emissive_scale                         palette emission 0..=1
//! output   = srgb(aces(colour * exposure))                              tonemap, sRGB target
//! ```
//!
//! Albedo is the palette's sRGB colour decoded to linear ([`srgb_to_linear`]). The sky (no
//! geometry) is `sky_colour`, tonemapped the same way. There are no shadows: the deferred pass
//! has no shadow map.

use bytemuck::{Pod, Zeroable};

/// Ambient light left at the most occluded corner (AO 0); AO 3 keeps all of it.
pub const AO_FLOOR: f32 = 0.4;

/// Light and sky of a frame. Colours are linear RGB; the sun direction points towards the sun.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lighting {
    /// Unit direction towards the sun.
    pub sun_direction: [f32; 3],
    /// Linear sun radiance.
    pub sun_colour: [f32; 3],
    /// Linear sky colour: ambient from above, and the background.
    pub sky_colour: [f32; 3],
    /// Linear ambient from below.
    pub ground_colour: [f32; 3],
    /// Scale of the hemisphere ambient.
    pub ambient_strength: f32,
    /// Scale of palette emission (`emission / 255 * emissive_scale * albedo`).
    pub emissive_scale: f32,
    /// Multiplies the linear colour before the tonemap.
    pub exposure: f32,
}

impl Default for Lighting {
    /// The viewer's default daylight.
    fn default() -> Self {
        let d = [0.45f32, 0.8, 0.35];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        Lighting {
            sun_direction: d.map(|c| c / len),
            sun_colour: [1.0 * 2.2, 0.95 * 2.2, 0.85 * 2.2],
            sky_colour: [0.45, 0.62, 0.9],
            ground_colour: [0.25, 0.22, 0.2],
            ambient_strength: 0.55,
            emissive_scale: 4.0,
            exposure: 1.0,
        }
    }
}

/// The sRGB transfer function's inverse: an 8-bit sRGB code to linear `0..=1`.
pub fn srgb_to_linear(code: u8) -> f32 {
    let c = f32::from(code) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear `0..=1` (clamped) to an 8-bit sRGB code, rounded to nearest (what an
/// `Rgba8UnormSrgb` render target stores, up to one code of rounding).
pub fn linear_to_srgb8(c: f32) -> u8 {
    let c = c.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0 + 0.5) as u8
}

/// The ambient multiplier of an interpolated AO value (`0..=3`, 3 = unoccluded).
pub fn ao_factor(ao: f32) -> f32 {
    AO_FLOOR + (1.0 - AO_FLOOR) * (ao / 3.0)
}

fn mix(a: [f32; 3], b: [f32; 3], t: f32) -> [f32; 3] {
    std::array::from_fn(|i| a[i] + (b[i] - a[i]) * t)
}

/// Linear colour of a surface point (the formula in the [module docs](self)).
///
/// `albedo` linear, `normal` unit length, `ao` interpolated `0..=3`, `emission` `0..=1`.
pub fn shade(
    params: &Lighting,
    albedo: [f32; 3],
    normal: [f32; 3],
    ao: f32,
    emission: f32,
) -> [f32; 3] {
    let hemisphere = 0.5 + 0.5 * normal[1];
    let ambient = mix(params.ground_colour, params.sky_colour, hemisphere);
    let occlusion = ao_factor(ao) * params.ambient_strength;
    let l = params.sun_direction;
    let n_dot_l = (normal[0] * l[0] + normal[1] * l[1] + normal[2] * l[2]).max(0.0);
    std::array::from_fn(|i| {
        let light = ambient[i] * occlusion + params.sun_colour[i] * n_dot_l;
        albedo[i] * light + albedo[i] * (emission * params.emissive_scale)
    })
}

/// The ACES filmic curve (Narkowicz's fit), clamped to `0..=1`.
pub fn aces(x: f32) -> f32 {
    ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// Tonemapped linear colour (exposure, then [`aces`] per channel), before sRGB encoding.
pub fn tonemap(params: &Lighting, colour: [f32; 3]) -> [f32; 3] {
    colour.map(|c| aces(c * params.exposure))
}

/// What the output target stores for a linear colour: [`tonemap`] then sRGB, alpha 255.
pub fn output_rgba8(params: &Lighting, colour: [f32; 3]) -> [u8; 4] {
    let [r, g, b] = tonemap(params, colour).map(linear_to_srgb8);
    [r, g, b, 255]
}

/// Alpha blending as the transparent pass does it: `src * alpha + dst * (1 - alpha)`.
pub fn blend(dst: [f32; 3], src: [f32; 3], alpha: f32) -> [f32; 3] {
    std::array::from_fn(|i| src[i] * alpha + dst[i] * (1.0 - alpha))
}

/// The lighting half of the frame uniforms (twin of the WGSL `Lighting`; a `gpu-backend` test
/// checks the layout against naga).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LightingUniforms {
    /// Towards the sun, unit length.
    pub sun_direction: [f32; 3],
    /// [`Lighting::ambient_strength`].
    pub ambient_strength: f32,
    /// Sun radiance.
    pub sun_colour: [f32; 3],
    /// [`Lighting::emissive_scale`].
    pub emissive_scale: f32,
    /// Sky colour.
    pub sky_colour: [f32; 3],
    /// [`Lighting::exposure`].
    pub exposure: f32,
    /// Ground colour.
    pub ground_colour: [f32; 3],
    /// [`AO_FLOOR`].
    pub ao_floor: f32,
}

const _: () = assert!(size_of::<LightingUniforms>() == 64);

impl LightingUniforms {
    /// The uniforms of `params`.
    pub fn new(params: &Lighting) -> LightingUniforms {
        LightingUniforms {
            sun_direction: params.sun_direction,
            ambient_strength: params.ambient_strength,
            sun_colour: params.sun_colour,
            emissive_scale: params.emissive_scale,
            sky_colour: params.sky_colour,
            exposure: params.exposure,
            ground_colour: params.ground_colour,
            ao_floor: AO_FLOOR,
        }
    }
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
    fn ao_scales_only_the_ambient() {
        let params = Lighting {
            sun_colour: [0.0; 3],
            ..Lighting::default()
        };
        let lit = shade(&params, [1.0; 3], [0.0, 1.0, 0.0], 3.0, 0.0);
        let dark = shade(&params, [1.0; 3], [0.0, 1.0, 0.0], 0.0, 0.0);
        for i in 0..3 {
            assert!((dark[i] - lit[i] * AO_FLOOR).abs() < 1e-6);
            assert!((lit[i] - params.sky_colour[i] * params.ambient_strength).abs() < 1e-6);
        }
    }

    #[test]
    fn aces_is_monotonic_and_bounded() {
        let mut last = -1.0;
        for i in 0..1000 {
            let y = aces(i as f32 * 0.02);
            assert!((0.0..=1.0).contains(&y) && y >= last);
            last = y;
        }
    }
}
