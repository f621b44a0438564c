//! [`DirtySet`]: what one batch of edits invalidates, at every level of detail, each node once.
//!
//! A node's mesh, skirts and far-draw list are all extracted from its padded neighbourhood (the
//! node plus a one-voxel border, `voxel_core::storage::neighbourhood`), so a changed voxel
//! dirties exactly the nodes whose padded neighbourhood holds it: its own node, and on each
//! axis where it lies on the node's first or last layer, the neighbour on that side (up to 8
//! nodes for one voxel; a box or sphere over a chunk's whole border dirties all 26
//! neighbours). At level `k` the voxel that may change is the coarse voxel `pos >> k` (a
//! coarse voxel is computed from its 8 children only, `mesher::lod`), and the same rule
//! applies to it.

use std::collections::BTreeSet;

use voxel_core::{ChunkCoord, ChunkSize, WorldPos};

/// One node of the level-of-detail hierarchy: a chunk of `level` (its voxels `2^level` blocks
/// wide) at `coord` in that level's chunk grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct NodeKey {
    /// The level (0 = full detail).
    pub level: u32,
    /// The chunk coordinate at that level.
    pub coord: ChunkCoord,
}

/// What a batch of edits dirties. Every set is sorted and holds each node once.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DirtySet {
    changed: BTreeSet<ChunkCoord>,
    /// Per level `0..=top`: the nodes whose padded neighbourhood holds a changed voxel.
    remesh: Vec<BTreeSet<ChunkCoord>>,
}

impl DirtySet {
    /// An empty set for levels `0..=top`.
    pub(crate) fn new(top: u32) -> DirtySet {
        DirtySet {
            changed: BTreeSet::new(),
            remesh: vec![BTreeSet::new(); top as usize + 1],
        }
    }

    /// Records that the block at `pos` (in level-0 chunk `chunk` of `size`) changed.
    pub(crate) fn add_voxel(&mut self, pos: WorldPos, chunk: ChunkCoord, size: ChunkSize) {
        self.changed.insert(chunk);
        let e = size.edge() as i32;
        for (level, set) in self.remesh.iter_mut().enumerate() {
            // Arithmetic shift: floor division by 2^level, right for negative positions.
            let v = [pos.x, pos.y, pos.z].map(|c| c >> level);
            let node = v.map(|c| c.div_euclid(e));
            let local = v.map(|c| c.rem_euclid(e));
            let sides = |a: usize| -> &'static [i32] {
                match (local[a] == 0, local[a] == e - 1) {
                    (true, true) => &[-1, 0, 1],
                    (true, false) => &[-1, 0],
                    (false, true) => &[0, 1],
                    (false, false) => &[0],
                }
            };
            let centre = ChunkCoord::new(node[0], node[1], node[2]);
            for &dz in sides(2) {
                for &dy in sides(1) {
                    for &dx in sides(0) {
                        // A neighbour past the i32 chunk range holds no blocks: nothing to redo.
                        if let Ok(n) = centre.checked_offset([dx, dy, dz]) {
                            set.insert(n);
                        }
                    }
                }
            }
        }
    }

    /// True when the batch changed no voxel.
    pub fn is_empty(&self) -> bool {
        self.changed.is_empty()
    }

    /// The highest level the set covers.
    pub fn top_level(&self) -> u32 {
        self.remesh.len().saturating_sub(1) as u32
    }

    /// Level-0 chunks whose voxels changed.
    pub fn changed(&self) -> impl Iterator<Item = ChunkCoord> + '_ {
        self.changed.iter().copied()
    }

    /// Level-0 chunks whose voxels did not change but whose border faces or ambient occlusion
    /// may (a changed voxel lies in their one-voxel border).
    pub fn neighbours(&self) -> impl Iterator<Item = ChunkCoord> + '_ {
        self.remesh[0]
            .iter()
            .copied()
            .filter(|c| !self.changed.contains(c))
    }

    /// Every chunk of `level` to re-mesh: [`changed`](Self::changed) and
    /// [`neighbours`](Self::neighbours) at level 0, the nodes above them at coarser levels.
    /// Empty above [`top_level`](Self::top_level).
    pub fn remesh(&self, level: u32) -> impl Iterator<Item = ChunkCoord> + '_ {
        self.remesh
            .get(level as usize)
            .into_iter()
            .flat_map(|s| s.iter().copied())
    }

    /// The level-of-detail nodes (levels 1 and up) to rebuild from the edited data
    /// ([`World::lod_node`](crate::World::lod_node)) and re-mesh, coarsest level last.
    pub fn lod_nodes(&self) -> impl Iterator<Item = NodeKey> + '_ {
        self.all_nodes().filter(|k| k.level > 0)
    }

    /// The nodes whose far-draw lists (surface blocks, skirt blocks, hiding and transparent
    /// masks) change: every node of every level to re-mesh, since those lists are extracted
    /// from the same padded neighbourhood as the mesh.
    pub fn far_lists(&self) -> impl Iterator<Item = NodeKey> + '_ {
        self.all_nodes()
    }

    /// Every node to re-mesh, level by level from level 0.
    pub fn all_nodes(&self) -> impl Iterator<Item = NodeKey> + '_ {
        self.remesh.iter().enumerate().flat_map(|(level, set)| {
            set.iter().map(move |&coord| NodeKey {
                level: level as u32,
                coord,
            })
        })
    }

    /// Adds every node of `other` (a later batch) to this set.
    pub fn merge(&mut self, other: &DirtySet) {
        self.changed.extend(other.changed.iter().copied());
        if self.remesh.len() < other.remesh.len() {
            self.remesh.resize(other.remesh.len(), BTreeSet::new());
        }
        for (mine, theirs) in self.remesh.iter_mut().zip(&other.remesh) {
            mine.extend(theirs.iter().copied());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_corner_voxel_dirties_eight_chunks_and_a_middle_voxel_one() {
        let mut d = DirtySet::new(1);
        d.add_voxel(
            WorldPos::new(0, 0, 0),
            ChunkCoord::new(0, 0, 0),
            ChunkSize::S8,
        );
        assert_eq!(d.remesh(0).count(), 8);
        assert_eq!(d.neighbours().count(), 7);
        assert!(
            d.remesh(0)
                .all(|c| [c.x, c.y, c.z].iter().all(|v| (-1..=0).contains(v)))
        );
        // At level 1 the coarse voxel (0,0,0) is a corner too.
        assert_eq!(d.lod_nodes().count(), 8);
        let mut m = DirtySet::new(1);
        m.add_voxel(
            WorldPos::new(-4, 3, 12),
            ChunkCoord::new(-1, 0, 1),
            ChunkSize::S8,
        );
        assert_eq!(
            m.remesh(0).collect::<Vec<_>>(),
            vec![ChunkCoord::new(-1, 0, 1)]
        );
        // Coarse voxel (-2, 1, 6): node (-1, 0, 0), local (6, 1, 6): inside.
        assert_eq!(
            m.lod_nodes().collect::<Vec<_>>(),
            vec![NodeKey {
                level: 1,
                coord: ChunkCoord::new(-1, 0, 0)
            }]
        );
        m.merge(&d);
        assert_eq!(m.changed().count(), 2);
        assert_eq!(m.far_lists().count(), 9 + 8);
    }
}
