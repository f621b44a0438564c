//! Seamless chunk borders for the smooth meshers: meshing a region chunk by chunk gives the mesh
//! of the whole region (same quads, shared border vertices coincide), and a closed surface
//! gives a closed union (no boundary edges after welding).
//!
//! - SurfaceNets: 2 x 2 x 2 chunks of 8^3 samples, each meshed from its padded 10^3 grid, against
//!   the padded 18^3 grid of the region (the padding contract in `mesher::smooth`).
//! - NoCubes: the same blocks stored as 8 chunks of 8^3 and as one chunk of 16^3, gathered
//!   with `voxel_core::gather_neighbourhood`; the smooth quads and the cube quads' unit faces
//!   together are closed.

#[path = "../../mesher/tests/smooth_support/mod.rs"]
mod smooth_support;

use std::collections::{BTreeSet, HashMap};

use glam::Vec3;
use mesher::BlockClasses;
use mesher::blocky::BlockyMesh;
use mesher::smooth::{GridShape, NoCubes, SmoothMesh, SmoothMeshF32, SurfaceNets};
use proptest::prelude::*;
use smooth_support::{open_edges, sample, sine, sphere, unit_faces, weld};
use voxel_core::storage::{DenseChunk, WorldMap};
use voxel_core::{
    BlockId, ChunkCoord, ChunkSize, FaceDirection, LocalPos, Material, MaterialClass,
    MaterialPalette, PaddedChunk, gather_neighbourhood,
};

const N: u32 = 8;
const CHUNKS: [[u32; 3]; 8] = [
    [0, 0, 0],
    [1, 0, 0],
    [0, 1, 0],
    [1, 1, 0],
    [0, 0, 1],
    [1, 0, 1],
    [0, 1, 1],
    [1, 1, 1],
];

/// A quad as the cycle of its corners' keys, rotated to start at the smallest.
fn cycle<K: Ord + Copy>(q: [K; 4]) -> [K; 4] {
    let k = (0..4).min_by_key(|&i| q[i]).unwrap_or(0);
    std::array::from_fn(|i| q[(i + k) % 4])
}

/// The SurfaceNets quads of a density field `f` over the region: chunk by chunk (in region
/// cells, with each vertex's region position) and whole.
struct DensitySeams {
    chunk_quads: Vec<[[u32; 3]; 4]>,
    whole_quads: Vec<[[u32; 3]; 4]>,
    /// Region cell -> positions computed for it (whole grid first, then each chunk).
    positions: HashMap<[u32; 3], Vec<Vec3>>,
}

fn density_seams(f: &dyn Fn([f32; 3]) -> f32) -> DensitySeams {
    let mut mesher = SurfaceNets::new();
    let mut out = SmoothMeshF32::default();
    let mut positions: HashMap<[u32; 3], Vec<Vec3>> = HashMap::new();

    // The whole region: world samples -1..=2N, region padded coordinate = world + 1.
    let region = GridShape::new([2 * N + 2; 3]).unwrap();
    let samples = sample(region, [-1.0; 3], f);
    mesher
        .mesh_f32_unpacked(&samples, region, &mut out)
        .unwrap();
    for (c, p) in out.cells.iter().zip(&out.positions) {
        positions.entry(*c).or_default().push(Vec3::from(*p));
    }
    let whole_quads = out
        .quads
        .iter()
        .map(|q| cycle(q.map(|i| out.cells[i as usize])))
        .collect();

    // Chunk k: world samples o-1..=o+N with o = N k; its cell c is region cell c + o.
    let shape = GridShape::padded_chunk(ChunkSize::S8);
    let mut chunk_quads = Vec::new();
    for k in CHUNKS {
        let o = k.map(|a| a * N);
        let samples = sample(shape, o.map(|a| a as f32 - 1.0), f);
        mesher.mesh_f32_unpacked(&samples, shape, &mut out).unwrap();
        let region_cell = |c: [u32; 3]| [0, 1, 2].map(|a| c[a] + o[a]);
        for (c, p) in out.cells.iter().zip(&out.positions) {
            let world = Vec3::from(*p) + Vec3::from(o.map(|a| a as f32));
            positions.entry(region_cell(*c)).or_default().push(world);
        }
        chunk_quads.extend(
            out.quads
                .iter()
                .map(|q| cycle(q.map(|i| region_cell(out.cells[i as usize])))),
        );
    }
    DensitySeams {
        chunk_quads,
        whole_quads,
        positions,
    }
}

