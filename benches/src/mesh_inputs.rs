//! Inputs of the blocky-mesher benches (`benches/benches/blocky.rs`): padded chunks with their
//! palettes, built once, deterministic.
//!
//! Every input is a [`PaddedChunk`] (what our meshers take) whose voxel buffer doubles as the
//! plain padded `u16` array the peer crates take (`p^3` ids, x fastest; for 62^3 chunks that is
//! the 64^3 array `binary-greedy-meshing` and `block-mesh` expect).
//!
//! | input | what it is |
//! | --- | --- |
//! | `sphere` | a solid ball of stone, radius `e / 2 - 1`, centred, air around |
//! | `terrain` | [`inputs::chunks::TERRAIN_CENTRE`](crate::inputs::chunks::TERRAIN_CENTRE) of the viewer's terrain gathered with its 26 neighbours: hills, caves, a sea (transparent water), 7 ids |
//! | `terrain area` | the same terrain over about 256 x 256 columns around that chunk: every chunk with a surface, gathered with its real neighbours ([`terrain_area`]) |
//! | `checkerboard` | 3-D checkerboard of stone: every face visible, nothing merges |
//! | `random50` | each voxel air with probability 1/2, else one of 4 opaque ids |
//! | `full` | every padded voxel stone: buried, no face |
//! | `empty` | all air |
//! | `menger L<level>` | a Menger sponge of level 3, 4 or 5 (edge 27, 81, 243) in stone at the origin, every chunk it touches ([`voxel_scene::detailed::menger`]) |
//! | `menger shaded L4` | the level-4 sponge in three shades of stone, one per 9^3 block ([`voxel_scene::detailed::menger_shaded`]): the same holes, with id edges every 9 voxels |
//! | `foliage` | a forest floor of 124 x 62 x 124 voxels: trees, leaves with holes in three shades, grass blades, flowers, vines ([`voxel_scene::detailed::foliage`]), every chunk it touches |
//! | `flat maze` | a maze of 90 x 90 cells in stone, 181 x 3 x 181 voxels: a floor under walls two voxels high, one wide ([`voxel_scene::detailed::flat_maze`]), every chunk it touches |
//! | `vox/<model>` | a MagicaVoxel model from `../shared/data/vox/` (or `BLOCKY_VOX_DIR`), every chunk it touches |
//!
//! Every input exists at any chunk size (the size is in its name); the benches use 32^3 and
//! 62^3.

use std::path::{Path, PathBuf};

use voxel_core::{
    BlockId, ChunkCoord, ChunkSize, Material, MaterialPalette, PaddedChunk, gather_neighbourhood,
};
use voxel_scene::TerrainBlocks;
use voxel_scene::detailed::{VoxelBox, flat_maze, foliage, menger, menger_shaded};
use voxel_scene::vox::load_vox_file;

use crate::inputs::chunks::{
    TERRAIN_CENTRE, terrain_top, terrain_world_between, terrain_world_dense,
};
use voxel_scene::rng::Rng;

/// One bench input: one or more padded chunks and the palette their ids index.
#[derive(Debug)]
pub struct MeshInput {
    /// Name used in the bench id, e.g. `terrain 62^3`.
    pub name: String,
    /// The chunks, each padded with its one-voxel border.
    pub chunks: Vec<PaddedChunk>,
    /// Materials of the ids.
    pub palette: MaterialPalette,
}

impl MeshInput {
    /// Non-air voxels in the chunks' interiors.
    pub fn interior_non_air(&self) -> usize {
        self.chunks
            .iter()
            .map(|c| {
                let p = c.padded_edge();
                let inner = (u64::MAX >> (64 - (p - 2))) << 1;
                c.columns()
                    .chunks_exact(p)
                    .enumerate()
                    .filter(|(z, _)| (1..p - 1).contains(z))
                    .flat_map(|(_, slab)| &slab[1..p - 1])
                    .map(|&col| (col & inner).count_ones() as usize)
                    .sum::<usize>()
            })
            .sum()
    }
}

/// The ids as a plain `u16` slice (the peers' input).
pub fn as_u16(padded: &PaddedChunk) -> &[u16] {
    bytemuck::cast_slice(padded.voxels())
}

/// A palette with 4 opaque materials (ids 1..=4) and nothing transparent.
pub fn opaque_palette() -> MaterialPalette {
    let mut palette = MaterialPalette::new();
    for i in 0..4u8 {
        palette
            .push(Material::opaque(60 * i, 100, 200 - 40 * i))
            .expect("a fresh palette has room");
    }
    palette
}

fn single(name: String, chunk: PaddedChunk, palette: MaterialPalette) -> MeshInput {
    MeshInput {
        name,
        chunks: vec![chunk],
        palette,
    }
}

