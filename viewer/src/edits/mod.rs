//! The streamed terrain as an editable world: a [`SharedWorld`] (the `voxel-world` crate's
//! [`World`] over the terrain, with the terrain's own coarse levels) that the streamers' node
//! builders read and the viewer's edits write, the block names edits use ([`parse_block`]),
//! picking a block by a ray through the world ([`pick()`]), and the flight's carving
//! ([`carve`]).
//!
//! ```text
//!  edit ─► SharedWorld::apply (write lock) ─► DirtySet ─► each streamer's invalidate:
//!          shown nodes re-meshed at once (rayon) and swapped before the next frame;
//!          other resident or loading nodes rebuilt by the workers, nearest first
//! ```

pub mod carve;
pub mod pick;

use std::path::{Path, PathBuf};
use std::sync::{Arc, RwLock, RwLockReadGuard, RwLockWriteGuard};

use mesher::BlockClasses;
use rayon::prelude::*;
use voxel_core::{BlockId, ChunkSize};
use voxel_scene::{Terrain, TerrainBlocks};
use voxel_world::{DirtySet, Edit, LoadReport, World, WorldError};

pub use carve::Carver;
pub use pick::{Pick, pick};

/// The terrain world every streamer of one view builds from (cheap to clone: one world).
#[derive(Clone, Debug)]
pub struct SharedWorld {
    inner: Arc<RwLock<World<Terrain>>>,
}

impl SharedWorld {
    /// The terrain of `seed` in chunks of `size`, unedited, with dirty sets up to level `top`.
    pub fn new(seed: i32, size: ChunkSize, top: u32) -> Result<SharedWorld, WorldError> {
        let (palette, blocks) = TerrainBlocks::palette();
        let mut world = World::new(Terrain::new(seed, blocks), size, top)?;
        world.use_base_levels(BlockClasses::from_palette(&palette))?;
        Ok(SharedWorld::wrap(world))
    }

    /// The terrain of `seed` with the edits saved in `dir`, which must hold a world of chunks
    /// of `size` (a folder without a world file is an error: see [`open_or_new`]).
    ///
    /// [`open_or_new`]: SharedWorld::open_or_new
    pub fn load(
        dir: &Path,
        seed: i32,
        size: ChunkSize,
        top: u32,
    ) -> Result<(SharedWorld, LoadReport), WorldError> {
        let (palette, blocks) = TerrainBlocks::palette();
        let (mut world, report) = World::load(Terrain::new(seed, blocks), dir, top)?;
        if world.size() != size {
            return Err(WorldError::WorldFile {
                path: dir.join(voxel_world::WORLD_FILE),
                reason: format!(
                    "the world holds chunks of {}^3, the viewer streams {}^3 (--chunk)",
                    world.size().edge(),
                    size.edge()
                ),
            });
        }
        world.use_base_levels(BlockClasses::from_palette(&palette))?;
        Ok((SharedWorld::wrap(world), report))
    }

    /// [`load`](Self::load) when `dir` holds a saved world, else a new world (saved there
    /// later); the report is `None` for a new world.
    pub fn open_or_new(
        dir: &Path,
        seed: i32,
        size: ChunkSize,
        top: u32,
    ) -> Result<(SharedWorld, Option<LoadReport>), WorldError> {
        if dir.join(voxel_world::WORLD_FILE).exists() {
            let (world, report) = SharedWorld::load(dir, seed, size, top)?;
            Ok((world, Some(report)))
        } else {
            Ok((SharedWorld::new(seed, size, top)?, None))
        }
    }

    /// An error naming the difference when this is not the world of a terrain of `seed` in
    /// chunks of `size` with dirty sets up to level `top` or higher.
    pub fn check_matches(&self, seed: i32, size: ChunkSize, top: u32) -> Result<(), String> {
        let world = self.read();
        if world.base().seed() != seed {
            return Err(format!(
                "the world is the terrain of seed {}, the view streams seed {seed}",
                world.base().seed()
            ));
        }
        if world.size() != size {
            return Err(format!(
                "the world holds chunks of {}^3, the view streams {}^3",
                world.size().edge(),
                size.edge()
            ));
        }
        if world.top_level() < top {
            return Err(format!(
                "the world's dirty sets reach level {}, the view streams up to level {top}",
                world.top_level()
            ));
        }
        Ok(())
    }

    fn wrap(world: World<Terrain>) -> SharedWorld {
        SharedWorld {
            inner: Arc::new(RwLock::new(world)),
        }
    }

