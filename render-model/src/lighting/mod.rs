//! The lighting model of the deferred renderer, and its CPU twin: one [`Lighting`] for every
//! renderer of the stack (the GPU passes, the CPU reference, the viewer).
//!
//! One model, written twice: in WGSL (`gpu-backend`'s `render_common.wgsl`, used by the
//! lighting pass, the transparent pass and the tonemap pass) and here in Rust, operation for
//! operation, so the CPU reference shades exactly like the GPU and images can be compared.
//!
//! ```text
//! ambient  = mix(ground, sky, 0.5 + 0.5 * n.y) * ambient_strength      hemisphere light
//! occluded = ambient * (AO_FLOOR + (1 - AO_FLOOR) * ao / 3)            per-vertex AO (0..=3)
//! light    = occluded + sun * max(dot(n, l), 0)                        Lambert sun
//! colour   = (albedo * light + albedo * emission * emissive_scale) * exposure_rgb
//! hazed    = mix(haze(dir), colour, transmittance(distance))           aerial perspective
//! output   = srgb(neutral(hazed))                                      tonemap, sRGB target
//! ```
//!
//! **Colour.** Palette colours are sRGB; albedo is their linear value ([`srgb_to_linear`]).
//! Lighting happens in linear light, and the frame's HDR colour is already exposed
//! ("display-linear"): 1.0 is the display's white.
//!
//! **Exposure rule** ([`Lighting::exposure_rgb`]): per channel, `exposure / reference` where
//! `reference` is the light a surface facing the sun receives unoccluded (the sun plus the
//! hemisphere ambient at the sun's direction, AO 3). A surface lit head-on therefore shows
//! its palette colour (at `exposure = 1`); the division per channel is the white balance of a
//! camera set to the scene's daylight, so a warm sun does not tint every palette colour.
//!
//! **Tonemap** ([`neutral`]): hue-preserving highlight compression after Khronos PBR Neutral:
//! below [`COMPRESSION_START`] (on the largest channel) the colour passes unchanged; above it
//! the largest channel is compressed towards 1 and the colour scaled with it (its hue and
//! ratios kept), then desaturated towards white by [`DESATURATION`] as highlights approach 1.
//! PBR Neutral's toe (it subtracts up to 0.04 to remove a specular term of a PBR renderer)
//! is left out: the diffuse model here adds no such term, and the toe would darken dark
//! palette colours. The compression starts at 0.85 rather than Neutral's 0.76 so that palette
//! whites stay within CIEDE2000 2 of their colour, at the cost of less headroom for
//! highlights (values above about 1.8 reach the display's white).
//!
//! **Sky and haze** ([`sky`]): the background is a display-referred gradient from the horizon
//! colour to the zenith colour with a sun disc and halo; distance haze blends every surface
//! towards the sky's colour in its direction (without the disc) with transmittance
//! `exp(-ln(255) * (d / haze_distance)^4)`: clear near the eye, 1/255 at `haze_distance`, so
//! the end of the loaded world vanishes into the sky when `haze_distance` is the streamed
//! radius.
//!
//! **Materials, water and glass** ([`surface`]): a specular lobe (Schlick Fresnel sky
//! reflection, GGX sun highlight) for surfaces that are not fully rough, metalness, and
//! transparent layers tinted with the distance the view ray travels inside them. A fully
//! rough dielectric is shaded exactly by the formula above.
//!
//! **Shadows and sky visibility** ([`shadow`]): the rule of the sun-shadow and
//! sky-visibility rays through block occupancy, with its bounds and switches
//! ([`Lighting::shadows`]): the sun term is multiplied by the sun's visibility (0 or 1) and
//! the hemisphere ambient by the sky's (the open fraction of 5 rays), [`shade_visible`].

mod shade;
pub mod shadow;
pub mod sky;
pub mod surface;
mod tonemap;
mod uniforms;

pub use shade::{AO_FLOOR, ao_factor, blend, hemisphere_ambient, shade, shade_visible};
pub use tonemap::{
    COMPRESSION_START, DESATURATION, linear_to_srgb8, neutral, output_rgba8, srgb_to_linear,
};
pub use uniforms::{
    LightingUniforms, SHADOW_FILL_LOD, SHADOW_SKY, SHADOW_SUN, ShadowFillUniforms,
    ShadowTraceUniforms,
};

use core::fmt;

use shadow::{ShadowSettings, ShadowSettingsError};

