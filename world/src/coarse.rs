//! The levels of detail of a world over a base with coarse levels of its own (the terrain):
//! every coarse voxel is the base's own, except where the level-0 blocks under it differ from
//! the base; those voxels are downsampled from the edited level below, by the mesher's rule
//! (`mesher::lod`).
//!
//! # Why not downsample whole nodes
//!
//! A base's coarse levels need not equal the downsampling of its level 0 (the terrain's do not:
//! its coarse cells ignore caves). A node rebuilt whole from the edited data would then differ
//! from the base's version of it everywhere, not only where the edit is, and its neighbours,
//! meshed against the base's version of its border, would no longer agree with it. Here a
//! coarse voxel changes only when a level-0 voxel under it changes, which is exactly what a
//! [`DirtySet`](crate::DirtySet) dirties, so the dirty set stays complete.
//!
//! # The rule, and why it does not depend on the order of edits
//!
//! A level-0 voxel *differs* when the world's block there is not the base's. A coarse voxel
//! differs when one of its 8 children does; a differing coarse voxel is the downsampling of its
//! children, any other is the base's. `CoarseLevels::update` re-evaluates, bottom up, only the
//! coarse voxels above the voxels a batch changed; every other coarse voxel's children did not
//! change, so its value still follows the rule. A loaded world evaluates the same rule from its
//! differing voxels, so saving and loading gives the same coarse nodes as the edits did.
//!
//! # What is stored
//!
//! Only the differing coarse voxels, per node: every other voxel is the base's, which a
//! reader fills from the base anyway. An edit reads the base's value of single cells
//! ([`Base::level_cell`], cached), never a whole coarse node, whose fill costs as much as the
//! area it covers (a top-level node of the terrain: millions of column heights).

use std::collections::{BTreeSet, HashMap};

use mesher::BlockClasses;
use mesher::lod::coarse_voxel;
use voxel_core::storage::{DenseChunk, PaletteChunk, VoxelStorage, WorldMap};
use voxel_core::{BlockId, ChunkCoord, ChunkSize, LocalPos, PaddedChunk, WorldPos};

use crate::{Base, NodeKey, WorldError};

/// The differing voxels of one coarse node: index `x + e * (y + e * z)` to id.
pub(crate) type DifferingCells = HashMap<u16, BlockId>;

/// Base cell values kept before the cache is emptied (about 40 MB).
const BASE_CELL_CACHE: usize = 1 << 20;

/// The differing coarse voxels above edits, and the base's version of every edited level-0
/// chunk (see the [module docs](self)).
#[derive(Clone, Debug)]
pub(crate) struct CoarseLevels {
    classes: BlockClasses,
    size: ChunkSize,
    nodes: HashMap<NodeKey, DifferingCells>,
    /// The base's blocks of each level-0 chunk that holds an edit.
    base0: HashMap<ChunkCoord, PaletteChunk>,
    /// Base values of coarse cells read so far, by level and cell.
    base_cells: HashMap<(u32, [i32; 3]), BlockId>,
}

impl CoarseLevels {
    /// No coarse node yet, for chunks of `size` downsampled with `classes`.
    pub(crate) fn new(classes: BlockClasses, size: ChunkSize) -> CoarseLevels {
        CoarseLevels {
            classes,
            size,
            nodes: HashMap::new(),
            base0: HashMap::new(),
            base_cells: HashMap::new(),
        }
    }

    /// True when level-0 chunk `coord`'s base blocks are kept (it holds an edit).
    pub(crate) fn has_base0(&self, coord: ChunkCoord) -> bool {
        self.base0.contains_key(&coord)
    }

    /// Keeps `chunk` as the base's blocks of level-0 chunk `coord` (before its first edit).
    pub(crate) fn keep_base0(&mut self, coord: ChunkCoord, chunk: PaletteChunk) {
        self.base0.entry(coord).or_insert(chunk);
    }

    /// The differing voxels of coarse node `key`, when it has any.
    pub(crate) fn node(&self, key: &NodeKey) -> Option<&DifferingCells> {
        self.nodes.get(key)
    }

    /// Re-evaluates the coarse voxels above `changed` (level-0 positions) at levels
    /// `1..=top`, reading level 0 from `chunks`.
    pub(crate) fn update<B: Base>(
        &mut self,
        base: &B,
        chunks: &WorldMap<PaletteChunk>,
        top: u32,
        changed: impl IntoIterator<Item = WorldPos>,
    ) -> Result<(), WorldError> {
        let mut cells: BTreeSet<[i32; 3]> = changed.into_iter().map(|p| [p.x, p.y, p.z]).collect();
        let e = self.size.edge() as i32;
        if self.base_cells.len() > BASE_CELL_CACHE {
            self.base_cells.clear();
        }
        for level in 1..=top {
            // Arithmetic shift: the parent of a negative cell is floor(cell / 2).
            let parents: BTreeSet<[i32; 3]> = cells.iter().map(|c| c.map(|v| v >> 1)).collect();
            for &cell in &parents {
                let (key, local) = split(level, cell, e);
                let mut children = [BlockId::AIR; 8];
                let mut any = false;
                for (d, child) in children.iter_mut().enumerate() {
                    let d = d as i32;
                    // Index dx + 2 dz + 4 dy: `coarse_voxel`'s order.
                    let pos = [
                        2 * cell[0] + (d & 1),
                        2 * cell[1] + ((d >> 2) & 1),
                        2 * cell[2] + ((d >> 1) & 1),
                    ];
                    let (id, differs) = self.fine(base, level - 1, pos, chunks, e)?;
                    *child = id;
                    any |= differs;
                }
                let index = bit_index(local, e);
                if any {
                    let id =
                        coarse_voxel(&children, &self.classes).map_err(|id| WorldError::Mesh {
                            level,
                            coord: key.coord,
                            error: mesher::MeshError::UnknownBlock {
                                id,
                                position: [local.x, local.y, local.z].map(u32::from),
                            },
                        })?;
                    self.nodes.entry(key).or_default().insert(index, id);
                } else if let Some(node) = self.nodes.get_mut(&key) {
                    node.remove(&index);
                    if node.is_empty() {
                        self.nodes.remove(&key);
                    }
                }
            }
            cells = parents;
        }
        Ok(())
    }

