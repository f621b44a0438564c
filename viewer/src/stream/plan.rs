//! A plan: the selection of one anchor and budget, and how it differs from the committed
//! selection (what to load, what leaves) and from the plan it replaces (what was loaded for
//! nothing). Made on rayon's pool, so a large selection never costs a frame.

use std::collections::HashSet;
use std::sync::Arc;

use render_model::cull::{LodAnchor, LodParams};
use voxel_core::ChunkCoord;

use super::placement::clutter_keys;
use super::selection::{Extent, NodeKey, Selection};
use super::settings::ClutterPlacement;

/// One anchor's selection and its differences (see the [module docs](self)).
#[derive(Debug)]
pub(super) struct Plan {
    /// The selection's inputs (anchor, budget, focal length, hysteresis, top level).
    pub params: LodParams,
    /// The selected nodes.
    pub keys: HashSet<NodeKey>,
    /// The selected nodes the committed plan lacks, nearest first: what to load.
    pub load: Vec<NodeKey>,
    /// The committed plan's nodes this one lacks: freed when this plan is committed.
    pub leaving: Vec<NodeKey>,
    /// The replaced plan's nodes that neither this plan nor the committed one has: freed
    /// when this plan takes its place.
    pub abandoned: Vec<NodeKey>,
    /// The selected level-0 nodes that get clutter (`stream/placement.rs`).
    pub clutter: Arc<HashSet<NodeKey>>,
}

impl Plan {
    /// The plan of `params` within `extent`, against the `committed` plan and the `replaced`
    /// one (the pending plan it supersedes), with clutter placed by `clutter` (`None`: off).
    pub(super) fn new(
        params: LodParams,
        extent: &Extent,
        committed: Option<&Plan>,
        replaced: Option<&Plan>,
        clutter: Option<ClutterPlacement>,
    ) -> Plan {
        let Selection {
            keys,
            nearest_first,
        } = Selection::of(&params, extent);
        let in_committed = |k: &NodeKey| committed.is_some_and(|c| c.keys.contains(k));
        let load = nearest_first
            .into_iter()
            .filter(|k| !in_committed(k))
            .collect();
        let leaving = committed.map_or_else(Vec::new, |c| {
            c.keys
                .iter()
                .filter(|k| !keys.contains(k))
                .copied()
                .collect()
        });
        let abandoned = replaced.map_or_else(Vec::new, |r| {
            r.keys
                .iter()
                .filter(|k| !keys.contains(k) && !in_committed(k))
                .copied()
                .collect()
        });
        let clutter = Arc::new(clutter_keys(&params, &keys, clutter));
        Plan {
            params,
            keys,
            load,
            leaving,
            abandoned,
            clutter,
        }
    }

    /// The anchor the plan selects from.
    pub(super) fn anchor(&self) -> LodAnchor {
        let [x, y, z] = self.params.anchor_chunk;
        LodAnchor {
            chunk: ChunkCoord::new(x, y, z),
            offset: self.params.anchor_offset,
        }
    }
}

/// Makes the plan of `params` on rayon's pool; it arrives on the returned receiver.
pub(super) fn spawn(
    params: LodParams,
    extent: Extent,
    committed: Option<Arc<Plan>>,
    replaced: Option<Arc<Plan>>,
    clutter: Option<ClutterPlacement>,
) -> std::sync::mpsc::Receiver<Plan> {
    let (sender, receiver) = std::sync::mpsc::channel();
    rayon::spawn(move || {
        let plan = Plan::new(
            params,
            &extent,
            committed.as_deref(),
            replaced.as_deref(),
            clutter,
        );
        // The streamer may have been dropped meanwhile: nothing to do then.
        let _ = sender.send(plan);
    });
    receiver
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn differences_name_what_to_load_and_free() {
        let extent = Extent {
            radius: 200.0,
            top_block: 40,
        };
        let at = |x: i32| LodParams {
            anchor_chunk: [x, 2, 0],
            top_level: 3,
            anchor_offset: [8.0; 3],
            budget_px: 1.0,
            focal_px: 48.0,
            hysteresis: 16.0,
            chunk_edge: 16.0,
            pad: 0,
        };
        let first = Plan::new(at(0), &extent, None, None, None);
        assert!(first.leaving.is_empty() && first.abandoned.is_empty());
        assert_eq!(first.load.len(), first.keys.len());
        let pending = Plan::new(at(4), &extent, Some(&first), None, None);
        let next = Plan::new(at(8), &extent, Some(&first), Some(&pending), None);
        for k in &next.load {
            assert!(next.keys.contains(k) && !first.keys.contains(k));
        }
        for k in &next.leaving {
            assert!(first.keys.contains(k) && !next.keys.contains(k));
        }
        for k in &next.abandoned {
            assert!(pending.keys.contains(k) && !next.keys.contains(k));
            assert!(!first.keys.contains(k));
        }
        assert!(!next.load.is_empty() && !next.leaving.is_empty() && !next.abandoned.is_empty());
        assert_eq!(next.anchor().chunk, ChunkCoord::new(8, 2, 0));
    }
}
