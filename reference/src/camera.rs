//! The viewer's camera: a pinhole camera whose eye is a world voxel plus a fraction, shared by
//! the CPU reference renderers, the GPU view (converted by `gpu_view::render_camera`) and the
//! window's fly camera.

use glam::DVec3;
use voxel_core::WorldPos;

/// A pinhole camera. The position is a world voxel plus a fraction inside it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The voxel the eye is in.
    pub voxel: WorldPos,
    /// The eye's offset inside that voxel, each axis in `[0, 1)`.
    pub fraction: DVec3,
    /// Rotation about +y, radians; 0 looks along -z.
    pub yaw: f64,
    /// Rotation above the horizon, radians.
    pub pitch: f64,
    /// Vertical field of view, radians.
    pub fov_y: f64,
}

impl Camera {
    /// The unit view direction.
    pub fn forward(&self) -> DVec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        DVec3::new(-sy * cp, sp, -cy * cp)
    }

    /// The direction through pixel `(px, py)` of a `width x height` image (pixel centres).
    pub fn ray_direction(&self, px: u32, py: u32, width: u32, height: u32) -> DVec3 {
        let forward = self.forward();
        let right = forward.cross(DVec3::Y).normalize_or(DVec3::X);
        let up = right.cross(forward);
        let half_h = (self.fov_y * 0.5).tan();
        let half_w = half_h * f64::from(width) / f64::from(height);
        let u = (2.0 * (f64::from(px) + 0.5) / f64::from(width) - 1.0) * half_w;
        let v = (1.0 - 2.0 * (f64::from(py) + 0.5) / f64::from(height)) * half_h;
        (forward + right * u + up * v).normalize()
    }
}
