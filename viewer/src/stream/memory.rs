//! [`NodeMemory`]: the node-data bytes a view may keep on the GPU, shared by every streamer of
//! the view, so a replacement streamer loading behind the drawing one (see `crate::view`)
//! gets what the drawing one leaves, not a second full budget.
//!
//! It counts what the streamers upload ([`BuiltNode::bytes`](super::build::BuiltNode::bytes),
//! every gigabuffer kind), taken before each upload and given back when the node is freed or
//! its streamer dropped. The gigabuffer of each renderer still has its own ceilings per kind
//! (`sizing.rs`); this is the one total the view as a whole keeps to.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// A shared count of node bytes against one limit (cloning shares it).
#[derive(Clone, Debug)]
pub struct NodeMemory {
    limit: u64,
    used: Arc<AtomicU64>,
}

impl NodeMemory {
    /// `limit` bytes, none used.
    pub fn new(limit: u64) -> NodeMemory {
        NodeMemory {
            limit,
            used: Arc::default(),
        }
    }

    /// The limit, bytes.
    pub fn limit(&self) -> u64 {
        self.limit
    }

    /// Bytes in use by every streamer sharing it.
    pub fn used(&self) -> u64 {
        self.used.load(Ordering::Acquire)
    }

    /// Takes `bytes` if they fit under the limit with what is used; false (and nothing taken)
    /// when they do not.
    pub fn try_take(&self, bytes: u64) -> bool {
        self.used
            .fetch_update(Ordering::AcqRel, Ordering::Acquire, |used| {
                used.checked_add(bytes).filter(|&total| total <= self.limit)
            })
            .is_ok()
    }

    /// Takes back `bytes` just given back, past the limit if need be: for a swap that gave
    /// a node's bytes back for its new data and then keeps the old data after all.
    pub(super) fn take_anyway(&self, bytes: u64) {
        self.used.fetch_add(bytes, Ordering::AcqRel);
    }

    /// Gives back `bytes` taken before.
    pub fn give_back(&self, bytes: u64) {
        let before = self.used.fetch_sub(bytes, Ordering::AcqRel);
        // Only bytes taken are given back, each once: anything else is a streamer's bug.
        debug_assert!(bytes <= before, "gave back {bytes} of {before} bytes");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn takes_only_what_fits_and_shares_the_count() {
        let memory = NodeMemory::new(100);
        let other = memory.clone();
        assert!(memory.try_take(60));
        assert!(!other.try_take(41), "60 + 41 is over 100");
        assert_eq!(other.used(), 60, "a refusal takes nothing");
        assert!(other.try_take(40));
        assert!(!memory.try_take(1));
        memory.give_back(60);
        assert_eq!(other.used(), 40);
        assert!(!memory.try_take(u64::MAX), "no overflow");
        assert!(memory.try_take(60));
        assert_eq!(memory.used(), 100);
    }
}
