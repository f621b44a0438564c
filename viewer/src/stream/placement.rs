//! Which level-0 nodes carry clutter: those of a plan that the grass pass can draw from an
//! eye within the anchor's hysteresis ([`chunk_may_draw_grass`], the fade's own rule, with
//! the plan's anchor, budget and focal length), and the zone the builders place clutter by.
//!
//! # Why the hysteresis is the slack
//!
//! A committed plan stays drawn until the camera is more than the hysteresis from its
//! anchor; then the next plan is made at the camera. So while the camera keeps within the
//! planner's pace, every eye a plan is drawn from lies within the hysteresis of its anchor,
//! and every level-0 node whose grass the cull can keep is one this rule admits. A camera
//! outrunning the planner can see grass missing at the edge of its reach (blades 4 to 8
//! budgets tall) until the next plan commits, as it sees coarser voxels meanwhile.
//!
//! # The zone
//!
//! A node is built with clutter when the committed or the wanted plan admits it (both may be
//! drawn: the committed now, the wanted once loaded). The streamer sets the zone whenever a
//! plan arrives or is committed; each build records whether it placed clutter, and the
//! streamer rebuilds a node whose clutter disagrees with the zone (`streamer/clutter.rs`).

use std::collections::HashSet;
use std::sync::{Arc, RwLock};

use render_model::cull::LodParams;
use render_model::grass::chunk_may_draw_grass;

use super::selection::NodeKey;
use super::settings::ClutterPlacement;

/// The nodes of a plan's selection `keys` (with `params`) that get clutter under
/// `placement` (`None`: clutter off, no node).
pub(super) fn clutter_keys(
    params: &LodParams,
    keys: &HashSet<NodeKey>,
    placement: Option<ClutterPlacement>,
) -> HashSet<NodeKey> {
    let Some(placement) = placement else {
        return HashSet::new();
    };
    keys.iter()
        .filter(|k| k.level == 0)
        .filter(|k| {
            placement == ClutterPlacement::Everywhere
                || chunk_may_draw_grass(params, [k.coord.x, k.coord.y, k.coord.z])
        })
        .copied()
        .collect()
}

/// The nodes built with clutter: those the committed or the wanted plan admits (see the
/// [module docs](self)), shared by a streamer and its builders.
#[derive(Debug, Default)]
pub(super) struct ClutterZone {
    plans: RwLock<[Arc<HashSet<NodeKey>>; 2]>,
}

impl ClutterZone {
    /// The zone is now `committed`'s and `wanted`'s clutter nodes.
    pub(super) fn set(&self, committed: Arc<HashSet<NodeKey>>, wanted: Arc<HashSet<NodeKey>>) {
        // A poisoned lock still holds a whole pair of sets: nothing panics between its writes.
        *self.plans.write().unwrap_or_else(|e| e.into_inner()) = [committed, wanted];
    }

    /// True when node `key` is built with clutter now.
    pub(super) fn contains(&self, key: &NodeKey) -> bool {
        let plans = self.plans.read().unwrap_or_else(|e| e.into_inner());
        plans.iter().any(|p| p.contains(key))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stream::selection::{Extent, Selection, distance};
    use render_model::grass::grass_reach;

    fn params(budget: f32) -> LodParams {
        LodParams {
            anchor_chunk: [2, 1, -3],
            top_level: 4,
            anchor_offset: [5.0, 3.0, 11.0],
            budget_px: budget,
            focal_px: 300.0,
            hysteresis: 16.0,
            chunk_edge: 16.0,
            pad: 0,
        }
    }

    const EXTENT: Extent = Extent {
        radius: 600.0,
        top_block: 40,
    };

    #[test]
    fn near_placement_keeps_the_nodes_within_the_grass_reach() {
        for budget in [1.0, 2.0] {
            let p = params(budget);
            let keys = Selection::of(&p, &EXTENT).keys;
            let level0 = keys.iter().filter(|k| k.level == 0).count();
            let near = clutter_keys(&p, &keys, Some(ClutterPlacement::Near));
            let everywhere = clutter_keys(&p, &keys, Some(ClutterPlacement::Everywhere));
            assert_eq!(everywhere.len(), level0);
            assert!(clutter_keys(&p, &keys, None).is_empty());
            let reach = f64::from(grass_reach(p.focal_px, budget)) + 16.0 + 2.0;
            for k in &near {
                assert_eq!(k.level, 0);
                assert!(distance(&p, *k) < reach, "{k:?}");
            }
            for k in everywhere.difference(&near) {
                assert!(distance(&p, *k) >= reach - 2.0, "{k:?} left out");
            }
            // The level-0 ring reaches several times as far as the grass.
            assert!(
                near.len() * 4 < level0 && !near.is_empty(),
                "{} of {level0} level-0 nodes at {budget} px",
                near.len()
            );
        }
    }

    #[test]
    fn the_zone_is_both_plans() {
        let zone = ClutterZone::default();
        let key = |x| NodeKey {
            level: 0,
            coord: voxel_core::ChunkCoord::new(x, 0, 0),
        };
        assert!(!zone.contains(&key(1)));
        zone.set(
            Arc::new([key(1)].into_iter().collect()),
            Arc::new([key(2)].into_iter().collect()),
        );
        assert!(zone.contains(&key(1)) && zone.contains(&key(2)) && !zone.contains(&key(3)));
    }
}