/// Light, sky and haze of a frame. Light colours are linear radiance; sky colours are
/// display-linear (what the tonemap receives); the sun direction points towards the sun.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lighting {
    /// Unit direction towards the sun.
    pub sun_direction: [f32; 3],
    /// Linear sun radiance.
    pub sun_colour: [f32; 3],
    /// Linear ambient radiance from above.
    pub sky_colour: [f32; 3],
    /// Linear ambient radiance from below.
    pub ground_colour: [f32; 3],
    /// Scale of the hemisphere ambient.
    pub ambient_strength: f32,
    /// Scale of palette emission (`emission / 255 * emissive_scale * albedo`).
    pub emissive_scale: f32,
    /// Multiplies the white-balanced exposure ([`Lighting::exposure_rgb`]); 1 shows a surface
    /// lit head-on in its palette colour.
    pub exposure: f32,
    /// Display-linear sky colour straight up.
    pub zenith_colour: [f32; 3],
    /// Display-linear sky colour at (and below) the horizon.
    pub horizon_colour: [f32; 3],
    /// Angular radius of the sun disc, radians (0 = no disc).
    pub sun_disc_radius: f32,
    /// Display-linear brightness of the sun disc (above 1.8 it is the display's white).
    pub sun_disc_brightness: f32,
    /// Strength of the halo around the sun (added to the sky and the haze).
    pub sun_halo: f32,
    /// Distance, blocks, at which haze hides everything (transmittance 1/255);
    /// `f32::INFINITY` turns haze off.
    pub haze_distance: f32,
    /// Sun shadows and sky visibility ([`shadow`]); [`ShadowSettings::OFF`] draws without
    /// them.
    pub shadows: ShadowSettings,
}

impl Default for Lighting {
    /// The viewer's default daylight, haze and shadows off.
    fn default() -> Self {
        let d = [0.45f32, 0.8, 0.35];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        Lighting {
            sun_direction: d.map(|c| c / len),
            sun_colour: [1.0 * 2.2, 0.95 * 2.2, 0.85 * 2.2],
            sky_colour: [0.45, 0.62, 0.9],
            ground_colour: [0.25, 0.22, 0.2],
            ambient_strength: 0.9,
            emissive_scale: 4.0,
            exposure: 1.0,
            zenith_colour: [0.16, 0.33, 0.75],
            horizon_colour: [0.6, 0.72, 0.88],
            sun_disc_radius: 0.75_f32.to_radians(),
            sun_disc_brightness: 20.0,
            sun_halo: 0.35,
            haze_distance: f32::INFINITY,
            shadows: ShadowSettings::OFF,
        }
    }
}

/// Why a [`Lighting`] cannot be rendered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightingError {
    /// A parameter is NaN or infinite (the haze distance may be `+inf`).
    NotFinite {
        /// The parameter's name.
        field: &'static str,
    },
    /// A parameter is negative.
    Negative {
        /// The parameter's name.
        field: &'static str,
    },
    /// The sun direction is not of unit length (within 1e-3).
    SunDirectionNotUnit {
        /// Its length.
        length: f32,
    },
    /// A surface facing the sun receives no light in a channel, so the exposure rule has
    /// nothing to divide by.
    NoHeadOnLight {
        /// The channel (0 = red, 1 = green, 2 = blue).
        channel: usize,
    },
    /// The haze distance is not positive.
    HazeDistanceNotPositive {
        /// The value given.
        value: f32,
    },
    /// The shadow settings are refused.
    Shadows(ShadowSettingsError),
}

impl fmt::Display for LightingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LightingError::NotFinite { field } => write!(f, "lighting: `{field}` is not finite"),
            LightingError::Negative { field } => write!(f, "lighting: `{field}` is negative"),
            LightingError::SunDirectionNotUnit { length } => {
                write!(f, "lighting: the sun direction has length {length}, not 1")
            }
            LightingError::NoHeadOnLight { channel } => write!(
                f,
                "lighting: a surface facing the sun receives no light in channel {channel}, so \
                 no exposure shows it"
            ),
            LightingError::HazeDistanceNotPositive { value } => {
                write!(f, "lighting: the haze distance {value} is not positive")
            }
            LightingError::Shadows(e) => write!(f, "lighting: {e}"),
        }
    }
}

impl std::error::Error for LightingError {}

