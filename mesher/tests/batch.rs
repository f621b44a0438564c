//! Whole-chunk and batch meshing: the same meshes whatever the thread count, skipped chunks are
//! exactly those with nothing to draw, and LOD borders are closed.

#[path = "blocky_support/mod.rs"]
mod blocky_support;

use mesher::blocky::{BlockyMesh, GreedyMesher};
use mesher::lod::{downsample_world, prepare_lod_border};
use mesher::{
    BlockClasses, ChunkMesh, ChunkMesher, ClutterLayer, ClutterParams, MeshSettings, SurfaceMode,
    mesh_chunks, mesh_chunks_sequential, place_clutter,
};
use voxel_core::storage::{DenseChunk, WorldMap, gather_neighbourhood};
use voxel_core::{
    BlockId, ChunkCoord, ChunkSize, FaceDirection, Material, MaterialClass, MaterialPalette,
    PaddedChunk, PaletteChunk, WorldPos,
};

const STONE: BlockId = BlockId(1);
const GRASS: BlockId = BlockId(2);
const WATER: BlockId = BlockId(3);
const DIRT: BlockId = BlockId(4);

fn palette() -> MaterialPalette {
    let mut p = MaterialPalette::new();
    p.push(Material::opaque(120, 120, 120)).unwrap();
    p.push(Material::opaque(80, 160, 60).with_class(MaterialClass::ClutterBearing))
        .unwrap();
    p.push(Material::opaque(40, 80, 200).with_class(MaterialClass::Transparent))
        .unwrap();
    p.push(Material::opaque(120, 80, 50).with_class(MaterialClass::Smoothable))
        .unwrap();
    p
}

/// Hills of stone, dirt and grass with a lake, over `chunks` x 2 x `chunks` chunks of `size`,
/// plus three layers of solid stone chunks below (the middle ones buried).
fn world(size: ChunkSize, chunks: i32) -> WorldMap<PaletteChunk> {
    let e = size.edge() as i32;
    let mut world = WorldMap::new(size);
    for cz in 0..chunks {
        for cx in 0..chunks {
            for cy in -3..0 {
                world
                    .insert(
                        ChunkCoord::new(cx, cy, cz),
                        PaletteChunk::filled(size, STONE),
                    )
                    .unwrap();
            }
            for cy in 0..2 {
                let coord = ChunkCoord::new(cx, cy, cz);
                let dense = DenseChunk::from_fn(size, |p| {
                    let (x, y, z) = (
                        cx * e + i32::from(p.x),
                        cy * e + i32::from(p.y),
                        cz * e + i32::from(p.z),
                    );
                    let h = e / 2
                        + ((x as f32 * 0.31).sin() * 3.0 + (z as f32 * 0.23).cos() * 4.0) as i32;
                    match y {
                        y if y > h && y <= e / 2 - 2 => WATER,
                        y if y > h => BlockId::AIR,
                        y if y == h => GRASS,
                        y if y >= h - 2 => DIRT,
                        _ => STONE,
                    }
                });
                world
                    .insert(coord, PaletteChunk::from_dense(&dense))
                    .unwrap();
            }
        }
    }
    world
}

fn region(chunks: i32) -> Vec<ChunkCoord> {
    let mut coords = Vec::new();
    for cz in -1..=chunks {
        for cy in -4..=2 {
            for cx in -1..=chunks {
                coords.push(ChunkCoord::new(cx, cy, cz));
            }
        }
    }
    coords
}

fn settings(surface: SurfaceMode) -> MeshSettings {
    MeshSettings {
        surface,
        clutter: Some(ClutterParams::new(1.5, 42).unwrap()),
    }
}

#[test]
fn batch_meshes_are_identical_for_any_thread_count() {
    let size = ChunkSize::S16;
    let world = world(size, 3);
    let classes = BlockClasses::from_palette(&palette());
    let coords = region(3);
    for surface in [
        SurfaceMode::Greedy,
        SurfaceMode::VisibleFaces,
        SurfaceMode::NoCubes,
    ] {
        let s = settings(surface);
        let sequential = mesh_chunks_sequential(&world, &coords, &classes, &s).unwrap();
        assert!(
            sequential.iter().any(|m| !m.blocky.transparent.is_empty()),
            "the lake shows"
        );
        assert!(
            sequential.iter().any(|m| !m.clutter.is_empty()),
            "grass grows clutter"
        );
        for threads in [1, 2, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let parallel = pool
                .install(|| mesh_chunks(&world, &coords, &classes, &s))
                .unwrap();
            assert_eq!(parallel, sequential, "{surface:?} on {threads} threads");
        }
        for (mesh, coord) in sequential.iter().zip(&coords) {
            assert_eq!(mesh.coord, *coord);
        }
    }
}

/// The parallel mesher keeps one mesher per thread between calls: calls that alternate chunk
/// sizes and surface modes on the same threads still match a fresh sequential mesher.
#[test]
fn per_thread_meshers_carry_nothing_between_calls() {
    let classes = BlockClasses::from_palette(&palette());
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let worlds = [
        (world(ChunkSize::S16, 2), SurfaceMode::NoCubes),
        (world(ChunkSize::S32, 1), SurfaceMode::Greedy),
        (world(ChunkSize::S8, 3), SurfaceMode::VisibleFaces),
        (world(ChunkSize::S16, 2), SurfaceMode::Greedy),
    ];
    for round in 0..2 {
        for (world, surface) in &worlds {
            let s = settings(*surface);
            let coords = region(3);
            let fresh = mesh_chunks_sequential(world, &coords, &classes, &s).unwrap();
            let reused = pool
                .install(|| mesh_chunks(world, &coords, &classes, &s))
                .unwrap();
            assert_eq!(
                reused,
                fresh,
                "round {round}, {:?} chunks, {surface:?}",
                world.size()
            );
        }
    }
}

