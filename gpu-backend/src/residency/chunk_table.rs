//! Chunk tables on the GPU: `MeshedChunkInfo` for near chunks, `ChunkDrawInfo` for far ones.
//!
//! A [`GpuTable`] is a fixed-capacity storage buffer of records with a CPU mirror. Slots are
//! handed out by [`insert`](GpuTable::insert) (lowest free slot first, so the live slots stay
//! packed at the front and the cull pass can dispatch over [`GpuTable::slot_bound`]), changed
//! by [`set`](GpuTable::set) and given back by [`remove`](GpuTable::remove), which writes the
//! type's [`TableEntry::VACANT`] record (one the cull pass skips). Each change marks its slot
//! dirty; [`flush`](GpuTable::flush) writes only the dirty slots, coalesced into runs of
//! adjacent slots, one `queue.write_buffer` per run, and reports the bytes it wrote.
//!
//! `queue.write_buffer` (rather than the gigabuffer's staging path) suits tables: a frame
//! changes few runs, and the writes land before the next submission's commands, so the cull
//! pass of that submission reads the new records.

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::fmt;

use bytemuck::Pod;
use render_model::cull::NodeRecord;
use voxel_core::formats::{ChunkDrawInfo, ChunkKind, MeshedChunkInfo};
use wgpu::{Buffer, BufferDescriptor, BufferUsages, Device, Queue};

use crate::device::alloc::AllocError;
use crate::dirty_ranges::DirtySlots;

/// A record type a [`GpuTable`] can hold.
pub trait TableEntry: Pod + PartialEq {
    /// The record a free slot holds: one the cull pass draws nothing for.
    const VACANT: Self;
    /// Buffer label.
    const LABEL: &'static str;
}

impl TableEntry for MeshedChunkInfo {
    /// All zero: every layer count is 0.
    const VACANT: Self = MeshedChunkInfo {
        chunk: [0; 3],
        lod: 0,
        centre: [0.0; 3],
        extent: [0.0; 3],
        opaque_quads: voxel_core::formats::FaceLayerRange {
            offset: 0,
            counts: [0; 6],
        },
        transparent_quads: voxel_core::formats::FaceLayerRange {
            offset: 0,
            counts: [0; 6],
        },
        smooth_vertices: voxel_core::formats::LayerRange {
            offset: 0,
            count: 0,
        },
        clutter_units: voxel_core::formats::LayerRange {
            offset: 0,
            count: 0,
        },
    };
    const LABEL: &'static str = "near chunk table (MeshedChunkInfo)";
}

impl TableEntry for ChunkDrawInfo {
    /// `ChunkKind::Empty`, draw count 0, not resident.
    const VACANT: Self = ChunkDrawInfo {
        chunk: [0; 3],
        kind: ChunkKind::Empty as u32,
        draw_count: 0,
        gigabuffer_index: -1,
    };
    const LABEL: &'static str = "far chunk table (ChunkDrawInfo)";
}

impl TableEntry for NodeRecord {
    /// Nothing: no smooth quads, no blocks.
    const VACANT: Self = NodeRecord {
        smooth_quad_offset: 0,
        smooth_quad_count: 0,
        smooth_quad_form: 0,
        block_offset: 0,
        block_count: 0,
        mask_offset: 0,
        mask_words: 0,
        flags: 0,
        opaque_skirts: [0; 3],
        block_skirts: [0; 3],
        shell_offset: 0,
        shell_count: 0,
    };
    const LABEL: &'static str = "node table (NodeRecord)";
}

/// The near-field table.
pub type MeshedChunkTable = GpuTable<MeshedChunkInfo>;
/// The far-field table.
pub type FarChunkTable = GpuTable<ChunkDrawInfo>;

/// A slot of a [`GpuTable`]: the record's index in the buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TableSlot(pub u32);

/// Why a table operation failed.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum TableError {
    /// Every slot is in use.
    Full {
        /// The table's capacity.
        capacity: u32,
    },
    /// The slot is not in use (never inserted, or removed).
    VacantSlot(TableSlot),
    /// The capacity does not fit one buffer of the device.
    TooLarge {
        /// Slots asked for.
        capacity: u32,
        /// Bytes that would take.
        bytes: u64,
        /// The device's limit for one storage binding.
        max_bytes: u64,
    },
    /// The device refused the table's buffer.
    Alloc(AllocError),
}

impl fmt::Display for TableError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TableError::Full { capacity } => write!(f, "chunk table full ({capacity} slots)"),
            TableError::VacantSlot(slot) => write!(f, "chunk table slot {} is not in use", slot.0),
            TableError::TooLarge {
                capacity,
                bytes,
                max_bytes,
            } => write!(
                f,
                "a chunk table of {capacity} slots takes {bytes} bytes, above the binding limit \
                 of {max_bytes}"
            ),
            TableError::Alloc(e) => write!(f, "chunk table: {e}"),
        }
    }
}

impl std::error::Error for TableError {}

impl From<AllocError> for TableError {
    fn from(e: AllocError) -> Self {
        TableError::Alloc(e)
    }
}

/// What one flush wrote.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TableFlushStats {
    /// Bytes passed to `queue.write_buffer`.
    pub bytes: u64,
    /// `write_buffer` calls (coalesced runs).
    pub writes: u32,
    /// Distinct slots written.
    pub slots: u32,
}

