//! [`Base`]: what a world holds where it has no edits (a procedural generator, or air).

use voxel_core::storage::PaletteChunk;
use voxel_core::{BlockId, ChunkCoord, ChunkSize, PaddedChunk, WorldPos};
use voxel_scene::terrain::Terrain;

/// The voxels of a world where nothing is edited: level-0 chunks on demand.
///
/// Implemented by [`Terrain`] (the built-in procedural terrain), [`AirBase`] (an empty world,
/// everything it holds is stored) and [`FnBase`] (any function of the world position).
pub trait Base: Sync {
    /// Fills `out` (of the world's chunk size) with level-0 chunk `coord`.
    fn fill_chunk(&self, coord: ChunkCoord, out: &mut PaletteChunk) -> Result<(), String>;

    /// True when the base has coarse levels of its own ([`fill_padded`](Self::fill_padded)),
    /// which [`World::use_base_levels`](crate::World::use_base_levels) draws on.
    fn has_levels(&self) -> bool {
        false
    }

    /// Fills `out` (of the world's chunk size) with the padded neighbourhood of node `coord` of
    /// `level` from the base's own levels, and returns true; false (and `out` untouched) when
    /// the base has no levels of its own.
    fn fill_padded(
        &self,
        level: u32,
        coord: ChunkCoord,
        out: &mut PaddedChunk,
    ) -> Result<bool, String> {
        let _ = (level, coord, out);
        Ok(false)
    }

    /// The voxel of cell `cell` (in cells of `level`) of the base's own levels: the value
    /// [`fill_padded`](Self::fill_padded) gives there. Only asked of a base with levels.
    fn level_cell(&self, level: u32, cell: [i32; 3]) -> Result<BlockId, String> {
        let _ = (level, cell);
        Err("the base has no coarse levels of its own".to_owned())
    }
}

/// A base of air: a world whose every non-air block is an edit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AirBase;

impl Base for AirBase {
    fn fill_chunk(&self, _coord: ChunkCoord, out: &mut PaletteChunk) -> Result<(), String> {
        use voxel_core::storage::VoxelStorage;
        out.fill(BlockId::AIR);
        Ok(())
    }
}

/// A base from a function of the world position (blocks past the `i32` range are air).
#[derive(Clone, Copy, Debug)]
pub struct FnBase<F>(pub F);

impl<F: Fn(WorldPos) -> BlockId + Sync> Base for FnBase<F> {
    fn fill_chunk(&self, coord: ChunkCoord, out: &mut PaletteChunk) -> Result<(), String> {
        let size = voxel_core::storage::VoxelStorage::size(out);
        let dense = voxel_core::storage::DenseChunk::from_fn(size, |local| {
            coord
                .world_pos(local, size)
                .map(&self.0)
                .unwrap_or(BlockId::AIR)
        });
        *out = PaletteChunk::from_dense(&dense);
        Ok(())
    }
}

impl Base for Terrain {
    /// Level 0 of [`Terrain::fill_node`]: the terrain's exact blocks.
    fn fill_chunk(&self, coord: ChunkCoord, out: &mut PaletteChunk) -> Result<(), String> {
        let size: ChunkSize = voxel_core::storage::VoxelStorage::size(out);
        let mut padded = PaddedChunk::new(size);
        self.fill_node(size, 0, coord, &mut padded)?;
        let dense = voxel_core::storage::DenseChunk::from_fn(size, |l| {
            padded
                .get(u32::from(l.x) + 1, u32::from(l.y) + 1, u32::from(l.z) + 1)
                .unwrap_or(BlockId::AIR)
        });
        *out = PaletteChunk::from_dense(&dense);
        Ok(())
    }

    fn has_levels(&self) -> bool {
        true
    }

    /// [`Terrain::node_cell`]: one cell by the rule of its fill.
    fn level_cell(&self, level: u32, cell: [i32; 3]) -> Result<BlockId, String> {
        self.node_cell(level, cell.map(i64::from))
    }

    /// [`Terrain::fill_node`]: the terrain's coarse levels straight from its height function.
    fn fill_padded(
        &self,
        level: u32,
        coord: ChunkCoord,
        out: &mut PaddedChunk,
    ) -> Result<bool, String> {
        self.fill_node(out.size(), level, coord, out).map(|_| true)
    }
}
