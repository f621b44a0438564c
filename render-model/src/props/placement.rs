//! Where an instance is: a world voxel (`i32` per axis, exact anywhere) plus a small `f32`
//! affine map, and the camera-relative rule every renderer applies to it.

use glam::DVec3;
use voxel_core::WorldPos;

use super::records::PropInstanceRecord;
use crate::Camera;

/// A prop instance's place: `anchor` (a world voxel) plus `local`, the affine map from mesh
/// space to anchor-relative space (column-major, `local[c][r]`; row 3 is ignored and treated
/// as `0, 0, 0, 1`). Keep `local`'s translation small (within a few chunks): it is what the GPU
/// adds in `f32` after the exact anchor difference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PropPlacement {
    /// The world voxel the instance is placed from.
    pub anchor: WorldPos,
    /// Mesh space to anchor-relative space.
    pub local: [[f32; 4]; 4],
}

/// Why a placement cannot be made.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PlacementError {
    /// The matrix holds NaN or an infinity.
    NonFinite,
    /// The world position lies outside the `i32` world (or is not finite).
    OutOfWorld {
        /// The position.
        position: [f64; 3],
    },
}

impl std::fmt::Display for PlacementError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlacementError::NonFinite => write!(f, "the placement matrix holds NaN or infinity"),
            PlacementError::OutOfWorld { position } => {
                write!(f, "world position {position:?} lies outside the i32 world")
            }
        }
    }
}

impl std::error::Error for PlacementError {}

impl PropPlacement {
    /// `local` placed from `anchor`; errors when `local` is not finite.
    pub fn new(anchor: WorldPos, local: [[f32; 4]; 4]) -> Result<PropPlacement, PlacementError> {
        if !local.iter().flatten().all(|x| x.is_finite()) {
            return Err(PlacementError::NonFinite);
        }
        Ok(PropPlacement { anchor, local })
    }

    /// The placement of `model` (a mesh-to-world linear map and translation, as a column-major
    /// affine matrix) at world `position` (`f64`, any size): the anchor is `floor(position)`,
    /// and `local` is `model` with the fraction `position - anchor` as its translation.
    pub fn at_world(
        position: DVec3,
        model: [[f32; 4]; 4],
    ) -> Result<PropPlacement, PlacementError> {
        let floor = position.floor();
        let out = || PlacementError::OutOfWorld {
            position: position.to_array(),
        };
        let fits = |v: f64| v.is_finite() && v >= f64::from(i32::MIN) && v <= f64::from(i32::MAX);
        if !(fits(floor.x) && fits(floor.y) && fits(floor.z)) {
            return Err(out());
        }
        let anchor = WorldPos::new(floor.x as i32, floor.y as i32, floor.z as i32);
        let fraction = (position - floor).to_array();
        let mut local = model;
        for (r, f) in fraction.iter().enumerate() {
            local[3][r] = model[3][r] + *f as f32;
        }
        PropPlacement::new(anchor, local)
    }

    /// The GPU record of this placement in batch `batch`.
    pub fn record(&self, batch: u32) -> PropInstanceRecord {
        PropInstanceRecord {
            anchor: [self.anchor.x, self.anchor.y, self.anchor.z],
            batch,
            local: std::array::from_fn(|c| [self.local[c][0], self.local[c][1], self.local[c][2]]),
        }
    }
}

/// The eye as the prop pass sees it: its voxel and the fraction inside it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PropEye {
    /// The voxel.
    pub voxel: [i32; 3],
    /// The fraction, each axis `0..1`.
    pub fraction: [f32; 3],
}

impl PropEye {
    /// The eye of `camera` (the fraction rounded to `f32` once).
    pub fn of(camera: &Camera) -> PropEye {
        let f = camera.fraction.to_array();
        PropEye {
            voxel: [camera.voxel.x, camera.voxel.y, camera.voxel.z],
            fraction: f.map(|c| c as f32),
        }
    }
}

/// The camera-relative position of an anchor: per axis `f32(anchor - eye.voxel) -
/// eye.fraction`, the difference in wrapping `i32` (exact for any two voxels of the world
/// closer than `2^31`), its `f32` conversion exact below `2^24` blocks.
pub fn relative_origin(anchor: [i32; 3], eye: &PropEye) -> [f32; 3] {
    std::array::from_fn(|i| anchor[i].wrapping_sub(eye.voxel[i]) as f32 - eye.fraction[i])
}

/// `((c0 * p.x + c1 * p.y) + c2 * p.z) + c3` per axis: a mesh point in anchor-relative space.
pub fn local_point(local: &[[f32; 3]; 4], p: [f32; 3]) -> [f32; 3] {
    std::array::from_fn(|i| {
        ((local[0][i] * p[0] + local[1][i] * p[1]) + local[2][i] * p[2]) + local[3][i]
    })
}

/// A mesh point of `record`, camera-relative: `relative_origin + local_point`, one `f32` add
/// per axis. What the vertex shader computes before the view-projection.
pub fn relative_point(record: &PropInstanceRecord, eye: &PropEye, p: [f32; 3]) -> [f32; 3] {
    let o = relative_origin(record.anchor, eye);
    let q = local_point(&record.local, p);
    std::array::from_fn(|i| o[i] + q[i])
}

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The normal of mesh normal `n` under `local`: the cofactor matrix (columns `c1 x c2`,
/// `c2 x c0`, `c0 x c1`: the inverse transpose times the determinant, right under
/// non-uniform scale) applied, negated when the determinant `dot(c0, c1 x c2)` is negative
/// (a mirror: the inverse transpose itself keeps outward normals outward), then normalized;
/// zero stays zero. The vertex shader computes the same cross products.
pub fn local_normal(local: &[[f32; 3]; 4], n: [f32; 3]) -> [f32; 3] {
    let cof = [
        cross(local[1], local[2]),
        cross(local[2], local[0]),
        cross(local[0], local[1]),
    ];
    let c0 = local[0];
    let det = (c0[0] * cof[0][0] + c0[1] * cof[0][1]) + c0[2] * cof[0][2];
    let sign = if det < 0.0 { -1.0 } else { 1.0 };
    let m: [f32; 3] =
        std::array::from_fn(|i| sign * ((cof[0][i] * n[0] + cof[1][i] * n[1]) + cof[2][i] * n[2]));
    let len = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
    if len > 0.0 && len.is_finite() {
        m.map(|c| c / len)
    } else {
        [0.0; 3]
    }
}
