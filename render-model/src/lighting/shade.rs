//! Surface shading: hemisphere ambient with AO, Lambert sun, emission, exposure.

use super::Lighting;

/// Ambient light left at the most occluded corner (AO 0); AO 3 keeps all of it.
pub const AO_FLOOR: f32 = 0.4;

/// The ambient multiplier of an interpolated AO value (`0..=3`, 3 = unoccluded).
pub fn ao_factor(ao: f32) -> f32 {
    AO_FLOOR + (1.0 - AO_FLOOR) * (ao / 3.0)
}

/// The hemisphere ambient radiance for a unit normal (before `ambient_strength` and AO):
/// the ground colour facing down, the sky colour facing up.
pub fn hemisphere_ambient(params: &Lighting, normal: [f32; 3]) -> [f32; 3] {
    let t = 0.5 + 0.5 * normal[1];
    let (g, s) = (params.ground_colour, params.sky_colour);
    core::array::from_fn(|i| g[i] + (s[i] - g[i]) * t)
}

/// Exposed (display-linear) colour of a surface point (the formula in the
/// [module docs](super)), unshadowed: [`shade_visible`] with sun and sky factors 1.
///
/// `albedo` linear, `normal` unit length, `ao` interpolated `0..=3`, `emission` `0..=1`.
pub fn shade(
    params: &Lighting,
    albedo: [f32; 3],
    normal: [f32; 3],
    ao: f32,
    emission: f32,
) -> [f32; 3] {
    shade_visible(params, albedo, normal, ao, emission, 1.0, 1.0)
}

/// [`shade`] with the sun term scaled by `sun` and the hemisphere ambient by `sky`
/// (`shadow::Visibility::sun_factor` and `sky_factor`, `0..=1`); the WGSL twin is
/// `shade_visible` in `render_common.wgsl`.
pub fn shade_visible(
    params: &Lighting,
    albedo: [f32; 3],
    normal: [f32; 3],
    ao: f32,
    emission: f32,
    sun: f32,
    sky: f32,
) -> [f32; 3] {
    let ambient = hemisphere_ambient(params, normal);
    let occlusion = ao_factor(ao) * params.ambient_strength * sky;
    let l = params.sun_direction;
    let n_dot_l = (normal[0] * l[0] + normal[1] * l[1] + normal[2] * l[2]).max(0.0) * sun;
    let exposure = params.exposure_rgb();
    core::array::from_fn(|i| {
        let light = ambient[i] * occlusion + params.sun_colour[i] * n_dot_l;
        (albedo[i] * light + albedo[i] * (emission * params.emissive_scale)) * exposure[i]
    })
}

/// Alpha blending as the transparent pass does it: `src * alpha + dst * (1 - alpha)`.
pub fn blend(dst: [f32; 3], src: [f32; 3], alpha: f32) -> [f32; 3] {
    core::array::from_fn(|i| src[i] * alpha + dst[i] * (1.0 - alpha))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ao_scales_only_the_ambient() {
        let params = Lighting {
            sun_colour: [0.0; 3],
            ..Lighting::default()
        };
        let lit = shade(&params, [1.0; 3], [0.0, 1.0, 0.0], 3.0, 0.0);
        let dark = shade(&params, [1.0; 3], [0.0, 1.0, 0.0], 0.0, 0.0);
        let exposure = params.exposure_rgb();
        for i in 0..3 {
            assert!((dark[i] - lit[i] * AO_FLOOR).abs() < 1e-6);
            let expected = params.sky_colour[i] * params.ambient_strength * exposure[i];
            assert!((lit[i] - expected).abs() < 1e-6);
        }
    }

    #[test]
    fn faces_turned_from_the_sun_get_only_ambient() {
        let params = Lighting::default();
        let away = params.sun_direction.map(|c| -c);
        let c = shade(&params, [1.0; 3], away, 3.0, 0.0);
        let ambient = hemisphere_ambient(&params, away);
        let exposure = params.exposure_rgb();
        for i in 0..3 {
            assert!((c[i] - ambient[i] * params.ambient_strength * exposure[i]).abs() < 1e-6);
        }
    }

    #[test]
    fn shadow_removes_the_sun_and_a_closed_sky_the_ambient() {
        let params = Lighting::default();
        let n = params.sun_direction;
        let lit = shade(&params, [1.0; 3], n, 3.0, 0.0);
        assert_eq!(shade_visible(&params, [1.0; 3], n, 3.0, 0.0, 1.0, 1.0), lit);
        let shadowed = shade_visible(&params, [1.0; 3], n, 3.0, 0.0, 0.0, 1.0);
        let ambient = hemisphere_ambient(&params, n);
        let exposure = params.exposure_rgb();
        for i in 0..3 {
            let expected = ambient[i] * params.ambient_strength * exposure[i];
            assert!((shadowed[i] - expected).abs() < 1e-6);
        }
        let cave = shade_visible(&params, [1.0; 3], n, 3.0, 0.0, 0.0, 0.0);
        assert_eq!(cave, [0.0; 3]);
    }
}
