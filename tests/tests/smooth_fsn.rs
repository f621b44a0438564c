//! `mesher::smooth::SurfaceNets` against `fast-surface-nets` 0.2 on the same densities: same
//! vertex count, same cells in the same order, positions within 1e-5 (2 ulps past coordinate
//! 64), normals (raw gradients) within 1e-4 relative (plus the rounding of the density
//! differences), and the same quads (corners and orientation) on every edge both meshers own.
//! Inputs: spheres, the peer's own benchmark shapes, sine fields, planes through the grid
//! borders, random densities (also wider than one 64-bit mask word).

#[path = "../../mesher/tests/smooth_support/mod.rs"]
mod smooth_support;

use std::collections::{HashMap, HashSet};

use fast_surface_nets::ndshape::RuntimeShape;
use fast_surface_nets::{SurfaceNetsBuffer, surface_nets};
use glam::Vec3;
use mesher::smooth::{GridShape, SmoothMesh, SmoothMeshF32, SurfaceNets};
use proptest::prelude::*;
use smooth_support::{sample, sine, sphere};
use voxel_core::{BlockId, ChunkSize};

/// Position tolerance against the peer (sample units), for coordinates below 64 (every
/// padded chunk); beyond, 2 units in the last place of the coordinate (see [`tolerance`]).
const POSITION_TOLERANCE: f32 = 1e-5;

/// The position tolerance at `p`: [`POSITION_TOLERANCE`], or 2 ulps where those are larger
/// (past coordinate 64 an `f32` ulp is 7.6e-6, so any rounding difference exceeds 1e-5).
fn tolerance(p: Vec3) -> f32 {
    POSITION_TOLERANCE.max(2.0 * f32::EPSILON * p.abs().max_element())
}
/// Gradient tolerance, relative to the gradient's largest component.
const NORMAL_TOLERANCE: f32 = 1e-4;

fn peer(samples: &[f32], dims: [u32; 3]) -> SurfaceNetsBuffer {
    let shape = RuntimeShape::<u32, 3>::new(dims);
    let mut out = SurfaceNetsBuffer::default();
    surface_nets(samples, &shape, [0; 3], dims.map(|d| d - 1), &mut out);
    out
}

/// A quad seen through the cells of its corners: the directed boundary edges and the diagonal.
#[derive(Debug, PartialEq, Eq)]
struct CellQuad {
    boundary: HashSet<([u32; 3], [u32; 3])>,
    diagonal: [[u32; 3]; 2],
}

/// The edge a quad belongs to: (axis, lower sample) = (the axis on which its 4 cells agree,
/// their componentwise maximum).
fn edge_of(cells: [[u32; 3]; 4]) -> (usize, [u32; 3]) {
    let axis = (0..3)
        .find(|&a| cells.iter().all(|c| c[a] == cells[0][a]))
        .expect("the 4 cells around an edge share its coordinate");
    let top = [0, 1, 2].map(|a| cells.iter().map(|c| c[a]).max().unwrap_or(0));
    (axis, top)
}

fn sorted(mut d: [[u32; 3]; 2]) -> [[u32; 3]; 2] {
    d.sort();
    d
}

/// Our quads by edge.
fn our_quads(out: &SmoothMeshF32) -> HashMap<(usize, [u32; 3]), CellQuad> {
    let mut map = HashMap::new();
    for q in &out.quads {
        let c = q.map(|i| out.cells[i as usize]);
        let boundary = (0..4).map(|k| (c[k], c[(k + 1) % 4])).collect();
        let prev = map.insert(
            edge_of(c),
            CellQuad {
                boundary,
                diagonal: sorted([c[0], c[2]]),
            },
        );
        assert!(prev.is_none(), "two quads on one edge");
    }
    map
}

/// The peer's quads (two triangles each, in order) by edge.
fn peer_quads(out: &SurfaceNetsBuffer) -> HashMap<(usize, [u32; 3]), CellQuad> {
    let cell = |i: u32| out.surface_points[i as usize];
    let mut map = HashMap::new();
    for six in out.indices.chunks_exact(6) {
        let edges: Vec<(u32, u32)> = six
            .chunks_exact(3)
            .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
            .collect();
        let inner: Vec<(u32, u32)> = edges
            .iter()
            .copied()
            .filter(|&(a, b)| edges.contains(&(b, a)))
            .collect();
        assert_eq!(inner.len(), 2, "two triangles sharing a diagonal");
        let boundary: HashSet<_> = edges
            .iter()
            .filter(|e| !inner.contains(e))
            .map(|&(a, b)| (cell(a), cell(b)))
            .collect();
        let mut corners: Vec<u32> = six.to_vec();
        corners.sort();
        corners.dedup();
        let c: [[u32; 3]; 4] = std::array::from_fn(|k| cell(corners[k]));
        map.insert(
            edge_of(c),
            CellQuad {
                boundary,
                diagonal: sorted([cell(inner[0].0), cell(inner[0].1)]),
            },
        );
    }
    map
}

