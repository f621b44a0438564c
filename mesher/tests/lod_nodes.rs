//! Node meshing for level-of-detail renderers: the parallel paths equal the sequential ones,
//! and each node carries exactly its chunk's quads, skirts, surface blocks and hiding mask.

use mesher::lod::{
    NodeSettings, Skirts, downsample_levels, downsample_world, downsample_world_parallel,
    mesh_nodes, mesh_nodes_sequential, skirt_blocks, skirt_quads,
};
use mesher::surface_blocks::hiding_mask;
use mesher::{BlockClasses, ChunkMesher, MeshSettings, SurfaceBlocks, surface_blocks};
use voxel_core::storage::{WorldMap, gather_neighbourhood};
use voxel_core::{
    BlockId, ChunkCoord, ChunkSize, FaceDirection, Material, MaterialClass, MaterialPalette,
    PaddedChunk, WorldPos,
};

fn palette() -> MaterialPalette {
    let mut p = MaterialPalette::new();
    p.push(Material::opaque(90, 90, 90)).unwrap(); // 1 stone
    p.push(Material::opaque(40, 160, 40)).unwrap(); // 2 grass
    p.push(Material::opaque(20, 40, 200).with_class(MaterialClass::Transparent))
        .unwrap(); // 3 water
    p
}

/// A hilly world of 6 x 3 x 6 chunks of 8^3 with caves and a pond, from a fixed hash.
fn world() -> WorldMap {
    let size = ChunkSize::S8;
    let mut world = WorldMap::new(size);
    for x in -24i32..24 {
        for z in -24i32..24 {
            let h = 6 + (x * 7 + z * 13).rem_euclid(11) / 2 + (x / 5 - z / 7).abs() % 4;
            for y in -8i32..h.min(15) {
                let hole = (x * 31 + y * 17 + z * 7).rem_euclid(23) == 0;
                if !hole {
                    let id = if y == h - 1 { BlockId(2) } else { BlockId(1) };
                    world.set_block(WorldPos::new(x, y, z), id);
                }
            }
            if h < 8 {
                for y in h..8 {
                    world.set_block(WorldPos::new(x, y, z), BlockId(3));
                }
            }
        }
    }
    world
}

fn coords<C: voxel_core::storage::VoxelStorage>(w: &WorldMap<C>) -> Vec<ChunkCoord> {
    let mut c: Vec<ChunkCoord> = w.iter().map(|(c, _)| c).collect();
    // Neighbours of stored chunks too: air chunks next to ground carry no geometry, but
    // must be visited and dropped.
    c.push(ChunkCoord::new(10, 10, 10));
    c.sort_unstable();
    c
}

#[test]
fn parallel_downsampling_and_node_meshing_equal_the_sequential_ones() {
    let classes = BlockClasses::from_palette(&palette());
    let world = world();
    let level1 = downsample_world(&world, &classes).unwrap();
    let parallel = downsample_world_parallel(&world, &classes).unwrap();
    let collect = |w: &WorldMap<voxel_core::storage::PaletteChunk>| {
        let mut v: Vec<_> = w.iter().map(|(c, chunk)| (c, chunk.clone())).collect();
        v.sort_by_key(|(c, _)| *c);
        v
    };
    assert_eq!(collect(&level1), collect(&parallel));
    let levels = downsample_levels(&world, &classes, 2).unwrap();
    assert_eq!(levels.len(), 2);
    assert_eq!(collect(&levels[0]), collect(&level1));
    let settings = NodeSettings {
        mesh: MeshSettings::default(),
        far_blocks: true,
        ..Default::default()
    };
    for (level, w) in [(1, &levels[0]), (2, &levels[1])] {
        let c = coords(w);
        let a = mesh_nodes(w, level, &c, &classes, &settings).unwrap();
        let b = mesh_nodes_sequential(w, level, &c, &classes, &settings).unwrap();
        assert_eq!(a, b, "level {level}");
        assert!(a.iter().all(|n| n.level == level && !n.is_empty()));
        assert!(!a.is_empty());
    }
}

#[test]
fn each_node_carries_its_chunks_layers() {
    let classes = BlockClasses::from_palette(&palette());
    let world = world();
    let settings = NodeSettings {
        mesh: MeshSettings::default(),
        far_blocks: true,
        ..Default::default()
    };
    let c = coords(&world);
    let nodes = mesh_nodes(&world, 0, &c, &classes, &settings).unwrap();
    let mut padded = PaddedChunk::new(ChunkSize::S8);
    let mut chunk = ChunkMesher::new();
    let mut surface = SurfaceBlocks::new();
    let mut skirts = Skirts::new();
    let mut mask = Vec::new();
    let mut with_skirt_blocks = 0;
    for node in &nodes {
        gather_neighbourhood(&world, node.coord, &mut padded);
        let mut mesh = mesher::ChunkMesh::default();
        chunk
            .mesh_gathered(
                &padded,
                node.coord,
                &classes,
                &MeshSettings::default(),
                &mut mesh,
            )
            .unwrap();
        assert_eq!(node.mesh, mesh, "{:?}", node.coord);
        surface_blocks(&padded, &classes, &mut surface).unwrap();
        assert_eq!(node.blocks, surface.blocks());
        hiding_mask(&padded, &classes, &mut mask);
        assert_eq!(node.hiding_mask, mask);
        skirt_quads(&padded, &classes, &mut skirts).unwrap();
        for side in FaceDirection::ALL {
            assert_eq!(node.skirts.quads(side), skirts.quads(side));
        }
        skirt_blocks(&padded, &classes, &mut skirts).unwrap();
        for side in FaceDirection::ALL {
            assert_eq!(node.skirts.blocks(side), skirts.blocks(side));
        }
        with_skirt_blocks += usize::from(skirts.block_counts() != [0; 6]);
    }
    assert!(with_skirt_blocks > 0, "the world has buried border blocks");
    // Without far blocks the far data stays empty.
    let plain = mesh_nodes(&world, 0, &c, &classes, &NodeSettings::default()).unwrap();
    assert!(
        plain
            .iter()
            .all(|n| n.blocks.is_empty() && n.hiding_mask.is_empty())
    );
    assert_eq!(plain.len(), nodes.len());
}

#[test]
fn meshing_a_filled_neighbourhood_equals_meshing_the_world() {
    use mesher::lod::{NodeMesh, NodeMesher};
    let classes = BlockClasses::from_palette(&palette());
    let world = world();
    let settings = NodeSettings {
        mesh: MeshSettings::default(),
        far_blocks: true,
        ..Default::default()
    };
    let mut from_world = NodeMesher::new();
    let mut from_padded = NodeMesher::new();
    let mut padded = PaddedChunk::new(ChunkSize::S8);
    let mut meshed = 0;
    for coord in coords(&world) {
        let (mut a, mut b) = (NodeMesh::default(), NodeMesh::default());
        from_world
            .mesh_node(&world, coord, 1, &classes, &settings, &mut a)
            .unwrap();
        // The caller's own neighbourhood: here gathered, as a generator would fill it.
        gather_neighbourhood(&world, coord, &mut padded);
        from_padded
            .mesh_padded(&padded, coord, 1, &classes, &settings, &mut b)
            .unwrap();
        if a.is_empty() {
            // mesh_node skips absent and buried chunks without extracting (no masks either).
            assert!(b.is_empty(), "chunk {coord:?} draws nothing either way");
        } else {
            assert_eq!(a, b, "chunk {coord:?}");
            meshed += 1;
        }
    }
    assert!(meshed > 10, "{meshed} chunks drew something");
}
