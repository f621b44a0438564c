//! [`World`]: level-0 chunks from a [`Base`], changed by [`Edit`]s, with the [`DirtySet`] of
//! every batch and the level-of-detail nodes rebuilt from the edited data.

use std::collections::{BTreeSet, HashMap, HashSet, VecDeque};
use std::sync::{Mutex, PoisonError};

use mesher::BlockClasses;
use mesher::lod::downsample_chunk;
use voxel_core::storage::{DenseChunk, PaletteChunk, VoxelStorage, WorldMap, gather_neighbourhood};
use voxel_core::{ChunkCoord, ChunkSize, PaddedChunk, WorldPos};

use crate::coarse::{CoarseLevels, overlay, overlay_cells, padded_interior};
use crate::{Base, DirtySet, Edit, NodeKey, WorldError};

/// The most levels above level 0 a world tracks: a level-30 voxel is as wide as the world.
pub const MAX_LEVEL: u32 = 30;

/// An editable world: a [`Base`] where nothing is edited, stored chunks where something is.
///
/// A chunk is *materialized* (copied from the base into [`chunks`](World::chunks)) the first
/// time an edit or a gather reads it; edits change stored chunks only, so the base is never
/// written. [`apply`](World::apply) returns the batch's [`DirtySet`] for levels `0..=top`.
#[derive(Debug)]
pub struct World<B> {
    base: B,
    size: ChunkSize,
    top: u32,
    chunks: WorldMap<PaletteChunk>,
    present: HashSet<ChunkCoord>,
    edited: BTreeSet<ChunkCoord>,
    unsaved: BTreeSet<ChunkCoord>,
    /// The base's own levels with the edits' coarse voxels, once
    /// [`use_base_levels`](World::use_base_levels) asked for them.
    coarse: Option<CoarseLevels>,
    /// Batches that changed a voxel since the world was made.
    version: u64,
    /// The base's padded fills of nodes read through [`gather_over_base`](World::gather_over_base)
    /// most recently: the nodes an edit dirties are read again and again while a user edits
    /// one place, and the base's fill (its noise) is most of a rebuild's cost.
    fills: Mutex<FillCache>,
}

/// The base's fills of the nodes gathered most recently, oldest first out.
#[derive(Debug, Default)]
struct FillCache {
    fills: HashMap<NodeKey, PaddedChunk>,
    order: VecDeque<NodeKey>,
}

impl FillCache {
    /// Fills kept (about 6 MB of 16^3 nodes).
    const CAPACITY: usize = 512;

    fn insert(&mut self, key: NodeKey, fill: PaddedChunk) {
        if self.fills.insert(key, fill).is_none() {
            self.order.push_back(key);
        }
        while self.order.len() > Self::CAPACITY {
            if let Some(old) = self.order.pop_front() {
                self.fills.remove(&old);
            }
        }
    }
}

impl<B: Base> World<B> {
    /// A world of chunks of `size` over `base`, whose dirty sets cover levels `0..=top`.
    pub fn new(base: B, size: ChunkSize, top: u32) -> Result<World<B>, WorldError> {
        if top > MAX_LEVEL {
            return Err(WorldError::BadLevel { level: top });
        }
        Ok(World {
            base,
            size,
            top,
            chunks: WorldMap::new(size),
            present: HashSet::new(),
            edited: BTreeSet::new(),
            unsaved: BTreeSet::new(),
            coarse: None,
            version: 0,
            fills: Mutex::default(),
        })
    }

    /// Makes the levels of detail the base's own levels, except where the edited blocks differ
    /// from the base (downsampled from the edited data there, with `classes`: see
    /// [`crate::coarse`]'s rule), instead of downsampling every node from level 0. Far cheaper
    /// for a base with levels of its own (the terrain): a node costs one base fill, not
    /// `8^level` chunks. The edits made so far (or loaded) are taken into account at once.
    pub fn use_base_levels(&mut self, classes: BlockClasses) -> Result<(), WorldError> {
        if !self.base.has_levels() {
            return Err(WorldError::NoBaseLevels);
        }
        let mut coarse = CoarseLevels::new(classes, self.size);
        let mut differing = Vec::new();
        let e = self.size.edge() as i32;
        for &coord in &self.edited {
            let mut base = PaletteChunk::new(self.size);
            self.base
                .fill_chunk(coord, &mut base)
                .map_err(|message| WorldError::Base { coord, message })?;
            for z in 0..e {
                for y in 0..e {
                    for x in 0..e {
                        let local = voxel_core::LocalPos {
                            x: x as u8,
                            y: y as u8,
                            z: z as u8,
                        };
                        let Ok(pos) = coord.world_pos(local, self.size) else {
                            continue;
                        };
                        if base.get(local).ok() != Some(self.chunks.get_block(pos)) {
                            differing.push(pos);
                        }
                    }
                }
            }
            coarse.keep_base0(coord, base);
        }
        coarse.update(&self.base, &self.chunks, self.top, differing)?;
        self.coarse = Some(coarse);
        Ok(())
    }