/// Compares our unpacked and packed meshes with the peer's on `samples`; returns the number of
/// quads compared.
fn compare(samples: &[f32], dims: [u32; 3]) -> Result<usize, TestCaseError> {
    let shape = GridShape::new(dims).unwrap();
    let theirs = peer(samples, dims);
    let mut mesher = SurfaceNets::new();
    let mut ours = SmoothMeshF32::default();
    mesher.mesh_f32_unpacked(samples, shape, &mut ours).unwrap();

    // Vertices: same cells, same order, positions within 1e-5.
    prop_assert_eq!(ours.positions.len(), theirs.positions.len());
    prop_assert_eq!(&ours.cells, &theirs.surface_points);
    for i in 0..ours.positions.len() {
        let (a, b) = (
            Vec3::from(ours.positions[i]),
            Vec3::from(theirs.positions[i]),
        );
        prop_assert!(
            (a - b).abs().max_element() <= tolerance(b),
            "{i}: {a} vs {b}"
        );
        // Gradients: within 1e-4 of their size, plus the rounding of sums of the corners'
        // differences, which cancel where the gradient is small next to the densities.
        let (n, m) = (Vec3::from(ours.normals[i]), Vec3::from(theirs.normals[i]));
        let [x, y, z] = ours.cells[i];
        let corners = (0..8).map(|k| {
            let c = [x + (k & 1), y + ((k >> 1) & 1), z + (k >> 2)];
            samples[shape.index(c)].abs()
        });
        let density = corners.fold(0.0f32, f32::max);
        let scale = m.abs().max_element().max(1e-6);
        let bound = NORMAL_TOLERANCE * scale + 16.0 * f32::EPSILON * density;
        prop_assert!((n - m).abs().max_element() <= bound, "{i}: {n} vs {m}");
    }

    // Quads: equal on every edge both own; each mesher only meshes edges it owns.
    let last = dims.map(|d| d - 2);
    let ours_owns = |_: usize, s: [u32; 3]| (0..3).all(|a| (1..=last[a]).contains(&s[a]));
    let peer_owns = |axis: usize, s: [u32; 3]| {
        (0..3).all(|a| {
            if a == axis {
                s[a] < last[a]
            } else {
                (1..=last[a]).contains(&s[a])
            }
        })
    };
    let (mine, peers) = (our_quads(&ours), peer_quads(&theirs));
    for (&(axis, s), q) in &mine {
        prop_assert!(ours_owns(axis, s));
        if !peer_owns(axis, s) {
            continue;
        }
        let p = peers.get(&(axis, s));
        prop_assert!(p.is_some(), "peer has no quad on edge {axis} {s:?}");
        let p = p.unwrap();
        prop_assert_eq!(&q.boundary, &p.boundary);
        if q.diagonal != p.diagonal {
            // Only on a near tie, where rounding differences in the positions may decide.
            let pos = |c: [u32; 3]| {
                let i = ours.cells.iter().position(|&d| d == c).unwrap();
                Vec3::from(ours.positions[i])
            };
            let len = |d: [[u32; 3]; 2]| pos(d[0]).distance_squared(pos(d[1]));
            prop_assert!((len(q.diagonal) - len(p.diagonal)).abs() < 1e-4);
        }
    }
    for &(axis, s) in peers.keys() {
        prop_assert!(peer_owns(axis, s));
        if ours_owns(axis, s) {
            prop_assert!(
                mine.contains_key(&(axis, s)),
                "we have no quad on {axis} {s:?}"
            );
        }
    }

    // The packed mesh: the used vertices, within the unorm16 bound of the peer's positions.
    let mut packed = SmoothMesh::new();
    mesher
        .mesh_f32(samples, shape, BlockId(1), &mut packed)
        .unwrap();
    let used: HashSet<u32> = ours.quads.iter().flatten().copied().collect();
    let kept: Vec<usize> = (0..ours.positions.len())
        .filter(|&i| used.contains(&(i as u32)))
        .collect();
    prop_assert_eq!(packed.vertices().len(), kept.len());
    for (v, &i) in packed.vertices().iter().zip(&kept) {
        let d = v.decode(packed.extent()).position;
        let b = Vec3::from(theirs.positions[i]);
        let bound = shape.extent().max_error() + tolerance(b);
        prop_assert!((d - b).abs().max_element() <= bound, "{d} vs {b}");
    }
    prop_assert_eq!(packed.quad_count(), ours.quads.len());
    Ok(mine.len())
}