fn label(kind: &str, size: ChunkSize) -> String {
    format!("{kind} {}^3", size.edge())
}

/// A solid stone ball of radius `e / 2 - 1` centred in the chunk.
pub fn sphere(size: ChunkSize) -> MeshInput {
    let e = size.edge() as f32;
    let c = e / 2.0 + 0.5; // centre in padded coordinates (interior is 1..=e)
    let r = e / 2.0 - 1.0;
    let chunk = PaddedChunk::from_fn(size, |x, y, z| {
        let d = [x, y, z].map(|a| a as f32 - c);
        let inside = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] <= r * r;
        BlockId(u16::from(inside))
    });
    single(label("sphere", size), chunk, opaque_palette())
}

/// The viewer's terrain chunk at [`TERRAIN_CENTRE`] with its real neighbours as the border.
pub fn terrain(size: ChunkSize) -> MeshInput {
    let world = terrain_world_dense(size);
    let mut chunk = PaddedChunk::new(size);
    gather_neighbourhood(&world, TERRAIN_CENTRE, &mut chunk);
    single(label("terrain", size), chunk, TerrainBlocks::palette().0)
}

/// The viewer's terrain over `n x n` chunk columns around [`TERRAIN_CENTRE`], `n` the chunks
/// that fit in 256 voxels (8 at 32^3, 4 at 62^3): every chunk that holds both air and
/// something else, gathered with its real neighbours. [`terrain`] is one chunk of this world;
/// here hills, valleys, beaches, sea floor and caves come in the mix a streamed view meshes.
pub fn terrain_area(size: ChunkSize) -> MeshInput {
    let e = size.edge() as i32;
    let n = (256 / e).max(1);
    let (x0, z0) = (TERRAIN_CENTRE.x - n / 2, TERRAIN_CENTRE.z - n / 2);
    // Every solid voxel below y = 0 is stone, and nothing lies above the top: the chunks in
    // between have the surfaces, the ones next to them are their borders.
    let (low, high) = (-1, terrain_top().div_euclid(e));
    let world = terrain_world_between(
        size,
        [x0 - 1, low - 1, z0 - 1],
        [x0 + n, high + 1, z0 + n],
        |c| c,
    );
    let mut chunks = Vec::new();
    for cz in 0..n {
        for cx in 0..n {
            for cy in low..=high {
                let mut chunk = PaddedChunk::new(size);
                gather_neighbourhood(&world, ChunkCoord::new(x0 + cx, cy, z0 + cz), &mut chunk);
                let p = chunk.padded_edge() as u32;
                let columns = chunk.columns();
                let any = columns.iter().any(|&c| c != 0);
                let full = columns.iter().all(|&c| c.count_ones() == p);
                if any && !full {
                    chunks.push(chunk);
                }
            }
        }
    }
    MeshInput {
        name: format!("terrain area ({} x {}^3)", chunks.len(), size.edge()),
        chunks,
        palette: TerrainBlocks::palette().0,
    }
}

/// A 3-D checkerboard: voxel `(x, y, z)` is stone iff `x + y + z` is even.
pub fn checkerboard(size: ChunkSize) -> MeshInput {
    let chunk = PaddedChunk::from_fn(size, |x, y, z| BlockId(u16::from((x + y + z) % 2 == 0)));
    single(label("checkerboard", size), chunk, opaque_palette())
}

/// Each voxel air with probability 1/2, else one of the 4 opaque ids, uniformly.
pub fn random_fill(size: ChunkSize, seed: u64) -> MeshInput {
    let mut rng = Rng::new(seed);
    let chunk = PaddedChunk::from_fn(size, |_, _, _| {
        if rng.below(2) == 0 {
            BlockId::AIR
        } else {
            BlockId(1 + rng.below(4) as u16)
        }
    });
    single(label("random50", size), chunk, opaque_palette())
}

/// Every padded voxel stone (`palette` decides whether the palette also has water).
pub fn full(size: ChunkSize, with_water: bool) -> MeshInput {
    let (palette, stone, name) = if with_water {
        let (palette, blocks) = TerrainBlocks::palette();
        (palette, blocks.stone, "full (water in palette)")
    } else {
        (opaque_palette(), BlockId(1), "full")
    };
    let chunk = PaddedChunk::from_fn(size, |_, _, _| stone);
    single(label(name, size), chunk, palette)
}

/// All air.
pub fn empty(size: ChunkSize) -> MeshInput {
    single(
        label("empty", size),
        PaddedChunk::new(size),
        opaque_palette(),
    )
}

/// The synthetic inputs at `size`, in bench order.
pub fn synthetic_inputs(size: ChunkSize) -> Vec<MeshInput> {
    vec![
        terrain(size),
        sphere(size),
        checkerboard(size),
        random_fill(size, 50),
        full(size, false),
        full(size, true),
        empty(size),
    ]
}

