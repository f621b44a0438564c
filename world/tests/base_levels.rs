//! A world over the terrain using its own coarse levels (`World::use_base_levels`): meshing what
//! a batch dirties equals meshing everything again at levels 0 to 2; a coarse voxel differs from
//! the terrain's only above changed blocks; reverting an edit gives the terrain's nodes back;
//! saving and loading gives the same nodes as the edits did.

use std::collections::BTreeMap;

use mesher::lod::{NodeMesh, NodeMesher, NodeSettings};
use mesher::{BlockClasses, MeshSettings};
use proptest::prelude::*;
use voxel_core::{BlockId, ChunkCoord, ChunkSize, LocalPos, PaddedChunk, WorldPos};
use voxel_scene::{Terrain, TerrainBlocks};
use voxel_world::{Base, Edit, World, WorldError};

const SIZE: ChunkSize = ChunkSize::S8;
const TOP: u32 = 2;
/// Edits land in x, z in `0..AREA`, within `DEPTH` blocks of the ground at the area's middle.
const AREA: i32 = 24;
const DEPTH: i32 = 6;

fn setup() -> (World<Terrain>, BlockClasses, [BlockId; 2], i32) {
    let (palette, blocks) = TerrainBlocks::palette();
    let classes = BlockClasses::from_palette(&palette);
    let terrain = Terrain::new(7, blocks);
    let ground = terrain.height(AREA / 2, AREA / 2);
    let mut world = World::new(terrain, SIZE, TOP).unwrap();
    world.use_base_levels(classes.clone()).unwrap();
    (world, classes, [blocks.stone, blocks.water], ground)
}

fn settings() -> NodeSettings {
    NodeSettings {
        mesh: MeshSettings::default(),
        far_blocks: true,
        ..Default::default()
    }
}

fn mesh_one(w: &World<Terrain>, level: u32, c: ChunkCoord, classes: &BlockClasses) -> NodeMesh {
    let mut padded = PaddedChunk::new(SIZE);
    w.gather_over_base(level, c, &mut padded).unwrap();
    let mut node = NodeMesh::default();
    NodeMesher::new()
        .mesh_padded(&padded, c, level, classes, &settings(), &mut node)
        .unwrap();
    node
}

/// The nodes of `level` whose padded neighbourhood can hold an edited block.
fn reachable(level: u32, ground: i32) -> Vec<ChunkCoord> {
    let e = SIZE.edge() as i32;
    let span =
        |lo: i32, hi: i32| ((lo >> level).div_euclid(e) - 1)..=((hi >> level).div_euclid(e) + 1);
    let mut out = Vec::new();
    for z in span(0, AREA) {
        for y in span(ground - DEPTH, ground + DEPTH) {
            for x in span(0, AREA) {
                out.push(ChunkCoord::new(x, y, z));
            }
        }
    }
    out
}

fn mesh_all(
    w: &World<Terrain>,
    classes: &BlockClasses,
    ground: i32,
) -> Vec<BTreeMap<ChunkCoord, NodeMesh>> {
    (0..=TOP)
        .map(|level| {
            reachable(level, ground)
                .into_iter()
                .map(|c| (c, mesh_one(w, level, c, classes)))
                .collect()
        })
        .collect()
}

fn edit_strategy() -> impl Strategy<Value = (u8, [i32; 3], u32, u8)> {
    (0u8..2, [0..AREA, -DEPTH..DEPTH, 0..AREA], 0u32..4, 0u8..3)
}

fn to_edit((kind, p, r, block): (u8, [i32; 3], u32, u8), ids: [BlockId; 2], ground: i32) -> Edit {
    let id = match block {
        0 => BlockId::AIR,
        1 => ids[0],
        _ => ids[1],
    };
    let pos = WorldPos::new(p[0], ground + p[1], p[2]);
    match kind {
        0 => Edit::Block { pos, id },
        _ => Edit::Sphere {
            centre: pos,
            radius: r,
            id,
        },
    }
}

