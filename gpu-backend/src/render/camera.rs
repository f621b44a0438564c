//! The renderer's camera: camera-relative, so nothing large ever becomes an `f32`.
//!
//! The eye is a chunk coordinate (`i32`) plus a small offset inside that chunk (blocks, `f32`).
//! Geometry reaches the vertex shader as `(chunk - camera chunk)` in wrapping `i32` (written by
//! the cull pass into each command's record) plus chunk-local corners, and is placed at
//! `f32(chunk - camera chunk) * edge - offset + local`: every term is small near the eye, so a
//! scene near `(2^30, 2^30, 2^30)` renders bit for bit like the same scene at the origin.
//!
//! The projection is the viewer's pinhole camera (yaw about +y, 0 looking along -z, pitch above
//! the horizon, vertical field of view), with **reversed-Z and an infinite far plane**: the
//! depth buffer stores `near / view_z` (1 at the near plane, 0 at infinity), which keeps
//! precision roughly constant with distance. [`RenderCamera::eye_distance`] turns a depth back
//! into the distance along the pixel's ray, the quantity the CPU raycaster reports.

use voxel_core::{ChunkCoord, ChunkSize, WorldPos};

use crate::cull::CullCamera;

/// A camera-relative pinhole camera (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderCamera {
    /// The chunk holding the eye.
    pub chunk: ChunkCoord,
    /// The eye inside `chunk`, blocks (normally `0..edge` per axis).
    pub offset: [f32; 3],
    /// Rotation about +y, radians; 0 looks along -z.
    pub yaw: f64,
    /// Rotation above the horizon, radians.
    pub pitch: f64,
    /// Vertical field of view, radians.
    pub fov_y: f64,
    /// Near plane distance, blocks.
    pub near: f64,
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

impl RenderCamera {
    /// Near plane used by [`from_world`](Self::from_world).
    pub const DEFAULT_NEAR: f64 = 0.05;

    /// The camera whose eye is at world voxel `voxel` plus `fraction` (each axis in `0..1`),
    /// split into a chunk and an offset for `size` (exact: the offset is the voxel's position in
    /// its chunk plus the fraction).
    pub fn from_world(
        voxel: WorldPos,
        fraction: [f64; 3],
        size: ChunkSize,
        yaw: f64,
        pitch: f64,
        fov_y: f64,
    ) -> RenderCamera {
        let (chunk, local) = voxel.split(size);
        let local = [local.x, local.y, local.z];
        RenderCamera {
            chunk,
            offset: std::array::from_fn(|i| (f64::from(local[i]) + fraction[i]) as f32),
            yaw,
            pitch,
            fov_y,
            near: Self::DEFAULT_NEAR,
        }
    }

    /// The view basis (the same formulas as the viewer's raycaster).
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

    /// The cull pass's view of this camera for a `width x height` image.
    pub fn cull_camera(&self, width: u32, height: u32) -> CullCamera {
        CullCamera::from_view_projection(
            self.chunk,
            self.offset,
            self.view_projection(width, height),
        )
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
        let cam = RenderCamera {
            chunk: ChunkCoord::new(0, 0, 0),
            offset: [0.0; 3],
            yaw: 0.0,
            pitch: 0.0,
            fov_y: 1.0,
            near: 0.05,
        };
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
    fn from_world_splits_exactly_far_from_the_origin() {
        let far = 1 << 30;
        let cam = RenderCamera::from_world(
            WorldPos::new(far + 5, -far - 3, 7),
            [0.25, 0.5, 0.75],
            ChunkSize::S16,
            0.0,
            0.0,
            1.0,
        );
        assert_eq!(cam.chunk, ChunkCoord::new(far / 16, (-far - 16) / 16, 0));
        assert_eq!(cam.offset, [5.25, 13.5, 7.75]);
    }
}