/// The edge of the foliage scene along x and z (its height is 62).
pub const FOLIAGE_EDGE: usize = 124;

/// The seed of the foliage scene.
pub const FOLIAGE_SEED: u64 = 11;

fn scene_input(name: &str, scene: &VoxelBox, size: ChunkSize) -> MeshInput {
    let chunks = scene.padded_chunks(size);
    MeshInput {
        name: format!("{name} ({} x {}^3)", chunks.len(), size.edge()),
        chunks,
        palette: scene.palette.clone(),
    }
}

/// The Menger sponges of levels 3 to 5, the shaded level-4 one, the foliage scene and the
/// flat maze, cut into chunks of `size`.
pub fn scene_inputs(size: ChunkSize) -> Vec<MeshInput> {
    let mut out: Vec<MeshInput> = (3..=5)
        .map(|level| scene_input(&format!("menger L{level}"), &menger(level), size))
        .collect();
    out.push(scene_input("menger shaded L4", &menger_shaded(4), size));
    let forest = foliage([FOLIAGE_EDGE, 62, FOLIAGE_EDGE], FOLIAGE_SEED);
    out.push(scene_input("foliage", &forest, size));
    let maze = flat_maze(FLAT_MAZE_CELLS, 2, FLAT_MAZE_SEED);
    out.push(scene_input("flat maze", &maze, size));
    out
}

/// The cells along each side of the flat maze scene: 181 voxels, 3 x 3 chunks of 62^3.
pub const FLAT_MAZE_CELLS: usize = 90;

/// The seed of the flat maze scene.
pub const FLAT_MAZE_SEED: u64 = 3;

/// Every input at `size`: the synthetic ones, the terrain area, the scenes, then the sample
/// models when `../shared/data/vox` is there (and `None` when it is not, so callers can say
/// so).
pub fn all_inputs(size: ChunkSize) -> (Vec<MeshInput>, Option<PathBuf>) {
    let mut inputs = synthetic_inputs(size);
    inputs.push(terrain_area(size));
    inputs.extend(scene_inputs(size));
    let dir = vox_dir();
    if let Some(dir) = &dir {
        inputs.extend(vox_inputs(dir, size));
    }
    (inputs, dir)
}

/// The input at `size` whose name starts with `name`, building only its family (the sample
/// models for `vox/...`, the scenes for `menger ...` and `foliage`, else the synthetic ones).
pub fn find_input(name: &str, size: ChunkSize) -> Option<MeshInput> {
    let family = if name.starts_with("vox/") {
        vox_inputs(&vox_dir()?, size)
    } else if name.starts_with("terrain area") {
        vec![terrain_area(size)]
    } else if ["menger", "foliage", "flat maze"]
        .iter()
        .any(|scene| name.starts_with(scene))
    {
        scene_inputs(size)
    } else {
        synthetic_inputs(size)
    };
    family.into_iter().find(|i| i.name.starts_with(name))
}

/// The folder of MagicaVoxel models to mesh: `BLOCKY_VOX_DIR` if set (to measure on models
/// of one's own), else the samples in `../shared/data/vox` beside the checkout, if present.
pub fn vox_dir() -> Option<PathBuf> {
    let dir = std::env::var_os("BLOCKY_VOX_DIR").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/vox"),
        PathBuf::from,
    );
    dir.is_dir().then_some(dir)
}

/// The models of `dir` cut into padded chunks of `size`: every chunk the model touches, in
/// chunk-coordinate order, each gathered with its neighbours. Models that fail to load are
/// skipped with a message on stderr.
pub fn vox_inputs(dir: &Path, size: ChunkSize) -> Vec<MeshInput> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|entries| entries.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.retain(|p| p.extension().is_some_and(|e| e == "vox"));
    files.sort();
    let mut out = Vec::new();
    for path in files {
        let name = path
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned();
        let scene = match load_vox_file(&path, size, 1 << 26) {
            Ok(scene) => scene,
            Err(e) => {
                eprintln!("{}: {e}", path.display());
                continue;
            }
        };
        let mut coords: Vec<_> = scene.world.iter().map(|(c, _)| c).collect();
        coords.sort_by_key(|c| (c.z, c.y, c.x));
        let chunks = coords
            .into_iter()
            .map(|coord| {
                let mut padded = PaddedChunk::new(size);
                gather_neighbourhood(&scene.world, coord, &mut padded);
                padded
            })
            .collect::<Vec<_>>();
        out.push(MeshInput {
            name: format!("vox/{name} ({} x {}^3)", chunks.len(), size.edge()),
            chunks,
            palette: scene.palette,
        });
    }
    out
}
