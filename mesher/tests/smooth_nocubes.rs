//! NoCubes: one smooth quad per visible face of a smoothable block, greedy cube quads covering
//! exactly the other blocks' visible faces, closed meshes (smooth quads welded to the cube
//! quads' unit faces) for closed inputs, the vertex block-id rule, pinned vertices exactly on
//! the lattice codes of cube corners, compact smooth quads, and degenerate chunks.

mod smooth_support;

use std::collections::{HashMap, HashSet};

use glam::Vec3;
use mesher::blocky::{BlockyMesh, GreedyMesher};
use mesher::smooth::{NoCubes, NoCubesStats, SmoothMesh, SmoothQuads, U16_INDEX_LIMIT};
use mesher::{BlockClasses, MeshError};
use proptest::prelude::*;
use smooth_support::{open_edges, unit_faces};
use voxel_core::formats::UnormExtent;
use voxel_core::{
    BlockId, ChunkSize, FaceDirection, Material, MaterialClass, MaterialPalette, PaddedChunk,
};

/// Air, smoothable dirt and grass, opaque stone, clutter-bearing moss (a cube too) and water.
struct Palette {
    classes: BlockClasses,
    ids: [BlockId; 6],
}

fn palette() -> Palette {
    let mut p = MaterialPalette::new();
    let smooth = Material::opaque(1, 2, 3).with_class(MaterialClass::Smoothable);
    let dirt = p.push(smooth).unwrap();
    let grass = p.push(smooth).unwrap();
    let stone = p.push(Material::opaque(9, 9, 9)).unwrap();
    let moss = p
        .push(Material::opaque(0, 99, 0).with_class(MaterialClass::ClutterBearing))
        .unwrap();
    let water = p
        .push(Material::opaque(0, 0, 200).with_class(MaterialClass::Transparent))
        .unwrap();
    Palette {
        classes: BlockClasses::from_palette(&p),
        ids: [BlockId::AIR, dirt, grass, stone, moss, water],
    }
}

fn is_smooth(classes: &BlockClasses, id: BlockId) -> bool {
    classes.class(id) == Some(MaterialClass::Smoothable)
}

/// Brute force: the owned smooth faces (smoothable voxel next to a non-opaque one, the lower
/// of the two voxels in padded `1..=edge` on every axis) and the cube faces (a visible face of
/// a non-smoothable opaque voxel of the chunk's own, padded `1..=edge`: the greedy mesher's
/// rule), each as (padded voxel, direction index of `FaceDirection::ALL`).
fn brute_force_faces(
    chunk: &PaddedChunk,
    classes: &BlockClasses,
) -> (usize, HashSet<([u32; 3], u8)>) {
    let p = chunk.padded_edge() as u32;
    let at = |v: [u32; 3]| chunk.get(v[0], v[1], v[2]).unwrap();
    let mut smooth = 0;
    for z in 1..p - 1 {
        for y in 1..p - 1 {
            for x in 1..p - 1 {
                let a = at([x, y, z]);
                for b in [at([x + 1, y, z]), at([x, y + 1, z]), at([x, y, z + 1])] {
                    let solid = match (classes.is_opaque(a), classes.is_opaque(b)) {
                        (true, false) => a,
                        (false, true) => b,
                        _ => continue,
                    };
                    smooth += usize::from(is_smooth(classes, solid));
                }
            }
        }
    }
    let mut cube = HashSet::new();
    for z in 1..p - 1 {
        for y in 1..p - 1 {
            for x in 1..p - 1 {
                let id = at([x, y, z]);
                if !classes.is_opaque(id) || is_smooth(classes, id) {
                    continue;
                }
                for face in FaceDirection::ALL {
                    let n = face.normal();
                    let next = [x as i32 + n[0], y as i32 + n[1], z as i32 + n[2]];
                    if !classes.is_opaque(at(next.map(|a| a as u32))) {
                        cube.insert(([x, y, z], face.index()));
                    }
                }
            }
        }
    }
    (smooth, cube)
}

/// A random chunk of `size`; with `closed`, everything outside padded `2..=edge` is air, so every
/// face is owned and the surface is closed.
fn random_chunk(size: ChunkSize, closed: bool) -> impl Strategy<Value = PaddedChunk> {
    let p = size.padded_edge();
    (
        proptest::collection::vec(0usize..12, p * p * p),
        prop::sample::select(vec![0usize, 3, 6]),
    )
        .prop_map(move |(picks, sparsity)| {
            let ids = palette().ids;
            let e = size.edge();
            PaddedChunk::from_fn(size, |x, y, z| {
                if closed && [x, y, z].iter().any(|&a| a < 2 || a > e) {
                    return BlockId::AIR;
                }
                let pick = picks[x as usize + p * (y as usize + p * z as usize)];
                if pick < sparsity {
                    BlockId::AIR
                } else {
                    ids[pick % 6]
                }
            })
        })
}

fn mesh(chunk: &PaddedChunk, classes: &BlockClasses) -> (SmoothMesh, BlockyMesh, NoCubesStats) {
    let (mut smooth, mut cubes) = (SmoothMesh::new(), BlockyMesh::new());
    let stats = NoCubes::new()
        .mesh(chunk, classes, &mut smooth, &mut cubes)
        .unwrap();
    (smooth, cubes, stats)
}

