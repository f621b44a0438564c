//! The lighting half of the frame uniforms.

use bytemuck::{Pod, Zeroable};

use super::{AO_FLOOR, Lighting};

/// The lighting half of the frame uniforms (twin of the WGSL `Lighting`; a `gpu-backend` test
/// checks the layout against naga). 112 bytes.
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
    /// Ambient radiance from above.
    pub sky_colour: [f32; 3],
    /// `1 / haze_distance` (0 with haze off).
    pub haze_inverse_distance: f32,
    /// Ambient radiance from below.
    pub ground_colour: [f32; 3],
    /// [`AO_FLOOR`].
    pub ao_floor: f32,
    /// [`Lighting::exposure_rgb`].
    pub exposure: [f32; 3],
    /// Cosine of the sun disc's angular radius.
    pub sun_disc_cos: f32,
    /// Display-linear sky colour straight up.
    pub zenith_colour: [f32; 3],
    /// [`Lighting::sun_disc_brightness`].
    pub sun_disc_brightness: f32,
    /// Display-linear sky colour at the horizon.
    pub horizon_colour: [f32; 3],
    /// [`Lighting::sun_halo`].
    pub sun_halo: f32,
}

const _: () = assert!(size_of::<LightingUniforms>() == 112);

impl LightingUniforms {
    /// The uniforms of `params` (checked with [`Lighting::check`] by the renderer).
    pub fn new(params: &Lighting) -> LightingUniforms {
        LightingUniforms {
            sun_direction: params.sun_direction,
            ambient_strength: params.ambient_strength,
            sun_colour: params.sun_colour,
            emissive_scale: params.emissive_scale,
            sky_colour: params.sky_colour,
            haze_inverse_distance: 1.0 / params.haze_distance,
            ground_colour: params.ground_colour,
            ao_floor: AO_FLOOR,
            exposure: params.exposure_rgb(),
            sun_disc_cos: params.sun_disc_radius.cos(),
            zenith_colour: params.zenith_colour,
            sun_disc_brightness: params.sun_disc_brightness,
            horizon_colour: params.horizon_colour,
            sun_halo: params.sun_halo,
        }
    }
}
