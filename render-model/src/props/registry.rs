//! [`PropRegistry`]: retained prop instances by generational handle, kept grouped into
//! batches (one per mesh primitive and material) with contiguous slot ranges, and the dirty
//! ranges a frame uploads.

use std::collections::HashMap;
use std::fmt;
use std::ops::Range;

use super::placement::PropPlacement;
use super::records::{PropBatchRecord, PropInstanceRecord};
use crate::cull::DrawIndexedArgs;

/// A mesh primitive the registry draws: where its indices are in the caller's index buffer and
/// its bounding sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PropPrimitiveDesc {
    /// Indices of the primitive.
    pub index_count: u32,
    /// First index in the index buffer.
    pub first_index: u32,
    /// Added to every index.
    pub base_vertex: i32,
    /// Bounding sphere centre, mesh space.
    pub sphere_centre: [f32; 3],
    /// Bounding sphere radius, mesh space.
    pub sphere_radius: f32,
}

/// A registered primitive.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct PrimitiveId(pub u32);

/// An instance: slot index in the handle table and the generation it was made in. A handle
/// of a deleted instance is refused ([`PropRegistryError::StaleHandle`]) even after its index
/// is reused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct PropHandle {
    /// Index in the handle table.
    pub index: u32,
    /// Generation of that entry when the handle was made.
    pub generation: u32,
}

/// Why a registry call was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PropRegistryError {
    /// The handle's instance was deleted (or never existed).
    StaleHandle {
        /// The handle.
        handle: PropHandle,
    },
    /// The primitive was not registered.
    UnknownPrimitive {
        /// The id.
        primitive: PrimitiveId,
    },
    /// The instance slots would pass `u32` range (or [`PropRegistry::MAX_SLOTS`]).
    TooManyInstances {
        /// The limit.
        limit: u32,
    },
}

impl fmt::Display for PropRegistryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PropRegistryError::StaleHandle { handle } => write!(
                f,
                "prop handle {} (generation {}) is stale: its instance was deleted",
                handle.index, handle.generation
            ),
            PropRegistryError::UnknownPrimitive { primitive } => {
                write!(f, "prop primitive {} is not registered", primitive.0)
            }
            PropRegistryError::TooManyInstances { limit } => {
                write!(f, "more than {limit} prop instance slots")
            }
        }
    }
}

impl std::error::Error for PropRegistryError {}

/// What changed since the last [`PropRegistry::take_upload`]: the slot and batch ranges to
/// copy from [`PropRegistry::instance_records`] and [`PropRegistry::batch_records`] (sorted,
/// disjoint, merged), or everything when the layout moved.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PropUpload {
    /// The layout changed (a batch grew): upload every record and resize the buffers to
    /// [`PropRegistry::slot_count`] and [`PropRegistry::batch_count`].
    pub full: bool,
    /// Instance slot ranges to upload.
    pub instances: Vec<Range<u32>>,
    /// Batch ranges to upload.
    pub batches: Vec<Range<u32>>,
}

#[derive(Clone, Debug)]
struct Batch {
    primitive: PrimitiveId,
    material: u32,
    start: u32,
    capacity: u32,
    /// Handle-table index of the instance at each position; shown ones first.
    members: Vec<u32>,
    visible: u32,
}

#[derive(Clone, Copy, Debug)]
struct Entry {
    generation: u32,
    alive: bool,
    batch: u32,
    position: u32,
    placement: PropPlacement,
}

/// Retained prop instances (see the [module docs](super)).
#[derive(Clone, Debug, Default)]
pub struct PropRegistry {
    primitives: Vec<PropPrimitiveDesc>,
    batches: Vec<Batch>,
    by_key: HashMap<(PrimitiveId, u32), u32>,
    entries: Vec<Entry>,
    free: Vec<u32>,
    instances: Vec<PropInstanceRecord>,
    batch_records: Vec<PropBatchRecord>,
    dirty_slots: Vec<u32>,
    dirty_batches: Vec<u32>,
    full: bool,
}

/// Slots a batch reserves when it is made; each growth doubles them.
const FIRST_CAPACITY: u32 = 4;

fn ranges(mut v: Vec<u32>) -> Vec<Range<u32>> {
    v.sort_unstable();
    v.dedup();
    let mut out: Vec<Range<u32>> = Vec::new();
    for x in v {
        match out.last_mut() {
            Some(r) if r.end == x => r.end = x + 1,
            _ => out.push(x..x + 1),
        }
    }
    out
}

