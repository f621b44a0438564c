//! Edits reaching a streamer: which of its nodes a [`DirtySet`] makes stale, the shown ones
//! rebuilt at once and swapped in one step, the others rebuilt by the workers.
//!
//! # Stale data, by world version
//!
//! Every build records the world version it read ([`World::version`], taken under the same
//! lock as the edits it overlays), and every edit the version after it. A node whose data was
//! read before the last edit that dirtied it is *stale*. A build's data replaces a node's only
//! when it is newer than the resident data, so a slow build never undoes a faster one.
//!
//! # Why no frame shows a hole, both meshes, or a stale node
//!
//! A swap uploads the node's new data, then frees the old, both before the next frame is
//! recorded, so that frame draws the new data and no frame draws neither or both (the frame
//! before, already submitted, keeps reading the old data: the renderer's uploads and frees
//! are ordered after it on the queue). The nodes the committed plan selects are rebuilt at
//! once on the calling thread's rayon pool when an edit dirties them, so the next frame
//! shows the edit at every level the plan draws. Resident nodes only the wanted plan selects
//! are rebuilt by the workers, nearest first, ahead of the streaming queue; when that plan is
//! otherwise loaded, the ones still stale (edits keep coming) are rebuilt at once before it
//! commits, so a stale node is never newly shown and a stream of edits cannot hold a plan
//! back. A built node waiting to upload that turns stale is built again.
//!
//! [`World::version`]: voxel_world::World::version

use rayon::prelude::*;
use voxel_world::DirtySet;

use super::{Entry, Streamer};
use crate::stream::StreamError;
use crate::stream::build::{BuildNode, Built, BuiltNode};
use crate::stream::selection::NodeKey;
use render_model::resident::ChunkMeshData;

/// What one batch's dirty set did to a streamer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Invalidated {
    /// Shown nodes rebuilt and swapped in at once.
    pub swapped: usize,
    /// The time the world took to apply the batch (filling the chunks it reaches, writing,
    /// the dirty set and the coarse voxels); set by the view, which applies it.
    pub world: std::time::Duration,
    /// The time the shown nodes took to rebuild and swap.
    pub rebuild: std::time::Duration,
    /// Resident nodes queued for the workers to rebuild.
    pub queued: usize,
    /// Builds made stale (queued, running or waiting to upload): built again.
    pub stale: usize,
}

impl Streamer {
    /// Makes the nodes `dirty` names stale as of world `version` (the version after the
    /// batch; see `stream/streamer/edits.rs`): the shown ones are rebuilt and swapped before
    /// this returns, so the next frame shows the edit.
    pub fn invalidate(
        &mut self,
        dirty: &DirtySet,
        version: u64,
    ) -> Result<Invalidated, StreamError> {
        let mut done = Invalidated::default();
        let mut later = Vec::new();
        for world_key in dirty.all_nodes() {
            let key = NodeKey {
                level: world_key.level,
                coord: world_key.coord,
            };
            // A cached node's data is stale now: freed, built afresh if a plan wants it.
            self.evict(key)?;
            let Some(entry) = self.entries.get(&key) else {
                continue;
            };
            self.dirty_since.insert(key, version);
            match entry {
                Entry::Loading | Entry::Built => done.stale += 1,
                Entry::Resident(_) => {
                    let shown = self
                        .committed
                        .as_ref()
                        .is_some_and(|c| c.keys.contains(&key));
                    if !shown && !self.rebuilding.contains(&key) {
                        later.push(key);
                    }
                }
            }
        }
        let committed = self.committed.clone();
        let started = std::time::Instant::now();
        done.swapped = self.refresh_now(
            |key| committed.as_ref().is_some_and(|c| c.keys.contains(key)),
            std::iter::empty(),
        )?;
        done.rebuild = started.elapsed();
        self.queue_rebuilds(later.clone(), true);
        done.queued = later.len();
        Ok(done)
    }

    /// True when `key`'s data (built or resident) was read before the last edit that
    /// dirtied it.
    pub(super) fn is_stale(&self, key: &NodeKey) -> bool {
        self.dirty_since
            .get(key)
            .is_some_and(|&d| self.read_at.get(key).is_none_or(|&r| r < d))
    }

    /// Rebuilds now (rayon) and swaps in every resident node `select` picks that is stale,
    /// or, among `clutter`, lacks the clutter its zone places (`streamer/clutter.rs`);
    /// returns how many.
    pub(super) fn refresh_now(
        &mut self,
        select: impl Fn(&NodeKey) -> bool,
        clutter: impl Iterator<Item = NodeKey>,
    ) -> Result<usize, StreamError> {
        let resident = |k: &NodeKey| matches!(self.entries.get(k), Some(Entry::Resident(_)));
        let mut now: Vec<NodeKey> = self
            .dirty_since
            .keys()
            .filter(|k| select(k) && self.is_stale(k) && resident(k))
            .copied()
            .collect();
        now.extend(clutter.filter(|k| select(k) && !self.is_stale(k) && self.lacks_clutter(k)));
        let source = &self.source;
        let built: Vec<(NodeKey, Result<Built, String>)> = now
            .par_iter()
            .map(|&key| (key, source.build(key)))
            .collect();
        for (key, result) in built {
            let built = result.map_err(StreamError::Build)?;
            self.swap(key, built.node, built.version)?;
        }
        Ok(now.len())
    }

