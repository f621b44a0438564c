//! The camera of the whole stack: the CPU reference renderers cast its rays, the GPU renderer
//! projects with its matrices, the viewer flies it.
//!
//! The eye is a world voxel (`i32` per axis) plus a fraction inside it, so it is exact
//! anywhere in the `i32` world. The GPU never sees that position: [`Camera::eye`] splits it
//! into the chunk holding the eye and a small `f32` offset inside that chunk ([`Eye`]), and
//! geometry reaches the vertex shader as `(chunk - eye chunk)` in wrapping `i32` (written by
//! the cull pass into each command's record) plus chunk-local corners, placed at
//! `f32(chunk - eye chunk) * edge - offset + local`: every term is small near the eye, so a
//! scene near `(2^30, 2^30, 2^30)` renders bit for bit like the same scene at the origin.
//!
//! The projection is a pinhole camera (yaw about +y, 0 looking along -z, pitch above the
//! horizon, vertical field of view), with **reversed-Z and an infinite far plane**: the depth
//! buffer stores `near / view_z` (1 at the near plane, 0 at infinity), which keeps precision
//! roughly constant with distance. [`Camera::eye_distance`] turns a depth back into the
//! distance along the pixel's ray, the quantity the CPU raycaster reports.

use glam::DVec3;
use voxel_core::{ChunkCoord, ChunkSize, CoordError, WorldPos};

use crate::cull::CullView;

/// A pinhole camera (see the [module docs](self)).
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
    /// Near plane distance, blocks ([`Camera::DEFAULT_NEAR`] unless a caller needs another).
    pub near: f64,
}

/// The eye as the GPU sees it: the chunk holding it and the eye's position inside that chunk.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eye {
    /// The chunk holding the eye.
    pub chunk: ChunkCoord,
    /// The eye inside `chunk`, blocks (`0..edge` per axis for an eye made by [`Camera::eye`]).
    pub offset: [f32; 3],
}

/// The camera's orthonormal basis: `forward`, `right`, `up` (world axes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraBasis {
    /// View direction.
    pub forward: [f64; 3],
    /// Screen right.
    pub right: [f64; 3],
    /// Screen up.
    pub up: [f64; 3],
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalize(v: [f64; 3], fallback: [f64; 3]) -> [f64; 3] {
    let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if len > 1e-12 && len.is_finite() {
        v.map(|c| c / len)
    } else {
        fallback
    }
}

impl Camera {
    /// The near plane of [`Camera::new`], blocks.
    pub const DEFAULT_NEAR: f64 = 0.05;

    /// A camera with its eye at world voxel `voxel` plus `fraction` (each axis in `0..1`) and
    /// the default near plane.
    pub fn new(voxel: WorldPos, fraction: DVec3, yaw: f64, pitch: f64, fov_y: f64) -> Camera {
        Camera {
            voxel,
            fraction,
            yaw,
            pitch,
            fov_y,
            near: Self::DEFAULT_NEAR,
        }
    }

    /// The camera whose [`eye`](Self::eye) for chunks of `size` is `eye` (exact for offsets
    /// in `0..edge`: the voxel is the chunk's origin plus the offset's floor, the fraction the
    /// rest). Errors when the eye lies outside the `i32` world.
    pub fn at_eye(
        eye: Eye,
        size: ChunkSize,
        yaw: f64,
        pitch: f64,
        fov_y: f64,
    ) -> Result<Camera, CoordError> {
        let origin = eye.chunk.origin(size)?;
        let floor = eye.offset.map(|c| f64::from(c).floor());
        let voxel = origin.checked_offset(floor.map(|c| c as i32))?;
        let fraction =
            DVec3::from_array(std::array::from_fn(|i| f64::from(eye.offset[i]) - floor[i]));
        Ok(Camera::new(voxel, fraction, yaw, pitch, fov_y))
    }

    /// The eye split for chunks of `size` (exact: the offset is the voxel's position in its
    /// chunk plus the fraction).
    pub fn eye(&self, size: ChunkSize) -> Eye {
        let (chunk, local) = self.voxel.split(size);
        let local = [local.x, local.y, local.z];
        let fraction = self.fraction.to_array();
        Eye {
            chunk,
            offset: std::array::from_fn(|i| (f64::from(local[i]) + fraction[i]) as f32),
        }
    }

