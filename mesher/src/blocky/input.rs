//! [`Input`]: everything the walk over a chunk's slices reads, built once per chunk.

use super::equal::EqualIds;
use super::masks::{Layouts, Slice};

/// Everything the walk reads.
pub(crate) struct Input<'a> {
    /// Padded ids, x fastest.
    pub voxels: &'a [u16],
    /// Padded edge.
    pub p: usize,
    /// Opaque masks.
    pub opaque: Layouts<'a>,
    /// Transparent masks, if any voxel is transparent.
    pub transparent: Option<Layouts<'a>>,
    /// Two different transparent ids occur.
    pub mixed_transparent: bool,
    /// Compute AO (else every corner is 3 and merging ignores AO).
    pub ao: bool,
    /// With AO off: the one id of every voxel with a face, if they share one (see `one_id`).
    pub one_id: Option<u16>,
    /// With AO off, the chunk's equal-id masks: faces are merged by them instead of keyed
    /// one by one (see `FROM_IDS`).
    pub equal: Option<&'a EqualIds>,
    /// Merge faces into greedy quads (else one quad per face).
    pub merge: bool,
    /// Per ±X direction, the rows whose lone faces `lone_x` emitted (bit z of line y); a
    /// direction's entry is read only when its `lone_x_rows` is set (else it may hold an
    /// earlier chunk's rows).
    pub handled: &'a [Slice; 2],
    /// Per ±X direction: some row is marked in `handled`.
    pub lone_x_rows: [bool; 2],
}
