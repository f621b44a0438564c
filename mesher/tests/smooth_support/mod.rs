//! Helpers shared by the smooth mesher tests (`mesher/tests/smooth_*.rs`, and the `tests`
//! crate's `tests/smooth_*.rs`, which include this file by path): density fields, welding,
//! the open-edge count and the unit faces of NoCubes' cube quads.
#![allow(dead_code, reason = "each test file uses a different subset")]

use std::collections::HashMap;
use std::hash::Hash;

use mesher::QuadLayer;
use mesher::smooth::GridShape;

/// Directed edges of `triangles` (after mapping each vertex through `key`, which welds
/// vertices with equal keys) that have no opposite edge to pair with: 0 for a closed,
/// consistently oriented surface. Edges whose ends weld together are skipped.
pub(crate) fn open_edges<K: Copy + Eq + Hash>(
    triangles: impl IntoIterator<Item = [u32; 3]>,
    key: impl Fn(u32) -> K,
) -> usize {
    let mut count: HashMap<(K, K), i64> = HashMap::new();
    for [a, b, c] in triangles {
        let [a, b, c] = [key(a), key(b), key(c)];
        for (p, q) in [(a, b), (b, c), (c, a)] {
            if p != q {
                *count.entry((p, q)).or_default() += 1;
            }
        }
    }
    count
        .iter()
        .map(|(&(p, q), &n)| (n - count.get(&(q, p)).copied().unwrap_or(0)).max(0) as usize)
        .sum()
}

/// Welds points closer than `tol` (on every axis), which must be much smaller than the
/// distance between points that are meant to differ: returns a representative id per point.
pub(crate) fn weld(points: &[[f32; 3]], tol: f32) -> Vec<usize> {
    let cell = |p: [f32; 3]| p.map(|a| (a / (4.0 * tol)).floor() as i64);
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    let mut ids = Vec::with_capacity(points.len());
    for (i, &p) in points.iter().enumerate() {
        let c = cell(p);
        let mut found = None;
        'search: for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let k = [c[0] + dx, c[1] + dy, c[2] + dz];
                    for &j in grid.get(&k).map_or(&[][..], |v| &v[..]) {
                        let q = points[j];
                        if (0..3).all(|a| (p[a] - q[a]).abs() <= tol) {
                            found = Some(ids[j]);
                            break 'search;
                        }
                    }
                }
            }
        }
        ids.push(found.unwrap_or(i));
        grid.entry(c).or_default().push(i);
    }
    ids
}

/// Samples `f` at every point of `shape`, at sample coordinates plus `origin`.
pub(crate) fn sample(shape: GridShape, origin: [f32; 3], f: impl Fn([f32; 3]) -> f32) -> Vec<f32> {
    (0..shape.sample_count())
        .map(|i| {
            let c = shape.coords(i);
            f([0, 1, 2].map(|a| c[a] as f32 + origin[a]))
        })
        .collect()
}

/// Signed distance to a sphere.
pub(crate) fn sphere(centre: [f32; 3], radius: f32) -> impl Fn([f32; 3]) -> f32 {
    move |p| {
        let d: f32 = (0..3).map(|a| (p[a] - centre[a]).powi(2)).sum();
        d.sqrt() - radius
    }
}

/// A periodic field whose zero set is a connected lattice of tubes (many handles).
pub(crate) fn sine(frequency: f32) -> impl Fn([f32; 3]) -> f32 {
    move |p| p.iter().map(|&a| (a * frequency).sin()).sum()
}

/// One unit face of a greedy quad: the chunk-local voxel it belongs to, its direction index
/// (`FaceDirection::index`) and its 4 corners, counter-clockwise from outside.
pub(crate) struct UnitFace {
    /// The voxel whose face it is.
    pub voxel: [u32; 3],
    /// Its direction.
    pub face: u8,
    /// Its corners (chunk-local lattice points).
    pub corners: [[u32; 3]; 4],
}

/// Splits every quad of `quads` into its unit faces.
pub(crate) fn unit_faces(quads: &QuadLayer) -> Vec<UnitFace> {
    let mut faces = Vec::new();
    for q in quads.iter() {
        let f = q.decode().expect("a valid quad");
        for v in 0..f.height {
            for u in 0..f.width {
                let mut unit = f;
                unit.position[f.face.width_axis()] += u;
                unit.position[f.face.height_axis()] += v;
                (unit.width, unit.height) = (1, 1);
                faces.push(UnitFace {
                    voxel: unit.position,
                    face: f.face.index(),
                    corners: unit.corners(),
                });
            }
        }
    }
    faces
}
