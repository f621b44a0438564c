//! The least-recently-used cache of nodes the plans dropped (`StreamSettings::cache_nodes`):
//! kept resident on the GPU, out of the streamer's entries, so a plan that wants one again
//! takes it back without meshing or uploading.
//!
//! # Why a cached node is never drawn
//!
//! The renderer draws the resident nodes its level-of-detail rule selects, and the rule walks
//! from the committed plan's anchor and budget exactly as the plan's own selection does: a
//! node the rule would select is one the committed plan selects, which is resident as an
//! entry, never cached. So cached nodes cost table slots, memory and cull work, not pixels.
//! That holds while the plan has more than one level: with a single level (a radius of fewer
//! than four nodes across, [`StreamSettings::top_level`] 0) the renderer selects every
//! resident node, so there the cache stays off.
//!
//! [`StreamSettings::top_level`]: crate::stream::StreamSettings::top_level
//!
//! # Memory
//!
//! Cached bytes stay taken from the view's [`NodeMemory`](crate::stream::NodeMemory). When an
//! upload finds no room, in the memory, a gigabuffer or the node table, the older half of the
//! cache goes first, again until the upload fits or the cache is empty
//! (`Streamer::free_unneeded`), before the budget is raised: the view's own detail never
//! gives way to it. A node an edit dirties is dropped from the cache (its data is stale).
//!
//! # Clutter
//!
//! A cached node keeps the clutter it was built with, and takes it back with it; a plan that
//! places clutter on it otherwise rebuilds it before it is drawn (`streamer/clutter.rs`).

use std::collections::{BTreeMap, HashMap};

use gpu_backend::residency::ChunkHandle;

use super::{Entry, Streamer};
use crate::stream::StreamError;
use crate::stream::selection::NodeKey;

/// One cached node: its GPU data (`None`: it draws nothing), the world version it read and
/// its clutter units (`None`: built without clutter).
#[derive(Clone, Copy, Debug)]
struct Cached {
    handle: Option<(ChunkHandle, u64)>,
    read_at: u64,
    clutter: Option<u32>,
    stamp: u64,
}

/// The cache (see the [module docs](self)).
#[derive(Debug, Default)]
pub(super) struct NodeCache {
    nodes: HashMap<NodeKey, Cached>,
    /// Keys by the stamp of their entry into the cache: the oldest first.
    order: BTreeMap<u64, NodeKey>,
    next: u64,
    bytes: u64,
}

impl NodeCache {
    /// Nodes cached.
    pub(super) fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Bytes of the cached nodes' data.
    pub(super) fn bytes(&self) -> u64 {
        self.bytes
    }

    fn insert(
        &mut self,
        key: NodeKey,
        handle: Option<(ChunkHandle, u64)>,
        read_at: u64,
        clutter: Option<u32>,
    ) {
        let stamp = self.next;
        self.next += 1;
        self.bytes += handle.map_or(0, |(_, b)| b);
        if let Some(old) = self.nodes.insert(
            key,
            Cached {
                handle,
                read_at,
                clutter,
                stamp,
            },
        ) {
            self.order.remove(&old.stamp);
            self.bytes -= old.handle.map_or(0, |(_, b)| b);
        }
        self.order.insert(stamp, key);
    }

    fn take(&mut self, key: &NodeKey) -> Option<Cached> {
        let cached = self.nodes.remove(key)?;
        self.order.remove(&cached.stamp);
        self.bytes -= cached.handle.map_or(0, |(_, b)| b);
        Some(cached)
    }

    fn oldest(&self) -> Option<NodeKey> {
        self.order.values().next().copied()
    }
}

impl Streamer {
    /// Keeps resident node `key`, which no plan selects any more, in the cache instead of
    /// freeing it; false when the cache is off (or the plan has a single level, see the
    /// [module docs](self)) or the node's data is stale (then the caller frees it).
    pub(super) fn cache_dropped(&mut self, key: NodeKey) -> Result<bool, StreamError> {
        if self.settings.cache_nodes == 0 || self.settings.top_level() == 0 || self.is_stale(&key) {
            return Ok(false);
        }
        let Some(&Entry::Resident(handle)) = self.entries.get(&key) else {
            return Ok(false);
        };
        let read_at = self.read_at.get(&key).copied().unwrap_or(0);
        let clutter = self.clutter_of(&key);
        self.remove_entry(&key);
        self.cache.insert(key, handle, read_at, clutter);
        while self.cache.len() > self.settings.cache_nodes as usize {
            let Some(oldest) = self.cache.oldest() else {
                break;
            };
            self.evict(oldest)?;
        }
        Ok(true)
    }

    /// Takes node `key` back from the cache as a resident entry: true when it was cached.
    pub(super) fn take_cached(&mut self, key: NodeKey) -> bool {
        let Some(cached) = self.cache.take(&key) else {
            return false;
        };
        self.set_entry(key, Entry::Resident(cached.handle));
        self.read_at.insert(key, cached.read_at);
        self.set_clutter(key, cached.clutter);
        self.counters.cache_hits += 1;
        true
    }

    /// Frees cached node `key` (GPU data and memory); nothing when it is not cached.
    pub(super) fn evict(&mut self, key: NodeKey) -> Result<(), StreamError> {
        let Some(cached) = self.cache.take(&key) else {
            return Ok(());
        };
        if let Some((handle, bytes)) = cached.handle {
            self.renderer
                .free_chunk(handle)
                .map_err(StreamError::Renderer)?;
            self.memory.give_back(bytes);
            self.counters.freed += 1;
        }
        self.counters.evicted += 1;
        Ok(())
    }

    /// Evicts the older half of the cache (at least one node): true when it held any. An
    /// upload that finds no room calls it until the upload fits, so a short gigabuffer costs
    /// the few oldest nodes, not the whole cache in one frame.
    pub(super) fn evict_older_half(&mut self) -> Result<bool, StreamError> {
        let n = self.cache.len().div_ceil(2);
        for _ in 0..n {
            let Some(oldest) = self.cache.oldest() else {
                break;
            };
            self.evict(oldest)?;
        }
        Ok(n > 0)
    }

    /// Empties the cache: true when that gave memory or table room back.
    pub(super) fn evict_all(&mut self) -> Result<bool, StreamError> {
        let any = self.cache.len() > 0;
        while let Some(oldest) = self.cache.oldest() {
            self.evict(oldest)?;
        }
        Ok(any)
    }

    /// Empties the cache of dropped nodes (a replacement streamer loading beside this one
    /// needs the memory more than a return would).
    pub fn drop_cache(&mut self) -> Result<(), StreamError> {
        self.evict_all().map(|_| ())
    }

    /// Nodes and bytes in the cache.
    pub(super) fn cached(&self) -> (usize, u64) {
        (self.cache.len(), self.cache.bytes())
    }
}
