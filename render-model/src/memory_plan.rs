//! Residency under a memory budget: which nodes to keep on the GPU, and the error budget to
//! draw them at, when everything the requested budget selects does not fit.
//!
//! # The rule
//!
//! The selection ([`cull::lod`](crate::cull::lod)) depends only on the anchor, the error
//! budget `B` and the hysteresis, and covers space exactly once. [`plan`] takes every node the
//! scene has (level, coordinate, bytes) and keeps the nodes the selection picks at `B`. If their
//! bytes (with [`NODE_OVERHEAD_BYTES`] each) exceed the memory budget, `B` is raised by factors
//! of `2^(1/4)` until they fit. A node refines when it is nearer than `e_k f / B`, so raising
//! `B` coarsens the farthest detail first: the farthest detail is evicted first and its
//! ancestors are drawn in its place. Since every budget's selection covers space once, the
//! drawn set never has a hole; the renderer draws at the plan's budget, which the caller
//! reports (the image error grows with it; BENCHMARKS.md has the trade).
//!
//! Nodes the plan does not keep may be freed in any order; a streaming caller moves the anchor
//! only once the plan for the new anchor is resident
//! (`gpu_backend::Renderer::set_lod_anchor`).
//!
//! A plan that does not fit even at a budget of [`MAX_PLAN_BUDGET_PX`] pixels (where only the
//! nodes within the hysteresis distance of the anchor refine) is an error naming both sizes.

use std::fmt;

use crate::cull::{LodParams, lod};

/// The renderer's bytes per resident node beside its gigabuffer data: its chunk record
/// (112 bytes) and node record (64 bytes).
pub const NODE_OVERHEAD_BYTES: u64 = 112 + 64;

/// The largest budget a plan raises to, pixels.
pub const MAX_PLAN_BUDGET_PX: f32 = 65_536.0;

/// One node the scene has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PlannedNode {
    /// Level of detail.
    pub level: u32,
    /// Coordinate among the nodes of its level.
    pub coord: [i32; 3],
    /// Gigabuffer bytes of its data (every kind).
    pub bytes: u64,
}

/// Which nodes to keep resident and the budget to draw them at.
#[derive(Clone, Debug, PartialEq)]
pub struct MemoryPlan {
    /// The error budget the kept nodes are selected at, pixels (at least the one asked for).
    pub budget_px: f32,
    /// Indices (into the planned nodes) of the nodes to keep.
    pub keep: Vec<usize>,
    /// Bytes of the kept nodes, overhead included.
    pub bytes: u64,
}

impl MemoryPlan {
    /// Whether the budget had to be raised above `asked_px` to fit.
    pub fn raised(&self, asked_px: f32) -> bool {
        self.budget_px > asked_px
    }
}

/// Why no plan fits.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanTooLarge {
    /// Bytes of the smallest selection tried (at [`MAX_PLAN_BUDGET_PX`]).
    pub needed: u64,
    /// The memory budget.
    pub memory_bytes: u64,
}

impl fmt::Display for PlanTooLarge {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the nodes around the camera need {} bytes even at an error budget of {} px, above \
             the memory budget of {} bytes",
            self.needed, MAX_PLAN_BUDGET_PX, self.memory_bytes
        )
    }
}

impl std::error::Error for PlanTooLarge {}

/// The nodes `params` selects, and their bytes.
fn selection(nodes: &[PlannedNode], params: &LodParams) -> (Vec<usize>, u64) {
    let keep: Vec<usize> = nodes
        .iter()
        .enumerate()
        .filter(|(_, n)| lod::selected(params, n.coord, n.level))
        .map(|(i, _)| i)
        .collect();
    let bytes = keep
        .iter()
        .map(|&i| nodes[i].bytes + NODE_OVERHEAD_BYTES)
        .sum();
    (keep, bytes)
}

