//! The built-in procedural scene: rolling hills with caves, a sea, sand beaches and snow caps.
//!
//! Deterministic for a seed: the same seed gives the same blocks on every machine, so tests and
//! benchmarks can use it as a fixed input.

pub mod node;
mod region;

use fastnoise_lite::{FastNoiseLite, FractalType, NoiseType};
use voxel_core::{BlockId, Material, MaterialClass, MaterialPalette};

pub use node::NodeContent;
pub use region::{TERRAIN_TOP, TerrainScene, terrain_columns, terrain_scene};

/// Block ids of the terrain's materials, in the order [`TerrainBlocks::palette`] adds them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TerrainBlocks {
    /// Grass-covered soil: opaque, carries clutter.
    pub grass: BlockId,
    /// Soil under the grass.
    pub dirt: BlockId,
    /// Rock below the soil.
    pub stone: BlockId,
    /// Beaches and sea floor.
    pub sand: BlockId,
    /// Sea water up to the sea level: transparent.
    pub water: BlockId,
    /// Mountain tops.
    pub snow: BlockId,
}

impl TerrainBlocks {
    /// Adds the terrain's materials to a fresh palette and returns both.
    pub fn palette() -> (MaterialPalette, TerrainBlocks) {
        let mut palette = MaterialPalette::new();
        let mut add = |m: Material| {
            palette
                .push(m)
                .expect("a fresh palette has room for six materials")
        };
        let blocks = TerrainBlocks {
            grass: add(Material::opaque(88, 150, 60).with_class(MaterialClass::ClutterBearing)),
            dirt: add(Material::opaque(120, 85, 55)),
            stone: add(Material::opaque(125, 125, 130)),
            sand: add(Material::opaque(215, 200, 140)),
            water: add(Material {
                colour: [40, 90, 170, 140],
                roughness: 20,
                emission: 0,
                metalness: 0,
                // A volume: tinted by the depth of water over the ground behind it.
                volume: true,
                class: MaterialClass::Transparent,
            }),
            snow: add(Material::opaque(240, 240, 245)),
        };
        (palette, blocks)
    }
}

/// Procedural terrain: a fractal heightmap plus 3-D noise caves.
pub struct Terrain {
    height_noise: FastNoiseLite,
    cave_noise: FastNoiseLite,
    blocks: TerrainBlocks,
    seed: i32,
    /// Height of the sea surface; columns below it are flooded.
    pub sea_level: i32,
    /// Average ground height.
    pub base_height: i32,
    /// Peak-to-valley amplitude of the hills.
    pub amplitude: f32,
}

impl std::fmt::Debug for Terrain {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // The noise generators have no Debug; their settings are fixed by `Terrain::new`.
        f.debug_struct("Terrain")
            .field("blocks", &self.blocks)
            .field("seed", &self.seed)
            .field("sea_level", &self.sea_level)
            .field("base_height", &self.base_height)
            .field("amplitude", &self.amplitude)
            .finish_non_exhaustive()
    }
}

impl Terrain {
    /// Terrain for `seed`, with the block ids of [`TerrainBlocks::palette`].
    pub fn new(seed: i32, blocks: TerrainBlocks) -> Terrain {
        let mut height_noise = FastNoiseLite::with_seed(seed);
        height_noise.set_noise_type(Some(NoiseType::OpenSimplex2));
        height_noise.set_fractal_type(Some(FractalType::FBm));
        height_noise.set_fractal_octaves(Some(4));
        height_noise.set_frequency(Some(0.012));

        let mut cave_noise = FastNoiseLite::with_seed(seed.wrapping_add(7919));
        cave_noise.set_noise_type(Some(NoiseType::OpenSimplex2));
        cave_noise.set_frequency(Some(0.06));

        Terrain {
            height_noise,
            cave_noise,
            blocks,
            seed,
            sea_level: 14,
            base_height: 18,
            amplitude: 14.0,
        }
    }

    /// The seed it was made with.
    pub fn seed(&self) -> i32 {
        self.seed
    }

    /// The block ids this terrain writes.
    pub fn blocks(&self) -> TerrainBlocks {
        self.blocks
    }

    /// Ground height of the column at `(x, z)`: the y of its top solid block.
    pub fn height(&self, x: i32, z: i32) -> i32 {
        let n = self.height_noise.get_noise_2d(x as f32, z as f32);
        self.base_height + (n * self.amplitude).round() as i32
    }

    /// True where the cave noise carves air out of the ground (never in the top two layers, so
    /// the surface stays closed except where caves open into valleys).
    fn is_cave(&self, x: i32, y: i32, z: i32, ground: i32) -> bool {
        if y > ground - 3 || y < 1 {
            return false;
        }
        let n = self
            .cave_noise
            .get_noise_3d(x as f32, y as f32 * 1.6, z as f32);
        n > 0.55
    }

    /// The block at a world position.
    pub fn block_at(&self, x: i32, y: i32, z: i32) -> BlockId {
        let ground = self.height(x, z);
        self.block_in_column(x, y, z, ground)
    }

    /// The block at `(x, y, z)` given the column's ground height (lets callers compute the
    /// height once per column).
    pub fn block_in_column(&self, x: i32, y: i32, z: i32, ground: i32) -> BlockId {
        let b = &self.blocks;
        if y > ground {
            return if y <= self.sea_level {
                b.water
            } else {
                BlockId::AIR
            };
        }
        if self.is_cave(x, y, z, ground) {
            return BlockId::AIR;
        }
        self.material(ground, y)
    }

    /// The block at height `y <= ground` of a column whose top solid block is at `ground`,
    /// caves left aside: the layers (grass or snow on top, dirt, stone; sand near the sea).
    fn material(&self, ground: i32, y: i32) -> BlockId {
        let b = &self.blocks;
        let depth = ground - y;
        if ground <= self.sea_level + 1 {
            return if depth < 3 { b.sand } else { b.stone };
        }
        match depth {
            0 if ground >= self.base_height + 10 => b.snow,
            0 => b.grass,
            1..=3 => b.dirt,
            _ => b.stone,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn terrain_is_deterministic_and_layered() {
        let (_, blocks) = TerrainBlocks::palette();
        let a = Terrain::new(3, blocks);
        let b = Terrain::new(3, blocks);
        let mut kinds = std::collections::HashSet::new();
        for x in -40..40 {
            for z in -40..40 {
                let h = a.height(x, z);
                assert_eq!(h, b.height(x, z));
                assert!(
                    (h - a.base_height).abs() <= a.amplitude as i32 + 1,
                    "height {h} out of the stated amplitude"
                );
                for y in -2..48 {
                    let id = a.block_at(x, y, z);
                    assert_eq!(id, b.block_at(x, y, z));
                    kinds.insert(id);
                    if y > h.max(a.sea_level) {
                        assert_eq!(id, BlockId::AIR, "air above ground and sea");
                    }
                }
            }
        }
        // Every material appears in an 80 x 80 patch, and air too.
        for id in [
            blocks.grass,
            blocks.dirt,
            blocks.stone,
            blocks.sand,
            blocks.water,
            BlockId::AIR,
        ] {
            assert!(kinds.contains(&id), "block {id:?} never generated");
        }
    }
}
