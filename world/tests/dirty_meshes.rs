//! Meshing only what a batch dirties gives the same meshes as meshing everything again, at
//! level 0 and at level 1, and the level-of-detail nodes are the downsampling of the edited
//! level-0 data.

use std::collections::BTreeMap;

use mesher::lod::{NodeMesh, NodeMesher, NodeSettings, downsample_world};
use mesher::{BlockClasses, MeshSettings};
use proptest::prelude::*;
use voxel_core::storage::PaletteChunk;
use voxel_core::{
    BlockId, ChunkCoord, ChunkSize, Material, MaterialPalette, PaddedChunk, WorldPos,
};
use voxel_world::{Edit, FnBase, World};

const SIZE: ChunkSize = ChunkSize::S8;
/// The edited area: 3 x 3 x 3 chunks of 8^3.
const BLOCKS: i32 = 24;

fn palette() -> (MaterialPalette, [BlockId; 2]) {
    let mut p = MaterialPalette::new();
    let stone = p.push(Material::opaque(120, 120, 120)).unwrap();
    let glass = p
        .push(Material::opaque(200, 220, 255).with_class(voxel_core::MaterialClass::Transparent))
        .unwrap();
    (p, [stone, glass])
}

type TestWorld = World<FnBase<Box<dyn Fn(WorldPos) -> BlockId + Sync>>>;

fn world(stone: BlockId) -> TestWorld {
    let f: Box<dyn Fn(WorldPos) -> BlockId + Sync> = Box::new(move |p: WorldPos| {
        let h = 9 + (p.x * 3 + p.z * 5).rem_euclid(7);
        if p.y < h && p.y >= 0 {
            stone
        } else {
            BlockId::AIR
        }
    });
    World::new(FnBase(f), SIZE, 1).unwrap()
}

fn settings() -> NodeSettings {
    NodeSettings {
        mesh: MeshSettings::default(),
        far_blocks: true,
        ..Default::default()
    }
}

/// Every node of `level` that the area's edits can reach, meshed from the world.
fn mesh_all(
    w: &mut TestWorld,
    level: u32,
    classes: &BlockClasses,
) -> BTreeMap<ChunkCoord, NodeMesh> {
    let (lo, hi) = if level == 0 { (-1, 3) } else { (-1, 2) };
    let mut out = BTreeMap::new();
    for z in lo..=hi {
        for y in lo..=hi {
            for x in lo..=hi {
                let c = ChunkCoord::new(x, y, z);
                out.insert(c, mesh_one(w, level, c, classes));
            }
        }
    }
    out
}

fn mesh_one(w: &mut TestWorld, level: u32, c: ChunkCoord, classes: &BlockClasses) -> NodeMesh {
    let mut padded = PaddedChunk::new(SIZE);
    w.gather_node(level, c, classes, &mut padded).unwrap();
    let mut node = NodeMesh::default();
    NodeMesher::new()
        .mesh_padded(&padded, c, level, classes, &settings(), &mut node)
        .unwrap();
    node
}

fn edit_strategy() -> impl Strategy<Value = (u8, [i32; 3], [i32; 3], u32, u8)> {
    (
        0u8..3,
        [0..BLOCKS, 0..BLOCKS, 0..BLOCKS],
        [0i32..5, 0..5, 0..5],
        0u32..4,
        0u8..3,
    )
}

fn to_edit((kind, p, d, r, block): (u8, [i32; 3], [i32; 3], u32, u8), ids: [BlockId; 2]) -> Edit {
    let id = match block {
        0 => BlockId::AIR,
        1 => ids[0],
        _ => ids[1],
    };
    let pos = WorldPos::new(p[0], p[1], p[2]);
    match kind {
        0 => Edit::Block { pos, id },
        1 => Edit::Box {
            min: pos,
            max: WorldPos::new(p[0] + d[0], p[1] + d[1], p[2] + d[2]),
            id,
        },
        _ => Edit::Sphere {
            centre: pos,
            radius: r,
            id,
        },
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn meshing_the_dirty_set_equals_meshing_everything(
        batch in proptest::collection::vec(edit_strategy(), 1..6)
    ) {
        let (palette, ids) = palette();
        let classes = BlockClasses::from_palette(&palette);
        let mut w = world(ids[0]);
        let mut before = [mesh_all(&mut w, 0, &classes), mesh_all(&mut w, 1, &classes)];
        let edits: Vec<Edit> = batch.into_iter().map(|e| to_edit(e, ids)).collect();
        let dirty = w.apply(&edits).unwrap();
        let all: Vec<_> = dirty.all_nodes().collect();
        let mut unique = all.clone();
        unique.dedup();
        prop_assert_eq!(all.len(), unique.len(), "a node listed twice");
        for key in dirty.all_nodes() {
            let mesh = mesh_one(&mut w, key.level, key.coord, &classes);
            before[key.level as usize].insert(key.coord, mesh);
        }
        for level in 0..2u32 {
            let after = mesh_all(&mut w, level, &classes);
            for (c, mesh) in &after {
                prop_assert!(
                    before[level as usize].get(c) == Some(mesh),
                    "level {} node {:?} changed but is not in the dirty set", level, c
                );
            }
        }
    }

    #[test]
    fn level_one_nodes_are_the_downsampled_edited_chunks(
        batch in proptest::collection::vec(edit_strategy(), 1..6)
    ) {
        let (palette, ids) = palette();
        let classes = BlockClasses::from_palette(&palette);
        let mut w = world(ids[0]);
        let edits: Vec<Edit> = batch.into_iter().map(|e| to_edit(e, ids)).collect();
        w.apply(&edits).unwrap();
        for z in 0..4 { for y in 0..4 { for x in 0..4 {
            w.materialize(ChunkCoord::new(x, y, z)).unwrap();
        }}}
        let coarse = downsample_world(w.chunks(), &classes).unwrap();
        for z in 0..2 { for y in 0..2 { for x in 0..2 {
            let c = ChunkCoord::new(x, y, z);
            let node = w.lod_node(1, c, &classes).unwrap();
            let expected = coarse.get(c).cloned().unwrap_or_else(|| PaletteChunk::new(SIZE));
            prop_assert!(node == expected, "level-1 node {:?}", c);
        }}}
    }
}