/// Every coarse voxel of node `key` equal to the terrain's, except those above a block in
/// `changed`.
fn differs_only_above(
    w: &mut World<Terrain>,
    classes: &BlockClasses,
    level: u32,
    coord: ChunkCoord,
    changed: &[WorldPos],
) -> Result<(), String> {
    let node = w
        .lod_node(level, coord, classes)
        .map_err(|e| e.to_string())?;
    let mut padded = PaddedChunk::new(SIZE);
    w.base().fill_padded(level, coord, &mut padded)?;
    let e = SIZE.edge();
    for z in 0..e {
        for y in 0..e {
            for x in 0..e {
                let local = LocalPos {
                    x: x as u8,
                    y: y as u8,
                    z: z as u8,
                };
                let ours = voxel_core::storage::VoxelStorage::get(&node, local).unwrap();
                let base = padded.get(x + 1, y + 1, z + 1).unwrap();
                if ours == base {
                    continue;
                }
                let cell = [x, y, z].map(|v| v as i32);
                let origin = [coord.x, coord.y, coord.z].map(|c| c * e as i32);
                let above = changed.iter().any(|p| {
                    [p.x, p.y, p.z]
                        .iter()
                        .zip(origin.iter().zip(cell))
                        .all(|(&v, (&o, c))| v >> level == o + c)
                });
                if !above {
                    return Err(format!(
                        "level {level} node {coord:?} voxel {cell:?} differs with no change under it"
                    ));
                }
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    #[test]
    fn meshing_the_dirty_set_equals_meshing_everything(
        batch in proptest::collection::vec(edit_strategy(), 1..5)
    ) {
        let (mut w, classes, ids, ground) = setup();
        let mut before = mesh_all(&w, &classes, ground);
        let edits: Vec<Edit> = batch.into_iter().map(|e| to_edit(e, ids, ground)).collect();
        let dirty = w.apply(&edits).unwrap();
        for key in dirty.all_nodes() {
            if let Some(map) = before.get_mut(key.level as usize) {
                map.insert(key.coord, mesh_one(&w, key.level, key.coord, &classes));
            }
        }
        let after = mesh_all(&w, &classes, ground);
        for (level, (was, now)) in before.iter().zip(&after).enumerate() {
            for (c, mesh) in now {
                prop_assert!(
                    was.get(c) == Some(mesh),
                    "level {} node {:?} changed but is not in the dirty set", level, c
                );
            }
        }
    }

    #[test]
    fn saving_and_loading_gives_the_same_nodes(
        batch in proptest::collection::vec(edit_strategy(), 1..5)
    ) {
        let (mut w, classes, ids, ground) = setup();
        let edits: Vec<Edit> = batch.into_iter().map(|e| to_edit(e, ids, ground)).collect();
        let dirty = w.apply(&edits).unwrap();
        let dir = tempfile::tempdir().unwrap();
        w.save(dir.path()).unwrap();
        let (_, blocks) = TerrainBlocks::palette();
        let (mut loaded, report) = World::load(Terrain::new(7, blocks), dir.path(), TOP).unwrap();
        prop_assert!(report.faults.is_empty());
        loaded.use_base_levels(classes.clone()).unwrap();
        for key in dirty.all_nodes() {
            let ours = w.lod_node(key.level, key.coord, &classes).unwrap();
            let theirs = loaded.lod_node(key.level, key.coord, &classes).unwrap();
            prop_assert!(ours == theirs, "node {:?} differs after loading", key);
            let mut a = PaddedChunk::new(SIZE);
            let mut b = PaddedChunk::new(SIZE);
            w.gather_over_base(key.level, key.coord, &mut a).unwrap();
            loaded.gather_over_base(key.level, key.coord, &mut b).unwrap();
            prop_assert!(a == b, "node {:?}'s neighbourhood differs after loading", key);
        }
    }
}

#[test]
fn coarse_voxels_differ_only_above_changed_blocks() {
    let (mut w, classes, ids, ground) = setup();
    // Dig a pit: a sphere of air at the ground, and a stone block in the air above.
    let centre = WorldPos::new(12, ground, 12);
    let above = WorldPos::new(3, ground + 5, 20);
    let dirty = w
        .apply(&[
            Edit::Sphere {
                centre,
                radius: 3,
                id: BlockId::AIR,
            },
            Edit::Block {
                pos: above,
                id: ids[0],
            },
        ])
        .unwrap();
    let mut changed = Vec::new();
    for z in -3..=3 {
        for y in -3..=3 {
            for x in -3..=3 {
                if x * x + y * y + z * z <= 9 {
                    changed.push(WorldPos::new(12 + x, ground + y, 12 + z));
                }
            }
        }
    }
    changed.push(above);
    let mut coarse_changed = 0;
    for key in dirty.lod_nodes() {
        differs_only_above(&mut w, &classes, key.level, key.coord, &changed).unwrap();
        let node = w.lod_node(key.level, key.coord, &classes).unwrap();
        let mut padded = PaddedChunk::new(SIZE);
        w.base()
            .fill_padded(key.level, key.coord, &mut padded)
            .unwrap();
        if node != voxel_world::coarse::padded_interior(&padded) {
            coarse_changed += 1;
        }
    }
    // The floating block makes its level-1 and level-2 voxels solid where the terrain's are air.
    assert!(
        coarse_changed >= 2,
        "the edits changed {coarse_changed} coarse nodes"
    );
}

#[test]
fn reverting_an_edit_gives_the_terrains_nodes_back() {
    let (mut w, classes, ids, ground) = setup();
    let pos = WorldPos::new(5, ground + 4, 5);
    let was = w.block(pos).unwrap();
    assert_eq!(was, BlockId::AIR, "the test block lies in the air");
    let dirty = w.apply(&[Edit::Block { pos, id: ids[0] }]).unwrap();
    w.apply(&[Edit::Block { pos, id: was }]).unwrap();
    for key in dirty.lod_nodes() {
        let node = w.lod_node(key.level, key.coord, &classes).unwrap();
        let mut padded = PaddedChunk::new(SIZE);
        w.base()
            .fill_padded(key.level, key.coord, &mut padded)
            .unwrap();
        assert!(
            node == voxel_world::coarse::padded_interior(&padded),
            "node {key:?} keeps the reverted edit"
        );
    }
}

#[test]
fn a_base_without_levels_is_refused_by_name() {
    let mut w = World::new(voxel_world::AirBase, SIZE, 1).unwrap();
    let (palette, _) = TerrainBlocks::palette();
    let err = w
        .use_base_levels(BlockClasses::from_palette(&palette))
        .unwrap_err();
    assert!(matches!(err, WorldError::NoBaseLevels), "{err}");
    assert!(err.to_string().contains("no coarse levels"), "{err}");
    let mut padded = PaddedChunk::new(SIZE);
    assert!(matches!(
        w.gather_over_base(0, ChunkCoord::new(0, 0, 0), &mut padded),
        Err(WorldError::NoBaseLevels)
    ));
}