fn check_density_seams(f: &dyn Fn([f32; 3]) -> f32, closed: bool) -> Result<(), TestCaseError> {
    let mut seams = density_seams(f);
    // No double faces: every edge's quad appears once across the chunks.
    let n = seams.chunk_quads.len();
    seams.chunk_quads.sort();
    seams.chunk_quads.dedup();
    prop_assert_eq!(seams.chunk_quads.len(), n, "a quad is meshed by two chunks");
    // No gaps: the union is exactly the region's mesh (corners and orientation).
    seams.whole_quads.sort();
    prop_assert_eq!(&seams.chunk_quads, &seams.whole_quads);
    // Every cell's vertex is the same in the region and in every chunk that has it, so the
    // border vertices of neighbouring chunks coincide.
    let mut shared = 0;
    for ps in seams.positions.values() {
        shared += usize::from(ps.len() > 2);
        for p in &ps[1..] {
            prop_assert!((*p - ps[0]).abs().max_element() <= 1e-5, "{p} vs {}", ps[0]);
        }
    }
    if closed {
        prop_assert!(shared > 0, "the surface crosses a chunk border");
        let tris = seams
            .chunk_quads
            .iter()
            .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]]);
        // Weld by region cell: the union is closed.
        let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
        let mut id = |c: [u32; 3]| {
            let next = ids.len() as u32;
            *ids.entry(c).or_insert(next)
        };
        let tris: Vec<[u32; 3]> = tris.map(|t| t.map(&mut id)).collect();
        prop_assert_eq!(open_edges(tris, |i| i), 0);
    }
    Ok(())
}

#[test]
fn sphere_across_eight_chunks_is_seamless_and_closed() {
    let f = sphere([7.6, 8.3, 8.1], 5.7);
    check_density_seams(&f, true).unwrap();
}

#[test]
fn sine_through_every_border_is_seamless() {
    check_density_seams(&sine(0.9), false).unwrap();
}

