//! Which nodes a view selects: the renderer's level-of-detail rule
//! ([`cull::lod`](render_model::cull::lod), its CPU twin) walked from the top level down, over
//! the nodes within the streamed radius of the anchor and within the terrain's height.
//!
//! ```text
//!  top-level nodes within the radius ─► refines? ─yes─► its 8 children (those in range) ─► ...
//!                                          └─no──► selected
//! ```
//!
//! Every selected node comes from the same [`lod::refines`] the GPU cull evaluates, so the set
//! is exactly what the renderer draws from this anchor and budget (where the nodes are
//! resident), with `top_level` = the plan's top level (see the [module docs](super) for why a
//! renderer whose highest resident level is lower still draws no hole).

use std::collections::HashSet;

use render_model::cull::{LodParams, lod};
use voxel_core::ChunkCoord;

/// One node: its level of detail and its coordinate among the nodes of that level.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeKey {
    /// Level of detail: the node's voxels are `2^level` blocks wide.
    pub level: u32,
    /// Coordinate among the nodes of its level.
    pub coord: ChunkCoord,
}

/// Where nodes exist: within `radius` blocks of the anchor (horizontally) and between heights
/// `0` and `top_block` (blocks).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extent {
    /// Streamed distance from the anchor, horizontally, blocks.
    pub radius: f64,
    /// Highest block that can be non-air.
    pub top_block: i64,
}

/// The anchor-relative box of a node, blocks: its minimum corner and its edge.
fn node_box(p: &LodParams, key: NodeKey) -> ([f64; 3], f64) {
    let edge = p.chunk_edge as i64;
    let size = edge << key.level;
    let coord = [key.coord.x, key.coord.y, key.coord.z];
    let lo = std::array::from_fn(|i| {
        let rel = i64::from(coord[i]) * size - i64::from(p.anchor_chunk[i]) * edge;
        rel as f64 - f64::from(p.anchor_offset[i])
    });
    (lo, size as f64)
}

/// Distance from 0 to the interval `[lo, lo + size]` (0 inside).
fn gap(lo: f64, size: f64) -> f64 {
    lo.max(-(lo + size)).max(0.0)
}

/// Horizontal distance from the anchor to a node's square, blocks (0 inside).
fn horizontal_distance(lo: [f64; 3], size: f64) -> f64 {
    gap(lo[0], size).hypot(gap(lo[2], size))
}