impl Lighting {
    /// Checks that every parameter can be rendered: finite, non-negative where a negative
    /// value has no meaning, a unit sun direction, some head-on light in every channel, a
    /// positive haze distance, usable shadow settings ([`ShadowSettings::check`], also when
    /// both features are off).
    pub fn check(&self) -> Result<(), LightingError> {
        let vectors: [(&'static str, [f32; 3], bool); 6] = [
            ("sun_direction", self.sun_direction, false),
            ("sun_colour", self.sun_colour, true),
            ("sky_colour", self.sky_colour, true),
            ("ground_colour", self.ground_colour, true),
            ("zenith_colour", self.zenith_colour, true),
            ("horizon_colour", self.horizon_colour, true),
        ];
        for (field, v, non_negative) in vectors {
            check_values(field, &v, non_negative)?;
        }
        let scalars: [(&'static str, f32); 6] = [
            ("ambient_strength", self.ambient_strength),
            ("emissive_scale", self.emissive_scale),
            ("exposure", self.exposure),
            ("sun_disc_radius", self.sun_disc_radius),
            ("sun_disc_brightness", self.sun_disc_brightness),
            ("sun_halo", self.sun_halo),
        ];
        for (field, v) in scalars {
            check_values(field, &[v], true)?;
        }
        let [x, y, z] = self.sun_direction;
        let length = (x * x + y * y + z * z).sqrt();
        if (length - 1.0).abs() > 1e-3 {
            return Err(LightingError::SunDirectionNotUnit { length });
        }
        let reference = self.head_on_light();
        if let Some(channel) = (0..3).find(|&i| reference[i] <= 0.0 || !reference[i].is_finite()) {
            return Err(LightingError::NoHeadOnLight { channel });
        }
        if self.haze_distance.is_nan() || self.haze_distance <= 0.0 {
            return Err(LightingError::HazeDistanceNotPositive {
                value: self.haze_distance,
            });
        }
        self.shadows.check().map_err(LightingError::Shadows)
    }

    /// The linear light a surface facing the sun receives, unoccluded (AO 3): the sun plus
    /// the hemisphere ambient at the sun's direction.
    pub fn head_on_light(&self) -> [f32; 3] {
        let ambient = hemisphere_ambient(self, self.sun_direction);
        core::array::from_fn(|i| ambient[i] * self.ambient_strength + self.sun_colour[i])
    }

    /// The exposure of each channel (the rule in the [module docs](self)): `exposure` over
    /// [`Lighting::head_on_light`]. Infinite in a channel without head-on light, which
    /// [`Lighting::check`] refuses.
    pub fn exposure_rgb(&self) -> [f32; 3] {
        self.head_on_light().map(|r| self.exposure / r)
    }
}

fn check_values(field: &'static str, v: &[f32], non_negative: bool) -> Result<(), LightingError> {
    if v.iter().any(|c| !c.is_finite()) {
        return Err(LightingError::NotFinite { field });
    }
    if non_negative && v.iter().any(|&c| c < 0.0) {
        return Err(LightingError::Negative { field });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_passes_its_check() {
        assert_eq!(Lighting::default().check(), Ok(()));
    }

    #[test]
    fn a_surface_facing_the_sun_reflects_its_albedo() {
        let params = Lighting::default();
        for albedo in [[0.8, 0.2, 0.05], [0.1, 0.1, 0.1], [0.0, 0.5, 0.85]] {
            let c = shade(&params, albedo, params.sun_direction, 3.0, 0.0);
            for i in 0..3 {
                assert!((c[i] - albedo[i]).abs() < 1e-5, "{c:?} against {albedo:?}");
            }
        }
    }

    #[test]
    fn every_bad_parameter_is_named() {
        let bad = |f: fn(&mut Lighting)| {
            let mut l = Lighting::default();
            f(&mut l);
            l.check()
        };
        assert_eq!(
            bad(|l| l.sun_colour[1] = f32::NAN),
            Err(LightingError::NotFinite {
                field: "sun_colour"
            })
        );
        assert_eq!(
            bad(|l| l.exposure = -1.0),
            Err(LightingError::Negative { field: "exposure" })
        );
        assert!(matches!(
            bad(|l| l.sun_direction = [0.0, 2.0, 0.0]),
            Err(LightingError::SunDirectionNotUnit { .. })
        ));
        assert_eq!(
            bad(|l| {
                l.sun_colour[2] = 0.0;
                l.sky_colour[2] = 0.0;
                l.ground_colour[2] = 0.0;
            }),
            Err(LightingError::NoHeadOnLight { channel: 2 })
        );
        assert!(matches!(
            bad(|l| l.haze_distance = 0.0),
            Err(LightingError::HazeDistanceNotPositive { .. })
        ));
        assert!(matches!(
            bad(|l| l.haze_distance = f32::NAN),
            Err(LightingError::HazeDistanceNotPositive { .. })
        ));
        assert_eq!(bad(|l| l.haze_distance = 300.0), Ok(()));
        assert_eq!(
            bad(|l| l.shadows.max_steps = 0),
            Err(LightingError::Shadows(ShadowSettingsError::Steps {
                max_steps: 0
            }))
        );
        assert!(matches!(
            bad(|l| l.shadows.normal_bias = f32::NAN),
            Err(LightingError::Shadows(ShadowSettingsError::Bias { .. }))
        ));
    }
}