    /// Applies `edits` (all or none) and returns what they dirty.
    pub fn apply(&self, edits: &[Edit]) -> Result<DirtySet, WorldError> {
        self.apply_versioned(edits).map(|(dirty, _)| dirty)
    }

    /// [`apply`](Self::apply), with the world's version after the batch
    /// ([`World::version`]): a build that read this version or a later one holds the edits.
    /// The chunks the edits reach that are not stored yet are filled from the terrain first,
    /// in parallel (rayon) and without holding the world for writing, so readers (the node
    /// builders) wait only for the edits themselves.
    pub fn apply_versioned(&self, edits: &[Edit]) -> Result<(DirtySet, u64), WorldError> {
        let filled = {
            let world = self.read();
            let missing = world.unmaterialized(edits)?;
            missing
                .par_iter()
                .map(|&c| world.base_chunk(c).map(|chunk| (c, chunk)))
                .collect::<Result<Vec<_>, _>>()?
        };
        let mut world = self.write();
        for (coord, chunk) in filled {
            world.insert_base_chunk(coord, chunk)?;
        }
        let dirty = world.apply(edits)?;
        Ok((dirty, world.version()))
    }

    /// Saves the edited chunks changed since the last save into `dir` (atomically: see
    /// `voxel_world::save`); returns how many region files it wrote.
    pub fn save(&self, dir: &Path) -> Result<usize, WorldError> {
        self.write().save(dir)
    }

    /// True when edits were made since the last save or load.
    pub fn unsaved(&self) -> bool {
        self.read().unsaved().next().is_some()
    }

    /// The world, for reading (node builders share it).
    pub fn read(&self) -> RwLockReadGuard<'_, World<Terrain>> {
        // A panic while writing leaves a world whose last batch is whole or absent (apply
        // checks every edit before writing, and a panic aborts the viewer), so a poisoned
        // lock still holds a usable world.
        self.inner.read().unwrap_or_else(|e| e.into_inner())
    }

    /// The world, for writing (edits, picking, which materializes chunks).
    pub fn write(&self) -> RwLockWriteGuard<'_, World<Terrain>> {
        self.inner.write().unwrap_or_else(|e| e.into_inner())
    }
}

/// Where `--world DIR` saves, and when: on demand and when the viewer closes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WorldDir(pub PathBuf);

/// The block an edit writes, by name (`air`, `grass`, `dirt`, `stone`, `sand`, `water`,
/// `snow`) or by palette index of the terrain's palette; anything else is an error naming
/// the accepted names.
pub fn parse_block(text: &str) -> Result<BlockId, String> {
    let (palette, b) = TerrainBlocks::palette();
    let named = [
        ("air", BlockId::AIR),
        ("grass", b.grass),
        ("dirt", b.dirt),
        ("stone", b.stone),
        ("sand", b.sand),
        ("water", b.water),
        ("snow", b.snow),
    ];
    let text = text.trim();
    if let Some((_, id)) = named.iter().find(|(n, _)| n.eq_ignore_ascii_case(text)) {
        return Ok(*id);
    }
    let names: Vec<&str> = named.iter().map(|(n, _)| *n).collect();
    let index: u16 = text.parse().map_err(|_| {
        format!(
            "unknown block {text:?}: give one of {} or a palette index",
            names.join(", ")
        )
    })?;
    let id = BlockId(index);
    if index != 0 && palette.get(id).is_err() {
        return Err(format!(
            "block {index} is not in the terrain's palette of {} materials",
            palette.len()
        ));
    }
    Ok(id)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_parse_by_name_and_index_and_refuse_the_rest_by_name() {
        let (_, b) = TerrainBlocks::palette();
        assert_eq!(parse_block("stone"), Ok(b.stone));
        assert_eq!(parse_block(" Water "), Ok(b.water));
        assert_eq!(parse_block("air"), Ok(BlockId::AIR));
        assert_eq!(parse_block("0"), Ok(BlockId::AIR));
        assert_eq!(parse_block(&b.sand.0.to_string()), Ok(b.sand));
        let e = parse_block("lava").unwrap_err();
        assert!(
            e.contains("unknown block \"lava\"") && e.contains("stone"),
            "{e}"
        );
        let e = parse_block("60000").unwrap_err();
        assert!(e.contains("not in the terrain's palette"), "{e}");
        assert!(parse_block("-3").is_err());
    }
}
