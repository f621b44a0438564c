//! Geometric error of the smooth meshes: the distance from SurfaceNets vertices and triangle
//! centroids to the analytic surface of a sphere and a torus, against the grid resolution (the
//! radius in voxels), and the extra error the packed formats add: unorm16 positions (in voxels)
//! and 8+8 / 16+16 octahedral normals (in degrees).

use glam::Vec3;
use mesher::smooth::{GridShape, SmoothMeshF32, SurfaceNets};
use voxel_core::ChunkSize;
use voxel_core::formats::UnormExtent;
use voxel_core::formats::octahedral::{oct16_decode, oct16_encode, oct32_decode, oct32_encode};
use voxel_core::formats::quantize::{unorm16x3_decode, unorm16x3_encode};

use super::ReportError;
use crate::rng::Rng;

/// Major radius of the torus as a multiple of its minor radius.
pub const TORUS_RATIO: f32 = 2.5;

/// An analytic shape with an exact signed distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A sphere of this radius.
    Sphere(f32),
    /// A torus about +y with this minor radius and [`TORUS_RATIO`] times it as major radius.
    Torus(f32),
}

impl Shape {
    /// The shape's name in the tables.
    pub fn name(self) -> &'static str {
        match self {
            Shape::Sphere(_) => "sphere",
            Shape::Torus(_) => "torus",
        }
    }

    /// The radius the resolution is counted in (sphere radius, torus minor radius), voxels.
    pub fn radius(self) -> f32 {
        match self {
            Shape::Sphere(r) | Shape::Torus(r) => r,
        }
    }

    /// Signed distance from `p` (relative to the centre) to the surface, negative inside.
    pub fn sdf(self, p: Vec3) -> f32 {
        match self {
            Shape::Sphere(r) => p.length() - r,
            Shape::Torus(r) => {
                let q = (p.x * p.x + p.z * p.z).sqrt() - TORUS_RATIO * r;
                (q * q + p.y * p.y).sqrt() - r
            }
        }
    }

    /// The outward unit normal at `p` (the normalized gradient of [`sdf`](Self::sdf)).
    pub fn normal(self, p: Vec3) -> Vec3 {
        match self {
            Shape::Sphere(_) => p.normalize_or(Vec3::Y),
            Shape::Torus(r) => {
                let ring = Vec3::new(p.x, 0.0, p.z).normalize_or(Vec3::X) * TORUS_RATIO * r;
                (p - ring).normalize_or(Vec3::Y)
            }
        }
    }

    /// Half extents of the shape's bounding box.
    fn half_extent(self) -> Vec3 {
        match self {
            Shape::Sphere(r) => Vec3::splat(r),
            Shape::Torus(r) => Vec3::new((TORUS_RATIO + 1.0) * r, r, (TORUS_RATIO + 1.0) * r),
        }
    }
}

/// A sampled shape: its grid, centre (off the lattice, so no symmetry hides errors) and mesh.
#[derive(Debug)]
pub struct Sampled {
    /// The shape.
    pub shape: Shape,
    /// The centre in sample coordinates.
    pub centre: Vec3,
    /// The grid's dimensions.
    pub grid: GridShape,
    /// The unquantized SurfaceNets mesh.
    pub mesh: SmoothMeshF32,
}

/// Samples `shape`'s signed distance on a grid with 3 samples of margin and meshes it.
pub fn sample(shape: Shape) -> Result<Sampled, ReportError> {
    let half = shape.half_extent();
    let dims = (half * 2.0 + Vec3::splat(6.0))
        .ceil()
        .to_array()
        .map(|d| d as u32);
    let grid = GridShape::new(dims).map_err(|e| ReportError(format!("{shape:?}: {e}")))?;
    let centre = Vec3::from_array(dims.map(|d| d as f32 * 0.5)) + Vec3::new(0.31, 0.17, 0.23);
    let samples: Vec<f32> = (0..grid.sample_count())
        .map(|i| shape.sdf(Vec3::from_array(grid.coords(i).map(|a| a as f32)) - centre))
        .collect();
    let mut mesh = SmoothMeshF32::default();
    SurfaceNets::new()
        .mesh_f32_unpacked(&samples, grid, &mut mesh)
        .map_err(|e| ReportError(format!("{shape:?}: {e}")))?;
    Ok(Sampled {
        shape,
        centre,
        grid,
        mesh,
    })
}

