//! One single-block edit, end to end on one core: apply it (the dirty set), then re-mesh every
//! level-0 chunk it dirties (greedy quads with AO, gathered from the world) and take each
//! chunk's packed upload view (`ChunkMesh::layers`), as a renderer would before uploading.
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
use mesher::{BlockClasses, ChunkMesh, ChunkMesher, MeshSettings};
use voxel_core::{
    BlockId, ChunkCoord, ChunkSize, Material, MaterialPalette, PaddedChunk, WorldPos,
};
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
    group.finish();
}

criterion_group!(benches, world_edit);
criterion_main!(benches);