    /// True when the levels of detail are the base's own, edited
    /// ([`use_base_levels`](Self::use_base_levels)).
    pub fn uses_base_levels(&self) -> bool {
        self.coarse.is_some()
    }

    /// How many batches changed a voxel since the world was made: a reader that records it
    /// with what it read knows whether a later batch made that stale.
    pub fn version(&self) -> u64 {
        self.version
    }

    /// True when node `coord` of `level` or one of its 26 neighbours holds edited data, so its
    /// padded neighbourhood differs from the base's (with base levels; without them, true for
    /// any level above 0 over an edited chunk's area, since those nodes are downsampled).
    pub fn touches(&self, level: u32, coord: ChunkCoord) -> bool {
        let near = |f: &dyn Fn(ChunkCoord) -> bool| {
            (-1..=1).any(|dz| {
                (-1..=1)
                    .any(|dy| (-1..=1).any(|dx| coord.checked_offset([dx, dy, dz]).is_ok_and(f)))
            })
        };
        match (&self.coarse, level) {
            (_, 0) => near(&|n| self.edited.contains(&n)),
            (Some(coarse), _) => near(&|n| coarse.node(&NodeKey { level, coord: n }).is_some()),
            (None, _) => !self.edited.is_empty(),
        }
    }

    /// Fills `out` with the padded neighbourhood of node `coord` of `level` without writing
    /// anything (so readers can share the world): the base's own fill
    /// ([`Base::fill_padded`]; the last few hundred nodes' fills are kept, so the nodes of
    /// repeated edits in one place are not filled again) with the edited data over it. Needs
    /// base levels ([`use_base_levels`](Self::use_base_levels)).
    pub fn gather_over_base(
        &self,
        level: u32,
        coord: ChunkCoord,
        out: &mut PaddedChunk,
    ) -> Result<(), WorldError> {
        if self.coarse.is_none() {
            return Err(WorldError::NoBaseLevels);
        }
        if level > MAX_LEVEL {
            return Err(WorldError::BadLevel { level });
        }
        let key = NodeKey { level, coord };
        // A poisoned cache holds whole fills only (inserted after they are made).
        let cached = self
            .fills
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .fills
            .get(&key)
            .cloned();
        match cached {
            Some(fill) => *out = fill,
            None => {
                out.reset(self.size);
                self.base
                    .fill_padded(level, coord, out)
                    .map_err(|message| WorldError::Base {
                        coord,
                        message: format!("level {level}: {message}"),
                    })?;
                self.fills
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .insert(key, out.clone());
            }
        }
        self.overlay_edits(level, coord, out)
    }