/// Mean and max of a set of non-negative errors.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stat {
    /// Mean.
    pub mean: f64,
    /// Maximum.
    pub max: f64,
    /// Number of values.
    pub count: usize,
}

impl Stat {
    /// The mean and max of `values`.
    pub fn of(values: impl IntoIterator<Item = f64>) -> Stat {
        let mut s = Stat::default();
        let mut sum = 0.0;
        for v in values {
            sum += v;
            s.max = s.max.max(v);
            s.count += 1;
        }
        s.mean = if s.count > 0 {
            sum / s.count as f64
        } else {
            0.0
        };
        s
    }
}

/// The error of one smooth mesh against its analytic surface.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceRow {
    /// `sphere` or `torus`.
    pub shape: &'static str,
    /// Sphere radius or torus minor radius, voxels.
    pub radius: f32,
    /// Quads of the mesh.
    pub quads: usize,
    /// Distance from the vertices to the surface, voxels.
    pub vertex: Stat,
    /// Distance from the triangle centroids to the surface, voxels.
    pub centroid: Stat,
    /// Angle between the mesher's normals (density gradient) and the analytic normal, degrees.
    pub normal_degrees: Stat,
}

/// The surface error of a sphere and a torus for every radius.
pub fn surface_error(radii: &[f32]) -> Result<Vec<SurfaceRow>, ReportError> {
    let mut rows = Vec::new();
    for make in [Shape::Sphere as fn(f32) -> Shape, Shape::Torus] {
        for &r in radii {
            let s = sample(make(r))?;
            rows.push(surface_row(&s));
        }
    }
    Ok(rows)
}

fn surface_row(s: &Sampled) -> SurfaceRow {
    let local = |p: [f32; 3]| Vec3::from_array(p) - s.centre;
    let dist = |p: Vec3| f64::from(s.shape.sdf(p).abs());
    let vertex = Stat::of(s.mesh.positions.iter().map(|&p| dist(local(p))));
    let centroid = Stat::of(s.mesh.triangles().map(|t| {
        let c = t
            .iter()
            .map(|&i| local(s.mesh.positions[i as usize]))
            .sum::<Vec3>()
            / 3.0;
        dist(c)
    }));
    let normal_degrees = Stat::of(s.mesh.positions.iter().zip(&s.mesh.normals).filter_map(
        |(&p, &n)| {
            let n = Vec3::from_array(n).try_normalize()?;
            Some(angle_degrees(n, s.shape.normal(local(p))))
        },
    ));
    SurfaceRow {
        shape: s.shape.name(),
        radius: s.shape.radius(),
        quads: s.mesh.quads.len(),
        vertex,
        centroid,
        normal_degrees,
    }
}

