//! NoCubes: one quad per visible face, smooth quads for smoothable blocks and cube faces for the
//! rest, closed welded meshes for closed inputs, the vertex block-id rule, pinned vertices on
//! cube corners, the quad form (compact when every quad fits it), and degenerate chunks.

mod smooth_support;

use std::collections::HashMap;

use glam::Vec3;
use mesher::smooth::{
    CUBE_FACE_FLAG, NoCubes, NoCubesStats, SmoothMesh, SmoothQuads, U16_INDEX_LIMIT,
};
use mesher::{BlockClasses, MeshError};
use proptest::prelude::*;
use smooth_support::open_edges;
use voxel_core::formats::compact_quad_encode;
use voxel_core::formats::octahedral::oct16_decode;
use voxel_core::{BlockId, ChunkSize, Material, MaterialClass, MaterialPalette, PaddedChunk};

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

/// Brute force: owned visible faces (opaque voxel next to a non-opaque one, the lower of the
/// two voxels in padded `1..=edge` on every axis), split into smoothable and other.
fn owned_faces(chunk: &PaddedChunk, classes: &BlockClasses) -> (usize, usize) {
    let p = chunk.padded_edge() as u32;
    let at = |x: u32, y: u32, z: u32| chunk.get(x, y, z).unwrap();
    let (mut smooth, mut cube) = (0, 0);
    for z in 1..p - 1 {
        for y in 1..p - 1 {
            for x in 1..p - 1 {
                let a = at(x, y, z);
                for b in [at(x + 1, y, z), at(x, y + 1, z), at(x, y, z + 1)] {
                    let solid = match (classes.is_opaque(a), classes.is_opaque(b)) {
                        (true, false) => a,
                        (false, true) => b,
                        _ => continue,
                    };
                    if is_smooth(classes, solid) {
                        smooth += 1;
                    } else {
                        cube += 1;
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

fn mesh(chunk: &PaddedChunk, classes: &BlockClasses) -> (SmoothMesh, NoCubesStats) {
    let mut out = SmoothMesh::new();
    let stats = NoCubes::new().mesh(chunk, classes, &mut out).unwrap();
    (out, stats)
}

fn check(chunk: &PaddedChunk, closed: bool) -> Result<(), TestCaseError> {
    let pal = palette();
    let classes = &pal.classes;
    let (out, stats) = mesh(chunk, classes);
    let extent = out.extent();
    prop_assert_eq!(extent.get(), chunk.padded_edge() as f32);

    // One quad per owned visible face.
    let (smooth, cube) = owned_faces(chunk, classes);
    prop_assert_eq!((stats.smooth_quads, stats.cube_quads), (smooth, cube));
    prop_assert_eq!(out.quad_count(), smooth + cube);
    prop_assert_eq!(
        out.vertices().len(),
        stats.smooth_vertices + stats.cube_vertices
    );

    // Every vertex is used.
    let mut used = vec![false; out.vertices().len()];
    out.quads()
        .iter()
        .flatten()
        .for_each(|i| used[i as usize] = true);
    prop_assert!(used.iter().all(|&u| u));

    let p = chunk.padded_edge() as u32;
    for q in out.quads().iter() {
        let v = q.map(|i| out.vertices()[i as usize]);
        let pos = v.map(|v| v.decode(extent).position);
        let cube = v[0].extra == CUBE_FACE_FLAG;
        prop_assert!(v.iter().all(|w| (w.extra == CUBE_FACE_FLAG) == cube));
        if !cube {
            continue;
        }
        // A cube face: one normal along an axis, one block id, counter-clockwise from outside.
        let normal = oct16_decode(v[0].normal);
        prop_assert!(
            v.iter()
                .all(|w| w.normal == v[0].normal && w.block == v[0].block)
        );
        prop_assert!([Vec3::X, Vec3::Y, Vec3::Z].contains(&normal.abs()));
        for [a, b, c] in [[0, 1, 2], [0, 2, 3]] {
            let n = (pos[b] - pos[a]).cross(pos[c] - pos[a]);
            prop_assert!(n.dot(normal) > 0.9, "{n} vs {normal}");
        }
        // A unit square on lattice points: the 4 corners of one voxel face.
        prop_assert!(
            pos.iter()
                .all(|p| (p.round() - *p).abs().max_element() < 1e-3)
        );
        let min = pos.iter().fold(Vec3::splat(f32::MAX), |m, p| m.min(*p));
        let max = pos.iter().fold(Vec3::splat(f32::MIN), |m, p| m.max(*p));
        prop_assert!(
            ((max - min) - (Vec3::ONE - normal.abs()))
                .abs()
                .max_element()
                < 1e-3
        );
        // Its block is the opaque, non-smoothable voxel behind the face.
        let behind = (min + max) * 0.5 - normal * 0.5;
        let id = chunk
            .get(behind.x as u32, behind.y as u32, behind.z as u32)
            .unwrap();
        prop_assert_eq!(id.0, v[0].block);
        prop_assert!(classes.is_opaque(id) && !is_smooth(classes, id));
    }

    // Smooth vertices: inside their cell's box, pinned to the lattice point when the cell
    // has a non-smoothable opaque voxel, carrying the most common smoothable id of the cell.
    for v in out.vertices().iter().filter(|v| v.extra != CUBE_FACE_FLAG) {
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
        let distance = (d.position - lattice).abs().max_element();
        if has_cube {
            prop_assert!(distance < 1e-3, "pinned: {} vs {}", d.position, lattice);
        } else {
            prop_assert!(
                distance < 0.5 - 1.0 / 48.0,
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

    // The quads are in the narrowest form that holds them all.
    let quads = out.quads();
    let all_compact = quads.iter().all(|q| compact_quad_encode(q).is_some());
    let small = out.vertices().len() <= U16_INDEX_LIMIT;
    match quads {
        SmoothQuads::Compact(_) => prop_assert!(all_compact),
        SmoothQuads::U16(_) => prop_assert!(!all_compact && small),
        // A 62^3 checkerboard has more than 65,536 vertices.
        SmoothQuads::U32(_) => prop_assert!(!small),
    }
    prop_assert_eq!(quads.bytes().len(), quads.quad_bytes() * quads.len());

    if closed {
        // Welded by packed position, a closed input gives a closed mesh.
        let tris: Vec<[u32; 3]> = out.triangles().collect();
        prop_assert_eq!(open_edges(tris, |i| out.vertices()[i as usize].position), 0);
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
    let (out, stats) = mesh(&chunk, &pal.classes);
    assert!(
        stats.smooth_quads > 1000 && stats.cube_quads > 1000,
        "{stats:?}"
    );
    // Shared cube corners: a flat floor costs about one vertex per face, not four.
    assert!(stats.cube_vertices < 2 * stats.cube_quads, "{stats:?}");
    // Cube-face vertices are made as their faces are, between the smooth vertices, so some
    // smooth quad's pair of vertices lies more than 63 apart and the mesh falls back to u16
    // quads (8 B): 16 B * 10,521 vertices / 9,770 quads + 8 B = 25.2 B per quad.
    assert!(matches!(out.quads(), SmoothQuads::U16(_)));
    assert!(out.bytes_per_quad() < 30.0, "{}", out.bytes_per_quad());

    // The same hill without stone: smooth quads only, whose vertices are numbered in cell scan
    // order as in SurfaceNets, so every quad is compact (6 B): 16 B * 9,772 vertices / 9,770
    // quads + 6 B = 22.0 B per quad.
    let smooth_only = PaddedChunk::from_fn(size, |x, y, z| match chunk.get(x, y, z) {
        Ok(id) if id == stone => dirt,
        Ok(id) => id,
        Err(e) => panic!("{e}"),
    });
    let (out, stats) = mesh(&smooth_only, &pal.classes);
    assert_eq!(stats.cube_quads, 0);
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
            let (out, stats) = mesh(&chunk, &pal.classes);
            assert!(out.is_empty(), "{size:?} {id:?}");
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
    let (_, stats) = mesh(&chunk, &pal.classes);
    assert_eq!(stats.smooth_quads, 6 * 9);
}

#[test]
fn unknown_ids_are_reported_before_any_output() {
    let pal = palette();
    let mut chunk = PaddedChunk::from_fn(ChunkSize::S16, |x, _, _| {
        if x < 9 { pal.ids[1] } else { BlockId::AIR }
    });
    chunk.set(4, 0, 17, BlockId(999)).unwrap();
    chunk.set(3, 5, 17, BlockId(998)).unwrap();
    let mut out = SmoothMesh::new();
    let mut mesher = NoCubes::new();
    mesher
        .mesh(
            &PaddedChunk::from_fn(ChunkSize::S16, |x, _, _| {
                if x < 9 { pal.ids[1] } else { BlockId::AIR }
            }),
            &pal.classes,
            &mut out,
        )
        .unwrap();
    assert!(!out.is_empty());
    assert_eq!(
        mesher.mesh(&chunk, &pal.classes, &mut out),
        Err(MeshError::UnknownBlock {
            id: BlockId(999),
            position: [4, 0, 17]
        })
    );
    assert!(out.is_empty());
}
