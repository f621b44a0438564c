//! Clutter following the grass reach: which resident nodes hold clutter, and the rebuilds
//! that give it to the nodes a plan's zone places it on and take it from those it leaves
//! (the zone: `stream/placement.rs`).
//!
//! # Why grass is never missing where it is drawn
//!
//! The zone is set when a plan arrives, before any of its nodes is queued, so its builds place
//! by it. Resident nodes it places clutter on that lack it (the committed plan's, or taken
//! back from the cache without it) are rebuilt by the workers ahead of the streaming queue,
//! and the plan is not committed while those rebuilds run; any still lacking then (a rebuild
//! that read an older zone) are rebuilt at once before the commit, with the stale nodes of
//! an edit (`streamer/edits.rs`). A built node waiting to upload whose clutter disagrees with
//! the zone is built again. So once a plan draws, every node it places clutter on has it.
//!
//! # Why clutter does not pile up
//!
//! After a commit the zone is the new plan's alone; resident nodes with clutter outside it
//! are rebuilt without, after the streaming queue (extra clutter is never drawn, so it can
//! wait). A rebuild's data replaces the resident data when it reads the same world version
//! and has the clutter the zone places where the resident data has not, so a late rebuild
//! for an older zone never undoes a newer one, and a node still wrong goes back to the
//! workers until the two agree.

use std::sync::Arc;

use super::{Entry, Streamer};
use crate::stream::selection::NodeKey;

impl Streamer {
    /// True when the committed or the wanted plan places clutter on `key`.
    pub(super) fn wants_clutter(&self, key: &NodeKey) -> bool {
        self.committed
            .as_ref()
            .is_some_and(|c| c.clutter.contains(key))
            || self
                .wanted
                .as_ref()
                .is_some_and(|w| w.plan.clutter.contains(key))
    }

    /// True when resident node `key` draws something and holds clutter where its zone places
    /// none, or none where it places some.
    pub(super) fn clutter_wrong(&self, key: &NodeKey) -> bool {
        matches!(self.entries.get(key), Some(Entry::Resident(Some(_))))
            && self.clutter.contains_key(key) != self.wants_clutter(key)
    }

    /// True when resident node `key` draws something and lacks the clutter its zone places.
    pub(super) fn lacks_clutter(&self, key: &NodeKey) -> bool {
        self.clutter_wrong(key) && !self.clutter.contains_key(key)
    }

    /// Records resident node `key`'s clutter: its units, or `None` when built without.
    pub(super) fn set_clutter(&mut self, key: NodeKey, units: Option<u32>) {
        let old = match units {
            Some(n) => self.clutter.insert(key, n),
            None => self.clutter.remove(&key),
        };
        self.clutter_units -= u64::from(old.unwrap_or(0));
        self.clutter_units += u64::from(units.unwrap_or(0));
    }

    /// Resident node `key`'s clutter units, `None` when built without (for the cache).
    pub(super) fn clutter_of(&self, key: &NodeKey) -> Option<u32> {
        self.clutter.get(key).copied()
    }

    /// Sets the builders' zone to the committed and the wanted plan's clutter nodes.
    pub(super) fn sync_clutter_zone(&self) {
        let of = |plan: Option<&super::Plan>| {
            plan.map_or_else(Default::default, |p| Arc::clone(&p.clutter))
        };
        self.source.zone.set(
            of(self.committed.as_deref()),
            of(self.wanted.as_ref().map(|w| &*w.plan)),
        );
    }

    /// Queues rebuilds, ahead of the streaming, of the resident nodes the wanted plan places
    /// clutter on that lack it.
    pub(super) fn queue_clutter_gains(&mut self) {
        let Some(wanted) = &self.wanted else {
            return;
        };
        let gains: Vec<NodeKey> = wanted
            .plan
            .clutter
            .iter()
            .filter(|k| self.lacks_clutter(k) && !self.rebuilding.contains(k))
            .copied()
            .collect();
        self.queue_rebuilds(gains, true);
    }

    /// True while the workers rebuild nodes the wanted plan places clutter on that lack it.
    pub(super) fn gaining_clutter(&self) -> bool {
        self.wanted.as_ref().is_some_and(|w| {
            w.plan
                .clutter
                .iter()
                .any(|k| self.rebuilding.contains(k) && self.lacks_clutter(k))
        })
    }

    /// Queues rebuilds, after the streaming, of the resident nodes a plan selects that hold
    /// clutter no plan places.
    pub(super) fn queue_clutter_drops(&mut self) {
        let drops: Vec<NodeKey> = self
            .clutter
            .keys()
            .filter(|k| self.needed(k) && self.clutter_wrong(k) && !self.rebuilding.contains(k))
            .copied()
            .collect();
        self.queue_rebuilds(drops, false);
    }

    /// The resident nodes built with clutter (the cache's left out).
    pub fn clutter_keys(&self) -> impl Iterator<Item = &NodeKey> {
        self.clutter.keys()
    }

    /// The committed plan's nodes that draw something and lack the clutter it places: bare
    /// ground where the grass pass would draw grass. Empty by construction (this module's
    /// docs say why); tests check it every frame.
    pub fn clutter_missing(&self) -> Vec<NodeKey> {
        self.committed
            .iter()
            .flat_map(|c| c.clutter.iter())
            .filter(|k| {
                matches!(self.entries.get(k), Some(Entry::Resident(Some(_))))
                    && !self.clutter.contains_key(k)
            })
            .copied()
            .collect()
    }

    /// Resident nodes holding clutter that neither plan places: rebuilt without it by the
    /// workers, so none once the streamer has settled.
    pub fn stray_clutter(&self) -> Vec<NodeKey> {
        self.clutter
            .keys()
            .filter(|k| !self.wants_clutter(k))
            .copied()
            .collect()
    }
}
