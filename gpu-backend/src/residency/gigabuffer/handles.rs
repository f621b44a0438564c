//! Generation-checked handles: a freed handle stays invalid forever.
//!
//! Each slot carries a generation that is bumped when its entry is removed; a handle holds the
//! slot index and the generation it was issued with, so a stale handle (its chunk freed, the
//! slot perhaps reused) is detected instead of silently naming another chunk. A slot whose
//! generation would wrap is retired rather than reused.

/// Names one live entry of a [`HandleTable`]: slot index and generation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(super) struct Handle {
    index: u32,
    generation: u32,
}

impl Handle {
    /// The slot index (dense, reused after a free with a new generation).
    pub(super) fn index(self) -> u32 {
        self.index
    }

    /// The generation the handle was issued with.
    pub(super) fn generation(self) -> u32 {
        self.generation
    }
}

#[derive(Debug)]
struct Slot<T> {
    generation: u32,
    value: Option<T>,
}

/// A slot map with generation checks.
#[derive(Debug)]
pub(super) struct HandleTable<T> {
    slots: Vec<Slot<T>>,
    free: Vec<u32>,
    live: usize,
}

impl<T> Default for HandleTable<T> {
    fn default() -> Self {
        HandleTable {
            slots: Vec::new(),
            free: Vec::new(),
            live: 0,
        }
    }
}

impl<T> HandleTable<T> {
    /// Stores `value` and returns its handle, or `None` when all `u32` slot indices are used.
    pub(super) fn insert(&mut self, value: T) -> Option<Handle> {
        let index = match self.free.pop() {
            Some(index) => index,
            None => {
                let index = u32::try_from(self.slots.len()).ok()?;
                self.slots.push(Slot {
                    generation: 0,
                    value: None,
                });
                index
            }
        };
        let slot = &mut self.slots[index as usize];
        slot.value = Some(value);
        self.live += 1;
        Some(Handle {
            index,
            generation: slot.generation,
        })
    }

    /// The entry of a live handle.
    pub(super) fn get(&self, handle: Handle) -> Option<&T> {
        let slot = self.slots.get(handle.index as usize)?;
        if slot.generation == handle.generation {
            slot.value.as_ref()
        } else {
            None
        }
    }

    /// True while `handle`'s entry exists.
    pub(super) fn contains(&self, handle: Handle) -> bool {
        self.get(handle).is_some()
    }

    /// Removes and returns the entry of a live handle; `None` for a stale or foreign one.
    pub(super) fn remove(&mut self, handle: Handle) -> Option<T> {
        let slot = self.slots.get_mut(handle.index as usize)?;
        if slot.generation != handle.generation {
            return None;
        }
        let value = slot.value.take()?;
        self.live -= 1;
        // A slot whose generation cannot grow is retired: reusing it would bring an old
        // generation back.
        if let Some(next) = slot.generation.checked_add(1) {
            slot.generation = next;
            self.free.push(handle.index);
        }
        Some(value)
    }

    /// Number of live entries.
    pub(super) fn len(&self) -> usize {
        self.live
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stale_handles_are_detected_after_reuse() {
        let mut table = HandleTable::default();
        let a = table.insert("a").unwrap();
        assert_eq!(table.remove(a), Some("a"));
        let b = table.insert("b").unwrap();
        assert_eq!(a.index(), b.index(), "the slot is reused");
        assert_ne!(a, b);
        assert!(!table.contains(a));
        assert_eq!(table.get(a), None);
        assert_eq!(
            table.remove(a),
            None,
            "a stale handle cannot free the new entry"
        );
        assert_eq!(table.get(b), Some(&"b"));
        assert_eq!(table.len(), 1);
    }

    #[test]
    fn double_remove_is_refused() {
        let mut table = HandleTable::default();
        let a = table.insert(1).unwrap();
        assert_eq!(table.remove(a), Some(1));
        assert_eq!(table.remove(a), None);
        assert_eq!(table.len(), 0);
    }

    #[test]
    fn exhausted_generations_retire_the_slot() {
        let mut table = HandleTable::default();
        let a = table.insert(0).unwrap();
        table.slots[0].generation = u32::MAX;
        let a = Handle {
            generation: u32::MAX,
            ..a
        };
        assert_eq!(table.remove(a), Some(0));
        let b = table.insert(1).unwrap();
        assert_ne!(b.index(), a.index(), "a retired slot is never reused");
        assert_eq!(table.len(), 1);
    }
}
