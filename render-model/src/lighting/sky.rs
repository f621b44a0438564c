//! The sky behind the world and the haze in front of it (the rule is in the
//! [module docs](super)). Directions are unit vectors in world axes; colours are
//! display-linear, like the exposed surface colours they blend with.

use super::Lighting;

/// `ln(255)`: the haze's transmittance at `haze_distance` is `exp(-HAZE_DENSITY) = 1/255`.
pub const HAZE_DENSITY: f32 = 5.541_264;

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The white-balanced sun colour: the sun's radiance times the exposure.
fn sun_white(params: &Lighting) -> [f32; 3] {
    let e = params.exposure_rgb();
    core::array::from_fn(|i| params.sun_colour[i] * e[i])
}

/// The sky's colour in direction `dir` without the sun disc: the horizon-to-zenith gradient
/// (`1 - (1 - up)^2` of the way, `up` the direction's height clamped to `0..=1`) plus the
/// sun's halo (`sun_halo * max(cos, 0)^16` of the white-balanced sun). This is also the
/// haze's colour.
pub fn haze_colour(params: &Lighting, dir: [f32; 3]) -> [f32; 3] {
    let up = dir[1].clamp(0.0, 1.0);
    let t = 1.0 - (1.0 - up) * (1.0 - up);
    let c = dot(dir, params.sun_direction).max(0.0);
    let c2 = c * c;
    let c4 = c2 * c2;
    let c8 = c4 * c4;
    let halo = params.sun_halo * (c8 * c8);
    let sun = sun_white(params);
    let (h, z) = (params.horizon_colour, params.zenith_colour);
    core::array::from_fn(|i| h[i] + (z[i] - h[i]) * t + sun[i] * halo)
}

/// The background in direction `dir`: [`haze_colour`] plus the sun disc (where the angle to
/// the sun is within `sun_disc_radius`: `sun_disc_brightness` times the white-balanced sun).
pub fn sky_background(params: &Lighting, dir: [f32; 3]) -> [f32; 3] {
    let sky = haze_colour(params, dir);
    if dot(dir, params.sun_direction) < params.sun_disc_radius.cos() {
        return sky;
    }
    let sun = sun_white(params);
    core::array::from_fn(|i| sky[i] + sun[i] * params.sun_disc_brightness)
}

/// The fraction of a surface's colour that reaches the eye from `distance` blocks:
/// `exp(-HAZE_DENSITY * (distance / haze_distance)^4)`, 1 with haze off.
pub fn haze_transmittance(params: &Lighting, distance: f32) -> f32 {
    let x = distance * (1.0 / params.haze_distance);
    let x2 = x * x;
    (-HAZE_DENSITY * (x2 * x2)).exp()
}

/// `colour` seen through the haze from `distance` blocks along `dir`.
pub fn apply_haze(params: &Lighting, colour: [f32; 3], dir: [f32; 3], distance: f32) -> [f32; 3] {
    let t = haze_transmittance(params, distance);
    let haze = haze_colour(params, dir);
    core::array::from_fn(|i| haze[i] + (colour[i] - haze[i]) * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn haze_is_clear_near_and_complete_at_its_distance() {
        let params = Lighting {
            haze_distance: 200.0,
            ..Lighting::default()
        };
        assert!(haze_transmittance(&params, 0.0) == 1.0);
        assert!(haze_transmittance(&params, 50.0) > 0.97);
        assert!((haze_transmittance(&params, 200.0) - 1.0 / 255.0).abs() < 1e-5);
        assert!(haze_transmittance(&params, 400.0) < 1e-6);
        let off = Lighting::default();
        assert_eq!(haze_transmittance(&off, 1e9), 1.0);
    }

    #[test]
    fn the_sky_brightens_towards_the_horizon_and_shows_the_sun() {
        let params = Lighting::default();
        let zenith = haze_colour(&params, [0.0, 1.0, 0.0]);
        let away = params.sun_direction.map(|c| -c);
        let horizon = haze_colour(
            &params,
            [away[0], 0.0, away[2]].map(|c| c / (away[0].hypot(away[2]))),
        );
        assert!(horizon[0] > zenith[0] && horizon[1] > zenith[1]);
        let sun = sky_background(&params, params.sun_direction);
        assert!(sun.iter().all(|&c| c > 10.0), "{sun:?}");
        let beside = haze_colour(&params, params.sun_direction);
        assert!(beside.iter().all(|&c| c < 2.0), "{beside:?}");
    }
}
