//! The edit loop with the mesher alone: edit a world over the procedural terrain, re-mesh
//! only what the edit dirties (level-0 chunks and the level-of-detail nodes above them), and
//! save and reload the world.
//!
//! ```sh
//! cargo run -p examples --example edit_remesh [-- WORLD_DIR]
//! ```
//!
//! Prints, per edit, the chunks it changed, the neighbours it dirtied and the nodes of each
//! level re-meshed with their packed bytes; then saves into `WORLD_DIR` (a temporary folder
//! by default) and checks that the reloaded world holds the same edited chunks.

use std::path::PathBuf;

use mesher::lod::{NodeMesh, NodeMesher, NodeSettings};
use mesher::{BlockClasses, MeshSettings};
use voxel_core::{BlockId, ChunkSize, PaddedChunk, WorldPos};
use voxel_scene::terrain::{Terrain, TerrainBlocks};
use voxel_world::{Edit, World};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            std::env::temp_dir().join(format!("edit_remesh-{}", std::process::id()))
        });
    let (palette, blocks) = TerrainBlocks::palette();
    let classes = BlockClasses::from_palette(&palette);
    let terrain = Terrain::new(7, blocks);
    let ground = terrain.height(0, 0);
    // Dirty sets up to level 2: nodes of 4-block voxels.
    let mut world = World::new(terrain, ChunkSize::S16, 2)?;
    let edits = [
        Edit::Block {
            pos: WorldPos::new(0, ground, 0),
            id: BlockId::AIR,
        },
        Edit::Sphere {
            centre: WorldPos::new(20, ground, -5),
            radius: 4,
            id: BlockId::AIR,
        },
        Edit::Box {
            min: WorldPos::new(-8, ground + 1, -8),
            max: WorldPos::new(-4, ground + 6, -4),
            id: blocks.stone,
        },
    ];
    let settings = NodeSettings {
        mesh: MeshSettings::default(),
        far_blocks: true,
        ..Default::default()
    };
    let mut padded = PaddedChunk::new(ChunkSize::S16);
    let mut mesher = NodeMesher::new();
    let mut node = NodeMesh::default();
    for edit in &edits {
        let dirty = world.apply(std::slice::from_ref(edit))?;
        println!(
            "{edit:?}: {} chunks changed, {} neighbours dirtied",
            dirty.changed().count(),
            dirty.neighbours().count()
        );
        for level in 0..=dirty.top_level() {
            let mut bytes = 0;
            let mut nodes = 0;
            for coord in dirty.remesh(level) {
                // Level 0 from the edited chunks, coarser levels downsampled from them.
                world.gather_node(level, coord, &classes, &mut padded)?;
                mesher.mesh_padded(&padded, coord, level, &classes, &settings, &mut node)?;
                // A renderer uploads node.layers() here, replacing the node's old data.
                let layers = node.layers();
                bytes += layers
                    .opaque_quads
                    .iter()
                    .map(|f| f.len() * 8)
                    .sum::<usize>()
                    + layers.draw_blocks.len() * 4;
                nodes += 1;
            }
            println!(
                "  level {level}: {nodes} nodes re-meshed, {bytes} bytes of quads and far blocks"
            );
        }
    }
    let written = world.save(&dir)?;
    let (loaded, report) = World::load(Terrain::new(7, blocks), &dir, 2)?;
    println!(
        "saved {written} region files to {}; reloaded {} chunks, {} faults",
        dir.display(),
        report.chunks,
        report.faults.len()
    );
    let same = world
        .edited()
        .all(|c| loaded.chunks().get(c) == world.chunks().get(c));
    if !same || report.chunks != world.edited().count() {
        return Err("the reloaded world differs from the saved one".into());
    }
    Ok(())
}
