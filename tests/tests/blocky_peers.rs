//! The blocky meshers against `block-mesh` 0.2 on the same padded arrays:
//!
//! - visible faces: exactly `visible_block_faces`' unit faces, direction by direction;
//! - greedy, AO off: exactly as many quads as `greedy_quads` (the same algorithm, on bits);
//! - greedy, AO on: exactly as many quads as `greedy_quads` run with each voxel's merge value
//!   set to its id plus the corner AO of its face in that direction (AO-safe merging);
//!
//! so the greedy quad count never exceeds `block-mesh`'s for the same merge rule. For inputs
//! with transparent ids, the opaque layer is compared with `block-mesh` run on a view where
//! transparent voxels are empty (its visibility rules for transparent voxels differ from ours:
//! it hides faces between two different transparent ids).

use block_mesh::ndshape::{RuntimeShape, Shape};
use block_mesh::{
    GreedyQuadsBuffer, MergeVoxel, RIGHT_HANDED_Y_UP_CONFIG, UnitQuadBuffer, Voxel,
    VoxelVisibility, greedy_quads, visible_block_faces,
};
use mesher::BlockClasses;
use mesher::blocky::{BlockyMesh, GreedyMesher};
use proptest::prelude::*;
use voxel_core::{
    BlockId, ChunkSize, FaceDirection, Material, MaterialClass, MaterialPalette, PaddedChunk,
};

/// A `block-mesh` voxel: visibility plus a merge value (id, and AO byte or 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct BmVoxel {
    visibility: VoxelVisibility,
    merge: (u16, u8),
}

impl Voxel for BmVoxel {
    fn get_visibility(&self) -> VoxelVisibility {
        self.visibility
    }
}

impl MergeVoxel for BmVoxel {
    type MergeValue = (u16, u8);
    fn merge_value(&self) -> (u16, u8) {
        self.merge
    }
}

/// Our direction index of `block-mesh`'s face group `g` in `RIGHT_HANDED_Y_UP_CONFIG`
/// (-X, -Y, -Z, +X, +Y, +Z).
const GROUP_TO_OURS: [usize; 6] = [1, 3, 5, 0, 2, 4];

fn palette(transparent: bool) -> MaterialPalette {
    let mut p = MaterialPalette::new();
    for i in 0..4u8 {
        p.push(Material::opaque(50 * i, 20, 20)).unwrap();
    }
    let glass = Material::opaque(200, 200, 255);
    p.push(if transparent {
        glass.with_class(MaterialClass::Transparent)
    } else {
        glass
    })
    .unwrap();
    p
}

fn random_chunk(size: ChunkSize, seed: u64, air_percent: u64, blocky: bool) -> PaddedChunk {
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut next = move |n: u64| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state % n
    };
    // `blocky` chunks are made of 4 x 4 x 4 cells of one id each, so faces merge.
    let cells: Vec<u16> = (0..16 * 16 * 16)
        .map(|_| {
            if next(100) < air_percent {
                0
            } else {
                1 + next(5) as u16
            }
        })
        .collect();
    let mut voxel = |x: u32, y: u32, z: u32| {
        if blocky {
            cells[(x / 4 + 16 * (y / 4 + 16 * (z / 4))) as usize]
        } else if next(100) < air_percent {
            0
        } else {
            1 + next(5) as u16
        }
    };
    PaddedChunk::from_fn(size, |x, y, z| BlockId(voxel(x, y, z)))
}

fn is_solid(classes: &BlockClasses, id: u16) -> bool {
    id != 0 && !classes.is_transparent(BlockId(id))
}

/// Corner AO of the face of padded voxel `pos` facing `face`, by brute force, packed as in
/// `PackedQuad` (corner i at bits 2i..2i+2), corners in `PackedQuadFields::corners` order.
fn face_ao(padded: &PaddedChunk, classes: &BlockClasses, pos: [i64; 3], face: FaceDirection) -> u8 {
    let p = padded.padded_edge() as i64;
    let solid = |q: [i64; 3]| {
        q.iter().all(|&a| (0..p).contains(&a))
            && is_solid(
                classes,
                padded.get(q[0] as u32, q[1] as u32, q[2] as u32).unwrap().0,
            )
    };
    let n = face.normal();
    let front = [
        pos[0] + i64::from(n[0]),
        pos[1] + i64::from(n[1]),
        pos[2] + i64::from(n[2]),
    ];
    let swap = matches!(
        face,
        FaceDirection::PosX | FaceDirection::PosY | FaceDirection::NegZ
    );
    let mut packed = 0u8;
    for (i, (a, b)) in [(0i64, 0i64), (1, 0), (1, 1), (0, 1)]
        .into_iter()
        .enumerate()
    {
        let (du, dv) = if swap { (b, a) } else { (a, b) };
        let mut w = [0i64; 3];
        w[face.width_axis()] = 2 * du - 1;
        let mut h = [0i64; 3];
        h[face.height_axis()] = 2 * dv - 1;
        let add = |x: [i64; 3], y: [i64; 3]| [x[0] + y[0], x[1] + y[1], x[2] + y[2]];
        let (s1, s2, c) = (
            solid(add(front, w)),
            solid(add(front, h)),
            solid(add(add(front, w), h)),
        );
        let ao = if s1 && s2 {
            0
        } else {
            3 - (u8::from(s1) + u8::from(s2) + u8::from(c))
        };
        packed |= ao << (2 * i);
    }
    packed
}

