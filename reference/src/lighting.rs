//! The viewer's light and sky: what both the CPU reference renderers and the GPU renderer
//! (through [`lighting_params`]) shade with.

use glam::Vec3;
use gpu_backend::render::lighting::LightingParams;

/// Light and sky used by the reference shading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lighting {
    /// Unit direction towards the sun.
    pub sun_direction: Vec3,
    /// Linear sun radiance.
    pub sun_colour: Vec3,
    /// Linear sky colour (ambient from above, and the background).
    pub sky_colour: Vec3,
    /// Linear ambient from below.
    pub ground_colour: Vec3,
}

impl Default for Lighting {
    fn default() -> Self {
        Lighting {
            sun_direction: Vec3::new(0.45, 0.8, 0.35).normalize(),
            sun_colour: Vec3::new(1.0, 0.95, 0.85) * 2.2,
            sky_colour: Vec3::new(0.45, 0.62, 0.9),
            ground_colour: Vec3::new(0.25, 0.22, 0.2),
        }
    }
}

/// The GPU renderer's lighting parameters for `lighting` (the same sun and sky; the GPU's
/// other parameters at their defaults).
pub fn lighting_params(lighting: &Lighting) -> LightingParams {
    LightingParams {
        sun_direction: lighting.sun_direction.to_array(),
        sun_colour: lighting.sun_colour.to_array(),
        sky_colour: lighting.sky_colour.to_array(),
        ground_colour: lighting.ground_colour.to_array(),
        ..LightingParams::default()
    }
}