impl PropRegistry {
    /// Most instance slots (shown, hidden and reserved) the registry lays out.
    pub const MAX_SLOTS: u32 = 1 << 28;

    /// An empty registry.
    pub fn new() -> PropRegistry {
        PropRegistry::default()
    }

    /// Registers a primitive to draw instances of.
    pub fn add_primitive(&mut self, desc: PropPrimitiveDesc) -> PrimitiveId {
        self.primitives.push(desc);
        PrimitiveId(self.primitives.len() as u32 - 1)
    }

    /// Creates an instance of `primitive` with `material`, shown or hidden.
    pub fn create(
        &mut self,
        primitive: PrimitiveId,
        material: u32,
        placement: PropPlacement,
        visible: bool,
    ) -> Result<PropHandle, PropRegistryError> {
        if primitive.0 as usize >= self.primitives.len() {
            return Err(PropRegistryError::UnknownPrimitive { primitive });
        }
        let b = self.batch_for(primitive, material)?;
        let index = match self.free.pop() {
            Some(i) => i,
            None => {
                self.entries.push(Entry {
                    generation: 0,
                    alive: false,
                    batch: 0,
                    position: 0,
                    placement,
                });
                self.entries.len() as u32 - 1
            }
        };
        let batch = &mut self.batches[b as usize];
        let position = batch.members.len() as u32;
        batch.members.push(index);
        let entry = &mut self.entries[index as usize];
        entry.alive = true;
        entry.batch = b;
        entry.position = position;
        entry.placement = placement;
        let handle = PropHandle {
            index,
            generation: entry.generation,
        };
        self.write_slot(b, position);
        if visible {
            let shown = self.batches[b as usize].visible;
            self.swap(b, position, shown);
            self.batches[b as usize].visible += 1;
        }
        self.touch_batch(b);
        Ok(handle)
    }

    /// Deletes an instance; its handle (and every copy) becomes stale.
    pub fn delete(&mut self, handle: PropHandle) -> Result<(), PropRegistryError> {
        let (b, mut p) = self.locate(handle)?;
        let batch = &self.batches[b as usize];
        if p < batch.visible {
            let last_shown = batch.visible - 1;
            self.swap(b, p, last_shown);
            p = last_shown;
            self.batches[b as usize].visible -= 1;
        }
        let last = self.batches[b as usize].members.len() as u32 - 1;
        self.swap(b, p, last);
        let batch = &mut self.batches[b as usize];
        batch.members.pop();
        let slot = batch.start + last;
        self.instances[slot as usize] = PropInstanceRecord::EMPTY;
        self.dirty_slots.push(slot);
        let entry = &mut self.entries[handle.index as usize];
        entry.alive = false;
        entry.generation = entry.generation.wrapping_add(1);
        self.free.push(handle.index);
        self.touch_batch(b);
        Ok(())
    }

    /// Moves an instance.
    pub fn set_placement(
        &mut self,
        handle: PropHandle,
        placement: PropPlacement,
    ) -> Result<(), PropRegistryError> {
        let (b, p) = self.locate(handle)?;
        self.entries[handle.index as usize].placement = placement;
        self.write_slot(b, p);
        Ok(())
    }

    /// Shows or hides an instance (a hidden one keeps its slot range, past the shown ones).
    pub fn set_visible(
        &mut self,
        handle: PropHandle,
        visible: bool,
    ) -> Result<(), PropRegistryError> {
        let (b, p) = self.locate(handle)?;
        let shown = self.batches[b as usize].visible;
        if visible && p >= shown {
            self.swap(b, p, shown);
            self.batches[b as usize].visible += 1;
            self.touch_batch(b);
        } else if !visible && p < shown {
            self.swap(b, p, shown - 1);
            self.batches[b as usize].visible -= 1;
            self.touch_batch(b);
        }
        Ok(())
    }

    /// The instance's placement, visibility and slot.
    pub fn get(&self, handle: PropHandle) -> Result<(PropPlacement, bool, u32), PropRegistryError> {
        let (b, p) = self.locate(handle)?;
        let batch = &self.batches[b as usize];
        Ok((
            self.entries[handle.index as usize].placement,
            p < batch.visible,
            batch.start + p,
        ))
    }

    /// Every instance slot's record (the instance buffer, [`slot_count`](Self::slot_count)
    /// long).
    pub fn instance_records(&self) -> &[PropInstanceRecord] {
        &self.instances
    }

    /// Every batch's record (the batch buffer), `args.instance_count` 0.
    pub fn batch_records(&self) -> &[PropBatchRecord] {
        &self.batch_records
    }

