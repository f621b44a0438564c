//! SurfaceNets on density grids: input checks, empty and full grids, the i8 path against the f32
//! path, closed meshes, the compact / u16 / u32 quad forms, and packing within the stated bounds.

mod smooth_support;

use glam::Vec3;
use mesher::MeshError;
use mesher::smooth::{
    FALLBACK_NORMAL, GridShape, I8_DENSITY_STEP, OCT16_FAST_MAX_ERROR_DEGREES, SmoothMesh,
    SmoothMeshF32, SmoothQuads, SurfaceNets, U16_INDEX_LIMIT,
};
use proptest::prelude::*;
use smooth_support::{open_edges, sample, sine, sphere};
use voxel_core::formats::compact_quad_encode;
use voxel_core::formats::octahedral::oct16_decode;
use voxel_core::{BlockId, ChunkSize};

fn shape(d: [u32; 3]) -> GridShape {
    GridShape::new(d).unwrap()
}

/// Random small grid dimensions.
fn dims() -> impl Strategy<Value = [u32; 3]> {
    [3u32..12, 3u32..12, 3u32..12]
}

/// A grid shape with random densities in -1..=1 (some exactly 0), and the outer layer
/// optionally forced outside (a closed surface).
fn random_grid(closed: bool) -> impl Strategy<Value = (GridShape, Vec<f32>)> {
    dims().prop_flat_map(move |d| {
        let s = shape(d);
        let n = s.sample_count();
        proptest::collection::vec(prop_oneof![-1.0f32..1.0, Just(0.0f32)], n).prop_map(
            move |mut v| {
                if closed {
                    // Outside on the grid's faces and on the first owned layer, so that every
                    // crossing edge starts at an owned sample (see the padding contract).
                    for (i, x) in v.iter_mut().enumerate() {
                        let c = s.coords(i);
                        if (0..3).any(|a| c[a] <= 1 || c[a] == d[a] - 1) {
                            *x = x.abs() + 0.25;
                        }
                    }
                }
                (s, v)
            },
        )
    })
}

#[test]
fn bad_shapes_are_rejected() {
    for d in [[2, 5, 5], [5, 1025, 5], [5, 5, 0]] {
        assert!(matches!(
            GridShape::new(d),
            Err(MeshError::BadShape { value, .. }) if value == 2 || value == 1025 || value == 0
        ));
    }
    let s = shape([4, 5, 6]);
    let mut mesher = SurfaceNets::new();
    let mut out = SmoothMesh::new();
    for len in [0, 119, 121] {
        let samples = vec![1.0f32; len];
        assert_eq!(
            mesher.mesh_f32(&samples, s, BlockId(1), &mut out),
            Err(MeshError::BadShape {
                reason: "density sample count does not match the grid shape",
                value: len
            })
        );
        let q = vec![1i8; len];
        assert!(matches!(
            mesher.mesh_i8(&q, s, BlockId(1), &mut out),
            Err(MeshError::BadShape { value, .. }) if value == len
        ));
    }
}

#[test]
fn empty_and_full_grids_give_empty_meshes() {
    let s = GridShape::padded_chunk(ChunkSize::S62);
    let mut mesher = SurfaceNets::new();
    let mut out = SmoothMesh::new();
    for v in [1.0f32, 0.0, -0.0, -1.0, f32::MAX, -f32::MAX] {
        let samples = vec![v; s.sample_count()];
        mesher.mesh_f32(&samples, s, BlockId(1), &mut out).unwrap();
        assert!(out.is_empty(), "{v}");
    }
    for v in [i8::MIN, -1, 0, i8::MAX] {
        mesher
            .mesh_i8(&vec![v; s.sample_count()], s, BlockId(1), &mut out)
            .unwrap();
        assert!(out.is_empty(), "{v}");
    }
}