/// The padded chunk as `block-mesh` voxels; transparent ids are empty (opaque layer only), and
/// with `ao_face` each voxel's merge value carries the AO of its face in that direction.
fn bm_voxels(
    padded: &PaddedChunk,
    classes: &BlockClasses,
    ao_face: Option<FaceDirection>,
) -> Vec<BmVoxel> {
    let p = padded.padded_edge() as u32;
    let mut out = Vec::with_capacity(padded.voxels().len());
    for z in 0..p {
        for y in 0..p {
            for x in 0..p {
                let id = padded.get(x, y, z).unwrap().0;
                let solid = is_solid(classes, id);
                let interior = [x, y, z].iter().all(|&a| (1..p - 1).contains(&a));
                let ao = match ao_face {
                    Some(face) if solid && interior => {
                        face_ao(padded, classes, [x, y, z].map(i64::from), face)
                    }
                    _ => 0,
                };
                out.push(BmVoxel {
                    visibility: if solid {
                        VoxelVisibility::Opaque
                    } else {
                        VoxelVisibility::Empty
                    },
                    merge: (id, ao),
                });
            }
        }
    }
    out
}

/// Checks one chunk against `block-mesh`; returns (ours, theirs) greedy counts with AO on.
fn compare(padded: &PaddedChunk, classes: &BlockClasses) -> (usize, usize) {
    let p = padded.padded_edge() as u32;
    let shape = RuntimeShape::<u32, 3>::new([p; 3]);
    assert_eq!(shape.size() as usize, padded.voxels().len());
    let faces = &RIGHT_HANDED_Y_UP_CONFIG.faces;
    let plain = bm_voxels(padded, classes, None);

    // Visible faces: the same unit faces per direction.
    let mut mesh = BlockyMesh::new();
    let mut mesher = GreedyMesher::new();
    mesher.visible_faces(padded, classes, &mut mesh).unwrap();
    let mut unit = UnitQuadBuffer::new();
    visible_block_faces(&plain, &shape, [0; 3], [p - 1; 3], faces, &mut unit);
    for (g, group) in unit.groups.iter().enumerate() {
        let d = GROUP_TO_OURS[g];
        let mut theirs: Vec<[u32; 3]> = group.iter().map(|q| q.minimum).collect();
        let mut ours: Vec<[u32; 3]> = mesh.opaque.faces[d]
            .iter()
            .map(|q| q.decode().unwrap().position.map(|a| a + 1))
            .collect();
        theirs.sort_unstable();
        ours.sort_unstable();
        assert_eq!(ours, theirs, "visible faces, direction {d}");
    }

    // Greedy without AO: the same count per direction.
    let mut no_ao = GreedyMesher::new().with_ambient_occlusion(false);
    no_ao.mesh(padded, classes, &mut mesh).unwrap();
    let mut greedy = GreedyQuadsBuffer::new(plain.len());
    greedy_quads(&plain, &shape, [0; 3], [p - 1; 3], faces, &mut greedy);
    for (g, group) in greedy.quads.groups.iter().enumerate() {
        let d = GROUP_TO_OURS[g];
        assert_eq!(
            mesh.opaque.faces[d].len(),
            group.len(),
            "greedy without AO, direction {d}"
        );
    }

    // Greedy with AO: the same count as block-mesh merging on (id, AO of that face).
    mesher.mesh(padded, classes, &mut mesh).unwrap();
    let mut theirs = 0;
    for (g, &d) in GROUP_TO_OURS.iter().enumerate() {
        let face = FaceDirection::ALL[d];
        let keyed = bm_voxels(padded, classes, Some(face));
        greedy_quads(&keyed, &shape, [0; 3], [p - 1; 3], faces, &mut greedy);
        let n = greedy.quads.groups[g].len();
        assert_eq!(
            mesh.opaque.faces[d].len(),
            n,
            "greedy with AO, direction {d}"
        );
        theirs += n;
    }
    (mesh.opaque.len(), theirs)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn matches_block_mesh_on_random_chunks(
        size in proptest::sample::select(ChunkSize::ALL.to_vec()),
        seed in any::<u64>(),
        air_percent in 0u64..=100,
        blocky in any::<bool>(),
        transparent in any::<bool>(),
    ) {
        let padded = random_chunk(size, seed, air_percent, blocky);
        let classes = BlockClasses::from_palette(&palette(transparent));
        let (ours, theirs) = compare(&padded, &classes);
        prop_assert!(ours <= theirs);
    }
}

