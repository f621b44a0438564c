//! The view a cull runs for: where the eye is (chunk + small offset) and the frustum planes in
//! camera-relative space. A [`Camera`](crate::Camera) makes one with
//! [`Camera::cull_view`](crate::Camera::cull_view); a shadow map or a second view is another.

use voxel_core::ChunkCoord;

/// Which quad layer of `MeshedChunkInfo` a cull reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CullLayer {
    /// `opaque_quads`.
    Opaque,
    /// `transparent_quads`.
    Transparent,
}

impl CullLayer {
    /// Both layers, opaque first (the draw order).
    pub const ALL: [CullLayer; 2] = [CullLayer::Opaque, CullLayer::Transparent];

    /// The value the shader reads (`0` opaque, `1` transparent).
    pub const fn index(self) -> u32 {
        match self {
            CullLayer::Opaque => 0,
            CullLayer::Transparent => 1,
        }
    }
}

/// A plane that keeps everything: `0 * p + 1 >= 0`.
pub const PLANE_KEEP_ALL: [f32; 4] = [0.0, 0.0, 0.0, 1.0];

/// One view of the cull pass, camera-relative: the eye sits at the origin of the space the
/// planes live in, and nothing large is ever an `f32`.
///
/// - `chunk`: the chunk holding the eye (`i32` per axis, any value);
/// - `offset`: the eye's position inside that chunk, in blocks (normally `0..edge` per axis;
///   any small value works);
/// - `planes`: six planes `[nx, ny, nz, d]`; a camera-relative point `p` is inside when
///   `nx * p.x + ny * p.y + nz * p.z + d >= 0`. Order does not matter; [`PLANE_KEEP_ALL`]
///   disables a plane.
///
/// A chunk `k` is placed at `f32(k - chunk) * edge - offset` (the difference wraps in `i32`);
/// see the [module docs](super) for the precision this has. A second view (shadow map,
/// reflection, another camera) is just another `CullView` in another cull request
/// (`gpu_backend::cull::CullRequest`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CullView {
    /// Chunk holding the eye.
    pub chunk: ChunkCoord,
    /// The eye inside `chunk`, blocks.
    pub offset: [f32; 3],
    /// Frustum planes in camera-relative space (inside: `dot(n, p) + d >= 0`).
    pub planes: [[f32; 4]; 6],
}

impl CullView {
    /// A view without frustum planes (every plane [`PLANE_KEEP_ALL`]): only the face-direction
    /// test culls.
    pub fn without_frustum(chunk: ChunkCoord, offset: [f32; 3]) -> CullView {
        CullView {
            chunk,
            offset,
            planes: [PLANE_KEEP_ALL; 6],
        }
    }

    /// The view whose frustum is that of `view_projection`, a column-major matrix (as glam's
    /// `Mat4::to_cols_array_2d`) that maps **camera-relative** positions (eye at the origin,
    /// world axes, blocks) to wgpu clip space (`-w <= x, y <= w`, `0 <= z <= w`).
    ///
    /// Planes are extracted the Gribb-Hartmann way (left `r3 + r0`, right `r3 - r0`, bottom
    /// `r3 + r1`, top `r3 - r1`, near `r2`, far `r3 - r2`, with `ri` the matrix rows), in
    /// `f64`, then normalized. A plane that degenerates (an infinite far plane gives
    /// `r3 - r2 = 0`) keeps everything. Works for reversed-Z matrices too (near and far swap).
    pub fn from_view_projection(
        chunk: ChunkCoord,
        offset: [f32; 3],
        view_projection: [[f32; 4]; 4],
    ) -> CullView {
        let row =
            |r: usize| -> [f64; 4] { std::array::from_fn(|c| f64::from(view_projection[c][r])) };
        let (r0, r1, r2, r3) = (row(0), row(1), row(2), row(3));
        let add = |a: [f64; 4], b: [f64; 4]| -> [f64; 4] { std::array::from_fn(|i| a[i] + b[i]) };
        let sub = |a: [f64; 4], b: [f64; 4]| -> [f64; 4] { std::array::from_fn(|i| a[i] - b[i]) };
        let raw = [
            add(r3, r0),
            sub(r3, r0),
            add(r3, r1),
            sub(r3, r1),
            r2,
            sub(r3, r2),
        ];
        CullView {
            chunk,
            offset,
            planes: raw.map(normalize_plane),
        }
    }
}

/// Scales `[n, d]` so that `|n| = 1`; a zero normal gives [`PLANE_KEEP_ALL`].
fn normalize_plane(p: [f64; 4]) -> [f32; 4] {
    let len = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    if !(len.is_finite() && len > 0.0) {
        return PLANE_KEEP_ALL;
    }
    p.map(|v| (v / len) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A column-major perspective matrix for wgpu depth (0..1), looking down -z, combined
    /// with a rotation of the world axes (identity here).
    fn perspective(fov_y: f32, aspect: f32, near: f32, far: f32) -> [[f32; 4]; 4] {
        let f = 1.0 / (fov_y / 2.0).tan();
        let r = far / (near - far);
        [
            [f / aspect, 0.0, 0.0, 0.0],
            [0.0, f, 0.0, 0.0],
            [0.0, 0.0, r, -1.0],
            [0.0, 0.0, r * near, 0.0],
        ]
    }

    fn inside(planes: &[[f32; 4]; 6], p: [f32; 3]) -> bool {
        planes
            .iter()
            .all(|n| n[0] * p[0] + n[1] * p[1] + n[2] * p[2] + n[3] >= 0.0)
    }

    #[test]
    fn perspective_planes_bound_the_frustum() {
        let m = perspective(std::f32::consts::FRAC_PI_2, 1.0, 0.5, 100.0);
        let cam = CullView::from_view_projection(ChunkCoord::new(0, 0, 0), [0.0; 3], m);
        for n in &cam.planes {
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-6, "{n:?}");
        }
        assert!(inside(&cam.planes, [0.0, 0.0, -10.0]));
        assert!(
            inside(&cam.planes, [9.0, -9.0, -10.0]),
            "inside the 90 degree cone"
        );
        assert!(
            !inside(&cam.planes, [11.0, 0.0, -10.0]),
            "right of the cone"
        );
        assert!(!inside(&cam.planes, [0.0, 11.0, -10.0]), "above the cone");
        assert!(!inside(&cam.planes, [0.0, 0.0, 10.0]), "behind the eye");
        assert!(
            !inside(&cam.planes, [0.0, 0.0, -0.25]),
            "before the near plane"
        );
        assert!(
            !inside(&cam.planes, [0.0, 0.0, -101.0]),
            "past the far plane"
        );
    }

    #[test]
    fn infinite_far_plane_keeps_everything_far() {
        // Infinite far plane: r -> -1, r * near -> -near.
        let mut m = perspective(1.0, 1.0, 0.5, 100.0);
        m[2][2] = -1.0;
        m[3][2] = -0.5;
        let cam = CullView::from_view_projection(ChunkCoord::new(0, 0, 0), [0.0; 3], m);
        assert_eq!(cam.planes[5], PLANE_KEEP_ALL);
        assert!(inside(&cam.planes, [0.0, 0.0, -1.0e9]));
    }
}