    /// Writes the edited data of node `coord` of `level` and its 26 neighbours over `out`, the
    /// base's padded neighbourhood of that node ([`Base::fill_padded`]): the second half of
    /// [`gather_over_base`](Self::gather_over_base), for a reader that fills from the base
    /// without holding the world (the fill of a coarse node is the slow half). Needs base
    /// levels ([`use_base_levels`](Self::use_base_levels)).
    pub fn overlay_edits(
        &self,
        level: u32,
        coord: ChunkCoord,
        out: &mut PaddedChunk,
    ) -> Result<(), WorldError> {
        let Some(coarse) = &self.coarse else {
            return Err(WorldError::NoBaseLevels);
        };
        if out.size() != self.size {
            return Err(WorldError::Base {
                coord,
                message: format!(
                    "a neighbourhood of {}^3 chunks over a world of {}^3",
                    out.size().edge(),
                    self.size.edge()
                ),
            });
        }
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let Ok(n) = coord.checked_offset([dx, dy, dz]) else {
                        continue;
                    };
                    if level == 0 {
                        if self.edited.contains(&n) {
                            overlay(out, [dx, dy, dz], self.chunks.get(n));
                        }
                    } else if let Some(node) = coarse.node(&NodeKey { level, coord: n }) {
                        overlay_cells(out, [dx, dy, dz], node);
                    }
                }
            }
        }
        Ok(())
    }

    /// The chunk size.
    pub fn size(&self) -> ChunkSize {
        self.size
    }

    /// The highest level the dirty sets cover.
    pub fn top_level(&self) -> u32 {
        self.top
    }

    /// The base.
    pub fn base(&self) -> &B {
        &self.base
    }

    /// The materialized level-0 chunks (all-air chunks are not stored: they read as air). A
    /// mesher reads this map directly once [`materialize_ring`](Self::materialize_ring) has
    /// stored the chunks it gathers.
    pub fn chunks(&self) -> &WorldMap<PaletteChunk> {
        &self.chunks
    }

    /// Level-0 chunks holding an edit, sorted: what a save stores.
    pub fn edited(&self) -> impl Iterator<Item = ChunkCoord> + '_ {
        self.edited.iter().copied()
    }

    /// Edited chunks changed since the last save or load, sorted.
    pub fn unsaved(&self) -> impl Iterator<Item = ChunkCoord> + '_ {
        self.unsaved.iter().copied()
    }

    pub(crate) fn mark_saved(&mut self) {
        self.unsaved.clear();
    }

    /// Stores a loaded chunk as edited (it replaces whatever was materialized there).
    pub(crate) fn insert_edited(
        &mut self,
        coord: ChunkCoord,
        chunk: PaletteChunk,
    ) -> Result<(), WorldError> {
        if chunk.non_air_count() == 0 {
            self.chunks.remove(coord);
        } else {
            self.chunks
                .insert(coord, chunk)
                .map_err(|e| WorldError::Base {
                    coord,
                    message: e.to_string(),
                })?;
        }
        self.present.insert(coord);
        self.edited.insert(coord);
        Ok(())
    }

    /// The level-0 chunks `edits` reach that are not stored yet: what [`apply`](Self::apply)
    /// would fill from the base first. A caller that shares the world fills them elsewhere
    /// (in parallel, without holding it: [`base_chunk`](Self::base_chunk)) and stores them
    /// with [`insert_base_chunk`](Self::insert_base_chunk). An edit that is refused is an
    /// error here too.
    pub fn unmaterialized(&self, edits: &[Edit]) -> Result<Vec<ChunkCoord>, WorldError> {
        let mut out = BTreeSet::new();
        for edit in edits {
            let (min, max) = edit.bounds().map_err(WorldError::Edit)?;
            let (cmin, _) = min.split(self.size);
            let (cmax, _) = max.split(self.size);
            for z in cmin.z..=cmax.z {
                for y in cmin.y..=cmax.y {
                    for x in cmin.x..=cmax.x {
                        let c = ChunkCoord::new(x, y, z);
                        if !self.present.contains(&c) {
                            out.insert(c);
                        }
                    }
                }
            }
        }
        Ok(out.into_iter().collect())
    }

    /// Chunk `coord` as the base fills it, without storing it.
    pub fn base_chunk(&self, coord: ChunkCoord) -> Result<PaletteChunk, WorldError> {
        let mut chunk = PaletteChunk::new(self.size);
        self.base
            .fill_chunk(coord, &mut chunk)
            .map_err(|message| WorldError::Base { coord, message })?;
        if chunk.size() != self.size {
            return Err(WorldError::Base {
                coord,
                message: format!(
                    "base gave a chunk of {:?}, not {:?}",
                    chunk.size(),
                    self.size
                ),
            });
        }
        Ok(chunk)
    }

    /// Stores `chunk`, the base's chunk `coord` ([`base_chunk`](Self::base_chunk)), unless
    /// the chunk is stored already (then it is left as it is: it may hold edits).
    pub fn insert_base_chunk(
        &mut self,
        coord: ChunkCoord,
        chunk: PaletteChunk,
    ) -> Result<(), WorldError> {
        if self.present.contains(&coord) {
            return Ok(());
        }
        if chunk.size() != self.size {
            return Err(WorldError::Base {
                coord,
                message: format!("a chunk of {:?}, not {:?}", chunk.size(), self.size),
            });
        }
        if chunk.non_air_count() > 0 {
            // Sizes match: insert cannot refuse it.
            let _ = self.chunks.insert(coord, chunk);
        }
        self.present.insert(coord);
        Ok(())
    }

    /// Copies chunk `coord` from the base unless it is stored already.
    pub fn materialize(&mut self, coord: ChunkCoord) -> Result<(), WorldError> {
        if self.present.contains(&coord) {
            return Ok(());
        }
        let chunk = self.base_chunk(coord)?;
        self.insert_base_chunk(coord, chunk)
    }

    /// Materializes chunk `coord` and its 26 neighbours: everything a gather of `coord` reads.
    pub fn materialize_ring(&mut self, coord: ChunkCoord) -> Result<(), WorldError> {
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    if let Ok(n) = coord.checked_offset([dx, dy, dz]) {
                        self.materialize(n)?;
                    }
                }
            }
        }
        Ok(())
    }

    /// The block at `pos` when its chunk holds an edit (`None` elsewhere: the base's block
    /// stands there), without writing anything: for readers that have the base's blocks
    /// another way (a raycaster over the terrain's function).
    pub fn edited_block(&self, pos: WorldPos) -> Option<voxel_core::BlockId> {
        let (coord, _) = pos.split(self.size);
        self.edited
            .contains(&coord)
            .then(|| self.chunks.get_block(pos))
    }

    /// The block at `pos` (materializing its chunk).
    pub fn block(&mut self, pos: WorldPos) -> Result<voxel_core::BlockId, WorldError> {
        let (coord, _) = pos.split(self.size);
        self.materialize(coord)?;
        Ok(self.chunks.get_block(pos))
    }

    /// Fills `out` with level-0 chunk `coord` and its border, materializing what it reads.
    pub fn gather_chunk(
        &mut self,
        coord: ChunkCoord,
        out: &mut PaddedChunk,
    ) -> Result<(), WorldError> {
        self.materialize_ring(coord)?;
        gather_neighbourhood(&self.chunks, coord, out);
        Ok(())
    }

    /// Applies `edits` in order and returns what they dirty. Every edit is checked first: a
    /// refused edit leaves the world unchanged. Writing a block's own id changes nothing and
    /// dirties nothing.
    pub fn apply(&mut self, edits: &[Edit]) -> Result<DirtySet, WorldError> {
        let bounds = edits
            .iter()
            .map(|e| e.bounds().map_err(WorldError::Edit))
            .collect::<Result<Vec<_>, _>>()?;
        let mut dirty = DirtySet::new(self.top);
        let mut changed = Vec::new();
        let size = self.size;
        let e = size.edge() as i32;
        for (edit, (min, max)) in edits.iter().zip(bounds) {
            let id = edit.id();
            let (cmin, _) = min.split(size);
            let (cmax, _) = max.split(size);
            for cz in cmin.z..=cmax.z {
                for cy in cmin.y..=cmax.y {
                    for cx in cmin.x..=cmax.x {
                        let coord = ChunkCoord::new(cx, cy, cz);
                        self.materialize(coord)?;
                        if let Some(coarse) = &mut self.coarse
                            && !coarse.has_base0(coord)
                        {
                            // Not edited before: the stored chunk is still the base's.
                            let base = self
                                .chunks
                                .get(coord)
                                .cloned()
                                .unwrap_or_else(|| PaletteChunk::new(size));
                            coarse.keep_base0(coord, base);
                        }
                        // The chunk's blocks inside the edit's box, in i64 (no overflow at the
                        // ends of the i32 range).
                        let lo = |c: i32, m: i32| (i64::from(c) * i64::from(e)).max(i64::from(m));
                        let hi = |c: i32, m: i32| {
                            (i64::from(c) * i64::from(e) + i64::from(e) - 1).min(i64::from(m))
                        };
                        let mut changed_here = false;
                        for z in lo(cz, min.z)..=hi(cz, max.z) {
                            for y in lo(cy, min.y)..=hi(cy, max.y) {
                                for x in lo(cx, min.x)..=hi(cx, max.x) {
                                    let pos = WorldPos::new(x as i32, y as i32, z as i32);
                                    if !edit.covers(pos) {
                                        continue;
                                    }
                                    let old = self.chunks.set_block(pos, id);
                                    if old != id {
                                        dirty.add_voxel(pos, coord, size);
                                        changed.push(pos);
                                        changed_here = true;
                                    }
                                }
                            }
                        }
                        if changed_here {
                            if self
                                .chunks
                                .get(coord)
                                .is_some_and(|c| c.non_air_count() == 0)
                            {
                                self.chunks.remove(coord);
                            }
                            self.edited.insert(coord);
                            self.unsaved.insert(coord);
                        }
                    }
                }
            }
        }
        if let Some(coarse) = &mut self.coarse {
            coarse.update(&self.base, &self.chunks, self.top, changed)?;
        }
        if !dirty.is_empty() {
            self.version += 1;
        }
        Ok(dirty)
    }

    /// The voxels of node `coord` of `level`, rebuilt from the edited level-0 data by the
    /// mesher's downsampling rule (`mesher::lod`), never from the base's own coarse levels:
    /// level `k` is downsampled from the 8 nodes of level `k - 1` under it, down to the
    /// materialized level-0 chunks. It reads `8^level` level-0 chunks, so it is meant for the
    /// nodes of a [`DirtySet`] at the few levels above the edit.
    pub fn lod_node(
        &mut self,
        level: u32,
        coord: ChunkCoord,
        classes: &BlockClasses,
    ) -> Result<PaletteChunk, WorldError> {
        if level > MAX_LEVEL {
            return Err(WorldError::BadLevel { level });
        }
        if level == 0 {
            self.materialize(coord)?;
            return Ok(self
                .chunks
                .get(coord)
                .cloned()
                .unwrap_or_else(|| PaletteChunk::new(self.size)));
        }
        if let Some(coarse) = &self.coarse {
            let mut padded = PaddedChunk::new(self.size);
            self.base
                .fill_padded(level, coord, &mut padded)
                .map_err(|message| WorldError::Base { coord, message })?;
            if let Some(node) = coarse.node(&NodeKey { level, coord }) {
                overlay_cells(&mut padded, [0, 0, 0], node);
            }
            return Ok(padded_interior(&padded));
        }
        let mut children: Vec<PaletteChunk> = Vec::with_capacity(8);
        for d in 0..8i64 {
            let c = [coord.x, coord.y, coord.z].map(i64::from);
            let child = [
                c[0] * 2 + (d & 1),
                c[1] * 2 + ((d >> 1) & 1),
                c[2] * 2 + (d >> 2),
            ];
            match child.map(i32::try_from) {
                [Ok(x), Ok(y), Ok(z)] => {
                    children.push(self.lod_node(level - 1, ChunkCoord::new(x, y, z), classes)?)
                }
                // Past the i32 chunk range: no blocks there.
                _ => children.push(PaletteChunk::new(self.size)),
            }
        }
        let mut out = DenseChunk::new(self.size);
        downsample_chunk(
            |dx, dy, dz| children.get((dx + 2 * dy + 4 * dz) as usize),
            classes,
            &mut out,
        )
        .map_err(|error| WorldError::Mesh {
            level,
            coord,
            error,
        })?;
        Ok(PaletteChunk::from_dense(&out))
    }

    /// Fills `out` with the padded neighbourhood of node `coord` of `level`, every node of it
    /// rebuilt by [`lod_node`](Self::lod_node) (at level 0, [`gather_chunk`](Self::gather_chunk)).
    pub fn gather_node(
        &mut self,
        level: u32,
        coord: ChunkCoord,
        classes: &BlockClasses,
        out: &mut PaddedChunk,
    ) -> Result<(), WorldError> {
        if level == 0 {
            return self.gather_chunk(coord, out);
        }
        if self.coarse.is_some() {
            return self.gather_over_base(level, coord, out);
        }
        let mut ring: WorldMap<PaletteChunk> = WorldMap::new(self.size);
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    if let Ok(n) = coord.checked_offset([dx, dy, dz]) {
                        let node = self.lod_node(level, n, classes)?;
                        // Same size: insert cannot refuse it.
                        let _ = ring.insert(n, node);
                    }
                }
            }
        }
        gather_neighbourhood(&ring, coord, out);
        Ok(())
    }
}
