//! Edits reaching a streamer: which of its nodes a [`DirtySet`] makes stale, the shown ones
//! rebuilt at once and swapped in one step, the others rebuilt by the workers.
//!
//! # Why no frame shows a hole or both meshes
//!
//! A swap uploads the node's new data, then frees the old, both before the next frame is
//! recorded, so that frame draws the new data and no frame draws neither or both (the frame
//! before, already submitted, keeps reading the old data: the renderer's uploads and frees
//! are ordered after it on the queue). A node the committed plan selects is rebuilt at once
//! on the calling thread's rayon pool, so the next frame shows the edit at every level the
//! plan draws. Other resident nodes are rebuilt by the workers, nearest first, ahead of the
//! streaming queue, and drawn as they are meanwhile; a plan that selects one does not commit
//! until its rebuild is swapped in, so a stale node is never newly shown. A build that may
//! have read the world before the edit (queued, running, or built and waiting to upload) is
//! marked stale and built again.

use rayon::prelude::*;
use voxel_world::DirtySet;

use super::{Entry, Streamer};
use crate::stream::StreamError;
use crate::stream::build::{BuildNode, BuiltNode};
use crate::stream::selection::NodeKey;
use render_model::resident::ChunkMeshData;

/// What one batch's dirty set did to a streamer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Invalidated {
    /// Shown nodes rebuilt and swapped in at once.
    pub swapped: usize,
    /// Resident nodes queued for the workers to rebuild.
    pub queued: usize,
    /// Builds marked stale (queued, running or waiting to upload).
    pub stale: usize,
}

impl Streamer {
    /// Makes the nodes `dirty` names stale (see the [module docs](self)): the shown ones are
    /// rebuilt and swapped before this returns, so the next frame shows the edit.
    pub fn invalidate(&mut self, dirty: &DirtySet) -> Result<Invalidated, StreamError> {
        let mut done = Invalidated::default();
        let mut now = Vec::new();
        let mut later = Vec::new();
        for world_key in dirty.all_nodes() {
            let key = NodeKey {
                level: world_key.level,
                coord: world_key.coord,
            };
            match self.entries.get(&key) {
                None => {}
                Some(Entry::Loading | Entry::Built) => {
                    done.stale += usize::from(self.stale.insert(key));
                }
                Some(Entry::Resident(_)) => {
                    if self.rebuilding.contains(&key) {
                        // Its rebuild in flight may have read the world before this batch.
                        done.stale += usize::from(self.stale.insert(key));
                    }
                    let shown = self
                        .committed
                        .as_ref()
                        .is_some_and(|c| c.keys.contains(&key));
                    if shown {
                        now.push(key);
                    } else if !self.rebuilding.contains(&key) {
                        later.push(key);
                    }
                }
            }
        }
        let source = &self.source;
        let built: Vec<(NodeKey, Result<Option<BuiltNode>, String>)> = now
            .par_iter()
            .map(|&key| (key, source.build(key)))
            .collect();
        for (key, result) in built {
            let built = result.map_err(StreamError::Build)?;
            self.swap(key, built)?;
            done.swapped += 1;
        }
        let eye = self.renderer.camera().eye(self.settings.chunk);
        let edge = f64::from(self.settings.chunk.edge());
        let distance = |key: &NodeKey| {
            let side = edge * f64::from(1u32 << key.level.min(30));
            let centre =
                [key.coord.x, key.coord.y, key.coord.z].map(|c| (f64::from(c) + 0.5) * side);
            let eye_chunk = [eye.chunk.x, eye.chunk.y, eye.chunk.z];
            (0..3)
                .map(|a| {
                    let e = f64::from(eye_chunk[a]) * edge + f64::from(eye.offset[a]);
                    (centre[a] - e).powi(2)
                })
                .sum::<f64>()
        };
        later.sort_by(|a, b| distance(a).total_cmp(&distance(b)));
        for &key in &later {
            self.rebuilding.insert(key);
        }
        self.in_flight += later.len();
        self.builders.queue_front(&later);
        done.queued = later.len();
        Ok(done)
    }

    /// A worker's rebuild of resident node `key` came back: swapped in, built again when an
    /// edit made it stale, or freed when no plan wants the node any more.
    pub(super) fn rebuilt(
        &mut self,
        key: NodeKey,
        result: Result<Option<BuiltNode>, String>,
    ) -> Result<(), StreamError> {
        let built = result.map_err(StreamError::Build)?;
        if self.stale.remove(&key) {
            self.rebuilding.insert(key);
            self.in_flight += 1;
            self.builders.queue_front(&[key]);
            return Ok(());
        }
        if !self.needed(&key) {
            return self.free(key);
        }
        self.swap(key, built)
    }

    /// Queues node `key` (its entry `Loading`) to be built again, ahead of the streaming.
    pub(super) fn requeue(&mut self, key: NodeKey) {
        self.in_flight += 1;
        self.builders.queue_front(&[key]);
    }

    /// Replaces resident node `key`'s data with `built` in one step: the new data uploaded,
    /// then the old freed (see the [module docs](self)).
    fn swap(&mut self, key: NodeKey, built: Option<BuiltNode>) -> Result<(), StreamError> {
        let Some(&Entry::Resident(old)) = self.entries.get(&key) else {
            return Ok(());
        };
        let old_bytes = old.map_or(0, |(_, b)| b);
        // The old data goes in this same step: its bytes count for the new.
        self.memory.give_back(old_bytes);
        let new = match built {
            None => None,
            Some(built) => {
                let size = built.bytes();
                let fits = self.memory.try_take(size)
                    || (self.free_unneeded()? && self.memory.try_take(size));
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
                match self.renderer.upload_chunk(&data) {
                    Ok(handle) => Some((handle, size)),
                    Err(e) => {
                        self.memory.give_back(size);
                        self.memory.take_anyway(old_bytes);
                        return Err(StreamError::Upload(key, e));
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
        self.counters.rebuilt += 1;
        if let Some((_, bytes)) = new {
            self.counters.uploaded += 1;
            self.counters.uploaded_bytes += bytes;
        }
        Ok(())
    }
}