    /// The voxel at `cell` of `level` and whether it differs from the base.
    fn fine<B: Base>(
        &mut self,
        base: &B,
        level: u32,
        cell: [i32; 3],
        chunks: &WorldMap<PaletteChunk>,
        e: i32,
    ) -> Result<(BlockId, bool), WorldError> {
        if level == 0 {
            let pos = WorldPos::new(cell[0], cell[1], cell[2]);
            let id = chunks.get_block(pos);
            let (coord, local) = pos.split(self.size);
            let differs = self
                .base0
                .get(&coord)
                .is_some_and(|b| b.get(local).unwrap_or(BlockId::AIR) != id);
            return Ok((id, differs));
        }
        let (key, local) = split(level, cell, e);
        if let Some(&id) = self
            .nodes
            .get(&key)
            .and_then(|n| n.get(&bit_index(local, e)))
        {
            return Ok((id, true));
        }
        if let Some(&id) = self.base_cells.get(&(level, cell)) {
            return Ok((id, false));
        }
        let id = base
            .level_cell(level, cell)
            .map_err(|message| WorldError::Base {
                coord: key.coord,
                message: format!("level {level}: {message}"),
            })?;
        self.base_cells.insert((level, cell), id);
        Ok((id, false))
    }
}

/// The node and local position of `cell` of `level`.
fn split(level: u32, cell: [i32; 3], e: i32) -> (NodeKey, LocalPos) {
    let coord = cell.map(|v| v.div_euclid(e));
    let local = cell.map(|v| v.rem_euclid(e) as u8);
    (
        NodeKey {
            level,
            coord: ChunkCoord::new(coord[0], coord[1], coord[2]),
        },
        LocalPos {
            x: local[0],
            y: local[1],
            z: local[2],
        },
    )
}

fn bit_index(local: LocalPos, e: i32) -> u16 {
    let e = e as u16;
    u16::from(local.x) + e * (u16::from(local.y) + e * u16::from(local.z))
}

/// The centre chunk of a padded neighbourhood (what a node holds without its border).
pub fn padded_interior(padded: &PaddedChunk) -> PaletteChunk {
    let dense = DenseChunk::from_fn(padded.size(), |l| {
        padded
            .get(u32::from(l.x) + 1, u32::from(l.y) + 1, u32::from(l.z) + 1)
            .unwrap_or(BlockId::AIR)
    });
    PaletteChunk::from_dense(&dense)
}

/// Writes `chunk`, the neighbour at `offset` (each axis in `-1..=1`) of a padded
/// neighbourhood's centre, over the part of `out` it covers.
pub(crate) fn overlay(out: &mut PaddedChunk, offset: [i32; 3], chunk: Option<&PaletteChunk>) {
    let e = out.size().edge();
    // Per axis: padded coordinates covered, and the neighbour's local coordinate of the first.
    let range = |d: i32| -> (u32, u32, u32) {
        match d {
            -1 => (0, 1, e - 1),
            0 => (1, e + 1, 0),
            _ => (e + 1, e + 2, 0),
        }
    };
    let (x0, x1, lx) = range(offset[0]);
    let (y0, y1, ly) = range(offset[1]);
    let (z0, z1, lz) = range(offset[2]);
    for pz in z0..z1 {
        for py in y0..y1 {
            for px in x0..x1 {
                let local = LocalPos {
                    x: (lx + px - x0) as u8,
                    y: (ly + py - y0) as u8,
                    z: (lz + pz - z0) as u8,
                };
                let id = chunk
                    .and_then(|c| c.get(local).ok())
                    .unwrap_or(BlockId::AIR);
                // In range by construction.
                let _ = out.set(px, py, pz, id);
            }
        }
    }
}

/// Writes the differing voxels `cells` of the neighbour at `offset` (each axis in `-1..=1`)
/// of a padded neighbourhood's centre over the part of `out` they fall in.
pub(crate) fn overlay_cells(out: &mut PaddedChunk, offset: [i32; 3], cells: &DifferingCells) {
    let e = out.size().edge() as i32;
    for (&index, &id) in cells {
        let i = i32::from(index);
        let local = [i % e, (i / e) % e, i / (e * e)];
        let p: [i32; 3] = core::array::from_fn(|a| local[a] + 1 + offset[a] * e);
        if p.iter().all(|&c| (0..=e + 1).contains(&c)) {
            // In range: checked above.
            let _ = out.set(p[0] as u32, p[1] as u32, p[2] as u32, id);
        }
    }
}