/// Distance from the anchor to a node's cube, blocks (0 inside): the loading order.
pub fn distance(p: &LodParams, key: NodeKey) -> f64 {
    let (lo, size) = node_box(p, key);
    let g = lo.map(|l| gap(l, size));
    (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt()
}

/// True when node `key` can hold terrain: within the radius and the height range.
pub fn in_extent(p: &LodParams, extent: &Extent, key: NodeKey) -> bool {
    let (lo, size) = node_box(p, key);
    let y0 = i64::from(key.coord.y) * size as i64;
    let heights = y0 <= extent.top_block && y0 + size as i64 > 0;
    heights && horizontal_distance(lo, size) <= extent.radius
}

/// The nodes `p` selects within `extent`, with `p.top_level` as the top level, in the order
/// of the walk (each top-level node's subtree in turn).
pub fn select(p: &LodParams, extent: &Extent) -> Vec<NodeKey> {
    let top = p.top_level;
    let edge = f64::from(p.chunk_edge) * f64::from(1u32 << top);
    let centre = |i: usize| {
        f64::from(p.anchor_chunk[i]) * f64::from(p.chunk_edge) + f64::from(p.anchor_offset[i])
    };
    let range = |i: usize| {
        let lo = ((centre(i) - extent.radius) / edge).floor() as i64;
        let hi = ((centre(i) + extent.radius) / edge).floor() as i64;
        lo.max(i64::from(i32::MIN))..=hi.min(i64::from(i32::MAX))
    };
    let top_y = extent
        .top_block
        .div_euclid(edge as i64)
        .min(i64::from(i32::MAX));
    let mut out = Vec::new();
    let mut stack = Vec::new();
    for z in range(2) {
        for x in range(0) {
            for y in 0..=top_y {
                let key = NodeKey {
                    level: top,
                    coord: ChunkCoord::new(x as i32, y as i32, z as i32),
                };
                if in_extent(p, extent, key) {
                    stack.push(key);
                }
            }
        }
    }
    while let Some(key) = stack.pop() {
        let c = [key.coord.x, key.coord.y, key.coord.z];
        if !lod::refines(p, c, key.level) {
            out.push(key);
            continue;
        }
        for child in 0..8u8 {
            let d = |bit: u8| i32::from((child >> bit) & 1);
            // Doubling a coordinate of level >= 1 stays in i32: it came from halving one.
            let coord = ChunkCoord::new(
                c[0].wrapping_mul(2).wrapping_add(d(0)),
                c[1].wrapping_mul(2).wrapping_add(d(1)),
                c[2].wrapping_mul(2).wrapping_add(d(2)),
            );
            let child = NodeKey {
                level: key.level - 1,
                coord,
            };
            if in_extent(p, extent, child) {
                stack.push(child);
            }
        }
    }
    out
}

/// A selection as a set, with its nodes nearest first.
#[derive(Clone, Debug, Default)]
pub struct Selection {
    /// The selected nodes.
    pub keys: HashSet<NodeKey>,
    /// The same nodes, nearest to the anchor first.
    pub nearest_first: Vec<NodeKey>,
}

impl Selection {
    /// The selection of `p` within `extent`.
    pub fn of(p: &LodParams, extent: &Extent) -> Selection {
        let mut keyed: Vec<(f64, NodeKey)> = select(p, extent)
            .into_iter()
            .map(|k| (distance(p, k), k))
            .collect();
        keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let nearest_first: Vec<NodeKey> = keyed.into_iter().map(|(_, k)| k).collect();
        Selection {
            keys: nearest_first.iter().copied().collect(),
            nearest_first,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(budget: f32, top: u32) -> LodParams {
        LodParams {
            anchor_chunk: [3, 1, -2],
            top_level: top,
            anchor_offset: [4.0, 2.0, 9.0],
            budget_px: budget,
            focal_px: 64.0,
            hysteresis: 16.0,
            chunk_edge: 16.0,
            pad: 0,
        }
    }

    const EXTENT: Extent = Extent {
        radius: 300.0,
        top_block: 40,
    };

    #[test]
    fn the_walk_selects_what_the_renderers_rule_selects() {
        for budget in [0.5, 1.0, 4.0] {
            let p = params(budget, 4);
            let walked = Selection::of(&p, &EXTENT);
            assert!(!walked.keys.is_empty());
            assert_eq!(
                walked.keys.len(),
                walked.nearest_first.len(),
                "no duplicates"
            );
            for key in &walked.keys {
                let c = [key.coord.x, key.coord.y, key.coord.z];
                assert!(
                    lod::selected(&p, c, key.level),
                    "{key:?} at budget {budget}"
                );
            }
            // Every level-0 chunk of the terrain's heights within the radius is covered by
            // exactly one selected node.
            let mut covered = 0;
            for z in -25..20 {
                for x in -15..30 {
                    for y in 0..3 {
                        let key = NodeKey {
                            level: 0,
                            coord: ChunkCoord::new(x, y, z),
                        };
                        if !in_extent(&p, &EXTENT, key) {
                            continue;
                        }
                        let ancestors = (0..=4)
                            .filter(|&l| {
                                walked.keys.contains(&NodeKey {
                                    level: l,
                                    coord: ChunkCoord::new(x >> l, y >> l, z >> l),
                                })
                            })
                            .count();
                        assert_eq!(ancestors, 1, "chunk {x},{y},{z} at budget {budget}");
                        covered += 1;
                    }
                }
            }
            assert!(covered > 500, "{covered}");
        }
    }

    #[test]
    fn nodes_come_nearest_first_and_stay_in_range() {
        let p = params(1.0, 4);
        let s = Selection::of(&p, &EXTENT);
        let d: Vec<f64> = s.nearest_first.iter().map(|&k| distance(&p, k)).collect();
        assert!(d.windows(2).all(|w| w[0] <= w[1]));
        assert_eq!(d[0], 0.0, "the anchor's own chunk first");
        for key in &s.keys {
            let (lo, size) = node_box(&p, *key);
            assert!(horizontal_distance(lo, size) <= EXTENT.radius);
            let edge = 16i64 << key.level;
            assert!(i64::from(key.coord.y) * edge <= 40 && key.coord.y >= 0);
        }
        // A larger budget selects coarser, fewer nodes.
        assert!(Selection::of(&params(8.0, 4), &EXTENT).keys.len() < s.keys.len());
    }
}