/// Every sample model, and with `BLOCKY_VOX_DIR` set the models of that folder too, in chunks
/// of 32^3: a few chunks of each against `block-mesh`.
#[test]
fn matches_block_mesh_on_the_sample_models() {
    for path in tests::sample_vox_files()
        .into_iter()
        .chain(tests::extra_vox_files())
    {
        let scene = viewer::scene::vox::load_vox_file(&path, ChunkSize::S32, 1 << 24)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let classes = BlockClasses::from_palette(&scene.palette);
        let mut coords: Vec<_> = scene.world.iter().map(|(c, _)| c).collect();
        coords.sort_by_key(|c| (c.x, c.y, c.z));
        // A few chunks per model keep the brute-force AO keys affordable.
        let step = coords.len().div_ceil(6).max(1);
        let mut padded = PaddedChunk::new(ChunkSize::S32);
        for coord in coords.into_iter().step_by(step) {
            voxel_core::gather_neighbourhood(&scene.world, coord, &mut padded);
            compare(&padded, &classes);
        }
    }
}

/// The Menger sponges of levels 3 and 4, a foliage scene and a flat maze, cut into chunks of
/// 32^3 and 16^3 the way a world is meshed: every chunk against `block-mesh`.
#[test]
fn matches_block_mesh_on_the_detailed_scenes() {
    use voxel_scene::detailed::{flat_maze, foliage, menger};
    let scenes = [
        ("menger L3", menger(3)),
        ("menger L4", menger(4)),
        ("foliage", foliage([56, 40, 56], 5)),
        ("flat maze", flat_maze(30, 2, 5)),
    ];
    for (name, scene) in &scenes {
        let classes = BlockClasses::from_palette(&scene.palette);
        for size in [ChunkSize::S16, ChunkSize::S32] {
            let chunks = scene.padded_chunks(size);
            assert!(!chunks.is_empty(), "{name}");
            for padded in &chunks {
                let (ours, theirs) = compare(padded, &classes);
                assert!(ours <= theirs, "{name} at {size:?}: {ours} > {theirs}");
            }
        }
    }
}

/// The viewer's terrain (seed 7, as the viewer and the benches use: hills, caves, beaches and
/// a sea of transparent water) over 3 x 3 chunk columns of 32^3 and 6 x 6 of 16^3, each chunk
/// gathered with its real neighbours: every chunk with a surface against `block-mesh`.
#[test]
fn matches_block_mesh_on_the_viewer_terrain() {
    use voxel_core::storage::{DenseChunk, WorldMap};
    use voxel_core::{ChunkCoord, LocalPos, gather_neighbourhood};
    use voxel_scene::{Terrain, TerrainBlocks};
    let (palette, blocks) = TerrainBlocks::palette();
    let terrain = Terrain::new(7, blocks);
    let classes = BlockClasses::from_palette(&palette);
    // Nothing solid and no water lies above the highest hill or the sea, and below y = 0
    // every voxel is stone.
    let top_voxel = (terrain.base_height + terrain.amplitude.ceil() as i32).max(terrain.sea_level);
    for (size, n) in [(ChunkSize::S32, 3), (ChunkSize::S16, 6)] {
        let e = size.edge() as i32;
        let top = top_voxel / e;
        let mut world = WorldMap::new(size);
        for cz in -1..=n {
            for cx in -1..=n {
                for cy in -2..=top + 1 {
                    let chunk = DenseChunk::from_fn(size, |p: LocalPos| {
                        let [x, y, z] = [p.x, p.y, p.z].map(i32::from);
                        terrain.block_at(cx * e + x, cy * e + y, cz * e + z)
                    });
                    world.insert(ChunkCoord::new(cx, cy, cz), chunk).unwrap();
                }
            }
        }
        let mut padded = PaddedChunk::new(size);
        let mut meshed = 0;
        for cz in 0..n {
            for cx in 0..n {
                for cy in -1..=top {
                    gather_neighbourhood(&world, ChunkCoord::new(cx, cy, cz), &mut padded);
                    if padded.columns().iter().all(|&c| c == 0) {
                        continue;
                    }
                    let (ours, theirs) = compare(&padded, &classes);
                    assert!(
                        ours <= theirs,
                        "{size:?} ({cx}, {cy}, {cz}): {ours} > {theirs}"
                    );
                    meshed += usize::from(ours > 0);
                }
            }
        }
        // Every column of chunks holds ground under air: at least one chunk with faces each.
        assert!(
            meshed >= (n * n) as usize,
            "{size:?}: {meshed} chunks with faces"
        );
    }
}