#[test]
fn planes_on_the_chunk_borders_are_seamless() {
    // Exactly on the samples where chunks meet, and half a sample off.
    for k in [7.0f32, 7.5, 8.0, 8.5, 9.0] {
        for axis in 0..3 {
            check_density_seams(&move |p: [f32; 3]| p[axis] - k, false).unwrap();
            check_density_seams(&move |p: [f32; 3]| k - p[axis], false).unwrap();
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn random_densities_are_seamless(seed in any::<u64>(), inside in 0.2f64..0.8) {
        let f = move |p: [f32; 3]| {
            let h = p
                .iter()
                .fold(seed, |h, &a| (h ^ a.to_bits() as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
            let u = ((h >> 11) as f64 / (1u64 << 53) as f64) as f32;
            u - inside as f32
        };
        check_density_seams(&f, false)?;
    }

    #[test]
    fn random_spheres_are_seamless_and_closed(
        // Within 1.5 of the corner where the 8 chunks meet, radius >= 2: crosses every border.
        centre in prop::array::uniform3(6.5f32..9.5),
        radius in 2.0f32..4.5,
    ) {
        check_density_seams(&sphere(centre, radius), true)?;
    }
}

#[test]
fn packed_border_vertices_coincide() {
    // Packed chunk meshes: each vertex decoded to world coordinates; vertices of the same
    // region cell from different chunks agree within twice the unorm16 bound.
    let f = sphere([7.6, 8.3, 8.1], 5.7);
    let shape = GridShape::padded_chunk(ChunkSize::S8);
    let bound = 2.0 * shape.extent().max_error();
    let mut mesher = SurfaceNets::new();
    let (mut packed, mut raw) = (SmoothMesh::new(), SmoothMeshF32::default());
    let mut world: HashMap<[u32; 3], Vec<Vec3>> = HashMap::new();
    let (mut points, mut quads) = (Vec::new(), Vec::new());
    for k in CHUNKS {
        let o = k.map(|a| a * N);
        let samples = sample(shape, o.map(|a| a as f32 - 1.0), &f);
        mesher
            .mesh_f32(&samples, shape, BlockId(1), &mut packed)
            .unwrap();
        mesher.mesh_f32_unpacked(&samples, shape, &mut raw).unwrap();
        // The packed vertices are the used unpacked ones, in order.
        let mut used = vec![false; raw.cells.len()];
        raw.quads
            .iter()
            .flatten()
            .for_each(|&i| used[i as usize] = true);
        let cells: Vec<[u32; 3]> = (0..used.len())
            .filter(|&i| used[i])
            .map(|i| [0, 1, 2].map(|a| raw.cells[i][a] + o[a]))
            .collect();
        assert_eq!(cells.len(), packed.vertices().len());
        let base = points.len() as u32;
        for (v, c) in packed.vertices().iter().zip(&cells) {
            let p = v.decode(packed.extent()).position + Vec3::from(o.map(|a| a as f32 - 1.0));
            world.entry(*c).or_default().push(p);
            points.push(p.to_array());
        }
        quads.extend(packed.quads().iter().map(|q| q.map(|i| i + base)));
    }
    let mut shared = 0;
    for ps in world.values() {
        shared += usize::from(ps.len() > 1);
        for p in &ps[1..] {
            assert!(
                (*p - ps[0]).abs().max_element() <= bound,
                "{p} vs {}",
                ps[0]
            );
        }
    }
    assert!(shared > 20);
    // Welded by position (tolerance far below the vertex spacing), the union is closed.
    let ids = weld(&points, 1e-3);
    let tris = quads
        .iter()
        .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]]);
    assert_eq!(open_edges(tris, |i| ids[i as usize]), 0);
}

// ---- NoCubes ----

struct Blocks {
    classes: BlockClasses,
    ids: [BlockId; 5],
}

/// Air, two smoothable ids, a cube id and water.
fn blocks() -> Blocks {
    let mut palette = MaterialPalette::new();
    let smooth = Material::opaque(1, 2, 3).with_class(MaterialClass::Smoothable);
    let dirt = palette.push(smooth).unwrap();
    let grass = palette.push(smooth).unwrap();
    let stone = palette.push(Material::opaque(9, 9, 9)).unwrap();
    let water = palette
        .push(Material::opaque(0, 0, 200).with_class(MaterialClass::Transparent))
        .unwrap();
    Blocks {
        classes: BlockClasses::from_palette(&palette),
        ids: [BlockId::AIR, dirt, grass, stone, water],
    }
}

/// A NoCubes region in world coordinates: smooth vertices and quads (world-vertex indices),
/// and the cube quads' unit faces as (world voxel, direction index) with their corners.
#[derive(Default)]
struct NoCubesWorld {
    points: Vec<[f32; 3]>,
    smooth_quads: Vec<[u32; 4]>,
    cube_faces: Vec<([i32; 3], u8, [[i32; 3]; 4])>,
}

/// Meshes `block(world position)` over [0, 16)^3 as chunks of `size` with NoCubes.
fn nocubes_world(
    size: ChunkSize,
    classes: &BlockClasses,
    block: &dyn Fn([i32; 3]) -> BlockId,
) -> NoCubesWorld {
    let e = size.edge() as i32;
    let n = 16 / e;
    let mut world = WorldMap::new(size);
    for cz in 0..n {
        for cy in 0..n {
            for cx in 0..n {
                let chunk = DenseChunk::from_fn(size, |p: LocalPos| {
                    block([
                        cx * e + i32::from(p.x),
                        cy * e + i32::from(p.y),
                        cz * e + i32::from(p.z),
                    ])
                });
                world.insert(ChunkCoord::new(cx, cy, cz), chunk).unwrap();
            }
        }
    }
    let mut padded = PaddedChunk::new(size);
    let mut mesher = NoCubes::new();
    let (mut smooth, mut cubes) = (SmoothMesh::new(), BlockyMesh::new());
    let mut out = NoCubesWorld::default();
    for (coord, _) in world.iter() {
        gather_neighbourhood(&world, coord, &mut padded);
        let stats = mesher
            .mesh(&padded, classes, &mut smooth, &mut cubes)
            .unwrap();
        assert_eq!(stats.smooth_quads, smooth.quad_count());
        let base = out.points.len() as u32;
        let corner = [coord.x, coord.y, coord.z].map(|c| c * e);
        let origin = Vec3::from(corner.map(|c| c as f32)) - 1.0;
        out.points.extend(
            smooth
                .vertices()
                .iter()
                .map(|v| (v.decode(smooth.extent()).position + origin).to_array()),
        );
        out.smooth_quads
            .extend(smooth.quads().iter().map(|q| q.map(|i| i + base)));
        let world_of = |p: [u32; 3]| std::array::from_fn(|i| corner[i] + p[i] as i32);
        out.cube_faces.extend(
            unit_faces(&cubes.opaque)
                .iter()
                .map(|f| (world_of(f.voxel), f.face, f.corners.map(world_of))),
        );
    }
    out
}

/// Visible faces in [0, 16)^3 (opaque next to non-opaque): the number of smoothable ones, and
/// the others as (voxel, direction index).
fn visible_faces(
    classes: &BlockClasses,
    block: &dyn Fn([i32; 3]) -> BlockId,
) -> (usize, BTreeSet<([i32; 3], u8)>) {
    let (mut smooth, mut cube) = (0, BTreeSet::new());
    for z in -1..=16 {
        for y in -1..=16 {
            for x in -1..=16 {
                let id = block([x, y, z]);
                if !classes.is_opaque(id) {
                    continue;
                }
                for face in FaceDirection::ALL {
                    let d = face.normal();
                    if !classes.is_opaque(block([x + d[0], y + d[1], z + d[2]])) {
                        if classes.class(id) == Some(MaterialClass::Smoothable) {
                            smooth += 1;
                        } else {
                            cube.insert(([x, y, z], face.index()));
                        }
                    }
                }
            }
        }
    }
    (smooth, cube)
}

fn check_nocubes_seams(block: &dyn Fn([i32; 3]) -> BlockId) -> Result<(), TestCaseError> {
    let b = blocks();
    let (faces_smooth, faces_cube) = visible_faces(&b.classes, block);
    let m8 = nocubes_world(ChunkSize::S8, &b.classes, block);
    let m16 = nocubes_world(ChunkSize::S16, &b.classes, block);
    // One smooth quad per smoothable visible face, and cube quads covering exactly the other
    // visible faces, each once, whether meshed in 8 chunks or in one.
    for m in [&m8, &m16] {
        prop_assert_eq!(m.smooth_quads.len(), faces_smooth);
        let cube: BTreeSet<_> = m.cube_faces.iter().map(|f| (f.0, f.1)).collect();
        prop_assert_eq!(cube.len(), m.cube_faces.len(), "overlapping cube quads");
        prop_assert_eq!(&cube, &faces_cube);
    }
    // Weld both meshes together (vertices are at least 1/24 voxel apart; unorm16 error is
    // below 2e-4): the chunked smooth quads are the whole chunk's quads.
    let points: Vec<[f32; 3]> = m8.points.iter().chain(&m16.points).copied().collect();
    let ids = weld(&points, 1e-3);
    let off = m8.points.len() as u32;
    let key = |q: [u32; 4], base: u32| cycle(q.map(|i| ids[(i + base) as usize]));
    let mut a: Vec<_> = m8.smooth_quads.iter().map(|&q| key(q, 0)).collect();
    let mut c: Vec<_> = m16.smooth_quads.iter().map(|&q| key(q, off)).collect();
    a.sort();
    c.sort();
    prop_assert_eq!(&a, &c);
    // The blocks are inside the region, so the smooth quads and the cube faces of the 8 chunks,
    // welded by position, close up: no crack at chunk borders or where the two meet.
    let mut points = m8.points.clone();
    let mut tris: Vec<[u32; 3]> = m8
        .smooth_quads
        .iter()
        .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
        .collect();
    for (_, _, corners) in &m8.cube_faces {
        let first = points.len() as u32;
        points.extend(corners.map(|c| c.map(|a| a as f32)));
        tris.extend([[first, first + 1, first + 2], [first, first + 2, first + 3]]);
    }
    let ids = weld(&points, 1e-3);
    prop_assert_eq!(open_edges(tris, |i| ids[i as usize]), 0);
    Ok(())
}

#[test]
fn nocubes_ball_pierced_by_a_stone_pillar_across_chunks() {
    let b = blocks();
    let [air, dirt, grass, stone, _] = b.ids;
    let block = move |p: [i32; 3]| {
        let d2: i32 = p.iter().map(|&a| (2 * a - 15) * (2 * a - 15)).sum();
        let pillar = (6..=9).contains(&p[0]) && (7..=8).contains(&p[2]) && (2..14).contains(&p[1]);
        if d2 < 4 * 9 || pillar {
            stone
        } else if d2 < 4 * 30 {
            if p[1] > 9 { grass } else { dirt }
        } else {
            air
        }
    };
    let (smooth, cube) = visible_faces(&b.classes, &block);
    assert!(smooth > 100 && cube.len() > 10, "{smooth} {}", cube.len());
    check_nocubes_seams(&block).unwrap();
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn nocubes_random_blocks_across_chunks(seed in any::<u64>(), fill in 1u64..4) {
        let b = blocks();
        let ids = b.ids;
        let block = move |p: [i32; 3]| {
            if p.iter().any(|&a| !(1..15).contains(&a)) {
                return BlockId::AIR;
            }
            let h = p.iter().fold(seed, |h, &a| {
                (h ^ a as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15).rotate_left(29)
            });
            if h % 4 < fill { ids[1 + (h >> 8) as usize % 4] } else { ids[0] }
        };
        check_nocubes_seams(&block)?;
    }
}
