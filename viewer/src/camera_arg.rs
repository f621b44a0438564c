//! `--camera X,Y,Z,YAW,PITCH` and `--fov DEG`: parsing them, and the camera they make.

use glam::DVec3;
use render_model::camera::Camera;
use voxel_core::WorldPos;

/// `--camera`: an eye position and direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CameraArg {
    /// World position in voxels.
    pub position: DVec3,
    /// Degrees about +y; 0 looks along -z.
    pub yaw_degrees: f64,
    /// Degrees above the horizon.
    pub pitch_degrees: f64,
}

impl CameraArg {
    /// The camera at this position and direction, with vertical field of view `fov_y`
    /// (radians).
    pub(crate) fn camera(&self, fov_y: f64) -> Camera {
        let floor = self.position.floor();
        Camera {
            voxel: WorldPos::new(floor.x as i32, floor.y as i32, floor.z as i32),
            fraction: self.position - floor,
            yaw: self.yaw_degrees.to_radians(),
            pitch: self.pitch_degrees.to_radians(),
            fov_y,
            near: Camera::DEFAULT_NEAR,
        }
    }
}

/// `X,Y,Z,YAW,PITCH`: finite numbers, the position inside the i32 world, the pitch from -90
/// to 90.
pub(crate) fn parse_camera(text: &str) -> Result<CameraArg, String> {
    let values: Vec<f64> = text
        .split(',')
        .map(|part| part.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("{text:?} is not five numbers X,Y,Z,YAW,PITCH"))?;
    let [x, y, z, yaw, pitch] = values[..] else {
        return Err(format!("{text:?} is not five numbers X,Y,Z,YAW,PITCH"));
    };
    let world = f64::from(i32::MIN)..f64::from(i32::MAX);
    for (name, v) in [("X", x), ("Y", y), ("Z", z)] {
        if !world.contains(&v) {
            return Err(format!("camera {name} = {v} is outside the i32 world"));
        }
    }
    if !yaw.is_finite() {
        return Err(format!(
            "camera yaw {yaw} is not a finite number of degrees"
        ));
    }
    if !(-90.0..=90.0).contains(&pitch) {
        return Err(format!(
            "camera pitch {pitch} is not from -90 to 90 degrees"
        ));
    }
    Ok(CameraArg {
        position: DVec3::new(x, y, z),
        yaw_degrees: yaw,
        pitch_degrees: pitch,
    })
}

/// Degrees from 1 to 179, returned in radians.
pub(crate) fn parse_fov(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(d) if (1.0..=179.0).contains(&d) => Ok(d.to_radians()),
        _ => Err(format!(
            "{text:?} is not a field of view from 1 to 179 degrees"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cameras_and_fields_of_view_parse_and_bad_ones_are_refused() {
        let camera = parse_camera("-10.5,40,3,90,-30")
            .unwrap()
            .camera(parse_fov("45").unwrap());
        assert_eq!(camera.voxel, WorldPos::new(-11, 40, 3));
        assert_eq!(camera.fraction, DVec3::new(0.5, 0.0, 0.0));
        assert!((camera.yaw - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert!((camera.pitch + 30f64.to_radians()).abs() < 1e-12);
        assert!((camera.fov_y - 45f64.to_radians()).abs() < 1e-12);
        // Yaw 90 looks along -x; pitch -30 looks down.
        let forward = camera.forward();
        assert!(
            (forward.x + 30f64.to_radians().cos()).abs() < 1e-12,
            "{forward}"
        );
        assert!(
            forward.z.abs() < 1e-12 && (forward.y + 0.5).abs() < 1e-12,
            "{forward}"
        );
        for (bad, named) in [
            ("1,2,3,4", "five numbers"),
            ("1,2,3,4,5,6", "five numbers"),
            ("a,2,3,4,5", "five numbers"),
            ("1,2,3,4,91", "pitch 91"),
            ("1,3e10,3,4,5", "Y = 30000000000"),
            ("1,2,NaN,4,5", "Z = NaN"),
            ("1,2,3,inf,5", "yaw inf"),
        ] {
            let err = parse_camera(bad).expect_err(bad);
            assert!(err.contains(named), "{bad}: {err}");
        }
        for bad in ["0", "180", "x", "-5"] {
            let err = parse_fov(bad).expect_err(bad);
            assert!(err.contains("field of view"), "{bad}: {err}");
        }
    }
}
