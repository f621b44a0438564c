//! One single-block edit, end to end on one core: apply it (the dirty set), then re-mesh every
//! level-0 chunk it dirties (greedy quads with AO, gathered from the world) and take each
//! chunk's packed upload view (`ChunkMesh::layers`), as a renderer would before uploading.
//! The second function is the viewer's own path: the terrain as the world's base with its
//! own levels (`World::use_base_levels`, dirty sets and coarse voxels up to level 6), each
//! dirtied level-0 node filled from the terrain with the edits over it
//! (`World::gather_over_base`) and meshed as the streamer meshes it (`NodeMesher`: quads,
//! far-draw blocks, skirts per side), its upload view taken.
//!
//! ```sh
//! cargo bench -p benches --bench world_edit
//! ```
//!
//! The block sits on a corner of chunk (0, 1, 0) of 16^3 chunks (x = z = 0, y = 16), in
//! rolling ground whose surface crosses it, so the edit dirties 8 chunks: the chunk and the 7
//! neighbours that share the corner (a single voxel lies in at most 8 padded
//! neighbourhoods). Each iteration toggles it between air and stone. All chunks the gathers
//! read are materialized before timing, as they are in a world the viewer has streamed.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use mesher::lod::{NodeMesh, NodeMesher, NodeSettings};
use mesher::{BlockClasses, ChunkMesh, ChunkMesher, MeshSettings};
use voxel_core::{
    BlockId, ChunkCoord, ChunkSize, Material, MaterialPalette, PaddedChunk, WorldPos,
};
use voxel_scene::{Terrain, TerrainBlocks};
use voxel_world::{Edit, FnBase, World};

fn world_edit(c: &mut Criterion) {
    let mut palette = MaterialPalette::new();
    let stone = palette
        .push(Material::opaque(120, 120, 120))
        .expect("palette");
    let classes = BlockClasses::from_palette(&palette);
    let ground = FnBase(move |p: WorldPos| {
        let h = 14 + (p.x * 3 + p.z * 5).rem_euclid(5);
        if p.y < h { stone } else { BlockId::AIR }
    });
    let mut world = World::new(ground, ChunkSize::S16, 0).expect("world");
    for z in -2..=2 {
        for y in -1..=3 {
            for x in -2..=2 {
                world
                    .materialize(ChunkCoord::new(x, y, z))
                    .expect("materialize");
            }
        }
    }
    let pos = WorldPos::new(0, 16, 0);
    let settings = MeshSettings::default();
    let mut padded = PaddedChunk::new(ChunkSize::S16);
    let mut mesher = ChunkMesher::new();
    let mut mesh = ChunkMesh::default();
    let mut toggle = false;
    let mut group = c.benchmark_group("world_edit");
    group.bench_function("single_block_16^3_dirty_remesh_pack_8_chunks", |b| {
        b.iter(|| {
            toggle = !toggle;
            let id = if toggle { stone } else { BlockId::AIR };
            let dirty = world.apply(&[Edit::Block { pos, id }]).expect("edit");
            let mut bytes = 0usize;
            let mut chunks = 0usize;
            for coord in dirty.remesh(0) {
                world.gather_chunk(coord, &mut padded).expect("gather");
                mesher
                    .mesh_gathered(&padded, coord, &classes, &settings, &mut mesh)
                    .expect("mesh");
                let layers = mesh.layers();
                bytes += layers
                    .opaque_quads
                    .iter()
                    .map(|f| f.len() * 8)
                    .sum::<usize>();
                chunks += 1;
            }
            assert_eq!(chunks, 8, "the corner edit dirties 8 chunks");
            black_box(bytes)
        })
    });
    terrain_node_edit(&mut group);
    group.finish();
}

/// The viewer's path (see the module docs): a block at a chunk corner on the terrain's
/// surface, toggled between air and stone.
fn terrain_node_edit(group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>) {
    let (palette, blocks) = TerrainBlocks::palette();
    let classes = BlockClasses::from_palette(&palette);
    let terrain = Terrain::new(1, blocks);
    let ground = terrain.height(0, 0);
    let mut world = World::new(terrain, ChunkSize::S16, 6).expect("world");
    world
        .use_base_levels(classes.clone())
        .expect("the terrain has levels");
    // The surface block at x = z = 0 sits on a chunk corner on x and z.
    let pos = WorldPos::new(0, ground, 0);
    let settings = NodeSettings {
        mesh: MeshSettings::default(),
        far_blocks: true,
        ..Default::default()
    };
    let mut padded = PaddedChunk::new(ChunkSize::S16);
    let mut mesher = NodeMesher::new();
    let mut node = NodeMesh::default();
    let mut toggle = false;
    group.bench_function("single_block_terrain_nodes_16^3_levels_0_to_6", |b| {
        b.iter(|| {
            toggle = !toggle;
            let id = if toggle { blocks.stone } else { BlockId::AIR };
            let dirty = world.apply(&[Edit::Block { pos, id }]).expect("edit");
            let mut bytes = 0u64;
            let mut nodes = 0usize;
            for coord in dirty.remesh(0) {
                world
                    .gather_over_base(0, coord, &mut padded)
                    .expect("gather");
                mesher
                    .mesh_padded(&padded, coord, 0, &classes, &settings, &mut node)
                    .expect("mesh");
                bytes += node.layers().byte_len();
                nodes += 1;
            }
            assert!(nodes >= 4, "the corner edit dirties {nodes} level-0 nodes");
            black_box(bytes)
        })
    });
}

criterion_group!(benches, world_edit);
criterion_main!(benches);