#[test]
fn a_single_inside_sample_gives_a_closed_octahedron() {
    let s = shape([5, 5, 5]);
    let mut samples = vec![1.0f32; s.sample_count()];
    samples[s.index([2, 2, 2])] = -1.0;
    let mut out = SmoothMeshF32::default();
    SurfaceNets::new()
        .mesh_f32_unpacked(&samples, s, &mut out)
        .unwrap();
    assert_eq!(out.positions.len(), 8);
    assert_eq!(out.quads.len(), 6);
    assert_eq!(open_edges(out.triangles(), |i| i), 0);
    // Every face points away from the inside sample.
    for [a, b, c] in out.triangles() {
        let p = [a, b, c].map(|i| Vec3::from(out.positions[i as usize]));
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let centre = (p[0] + p[1] + p[2]) / 3.0;
        assert!(n.dot(centre - Vec3::splat(2.0)) > 0.0);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn non_finite_samples_are_reported_with_their_index(
        (s, mut samples) in random_grid(false),
        at in any::<prop::sample::Index>(),
        second in any::<prop::sample::Index>(),
        bad in prop_oneof![Just(f32::NAN), Just(f32::INFINITY), Just(f32::NEG_INFINITY)],
    ) {
        let i = at.index(samples.len());
        let j = second.index(samples.len());
        samples[i] = bad;
        samples[j] = f32::INFINITY;
        let first = i.min(j);
        let mut out = SmoothMesh::new();
        let mut unpacked = SmoothMeshF32::default();
        let mut mesher = SurfaceNets::new();
        for result in [
            mesher.mesh_f32(&samples, s, BlockId(1), &mut out),
            mesher.mesh_f32_unpacked(&samples, s, &mut unpacked),
        ] {
            match result {
                Err(MeshError::NonFiniteDensity { index, value }) => {
                    prop_assert_eq!(index, first);
                    prop_assert_eq!(value.to_bits(), samples[first].to_bits());
                }
                other => prop_assert!(false, "expected NonFiniteDensity, got {:?}", other),
            }
        }
        prop_assert!(out.is_empty());
        prop_assert!(unpacked.positions.is_empty());
    }

    #[test]
    fn i8_equals_f32_on_representable_grids(
        (s, q) in dims().prop_flat_map(|d| {
            let s = shape(d);
            (Just(s), proptest::collection::vec(any::<i8>(), s.sample_count()))
        })
    ) {
        let f: Vec<f32> = q.iter().map(|&q| f32::from(q) * I8_DENSITY_STEP).collect();
        let mut mesher = SurfaceNets::new();
        let (mut a, mut b) = (SmoothMesh::new(), SmoothMesh::new());
        mesher.mesh_i8(&q, s, BlockId(7), &mut a).unwrap();
        mesher.mesh_f32(&f, s, BlockId(7), &mut b).unwrap();
        prop_assert_eq!(&a, &b);
        let (mut ua, mut ub) = (SmoothMeshF32::default(), SmoothMeshF32::default());
        mesher.mesh_i8_unpacked(&q, s, &mut ua).unwrap();
        mesher.mesh_f32_unpacked(&f, s, &mut ub).unwrap();
        prop_assert_eq!(ua, ub);
    }

    #[test]
    fn closed_surfaces_give_closed_meshes((s, samples) in random_grid(true)) {
        let mut mesher = SurfaceNets::new();
        let mut out = SmoothMesh::new();
        mesher.mesh_f32(&samples, s, BlockId(1), &mut out).unwrap();
        prop_assert_eq!(open_edges(out.triangles(), |i| i), 0);
        // Every vertex index is in range and every quad has 4 distinct corners.
        for q in out.quads().iter() {
            prop_assert!(q.iter().all(|&i| (i as usize) < out.vertices().len()));
            prop_assert!(q[0] != q[1] && q[0] != q[2] && q[0] != q[3] && q[1] != q[2]);
        }
    }

    #[test]
    fn packed_equals_unpacked_within_the_stated_bounds((s, samples) in random_grid(false)) {
        let mut mesher = SurfaceNets::new();
        let mut packed = SmoothMesh::new();
        let mut raw = SmoothMeshF32::default();
        mesher.mesh_f32(&samples, s, BlockId(3), &mut packed).unwrap();
        mesher.mesh_f32_unpacked(&samples, s, &mut raw).unwrap();
        let kept = same_quads(&packed, &raw)?;
        let extent = s.extent();
        prop_assert_eq!(packed.extent(), extent);
        for (v, &i) in packed.vertices().iter().zip(&kept) {
            let d = v.decode(extent);
            let p = Vec3::from(raw.positions[i]);
            prop_assert!((d.position - p).abs().max_element() <= extent.max_error(),
                "{} vs {}", d.position, p);
            let g = Vec3::from(raw.normals[i]);
            if g.length() > 1e-20 {
                let angle = d.normal.angle_between(g.normalize()).to_degrees();
                prop_assert!(angle <= OCT16_FAST_MAX_ERROR_DEGREES, "{angle} degrees");
            } else {
                prop_assert_eq!(v.normal, FALLBACK_NORMAL);
            }
            prop_assert_eq!(v.block, 3);
            prop_assert_eq!((v.uv, v.extra), ([0, 0], 0));
        }
        quad_form_is_the_narrowest(&packed, s)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Smooth random surfaces (blobs and waves, plus a little noise) in the padded grids of
    /// every chunk size: compact quads (up to 65,536 vertices), each decoding to the quad of the
    /// unpacked path.
    #[test]
    fn chunk_grids_keep_compact_quads(
        (s, samples) in (proptest::sample::select(ChunkSize::ALL.to_vec()), smooth_field())
            .prop_map(|(size, f)| {
                let s = GridShape::padded_chunk(size);
                let n = s.dims()[0] as f32;
                (s, sample(s, [0.0; 3], |p| f.at(p.map(|a| a / n))))
            })
    ) {
        prop_assert!(s.dims()[0] <= 64);
        let packed = packed_same_as_unpacked(&samples, s)?;
        if packed.vertices().len() <= U16_INDEX_LIMIT {
            prop_assert!(matches!(packed.quads(), SmoothQuads::Compact(_)));
        } else {
            prop_assert!(matches!(packed.quads(), SmoothQuads::U32(_)));
        }
        quad_form_is_the_narrowest(&packed, s)?;
    }

    /// Random densities on grids up to 140 samples a row: rows longer than 64 put more than
    /// 63 vertices between a cell and the one behind it along y, so their meshes fall back to
    /// u16, exactly.
    #[test]
    fn wide_grids_fall_back_exactly(
        (s, samples) in [3u32..141, 3u32..7, 3u32..7].prop_flat_map(|d| {
            let s = shape(d);
            (Just(s), proptest::collection::vec(-1.0f32..1.0, s.sample_count()))
        })
    ) {
        let packed = packed_same_as_unpacked(&samples, s)?;
        quad_form_is_the_narrowest(&packed, s)?;
    }
}

/// A smooth random field over the unit cube: the union of up to 3 balls, or a wave, plus a
/// little bumpiness.
#[derive(Clone, Debug)]
struct SmoothField {
    balls: Vec<([f32; 3], f32)>,
    wave: Option<(f32, f32)>,
    bump: f32,
}

impl SmoothField {
    fn at(&self, p: [f32; 3]) -> f32 {
        let base = match self.wave {
            Some((frequency, phase)) => {
                p.iter()
                    .map(|&a| (a * frequency + phase).sin())
                    .sum::<f32>()
                    * 0.2
            }
            None => self
                .balls
                .iter()
                .map(|&(c, r)| sphere(c, r)(p))
                .fold(f32::INFINITY, f32::min),
        };
        base + self.bump * (p[0] * 91.0 + p[1] * 53.0 + p[2] * 37.0).sin()
    }
}

fn smooth_field() -> impl Strategy<Value = SmoothField> {
    let ball = ([0.2f32..0.8, 0.2f32..0.8, 0.2f32..0.8], 0.1f32..0.45);
    (
        proptest::collection::vec(ball, 1..4),
        proptest::option::of((2.0f32..9.0, 0.0f32..6.0)),
        0.0f32..0.04,
    )
        .prop_map(|(balls, wave, bump)| SmoothField { balls, wave, bump })
}

/// Checks that the packed mesh has the unpacked mesh's vertices less those no quad uses (in
/// order) and the same quads, corner for corner once renumbered (both paths choose each
/// diagonal on the same unquantized positions), whatever form the packed quads are stored in.
/// Returns the unpacked index of each packed vertex.
/// Meshes `samples` packed and unpacked, checks that both have the same quads
/// ([`same_quads`]) and returns the packed mesh.
fn packed_same_as_unpacked(samples: &[f32], s: GridShape) -> Result<SmoothMesh, TestCaseError> {
    let mut mesher = SurfaceNets::new();
    let mut packed = SmoothMesh::new();
    let mut raw = SmoothMeshF32::default();
    mesher
        .mesh_f32(samples, s, BlockId(1), &mut packed)
        .unwrap();
    mesher.mesh_f32_unpacked(samples, s, &mut raw).unwrap();
    same_quads(&packed, &raw)?;
    Ok(packed)
}

fn same_quads(packed: &SmoothMesh, raw: &SmoothMeshF32) -> Result<Vec<usize>, TestCaseError> {
    let mut used = vec![false; raw.positions.len()];
    raw.quads
        .iter()
        .flatten()
        .for_each(|&i| used[i as usize] = true);
    let kept: Vec<usize> = (0..used.len()).filter(|&i| used[i]).collect();
    let mut renumber = vec![u32::MAX; used.len()];
    for (new, &old) in kept.iter().enumerate() {
        renumber[old] = new as u32;
    }
    prop_assert_eq!(packed.vertices().len(), kept.len());
    prop_assert_eq!(packed.quad_count(), raw.quads.len());
    prop_assert_eq!(packed.quads().iter().count(), raw.quads.len());
    for (q, r) in packed.quads().iter().zip(&raw.quads) {
        let r = r.map(|i| renumber[i as usize]);
        prop_assert_eq!(q, r);
    }
    Ok(kept)
}

/// Checks that the mesh's quad form is the narrowest that holds its quads: compact when every
/// quad has a compact record (always on grids of at most 64 samples a row with at most 65,536
/// vertices), u16 when one does not and the mesh has at most 65,536 vertices, else u32; and
/// that the buffer has the form's size.
fn quad_form_is_the_narrowest(mesh: &SmoothMesh, s: GridShape) -> Result<(), TestCaseError> {
    let quads = mesh.quads();
    let all_compact = quads.iter().all(|q| compact_quad_encode(q).is_some());
    let small = mesh.vertices().len() <= U16_INDEX_LIMIT;
    if s.dims()[0] <= 64 && small {
        prop_assert!(all_compact);
    }
    match quads {
        SmoothQuads::Compact(_) => prop_assert!(all_compact),
        SmoothQuads::U16(_) => prop_assert!(!all_compact && small),
        SmoothQuads::U32(_) => prop_assert!(!small),
    }
    prop_assert_eq!(quads.bytes().len(), quads.quad_bytes() * quads.len());
    Ok(())
}

#[test]
fn past_65536_vertices_quads_switch_to_u32() {
    // A 3-D checkerboard: every cell is a surface cell, every inner one used.
    let s = shape([48, 48, 48]);
    let samples: Vec<f32> = (0..s.sample_count())
        .map(|i| {
            let [x, y, z] = s.coords(i);
            if (x + y + z) % 2 == 0 { -1.0 } else { 1.0 }
        })
        .collect();
    let mut mesher = SurfaceNets::new();
    let mut out = SmoothMesh::new();
    mesher.mesh_f32(&samples, s, BlockId(1), &mut out).unwrap();
    assert!(out.vertices().len() >= 45 * 45 * 45);
    assert!(out.vertices().len() > U16_INDEX_LIMIT);
    let SmoothQuads::U32(quads) = out.quads() else {
        panic!("expected u32 quads");
    };
    assert_eq!(out.quads().bytes().len(), 16 * quads.len());
    let mut raw = SmoothMeshF32::default();
    mesher.mesh_f32_unpacked(&samples, s, &mut raw).unwrap();
    assert_eq!(quads.len(), raw.quads.len());
    assert!(
        quads
            .iter()
            .flatten()
            .any(|&i| i as usize >= U16_INDEX_LIMIT)
    );

    // The buffer is reusable: a small mesh afterwards is compact again.
    let small = shape([8, 8, 8]);
    let samples = sample(small, [0.0; 3], sphere([3.5; 3], 2.2));
    mesher
        .mesh_f32(&samples, small, BlockId(1), &mut out)
        .unwrap();
    assert!(matches!(out.quads(), SmoothQuads::Compact(q) if !q.is_empty()));
}

#[test]
fn rows_of_more_than_64_samples_can_need_u16() {
    // Random densities: nearly every cell has a vertex, so a cell and the one behind it along
    // y are a whole row of cells apart: 63 in a 64-wide grid (compact), 99 in a 100-wide one.
    let mut mesher = SurfaceNets::new();
    let mut packed = SmoothMesh::new();
    let mut raw = SmoothMeshF32::default();
    for (dx, wide) in [(64, false), (100, true)] {
        let s = shape([dx, 5, 5]);
        let samples: Vec<f32> = (0..s.sample_count())
            .map(|i| ((i as f32 * 12.9898).sin() * 43_758.547).fract())
            .collect();
        mesher
            .mesh_f32(&samples, s, BlockId(1), &mut packed)
            .unwrap();
        mesher.mesh_f32_unpacked(&samples, s, &mut raw).unwrap();
        same_quads(&packed, &raw).unwrap();
        quad_form_is_the_narrowest(&packed, s).unwrap();
        if wide {
            assert!(matches!(packed.quads(), SmoothQuads::U16(_)));
            assert_eq!(packed.quads().bytes().len(), 8 * packed.quad_count());
        } else {
            assert!(matches!(packed.quads(), SmoothQuads::Compact(_)));
            assert_eq!(packed.quads().bytes().len(), 6 * packed.quad_count());
        }
    }
}

#[test]
fn sphere_and_sine_are_closed_and_at_most_24_bytes_per_quad() {
    let s = GridShape::padded_chunk(ChunkSize::S32);
    let mut mesher = SurfaceNets::new();
    let mut out = SmoothMesh::new();
    let ball = sample(s, [0.0; 3], sphere([16.7, 17.1, 16.9], 12.3));
    mesher.mesh_f32(&ball, s, BlockId(1), &mut out).unwrap();
    assert_eq!(open_edges(out.triangles(), |i| i), 0);
    // Genus 0: V = F + 2, so 16 + 6 = 22 B per quad (compact quads) plus 32 B in all.
    assert_eq!(out.vertices().len(), out.quad_count() + 2);
    assert!(matches!(out.quads(), SmoothQuads::Compact(_)));
    assert_eq!(out.byte_len(), 22 * out.quad_count() + 32);

    // Sine: the surface leaves the grid on every side, and the vertices on the border are
    // shared with the neighbours' meshes, so a few percent more vertices than quads: about
    // 22.8 B per quad.
    let wave = sample(s, [0.0; 3], sine(0.7));
    mesher.mesh_f32(&wave, s, BlockId(1), &mut out).unwrap();
    assert!(matches!(out.quads(), SmoothQuads::Compact(_)));
    assert!(out.bytes_per_quad() <= 24.0, "{}", out.bytes_per_quad());
    let used: std::collections::HashSet<u32> = out.quads().iter().flatten().collect();
    assert_eq!(used.len(), out.vertices().len(), "every vertex is used");
}

#[test]
fn wide_grids_are_closed_and_match_narrow_ones() {
    // Rows of more than 64 samples take the multi-word path; a sphere meshed in a 150-wide grid
    // gives the mesh of the same sphere in a 40-wide grid, shifted.
    let wide = shape([150, 20, 22]);
    let narrow = shape([40, 20, 22]);
    let f = |shift: f32| sphere([shift + 19.3, 9.6, 10.2], 7.4);
    let mut mesher = SurfaceNets::new();
    let (mut a, mut b) = (SmoothMeshF32::default(), SmoothMeshF32::default());
    mesher
        .mesh_f32_unpacked(&sample(wide, [0.0; 3], f(100.0)), wide, &mut a)
        .unwrap();
    mesher
        .mesh_f32_unpacked(&sample(narrow, [0.0; 3], f(0.0)), narrow, &mut b)
        .unwrap();
    assert_eq!(a.quads, b.quads);
    assert_eq!(a.positions.len(), b.positions.len());
    for (p, q) in a.positions.iter().zip(&b.positions) {
        // The densities differ by the rounding of `x - centre` at another x.
        let d = [p[0] - 100.0 - q[0], p[1] - q[1], p[2] - q[2]];
        assert!(d.iter().all(|d| d.abs() < 1e-4), "{p:?} vs {q:?}");
    }
    assert_eq!(open_edges(a.triangles(), |i| i), 0);
    let mut packed = SmoothMesh::new();
    mesher
        .mesh_f32(
            &sample(wide, [0.0; 3], f(100.0)),
            wide,
            BlockId(1),
            &mut packed,
        )
        .unwrap();
    assert_eq!(packed.quad_count(), a.quads.len());
    assert_eq!(open_edges(packed.triangles(), |i| i), 0);
    // A wide grid keeps compact quads while its rows hold few vertices (a small sphere).
    assert!(matches!(packed.quads(), SmoothQuads::Compact(_)));
    quad_form_is_the_narrowest(&packed, wide).unwrap();
}

#[test]
fn clear_keeps_capacity() {
    let s = GridShape::padded_chunk(ChunkSize::S16);
    let ball = sample(s, [0.0; 3], sphere([9.0; 3], 6.0));
    let mut mesher = SurfaceNets::new();
    let mut out = SmoothMesh::new();
    mesher.mesh_f32(&ball, s, BlockId(1), &mut out).unwrap();
    let before = out.clone();
    let bytes = out.vertex_bytes().as_ptr();
    out.clear();
    assert!(out.is_empty());
    mesher.mesh_f32(&ball, s, BlockId(1), &mut out).unwrap();
    assert_eq!(out, before);
    assert_eq!(out.vertex_bytes().as_ptr(), bytes, "no reallocation");
    // Decoded normals point away from the centre.
    for v in out.vertices() {
        let d = v.decode(out.extent());
        assert!(
            d.normal.dot(d.position - Vec3::splat(9.0))
                > 0.9 * (d.position - Vec3::splat(9.0)).length()
        );
        assert_eq!(oct16_decode(v.normal), d.normal);
    }
}