/// The angle between two directions, degrees: `atan2(|a x b|, a . b)` in `f64`, exact for
/// tiny angles (an `f32` `acos` of the dot product cannot resolve angles below about 0.02°,
/// far above the 16+16 encoding's error).
pub fn angle_degrees(a: Vec3, b: Vec3) -> f64 {
    let (a, b) = (a.as_dvec3(), b.as_dvec3());
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

/// What the packed formats add to the error.
#[derive(Clone, Debug, PartialEq)]
pub struct Quantization {
    /// unorm16 position error (the largest of the three axes, comparable with the per-axis
    /// bound) of the mesh vertices of every shape and radius, packed as a chunk's vertices are (chunk-local position + 1 over the padded chunk's extent), per
    /// chunk size: (edge, error in voxels, the stated bound of half a step).
    pub position: Vec<(u32, Stat, f32)>,
    /// Change of the mean vertex-to-surface distance after packing in 62^3 chunks, averaged
    /// over shapes and radii, voxels (can be negative).
    pub surface_mean_change: f64,
    /// 8+8 octahedral normals: angle to the encoded direction, degrees.
    pub oct16: Stat,
    /// 16+16 octahedral normals, degrees.
    pub oct32: Stat,
    /// Random unit directions in the normal figures (besides the mesh normals).
    pub random_normals: usize,
}

/// Measures the unorm16 position error on the meshes of `radii` and the octahedral normal
/// error on their normals plus `normal_samples` random unit directions.
pub fn quantization(radii: &[f32], normal_samples: usize) -> Result<Quantization, ReportError> {
    const SIZES: [ChunkSize; 3] = [ChunkSize::S16, ChunkSize::S32, ChunkSize::S62];
    let mut position: [Vec<f64>; 3] = Default::default();
    let mut normals = Vec::new();
    let mut mean_change = 0.0;
    let mut meshes = 0usize;
    for make in [Shape::Sphere as fn(f32) -> Shape, Shape::Torus] {
        for &r in radii {
            let s = sample(make(r))?;
            let (mut before, mut after) = (0.0, 0.0);
            for &p in &s.mesh.positions {
                let p = Vec3::from_array(p);
                for (i, size) in SIZES.into_iter().enumerate() {
                    let q = pack_in_chunk(p, size)?;
                    position[i].push(f64::from((p - q).abs().max_element()));
                    if size == ChunkSize::S62 {
                        before += f64::from(s.shape.sdf(p - s.centre).abs());
                        after += f64::from(s.shape.sdf(q - s.centre).abs());
                    }
                }
            }
            let n = s.mesh.positions.len().max(1) as f64;
            mean_change += (after - before) / n;
            meshes += 1;
            normals.extend(
                s.mesh
                    .normals
                    .iter()
                    .filter_map(|&n| Vec3::from_array(n).try_normalize()),
            );
        }
    }
    let mut rng = Rng::new(0x6f63_7461);
    let target = normals.len() + normal_samples;
    while normals.len() < target {
        let v = Vec3::new(
            rng.range_f32(-1.0, 1.0),
            rng.range_f32(-1.0, 1.0),
            rng.range_f32(-1.0, 1.0),
        );
        if let Some(v) = v.try_normalize() {
            normals.push(v);
        }
    }
    let oct = |encode: &dyn Fn(Vec3) -> Option<Vec3>| {
        Stat::of(
            normals
                .iter()
                .filter_map(|&n| encode(n).map(|d| angle_degrees(n, d))),
        )
    };
    let oct16 = oct(&|n| oct16_encode(n).ok().map(oct16_decode));
    let oct32 = oct(&|n| oct32_encode(n).ok().map(oct32_decode));
    Ok(Quantization {
        position: SIZES
            .into_iter()
            .zip(position)
            .map(|(size, errors)| {
                (
                    size.edge(),
                    Stat::of(errors),
                    UnormExtent::padded_chunk(size).max_error(),
                )
            })
            .collect(),
        surface_mean_change: mean_change / meshes.max(1) as f64,
        oct16,
        oct32,
        random_normals: normal_samples,
    })
}

/// `p` (sample coordinates) packed as the vertex of the chunk of `size` it falls in: its
/// chunk-local position + 1 through unorm16 over [`UnormExtent::padded_chunk`], and back.
fn pack_in_chunk(p: Vec3, size: ChunkSize) -> Result<Vec3, ReportError> {
    let edge = size.edge() as f32;
    let origin = (p / edge).floor() * edge;
    let extent = UnormExtent::padded_chunk(size);
    let local = p - origin + Vec3::ONE;
    let codes = unorm16x3_encode(local, extent).map_err(|e| ReportError(format!("{p}: {e}")))?;
    Ok(unorm16x3_decode(codes, extent) - Vec3::ONE + origin)
}
