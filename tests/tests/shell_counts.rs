//! Shells against greedy quads on real voxels (a MagicaVoxel sample and a patch of the built-in
//! terrain, at levels 0 and 1): a node meshed as shells draws the same opaque surface as its
//! greedy quads (every voxel face a quad covers lies on a run with that side bit, and every
//! side bit of a run has a quad face on it), keeps its transparent quads and skirts, and the
//! per-node counts ([`geometry_counts`]) agree with the node meshes. Prints the instance
//! counts, bytes and triangles of both geometries.

use std::collections::HashMap;

use mesher::BlockClasses;
use mesher::lod::{
    Geometry, GeometryCounts, NodeMesh, NodeMesher, NodeSettings, downsample_levels,
    geometry_counts,
};
use tests::sample_data;
use viewer::scene::vox::load_vox_file;
use voxel_core::formats::FaceDirection;
use voxel_core::storage::{PaletteChunk, WorldMap, gather_neighbourhood};
use voxel_core::{ChunkCoord, ChunkSize, MaterialPalette, PaddedChunk};

/// The voxels the opaque greedy quads of `node` cover, with the faces they show.
fn quad_faces(node: &NodeMesh) -> HashMap<[u32; 3], u8> {
    let mut faces = HashMap::new();
    for quad in node.mesh.blocky.opaque.iter() {
        let q = quad.decode().expect("the mesher writes valid quads");
        let (w, h) = (q.face.width_axis(), q.face.height_axis());
        for du in 0..q.width {
            for dv in 0..q.height {
                let mut p = q.position;
                p[w] += du;
                p[h] += dv;
                *faces.entry(p).or_insert(0u8) |= 1 << q.face.index();
            }
        }
    }
    faces
}

/// Checks that `shells` (meshed as shells) draws what `greedy` draws; returns the counts.
fn same_surface(greedy: &NodeMesh, shells: &NodeMesh) -> GeometryCounts {
    assert!(
        shells.mesh.blocky.opaque.is_empty(),
        "shells replace opaque quads"
    );
    assert_eq!(
        shells.mesh.blocky.transparent,
        greedy.mesh.blocky.transparent
    );
    assert_eq!(shells.skirts, greedy.skirts);
    assert!(greedy.shells.is_empty());
    let quads = quad_faces(greedy);
    let mut runs: HashMap<[u32; 3], u8> = HashMap::new();
    for run in &shells.shells {
        let fields = run.decode().expect("the mesher writes valid runs");
        for voxel in run.voxels() {
            assert!(runs.insert(voxel, fields.sides).is_none(), "runs overlap");
        }
        // Every side the run draws has a greedy face on one of its voxels.
        for face in FaceDirection::ALL.into_iter().filter(|f| run.has_side(*f)) {
            let bit = 1 << face.index();
            assert!(
                run.voxels()
                    .any(|v| quads.get(&v).is_some_and(|q| q & bit != 0)),
                "{:?}: run {run:?} draws side {face:?} that no quad shows",
                greedy.coord
            );
        }
    }
    for (voxel, faces) in &quads {
        let sides = runs.get(voxel).copied().unwrap_or(0);
        assert_eq!(
            faces & !sides,
            0,
            "{:?}: voxel {voxel:?} shows faces {faces:#08b}, its run draws {sides:#08b}",
            greedy.coord
        );
    }
    GeometryCounts {
        quads: greedy.mesh.blocky.opaque.len() as u64,
        runs: shells.shells.len() as u64,
    }
}

/// Meshes every chunk of `world` (level `level`) both ways and compares; returns the totals.
fn compare_world(
    world: &WorldMap<PaletteChunk>,
    level: u32,
    palette: &MaterialPalette,
) -> GeometryCounts {
    let classes = BlockClasses::from_palette(palette);
    let greedy_settings = NodeSettings::default();
    let shell_settings = NodeSettings {
        geometry: Geometry::Shells,
        ..Default::default()
    };
    let mut mesher = NodeMesher::new();
    let mut padded = PaddedChunk::new(world.size());
    let mut coords: Vec<ChunkCoord> = world.iter().map(|(c, _)| c).collect();
    coords.sort_unstable();
    let mut total = GeometryCounts::default();
    for coord in coords {
        let (mut greedy, mut shells) = (NodeMesh::default(), NodeMesh::default());
        mesher
            .mesh_node(world, coord, level, &classes, &greedy_settings, &mut greedy)
            .expect("greedy node");
        mesher
            .mesh_node(world, coord, level, &classes, &shell_settings, &mut shells)
            .expect("shell node");
        let counts = same_surface(&greedy, &shells);
        gather_neighbourhood(world, coord, &mut padded);
        let direct = geometry_counts(&padded, &classes, &greedy_settings.mesh).expect("counts");
        assert_eq!(direct, counts, "{coord:?}: geometry_counts");
        total = total + counts;
    }
    total
}

fn report(name: &str, level: u32, c: GeometryCounts) {
    eprintln!(
        "{name} level {level}: {} runs ({} B, {} triangles) vs {} greedy quads ({} B, {} \
         triangles): runs / quads = {:.3}",
        c.runs,
        c.run_bytes(),
        c.run_triangles(),
        c.quads,
        c.quad_bytes(),
        c.quad_triangles(),
        c.runs as f64 / c.quads.max(1) as f64
    );
}

/// Levels 0 and 1 of `world`, compared; fails if a level has no surface.
fn compare_levels(name: &str, world: &WorldMap<PaletteChunk>, palette: &MaterialPalette) {
    let classes = BlockClasses::from_palette(palette);
    let level1 = downsample_levels(world, &classes, 1).expect("downsampling");
    for (level, w) in [(0, world), (1, &level1[0])] {
        let counts = compare_world(w, level, palette);
        assert!(
            counts.quads > 0 && counts.runs > 0,
            "{name} level {level}: {counts:?}"
        );
        report(name, level, counts);
    }
}

#[test]
fn shells_draw_the_greedy_surface_of_the_built_in_terrain() {
    let scene = viewer::scene::terrain_scene(7, ChunkSize::S16, 3, 2, 3);
    compare_levels("terrain 48x32x48", &scene.world, &scene.palette);
}

#[test]
fn shells_draw_the_greedy_surface_of_a_magicavoxel_model() {
    let Some(dir) = sample_data("vox") else {
        return;
    };
    let path = dir.join("chr_knight.vox");
    let scene = load_vox_file(&path, ChunkSize::S16, 1 << 24).expect("the sample loads");
    assert!(scene.voxel_count > 0);
    compare_levels("chr_knight.vox", &scene.world, &scene.palette);
}
