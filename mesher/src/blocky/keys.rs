//! [`Keys`]: the greedy pass's scratch for one slice (every face's key, the equal-key masks),
//! and [`key_bits`], the bits of a quad's word 1 that its key leaves out.

use voxel_core::formats::PackedQuad;

use super::direction::Facing;
use super::masks::{Front, Slice};
use super::memo::NeighbourhoodMemo;

/// Scratch of the greedy pass for one slice: the key of every face by line and bit, and per
/// line which neighbouring faces have equal keys. Only entries of faces (and of lines with
/// faces) are meaningful; everything is rewritten before it is read, so nothing is cleared
/// between slices.
///
/// On a cache line, as each of its masks is (`repr(C)` keeps them in this order: the keys
/// take 16 KiB, each mask 512 bytes), for the same reason as the masks' slices (see
/// [`Slices`](super::aligned::Slices)).
#[derive(Clone, Debug)]
#[repr(C, align(64))]
pub(crate) struct Keys {
    /// Key by line and bit.
    pub(crate) keys: [[u32; 64]; 64],
    /// `along[l]` bit `b`: the faces at `(l, b)` and `(l, b + 1)` merge and have equal keys.
    pub(crate) along: Slice,
    /// `across[l]` bit `b`: the faces at `(l, b)` and `(l + 1, b)` merge and have equal keys.
    pub(crate) across: Slice,
    /// `alone[l]` bit `b`: the face at `(l, b)` has no neighbour with an equal key.
    pub(crate) alone: Slice,
    /// The AO splits of the last lines of many lone faces (reset per direction: its entries
    /// hold AO looked up in the direction's table).
    pub(crate) memo: NeighbourhoodMemo<Front>,
    /// The key of every face of a chunk whose faces all have one id, meshed with AO
    /// off (the passes that take `ONE`): no face is keyed, this is read instead.
    pub(crate) one: u32,
}

impl Keys {
    /// Zeroed scratch.
    pub(crate) fn new() -> Self {
        Keys {
            keys: [[0; 64]; 64],
            along: [0; 64],
            across: [0; 64],
            alone: [0; 64],
            memo: NeighbourhoodMemo::new(),
            one: 0,
        }
    }

    /// The key of the face at line `l`, bit `b` (meaningful only where a face was keyed).
    #[inline(always)]
    pub(crate) fn key(&self, l: usize, b: usize) -> u32 {
        self.keys[l][b]
    }
}

/// The greedy pass's keys from the table, written face by face while keying. This and the
/// next two are the values of the const parameter `K` of its passes: where each face's key
/// comes from.
pub(crate) const FROM_TABLE: u8 = 0;
/// [`Keys::one`] for every face: a one-id chunk meshed with AO off, nothing keyed.
pub(crate) const FROM_ONE: u8 = 1;
/// The face's id, read from the voxels when a quad is written: AO off, the equal-key masks
/// taken from the chunk's equal-id masks ([`super::equal`]), nothing keyed or stored.
pub(crate) const FROM_IDS: u8 = 2;

/// The bits of `PackedQuad` word 1 that a quad of the greedy pass has besides its key: the
/// face direction and, with AO off, the 4 unoccluded corners (all 3), which the keys then
/// leave out (one operation less per face).
#[inline(always)]
pub(crate) const fn key_bits<const AO: bool>(facing: Facing) -> u32 {
    let ao = if AO {
        0
    } else {
        PackedQuad::AO_UNOCCLUDED << PackedQuad::AO_SHIFT
    };
    facing.face_bits | ao
}