#[test]
fn skipped_chunks_are_exactly_those_with_nothing_to_draw() {
    let size = ChunkSize::S16;
    let world = world(size, 3);
    let classes = BlockClasses::from_palette(&palette());
    let s = settings(SurfaceMode::Greedy);
    let mut mesher = ChunkMesher::new();
    let mut padded = PaddedChunk::new(size);
    let mut greedy = GreedyMesher::new();
    let (mut skipped, mut meshed) = (0, 0);
    for coord in region(3) {
        let mut got = ChunkMesh::default();
        mesher
            .mesh_chunk(&world, coord, &classes, &s, &mut got)
            .unwrap();
        // The long way: always gather, then mesh every layer.
        gather_neighbourhood(&world, coord, &mut padded);
        let mut blocky = BlockyMesh::new();
        greedy.mesh(&padded, &classes, &mut blocky).unwrap();
        let mut clutter = ClutterLayer::new();
        place_clutter(
            &padded,
            &classes,
            coord,
            s.clutter.as_ref().unwrap(),
            &mut clutter,
        )
        .unwrap();
        assert_eq!(got.blocky, blocky, "{coord:?}");
        assert_eq!(got.clutter, clutter, "{coord:?}");
        if got.is_empty() {
            skipped += 1
        } else {
            meshed += 1
        }
    }
    assert!(
        skipped > 0 && meshed > 0,
        "the region has both kinds ({skipped} empty, {meshed} drawn)"
    );
}

#[test]
fn an_unknown_id_is_reported_and_leaves_the_mesh_empty() {
    let mut world: WorldMap = WorldMap::new(ChunkSize::S8);
    world.set_block(WorldPos::new(2, 2, 2), BlockId(999));
    let classes = BlockClasses::from_palette(&palette());
    let mut out = ChunkMesh::default();
    let err = ChunkMesher::new()
        .mesh_chunk(
            &world,
            ChunkCoord::new(0, 0, 0),
            &classes,
            &settings(SurfaceMode::Greedy),
            &mut out,
        )
        .unwrap_err();
    assert!(
        matches!(
            err,
            mesher::MeshError::UnknownBlock {
                id: BlockId(999),
                ..
            }
        ),
        "{err:?}"
    );
    assert!(out.is_empty());
}

/// Unit faces of a layer that lie on the chunk's `face` boundary plane.
fn boundary_faces(mesh: &BlockyMesh, face: FaceDirection, e: u32) -> i64 {
    let plane = if face.is_positive() { e } else { 0 };
    mesh.opaque
        .face(face)
        .iter()
        .map(|q| q.decode().unwrap())
        .filter(|f| f.corners()[0][face.normal_axis()] == plane)
        .map(|f| i64::from(f.width * f.height))
        .sum()
}

#[test]
fn chunks_at_a_level_border_close_their_side_so_no_crack_can_open() {
    let size = ChunkSize::S16;
    let e = size.edge();
    let fine = world(size, 4);
    let classes = BlockClasses::from_palette(&palette());
    let coarse = downsample_world(&fine, &classes).unwrap();
    let mut padded = PaddedChunk::new(size);
    let mut greedy = GreedyMesher::new();
    let mut mesh = BlockyMesh::new();
    // Fine chunk (1, 0, 1) is drawn at level 0; everything beyond x = 2 chunks at level 1, so its
    // +X side borders a coarser chunk. The coarse chunk (1, 0, 0) at level 1 covers fine chunks
    // x = 2..=3, z = 0..=1: its -X side borders level 0.
    for (world, coord, face) in [
        (&fine, ChunkCoord::new(1, 0, 1), FaceDirection::PosX),
        (&coarse, ChunkCoord::new(1, 0, 0), FaceDirection::NegX),
    ] {
        gather_neighbourhood(world, coord, &mut padded);
        prepare_lod_border(&mut padded, |f| f != face);
        greedy.mesh(&padded, &classes, &mut mesh).unwrap();
        // Every opaque voxel of the border layer shows its border face: that side is closed.
        let layer = if face.is_positive() { e } else { 1 };
        let mut solid_on_border = 0;
        for a in 1..=e {
            for b in 1..=e {
                let mut p = [a, b, a];
                p[face.normal_axis()] = layer;
                p[(face.normal_axis() + 1) % 3] = a;
                p[(face.normal_axis() + 2) % 3] = b;
                solid_on_border +=
                    i64::from(classes.is_opaque(padded.get(p[0], p[1], p[2]).unwrap()));
            }
        }
        assert!(solid_on_border > 0, "the border cuts through ground");
        assert_eq!(
            boundary_faces(&mesh, face, e),
            solid_on_border,
            "{coord:?} {face:?}"
        );
        // Closing every side closes the whole chunk: its signed volume is its voxel count.
        prepare_lod_border(&mut padded, |_| false);
        greedy.mesh(&padded, &classes, &mut mesh).unwrap();
        let volume = blocky_support::opaque_voxels(&padded, &classes);
        assert_eq!(blocky_support::six_times_volume(&mesh.opaque), 6 * volume);
    }
}
