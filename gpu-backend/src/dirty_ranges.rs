//! Dirty slot tracking for incrementally updated GPU tables.
//!
//! Slots marked since the last flush are kept once each; [`DirtySlots::take_ranges`] sorts them
//! and coalesces runs of adjacent slots into ranges, so a frame writes one range per run
//! instead of one per slot (and never rewrites clean slots).

use std::ops::Range;

/// The set of slots changed since the last flush.
#[derive(Clone, Debug, Default)]
pub(crate) struct DirtySlots {
    marked: Vec<bool>,
    slots: Vec<u32>,
}

impl DirtySlots {
    /// Marks `slot` as changed.
    pub(crate) fn mark(&mut self, slot: u32) {
        let i = slot as usize;
        if i >= self.marked.len() {
            self.marked.resize(i + 1, false);
        }
        if !self.marked[i] {
            self.marked[i] = true;
            self.slots.push(slot);
        }
    }

    /// Number of distinct dirty slots.
    pub(crate) fn len(&self) -> usize {
        self.slots.len()
    }

    /// The dirty slots as sorted, disjoint, non-adjacent ranges; clears the set.
    pub(crate) fn take_ranges(&mut self) -> Vec<Range<u32>> {
        self.slots.sort_unstable();
        let mut ranges: Vec<Range<u32>> = Vec::new();
        for &slot in &self.slots {
            self.marked[slot as usize] = false;
            match ranges.last_mut() {
                Some(last) if last.end == slot => last.end = slot + 1,
                _ => ranges.push(slot..slot + 1),
            }
        }
        self.slots.clear();
        ranges
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn adjacent_slots_coalesce() {
        let mut d = DirtySlots::default();
        for slot in [5, 3, 4, 10, 4, 12, 11, 0] {
            d.mark(slot);
        }
        assert_eq!(d.len(), 7, "slot 4 counted once");
        assert_eq!(d.take_ranges(), vec![0..1, 3..6, 10..13]);
        assert_eq!(d.len(), 0);
        assert!(d.take_ranges().is_empty());
        d.mark(4);
        assert_eq!(d.take_ranges(), vec![4..5], "marks reset after a take");
    }
}