fn check(chunk: &PaddedChunk, closed: bool) -> Result<(), TestCaseError> {
    let pal = palette();
    let classes = &pal.classes;
    let (out, cubes, stats) = mesh(chunk, classes);
    let extent = out.extent();
    prop_assert_eq!(extent, UnormExtent::padded_lattice(chunk.size()));
    // Codes per voxel: integer positions have exact codes.
    let scale = (65535.0 / extent.get()).round() as u32;
    prop_assert_eq!(scale.count_ones(), 1);

    // One smooth quad per owned smooth face; the cube quads cover exactly the cube faces, each
    // once, and the transparent quads are the greedy mesher's.
    let (smooth, cube) = brute_force_faces(chunk, classes);
    prop_assert_eq!(stats.smooth_quads, smooth);
    prop_assert_eq!(out.quad_count(), smooth);
    prop_assert_eq!(out.vertices().len(), stats.smooth_vertices);
    prop_assert_eq!(stats.cube_quads, cubes.opaque.len());
    let faces = unit_faces(&cubes.opaque);
    let covered: HashSet<_> = faces
        .iter()
        .map(|f| (f.voxel.map(|a| a + 1), f.face))
        .collect();
    prop_assert_eq!(covered.len(), faces.len(), "overlapping cube quads");
    prop_assert_eq!(&covered, &cube);
    let mut greedy = BlockyMesh::new();
    GreedyMesher::new()
        .mesh(chunk, classes, &mut greedy)
        .unwrap();
    prop_assert_eq!(&cubes.transparent, &greedy.transparent);

    // Every vertex is used.
    let mut used = vec![false; out.vertices().len()];
    out.quads()
        .iter()
        .flatten()
        .for_each(|i| used[i as usize] = true);
    prop_assert!(used.iter().all(|&u| u));

    // Smooth vertices: inside their cell's box, exactly on the lattice point's code when the
    // cell has a non-smoothable opaque voxel, carrying the most common smoothable id of the
    // cell.
    let p = chunk.padded_edge() as u32;
    for v in out.vertices() {
        let d = v.decode(extent);
        let cell = (d.position - Vec3::splat(0.5)).floor();
        let lattice = cell + Vec3::ONE;
        let c = cell.to_array().map(|a| a as u32);
        prop_assert!(
            c.iter().all(|&a| a + 1 < p),
            "vertex {} outside the cells",
            d.position
        );
        let corners: Vec<BlockId> = (0..8)
            .map(|i| {
                chunk
                    .get(c[0] + (i & 1), c[1] + ((i >> 1) & 1), c[2] + (i >> 2))
                    .unwrap()
            })
            .collect();
        let has_cube = corners
            .iter()
            .any(|&id| classes.is_opaque(id) && !is_smooth(classes, id));
        if has_cube {
            let code = c.map(|a| ((a + 1) * scale) as u16);
            prop_assert_eq!(v.position, code, "pinned to {}", lattice);
        } else {
            prop_assert!(
                (d.position - lattice).abs().max_element() < 0.5 - 1.0 / 48.0,
                "{} in cell {}",
                d.position,
                cell
            );
        }
        let smooth_ids: Vec<u16> = corners
            .iter()
            .filter(|&&id| is_smooth(classes, id))
            .map(|id| id.0)
            .collect();
        let mut counts: HashMap<u16, usize> = HashMap::new();
        smooth_ids
            .iter()
            .for_each(|&id| *counts.entry(id).or_default() += 1);
        let best = counts.values().max().copied().unwrap_or(0);
        let want = counts
            .iter()
            .filter(|(_, n)| **n == best)
            .map(|(id, _)| *id)
            .min();
        prop_assert_eq!(Some(v.block), want);
    }

    // Smooth quads are compact (6 B) up to 65,536 vertices (vertices in cell scan order).
    let quads = out.quads();
    match quads {
        SmoothQuads::Compact(_) => {}
        SmoothQuads::U16(_) => prop_assert!(false, "u16 quads in a chunk grid"),
        // A 62^3 checkerboard has more than 65,536 vertices.
        SmoothQuads::U32(_) => prop_assert!(out.vertices().len() > U16_INDEX_LIMIT),
    }
    prop_assert_eq!(quads.bytes().len(), quads.quad_bytes() * quads.len());

    if closed {
        // Welded by position code, the smooth quads and the cube quads' unit faces close up:
        // a closed input gives a closed surface, with no crack where they meet.
        let mut points: Vec<[u16; 3]> = out.vertices().iter().map(|v| v.position).collect();
        let mut tris: Vec<[u32; 3]> = out.triangles().collect();
        for f in &faces {
            let first = points.len() as u32;
            points.extend(f.corners.map(|c| c.map(|a| ((a + 1) * scale) as u16)));
            tris.push([first, first + 1, first + 2]);
            tris.push([first, first + 2, first + 3]);
        }
        prop_assert_eq!(open_edges(tris, |i| points[i as usize]), 0);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn closed_random_chunks_8(chunk in random_chunk(ChunkSize::S8, true)) {
        check(&chunk, true)?;
    }

    #[test]
    fn open_random_chunks_8(chunk in random_chunk(ChunkSize::S8, false)) {
        check(&chunk, false)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(8))]

    #[test]
    fn closed_random_chunks_16(chunk in random_chunk(ChunkSize::S16, true)) {
        check(&chunk, true)?;
    }
}