    /// The unit view direction (glam's `f64` arithmetic: the CPU raycaster's rays).
    pub fn forward(&self) -> DVec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        DVec3::new(-sy * cp, sp, -cy * cp)
    }

    /// The unit direction through pixel `(px, py)` of a `width x height` image (pixel centres),
    /// as the CPU raycaster casts it.
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

    /// The view basis the GPU's matrices are made from (the same formulas as
    /// [`ray_direction`](Self::ray_direction), on arrays).
    pub fn basis(&self) -> CameraBasis {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        let forward = [-sy * cp, sp, -cy * cp];
        let right = normalize(cross(forward, [0.0, 1.0, 0.0]), [1.0, 0.0, 0.0]);
        let up = cross(right, forward);
        CameraBasis { forward, right, up }
    }

    /// Tangents of the half field of view, horizontal and vertical, for `width x height`.
    pub fn half_extents(&self, width: u32, height: u32) -> (f64, f64) {
        let half_h = (self.fov_y * 0.5).tan();
        (half_h * f64::from(width) / f64::from(height.max(1)), half_h)
    }

    /// The column-major view-projection of camera-relative positions (eye at the origin, world
    /// axes, blocks) to wgpu clip space, reversed-Z with an infinite far plane: clip =
    /// `(dot(right, p) / half_w, dot(up, p) / half_h, near, dot(forward, p))`.
    pub fn view_projection(&self, width: u32, height: u32) -> [[f32; 4]; 4] {
        let b = self.basis();
        let (half_w, half_h) = self.half_extents(width, height);
        let rows = [
            b.right.map(|c| c / half_w),
            b.up.map(|c| c / half_h),
            [0.0; 3],
            b.forward,
        ];
        let w = [0.0, 0.0, self.near, 0.0];
        // Column c holds element c of every row; column 3 the translation (w).
        std::array::from_fn(|c| {
            std::array::from_fn(|r| {
                if c < 3 {
                    rows[r][c] as f32
                } else {
                    w[r] as f32
                }
            })
        })
    }

    /// The cull pass's view of this camera for chunks of `size` and a `width x height` image.
    pub fn cull_view(&self, size: ChunkSize, width: u32, height: u32) -> CullView {
        let eye = self.eye(size);
        CullView::from_view_projection(eye.chunk, eye.offset, self.view_projection(width, height))
    }

    /// Distance from the eye along the ray through the centre of pixel `(px, py)` to the point
    /// whose reversed-Z depth is `depth`; infinity for `depth <= 0` (nothing drawn).
    pub fn eye_distance(&self, px: u32, py: u32, width: u32, height: u32, depth: f32) -> f32 {
        if depth <= 0.0 {
            return f32::INFINITY;
        }
        let (half_w, half_h) = self.half_extents(width, height);
        let u = (2.0 * (f64::from(px) + 0.5) / f64::from(width) - 1.0) * half_w;
        let v = (1.0 - 2.0 * (f64::from(py) + 0.5) / f64::from(height)) * half_h;
        // The ray direction forward + u right + v up has unit forward component.
        let view_z = self.near / f64::from(depth);
        (view_z * (1.0 + u * u + v * v).sqrt()) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn apply(m: &[[f32; 4]; 4], p: [f32; 3]) -> [f32; 4] {
        std::array::from_fn(|r| m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + m[3][r])
    }

    #[test]
    fn the_view_axis_projects_to_the_centre_with_depth_near_over_distance() {
        let cam = Camera::new(WorldPos::new(0, 0, 0), DVec3::ZERO, 0.0, 0.0, 1.0);
        let m = cam.view_projection(64, 32);
        let c = apply(&m, [0.0, 0.0, -10.0]);
        assert!(c[0].abs() < 1e-6 && c[1].abs() < 1e-6);
        assert!((c[2] / c[3] - 0.005).abs() < 1e-7);
        // A point on the right edge of the image.
        let (half_w, _) = cam.half_extents(64, 32);
        let c = apply(&m, [10.0 * half_w as f32, 0.0, -10.0]);
        assert!((c[0] / c[3] - 1.0).abs() < 1e-5);
        let d = cam.eye_distance(32, 16, 64, 32, 0.005);
        assert!((d - 10.0).abs() < 0.01, "{d}");
    }

    #[test]
    fn the_eye_splits_exactly_far_from_the_origin() {
        let far = 1 << 30;
        let cam = Camera::new(
            WorldPos::new(far + 5, -far - 3, 7),
            DVec3::new(0.25, 0.5, 0.75),
            0.0,
            0.0,
            1.0,
        );
        let eye = cam.eye(ChunkSize::S16);
        assert_eq!(eye.chunk, ChunkCoord::new(far / 16, (-far - 16) / 16, 0));
        assert_eq!(eye.offset, [5.25, 13.5, 7.75]);
        // And back.
        let back = Camera::at_eye(eye, ChunkSize::S16, 0.0, 0.0, 1.0).unwrap();
        assert_eq!(back, cam);
    }

    #[test]
    fn rays_and_basis_agree() {
        let cam = Camera::new(WorldPos::new(3, 4, 5), DVec3::splat(0.5), 0.7, -0.3, 1.1);
        let b = cam.basis();
        let centre = cam.ray_direction(50, 50, 101, 101).to_array();
        for (ray, forward) in centre.iter().zip(b.forward) {
            assert!((ray - forward).abs() < 1e-12);
        }
    }
}