/// A storage buffer of `T` records updated incrementally (see the [module docs](self)).
#[derive(Debug)]
pub struct GpuTable<T: TableEntry> {
    buffer: Buffer,
    records: Vec<T>,
    used: Vec<bool>,
    free: BinaryHeap<Reverse<u32>>,
    /// One past the highest slot ever handed out; slots at and above it were never used.
    bound: u32,
    live: u32,
    dirty: DirtySlots,
}

impl<T: TableEntry> GpuTable<T> {
    /// A table of `capacity` vacant slots, at most `max_binding_bytes` long (the device's
    /// `max_storage_buffer_binding_size`). The buffer starts zeroed by wgpu; slots are written
    /// once used, and [`slot_bound`](Self::slot_bound) keeps the cull pass away from slots
    /// never used.
    pub fn new(device: &Device, capacity: u32, max_binding_bytes: u64) -> Result<Self, TableError> {
        let bytes = u64::from(capacity.max(1)) * size_of::<T>() as u64;
        if bytes > max_binding_bytes {
            return Err(TableError::TooLarge {
                capacity,
                bytes,
                max_bytes: max_binding_bytes,
            });
        }
        let buffer = crate::device::alloc::create_buffer(
            device,
            &BufferDescriptor {
                label: Some(T::LABEL),
                size: bytes,
                usage: BufferUsages::STORAGE | BufferUsages::COPY_DST | BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            },
        )?;
        Ok(GpuTable {
            buffer,
            records: vec![T::VACANT; capacity as usize],
            used: vec![false; capacity as usize],
            free: BinaryHeap::new(),
            bound: 0,
            live: 0,
            dirty: DirtySlots::default(),
        })
    }

    /// Stores `record` in the lowest free slot.
    pub fn insert(&mut self, record: T) -> Result<TableSlot, TableError> {
        let slot = match self.free.pop() {
            Some(Reverse(slot)) => slot,
            None if (self.bound as usize) < self.records.len() => {
                self.bound += 1;
                self.bound - 1
            }
            None => {
                return Err(TableError::Full {
                    capacity: self.capacity(),
                });
            }
        };
        self.used[slot as usize] = true;
        self.live += 1;
        self.write(slot, record);
        Ok(TableSlot(slot))
    }

    /// Replaces the record of a used slot.
    pub fn set(&mut self, slot: TableSlot, record: T) -> Result<(), TableError> {
        self.check(slot)?;
        if self.records[slot.0 as usize] != record {
            self.write(slot.0, record);
        }
        Ok(())
    }

    /// Frees a used slot, writing [`TableEntry::VACANT`] there; returns the old record.
    pub fn remove(&mut self, slot: TableSlot) -> Result<T, TableError> {
        self.check(slot)?;
        let old = self.records[slot.0 as usize];
        self.used[slot.0 as usize] = false;
        self.live -= 1;
        self.free.push(Reverse(slot.0));
        self.write(slot.0, T::VACANT);
        Ok(old)
    }

    /// The record of a used slot.
    pub fn get(&self, slot: TableSlot) -> Option<&T> {
        let i = slot.0 as usize;
        (self.used.get(i) == Some(&true)).then(|| &self.records[i])
    }

    fn check(&self, slot: TableSlot) -> Result<(), TableError> {
        match self.used.get(slot.0 as usize) {
            Some(true) => Ok(()),
            _ => Err(TableError::VacantSlot(slot)),
        }
    }

    fn write(&mut self, slot: u32, record: T) {
        self.records[slot as usize] = record;
        self.dirty.mark(slot);
    }

    /// Writes the dirty slots to the buffer, one `write_buffer` per run of adjacent slots.
    pub fn flush(&mut self, queue: &Queue) -> TableFlushStats {
        let mut stats = TableFlushStats::default();
        let size = size_of::<T>() as u64;
        for run in self.dirty.take_ranges() {
            let data: &[u8] =
                bytemuck::cast_slice(&self.records[run.start as usize..run.end as usize]);
            queue.write_buffer(&self.buffer, u64::from(run.start) * size, data);
            stats.bytes += data.len() as u64;
            stats.writes += 1;
            stats.slots += run.end - run.start;
        }
        stats
    }

    /// Slots changed since the last flush.
    pub fn dirty_slots(&self) -> usize {
        self.dirty.len()
    }

    /// The GPU buffer (`array<T>` in WGSL).
    pub fn buffer(&self) -> &Buffer {
        &self.buffer
    }

    /// Slots in the buffer.
    pub fn capacity(&self) -> u32 {
        self.records.len() as u32
    }

    /// Used slots.
    pub fn len(&self) -> u32 {
        self.live
    }

    /// True when no slot is used.
    pub fn is_empty(&self) -> bool {
        self.live == 0
    }

    /// One past the highest slot ever used: the cull pass dispatches over `0..slot_bound()`
    /// (vacant slots inside it hold [`TableEntry::VACANT`]).
    pub fn slot_bound(&self) -> u32 {
        self.bound
    }

    /// The CPU mirror of every slot below [`slot_bound`](Self::slot_bound), as flushed or
    /// about to be.
    pub fn records(&self) -> &[T] {
        &self.records[..self.bound as usize]
    }
}