#[test]
fn smooth_hill_on_a_stone_floor_is_closed() {
    // A 62^3 chunk: a stone slab with a smoothable hill on it, and a stone cube on the hill.
    let pal = palette();
    let [air, dirt, grass, stone, ..] = pal.ids;
    let size = ChunkSize::S62;
    let chunk = PaddedChunk::from_fn(size, |x, y, z| {
        if [x, y, z].iter().any(|&a| !(2..=62).contains(&a)) {
            return air;
        }
        let (fx, fz) = (x as f32 - 31.0, z as f32 - 31.0);
        let hill = 20.0 - (fx * fx + fz * fz).sqrt() * 0.7;
        if y < 6 {
            stone
        } else if (y as f32) < hill {
            if (y as f32) + 1.0 >= hill {
                grass
            } else {
                dirt
            }
        } else if (28..=33).contains(&x) && (28..=33).contains(&z) && y < 26 {
            stone
        } else {
            air
        }
    });
    check(&chunk, true).unwrap();
    let (out, cubes, stats) = mesh(&chunk, &pal.classes);
    let faces = unit_faces(&cubes.opaque).len();
    assert!(stats.smooth_quads > 1000 && faces > 1000, "{stats:?}");
    // Cube faces merge: the stone slab's flat top and bottom are few quads.
    assert!(4 * stats.cube_quads < faces, "{stats:?}, {faces} faces");
    // Smooth vertices are numbered in cell scan order as in SurfaceNets, so every smooth quad
    // is compact (6 B): 16 B * 9,772 vertices / 9,770 quads + 6 B = 22.0 B per smooth quad.
    assert!(matches!(out.quads(), SmoothQuads::Compact(_)));
    assert!(out.bytes_per_quad() <= 24.0, "{}", out.bytes_per_quad());
}

#[test]
fn degenerate_chunks() {
    let pal = palette();
    let [air, dirt, _, stone, _, water] = pal.ids;
    for size in ChunkSize::ALL {
        for id in [air, dirt, stone, water] {
            let chunk = PaddedChunk::from_fn(size, |_, _, _| id);
            let (out, cubes, stats) = mesh(&chunk, &pal.classes);
            assert!(out.is_empty() && cubes.is_empty(), "{size:?} {id:?}");
            assert_eq!(stats, NoCubesStats::default());
        }
        // A 3-D checkerboard of dirt and air, and of stone and dirt, and single voxels.
        for (a, b) in [(dirt, air), (stone, dirt), (dirt, water)] {
            let chunk =
                PaddedChunk::from_fn(size, |x, y, z| if (x + y + z) % 2 == 0 { a } else { b });
            check(&chunk, false).unwrap();
        }
        let e = size.edge();
        for at in [[1, 1, 1], [e, e, e], [2, e, 1]] {
            for id in [dirt, stone] {
                let chunk =
                    PaddedChunk::from_fn(size, |x, y, z| if [x, y, z] == at { id } else { air });
                check(&chunk, false).unwrap();
            }
        }
    }
}

#[test]
fn transparent_blocks_are_outside() {
    let pal = palette();
    let [_, dirt, _, _, _, water] = pal.ids;
    let chunk = PaddedChunk::from_fn(ChunkSize::S8, |x, y, z| {
        if [x, y, z].iter().all(|a| (3..6).contains(a)) {
            dirt
        } else {
            water
        }
    });
    let (_, cubes, stats) = mesh(&chunk, &pal.classes);
    assert_eq!(stats.smooth_quads, 6 * 9);
    // Water against water or dirt shows no face, and there is no cube.
    assert!(cubes.is_empty());
}

#[test]
fn unknown_ids_are_reported_before_any_output() {
    let pal = palette();
    let known = PaddedChunk::from_fn(ChunkSize::S16, |x, y, _| match x {
        0..9 => pal.ids[1],
        9 if y < 5 => pal.ids[3],
        _ => BlockId::AIR,
    });
    let mut chunk = known.clone();
    chunk.set(4, 0, 17, BlockId(999)).unwrap();
    chunk.set(3, 5, 17, BlockId(998)).unwrap();
    let (mut smooth, mut cubes) = (SmoothMesh::new(), BlockyMesh::new());
    let mut mesher = NoCubes::new();
    mesher
        .mesh(&known, &pal.classes, &mut smooth, &mut cubes)
        .unwrap();
    assert!(!smooth.is_empty() && !cubes.is_empty());
    assert_eq!(
        mesher.mesh(&chunk, &pal.classes, &mut smooth, &mut cubes),
        Err(MeshError::UnknownBlock {
            id: BlockId(999),
            position: [4, 0, 17]
        })
    );
    assert!(smooth.is_empty() && cubes.is_empty());
}