/// The plan for `nodes` seen from `params` (its anchor, hysteresis and asked budget) within
/// `memory_bytes` (see the [module docs](self) for the rule).
pub fn plan(
    nodes: &[PlannedNode],
    params: &LodParams,
    memory_bytes: u64,
) -> Result<MemoryPlan, PlanTooLarge> {
    let mut params = *params;
    loop {
        let (keep, bytes) = selection(nodes, &params);
        if bytes <= memory_bytes {
            return Ok(MemoryPlan {
                budget_px: params.budget_px,
                keep,
                bytes,
            });
        }
        if params.budget_px >= MAX_PLAN_BUDGET_PX {
            return Err(PlanTooLarge {
                needed: bytes,
                memory_bytes,
            });
        }
        // From 0 (full detail) the first step is a quarter pixel.
        params.budget_px = (params.budget_px.max(0.25 / 2f32.powf(0.25)) * 2f32.powf(0.25))
            .min(MAX_PLAN_BUDGET_PX);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A row of level-0 nodes along +x from the anchor, their level-1 parents and one
    /// level-2 node; each node 1000 bytes.
    fn row() -> (Vec<PlannedNode>, LodParams) {
        let mut nodes = Vec::new();
        for x in 0..16 {
            nodes.push(PlannedNode {
                level: 0,
                coord: [x, 0, 0],
                bytes: 1000,
            });
        }
        for x in 0..8 {
            nodes.push(PlannedNode {
                level: 1,
                coord: [x, 0, 0],
                bytes: 1000,
            });
        }
        for x in 0..4 {
            nodes.push(PlannedNode {
                level: 2,
                coord: [x, 0, 0],
                bytes: 1000,
            });
        }
        let params = LodParams {
            top_level: 2,
            // Fine enough that level 0 reaches 10 chunks out: room to coarsen.
            budget_px: 0.1,
            focal_px: 16.0,
            chunk_edge: 16.0,
            ..LodParams::default()
        };
        (nodes, params)
    }

    /// Each level-0 cell of the row is covered by exactly one kept node.
    fn covers_once(nodes: &[PlannedNode], keep: &[usize]) -> bool {
        (0..16).all(|x: i32| {
            keep.iter()
                .filter(|&&i| nodes[i].coord[0] == x >> nodes[i].level)
                .count()
                == 1
        })
    }

    #[test]
    fn enough_memory_keeps_the_asked_selection() {
        let (nodes, params) = row();
        let plan = plan(&nodes, &params, u64::MAX).unwrap();
        assert_eq!(plan.budget_px, 0.1);
        assert!(!plan.raised(0.1));
        assert!(covers_once(&nodes, &plan.keep));
        let (keep, bytes) = selection(&nodes, &params);
        assert_eq!((plan.keep, plan.bytes), (keep, bytes));
    }

    #[test]
    fn less_memory_coarsens_the_farthest_detail_first() {
        let (nodes, params) = row();
        let full = plan(&nodes, &params, u64::MAX).unwrap();
        let tight = plan(&nodes, &params, full.bytes - 1).unwrap();
        assert!(tight.raised(0.1) && tight.bytes < full.bytes);
        assert!(covers_once(&nodes, &tight.keep));
        // The nearest level-0 node stays; what went coarser lies beyond what stayed fine.
        let level0 = |p: &MemoryPlan| -> Vec<i32> {
            p.keep
                .iter()
                .filter(|&&i| nodes[i].level == 0)
                .map(|&i| nodes[i].coord[0])
                .collect()
        };
        let (before, after) = (level0(&full), level0(&tight));
        assert!(after.contains(&0));
        assert!(after.iter().all(|x| before.contains(x)));
        assert!(after.len() < before.len() || tight.keep.len() < full.keep.len());
        let nearest_lost = before.iter().filter(|x| !after.contains(x)).min();
        if let Some(lost) = nearest_lost {
            assert!(after.iter().all(|x| x < lost), "{after:?} vs lost {lost}");
        }
    }

    #[test]
    fn too_little_memory_is_an_error_naming_both_sizes() {
        let (nodes, params) = row();
        let error = plan(&nodes, &params, 10).unwrap_err();
        assert!(error.needed > 10);
        let text = error.to_string();
        assert!(text.contains("10 bytes") && text.contains(&error.needed.to_string()));
    }
}