fn check(samples: &[f32], dims: [u32; 3]) -> usize {
    match compare(samples, dims) {
        Ok(n) => n,
        Err(e) => panic!("{e}"),
    }
}

/// The peer's benchmark domain: sample `i` of `n` cells maps to `2 i / n - 1`.
fn into_domain(n: u32, c: [f32; 3]) -> [f32; 3] {
    c.map(|a| 2.0 * a / n as f32 - 1.0)
}

#[test]
fn peer_benchmark_shapes_34() {
    let s = GridShape::padded_chunk(ChunkSize::S32);
    let ball = sample(s, [0.0; 3], |p| {
        let [x, y, z] = into_domain(32, p);
        x * x + y * y + z * z - 0.9
    });
    assert!(check(&ball, s.dims()) > 2000);
    let wave = sample(s, [0.0; 3], |p| {
        let [x, y, z] = into_domain(32, p);
        let f = |a: f32| (a / 2.0 * 5.0 * std::f32::consts::PI).sin();
        f(x) + f(y) + f(z)
    });
    assert!(check(&wave, s.dims()) > 5000);
}

#[test]
fn spheres_and_sines_at_every_chunk_size() {
    for size in ChunkSize::ALL {
        let s = GridShape::padded_chunk(size);
        let e = size.edge() as f32;
        let ball = sample(
            s,
            [0.0; 3],
            sphere([e * 0.5 + 0.3, e * 0.5, e * 0.45], e * 0.4),
        );
        assert!(check(&ball, s.dims()) > 0);
        let wave = sample(s, [0.0; 3], sine(0.45));
        assert!(check(&wave, s.dims()) > 0);
    }
}

#[test]
fn planes_through_the_borders() {
    let dims = [10, 11, 12];
    let s = GridShape::new(dims).unwrap();
    for axis in 0..3 {
        let d = dims[axis] as f32;
        // Exactly on the samples of the first, second, last-but-one and last layers, and between.
        for k in [0.0, 0.5, 1.0, 1.5, d - 2.5, d - 2.0, d - 1.5, d - 1.0] {
            for sign in [1.0f32, -1.0] {
                let plane = sample(s, [0.0; 3], |p| sign * (p[axis] - k));
                check(&plane, dims);
                // Tilted through the same line.
                let tilted = sample(s, [0.0; 3], |p| {
                    sign * (p[axis] - k + 0.3 * (p[(axis + 1) % 3] - 4.0))
                });
                check(&tilted, dims);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn random_densities(
        (dims, samples) in [3u32..10, 3u32..10, 3u32..10].prop_flat_map(|d| {
            let n = (d[0] * d[1] * d[2]) as usize;
            (
                Just(d),
                proptest::collection::vec(
                    prop_oneof![4 => -1.0f32..1.0, 1 => Just(0.0f32), 1 => -1e6f32..1e6],
                    n,
                ),
            )
        })
    ) {
        compare(&samples, dims)?;
    }

    #[test]
    fn random_densities_wider_than_a_mask_word(
        (dims, samples) in [65u32..140, 3u32..6, 3u32..6].prop_flat_map(|d| {
            let n = (d[0] * d[1] * d[2]) as usize;
            (
                Just(d),
                proptest::collection::vec(prop_oneof![4 => -1.0f32..1.0, 1 => Just(0.0f32)], n),
            )
        })
    ) {
        compare(&samples, dims)?;
    }

    #[test]
    fn random_spheres(
        centre in prop::array::uniform3(-4.0f32..22.0),
        radius in 0.3f32..14.0,
    ) {
        let s = GridShape::padded_chunk(ChunkSize::S16);
        let ball = sample(s, [0.0; 3], sphere(centre, radius));
        compare(&ball, s.dims())?;
    }
}