    /// Hands resident nodes to the workers to rebuild, nearest to the camera first, ahead
    /// of the streaming queue when `front` (else after it).
    pub(super) fn queue_rebuilds(&mut self, mut keys: Vec<NodeKey>, front: bool) {
        if keys.is_empty() {
            return;
        }
        let eye = self.renderer.camera().eye(self.settings.chunk);
        let edge = f64::from(self.settings.chunk.edge());
        let distance = |key: &NodeKey| {
            let side = edge * f64::from(1u32 << key.level.min(30));
            let centre =
                [key.coord.x, key.coord.y, key.coord.z].map(|c| (f64::from(c) + 0.5) * side);
            let chunk = [eye.chunk.x, eye.chunk.y, eye.chunk.z];
            (0..3)
                .map(|a| {
                    let e = f64::from(chunk[a]) * edge + f64::from(eye.offset[a]);
                    (centre[a] - e).powi(2)
                })
                .sum::<f64>()
        };
        keys.sort_by(|a, b| distance(a).total_cmp(&distance(b)));
        for &key in &keys {
            self.rebuilding.insert(key);
        }
        self.in_flight += keys.len();
        if front {
            self.builders.queue_front(&keys);
        } else {
            self.builders.queue(keys);
        }
    }

    /// A stale resident node (an empty one just marked, or a rebuild that came back before
    /// the last edit), or one whose clutter disagrees with its zone, goes back to the
    /// workers while a plan selects it.
    pub(super) fn rebuild_if_stale(&mut self, key: NodeKey) {
        let wrong = self.is_stale(&key) || self.clutter_wrong(&key);
        if self.needed(&key) && wrong && !self.rebuilding.contains(&key) {
            self.queue_rebuilds(vec![key], true);
        }
    }

    /// A worker's rebuild of resident node `key` came back: swapped in when newer than the
    /// resident data, or as new and with the clutter its zone places where the resident data
    /// is not; built again while still stale or with the wrong clutter; freed when no plan
    /// wants the node.
    pub(super) fn rebuilt(
        &mut self,
        key: NodeKey,
        result: Result<Built, String>,
    ) -> Result<(), StreamError> {
        let built = result.map_err(StreamError::Build)?;
        if !self.needed(&key) {
            return self.free(key);
        }
        let read = self.read_at.get(&key).copied();
        let newer = read.is_none_or(|r| built.version > r);
        let wants = self.wants_clutter(&key);
        let fixes_clutter = read == Some(built.version)
            && built
                .node
                .as_ref()
                .is_some_and(|n| n.clutter().is_some() == wants)
            && self.clutter_wrong(&key);
        if newer || fixes_clutter {
            self.swap(key, built.node, built.version)?;
        }
        self.rebuild_if_stale(key);
        Ok(())
    }

    /// Queues node `key` (its entry `Loading`) to be built again, ahead of the streaming.
    pub(super) fn requeue(&mut self, key: NodeKey) {
        self.in_flight += 1;
        self.builders.queue_front(&[key]);
    }

    /// Replaces resident node `key`'s data with `built`, read at world `version`, in one
    /// step: the new data uploaded, then the old freed (see the [module docs](self)).
    fn swap(
        &mut self,
        key: NodeKey,
        built: Option<BuiltNode>,
        version: u64,
    ) -> Result<(), StreamError> {
        let Some(&Entry::Resident(old)) = self.entries.get(&key) else {
            return Ok(());
        };
        let old_bytes = old.map_or(0, |(_, b)| b);
        let old_clutter = self.clutter.contains_key(&key);
        // The same world version: the rebuild changed only the clutter.
        let same_data = self.read_at.get(&key) == Some(&version);
        let clutter = built.as_ref().and_then(|b| b.clutter());
        // The old data goes in this same step: its bytes count for the new.
        self.memory.give_back(old_bytes);
        let new = match built {
            None => None,
            Some(built) => {
                let size = built.bytes();
                let mut fits = self.memory.try_take(size);
                while !fits && self.free_unneeded()? {
                    fits = self.memory.try_take(size);
                }
                if !fits {
                    self.memory.take_anyway(old_bytes);
                    return Err(StreamError::Memory(format!(
                        "an edit grew node {:?} of level {} to {size} bytes, past the view's \
                         {} bytes of node memory ({} in use); give more memory (--memory)",
                        key.coord,
                        key.level,
                        self.memory.limit(),
                        self.memory.used()
                    )));
                }
                let data = ChunkMeshData {
                    coord: key.coord,
                    lod: key.level,
                    layers: built.layers(),
                };
                loop {
                    match self.renderer.upload_chunk(&data) {
                        Ok(handle) => break Some((handle, size)),
                        // No room in a gigabuffer or the table: what no view needs goes first.
                        Err(e) if super::out_of_room(&e) && self.free_unneeded()? => {}
                        Err(e) => {
                            self.memory.give_back(size);
                            self.memory.take_anyway(old_bytes);
                            return Err(StreamError::Upload(key, e));
                        }
                    }
                }
            }
        };
        if let Some((handle, _)) = old {
            self.renderer
                .free_chunk(handle)
                .map_err(StreamError::Renderer)?;
        }
        self.set_entry(key, Entry::Resident(new));
        self.set_clutter(key, clutter);
        if same_data && old_clutter != clutter.is_some() {
            self.counters.clutter_swaps += 1;
        }
        self.read_at.insert(key, version);
        if !self.is_stale(&key) {
            self.dirty_since.remove(&key);
        }
        self.counters.rebuilt += 1;
        if let Some((_, bytes)) = new {
            self.counters.uploaded += 1;
            self.counters.uploaded_bytes += bytes;
        }
        Ok(())
    }
}