    /// Instance slots laid out (the instance and visible-list buffers' length).
    pub fn slot_count(&self) -> u32 {
        self.instances.len() as u32
    }

    /// Batches.
    pub fn batch_count(&self) -> u32 {
        self.batches.len() as u32
    }

    /// Live instances.
    pub fn len(&self) -> usize {
        self.entries.iter().filter(|e| e.alive).count()
    }

    /// True when no instance lives.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// What to upload since the last call, and clears it.
    pub fn take_upload(&mut self) -> PropUpload {
        let full = std::mem::take(&mut self.full);
        let slots = std::mem::take(&mut self.dirty_slots);
        let batches = std::mem::take(&mut self.dirty_batches);
        if full {
            return PropUpload {
                full,
                instances: std::iter::once(0..self.slot_count()).collect(),
                batches: std::iter::once(0..self.batch_count()).collect(),
            };
        }
        PropUpload {
            full,
            instances: ranges(slots),
            batches: ranges(batches),
        }
    }

    fn locate(&self, handle: PropHandle) -> Result<(u32, u32), PropRegistryError> {
        match self.entries.get(handle.index as usize) {
            Some(e) if e.alive && e.generation == handle.generation => Ok((e.batch, e.position)),
            _ => Err(PropRegistryError::StaleHandle { handle }),
        }
    }

    /// The batch of `(primitive, material)`, made or grown to hold one more instance.
    fn batch_for(
        &mut self,
        primitive: PrimitiveId,
        material: u32,
    ) -> Result<u32, PropRegistryError> {
        let b = match self.by_key.get(&(primitive, material)) {
            Some(&b) => b,
            None => {
                let b = self.batches.len() as u32;
                self.batches.push(Batch {
                    primitive,
                    material,
                    start: self.instances.len() as u32,
                    capacity: 0,
                    members: Vec::new(),
                    visible: 0,
                });
                self.by_key.insert((primitive, material), b);
                self.batch_records.push(PropBatchRecord::default());
                self.full = true;
                b
            }
        };
        let batch = &self.batches[b as usize];
        if batch.members.len() as u32 == batch.capacity {
            let capacity = (batch.capacity * 2).max(FIRST_CAPACITY);
            let total =
                self.instances.len() as u64 - u64::from(batch.capacity) + u64::from(capacity);
            if total > u64::from(Self::MAX_SLOTS) {
                return Err(PropRegistryError::TooManyInstances {
                    limit: Self::MAX_SLOTS,
                });
            }
            self.batches[b as usize].capacity = capacity;
            self.relayout();
        }
        Ok(b)
    }

    /// Lays batches out one after another, in creation order, and rewrites every record.
    fn relayout(&mut self) {
        let mut start = 0u32;
        for batch in &mut self.batches {
            batch.start = start;
            start += batch.capacity;
        }
        self.instances = vec![PropInstanceRecord::EMPTY; start as usize];
        for b in 0..self.batches.len() as u32 {
            for p in 0..self.batches[b as usize].members.len() as u32 {
                self.write_slot(b, p);
            }
            self.touch_batch(b);
        }
        self.full = true;
    }

    fn write_slot(&mut self, b: u32, p: u32) {
        let batch = &self.batches[b as usize];
        let index = batch.members[p as usize];
        let slot = batch.start + p;
        let entry = &mut self.entries[index as usize];
        entry.batch = b;
        entry.position = p;
        self.instances[slot as usize] = entry.placement.record(b);
        self.dirty_slots.push(slot);
    }

    fn swap(&mut self, b: u32, p: u32, q: u32) {
        if p == q {
            return;
        }
        self.batches[b as usize]
            .members
            .swap(p as usize, q as usize);
        self.write_slot(b, p);
        self.write_slot(b, q);
    }

    fn touch_batch(&mut self, b: u32) {
        let batch = &self.batches[b as usize];
        let desc = &self.primitives[batch.primitive.0 as usize];
        self.batch_records[b as usize] = PropBatchRecord {
            args: DrawIndexedArgs {
                index_count: desc.index_count,
                instance_count: 0,
                first_index: desc.first_index,
                base_vertex: desc.base_vertex,
                first_instance: batch.start,
            },
            visible_count: batch.visible,
            live_count: batch.members.len() as u32,
            material: batch.material,
            sphere_centre: desc.sphere_centre,
            sphere_radius: desc.sphere_radius,
        };
        self.dirty_batches.push(b);
    }
}
