//! [`SliceFaces`]: the faces of one slice as the merge passes read them (ids, AO from the
//! front slice, quad words), and [`Quads`], the buffer their quads are written to.

use alloc::vec::Vec;

use voxel_core::BlockId;
use voxel_core::formats::PackedQuad;

use super::bits::masked;
use super::direction::{Axis, Facing};
use super::equal::EqualIds;
use super::keys::{FROM_IDS, FROM_ONE, Keys};
use super::masks::{Front, Slice};
use crate::MeshError;

/// The faces of one slice along axis `A`, facing one way, as the merge passes see them.
pub(crate) struct SliceFaces<'a, const A: usize> {
    /// Padded ids, x fastest.
    pub voxels: &'a [u16],
    /// Index of the slice's voxel at line 0, bit 0.
    pub base: usize,
    /// Voxel index stride of one line.
    pub stride_l: usize,
    /// Voxel index stride of one bit.
    pub stride_b: usize,
    /// Opaque lines of the front slice (for AO).
    pub front: &'a Slice,
    /// The slice's padded coordinate.
    pub n: usize,
    /// Ids below this are known (see [`check`](Self::check)): the classes' bound for the
    /// opaque layer, `u32::MAX` for the transparent one (its ids have a class).
    pub known_below: u32,
    /// The chunk is 32^3 or smaller: a line's faces lie in its first 48 bits.
    pub short: bool,
    /// The chunk's equal-id masks, when faces are merged by them (AO off; see
    /// [`FROM_IDS`]).
    pub equal: Option<&'a EqualIds>,
    /// Which of the axis's two faces these are.
    pub facing: Facing,
}

/// Where the ids of one line of faces are: a contiguous row (bits along x, the ±Y and ±Z faces)
/// or one voxel every `stride` (the ±X faces). Which one is known from the axis at compile
/// time, so the per-face loops carry no branch for it.
#[derive(Clone, Copy)]
pub(crate) enum LineIds<'a> {
    /// The 64 ids of the row, bit `b` at index `b`.
    Row(&'a [u16; 64]),
    /// Bit `b` at `voxels[start + b * stride]`.
    Strided {
        /// Padded ids.
        voxels: &'a [u16],
        /// Index of bit 0.
        start: usize,
        /// Index step of one bit.
        stride: usize,
    },
}

impl LineIds<'_> {
    /// The id at bit `b`.
    #[inline(always)]
    pub(crate) fn id(self, b: usize) -> u32 {
        match self {
            LineIds::Row(row) => u32::from(row[b]),
            LineIds::Strided {
                voxels,
                start,
                stride,
            } => u32::from(voxels.get(start + b * stride).copied().unwrap_or(0)),
        }
    }
}

/// Room for the quads of one slice (at most 62 x 62 faces), written in place and appended to
/// the output with one copy per slice, which keeps the loops free of the output vector's
/// length and capacity bookkeeping.
pub(crate) type SliceQuads = [PackedQuad; 4096];

/// Where the 1 x 1 quads of one line of faces go: word 0 of the quad at bit 1 of the line
/// (slice, line, sizes 1 x 1) and the shift of the line's bit axis in it.
///
/// Every 1 x 1 quad of the mesher is encoded by [`quad`](Self::quad) (or, in bulk, by
/// [`Quads::push_bits`], which adds to the same word); the writers differ only in where a
/// face's key comes from: the table of stored keys (`merge`), the ids and AO of the line
/// (`line_units`), or one key shared by a whole line (`push_bits`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct UnitLine {
    /// Word 0 of the quad at bit 1.
    pub first: u32,
    /// The bit axis' shift in word 0.
    pub shift: u32,
}

impl UnitLine {
    /// The 1 x 1 quad at bit `b` (at least 1) with word 1 `key` (id, AO and face bits).
    #[inline(always)]
    pub(crate) fn quad(self, b: usize, key: u32) -> PackedQuad {
        PackedQuad {
            position_size: self.first | ((b as u32).wrapping_sub(1) << self.shift),
            face_ao_block: key,
        }
    }
}

/// The most quads of a slice [`Quads::flush`] appends with a copy of constant length: most
/// slices of an 8^3 chunk hold fewer.
const FLUSHED_AT_ONCE: usize = 8;

/// Where the quads being meshed go: a buffer of one slice's quads and how many it holds,
/// appended to the output layer by [`flush`](Quads::flush), and the output layer itself, which
/// the bulk path [`push_bits`](Quads::push_bits) writes to directly.
pub(crate) struct Quads<'a> {
    /// The buffer.
    pub buf: &'a mut SliceQuads,
    /// Quads written so far.
    pub len: usize,
    /// The output, appended to with the buffer's quads once the slice is done.
    pub out: &'a mut Vec<PackedQuad>,
}

impl<'a> Quads<'a> {
    /// An empty buffer in front of `out`.
    #[inline(always)]
    pub(crate) fn new(buf: &'a mut SliceQuads, out: &'a mut Vec<PackedQuad>) -> Self {
        Quads { buf, len: 0, out }
    }

    /// Appends one quad.
    #[inline(always)]
    pub(crate) fn push(&mut self, q: PackedQuad) {
        self.buf[masked::<4096>(self.len)] = q;
        self.len += 1;
    }

    /// Appends the 1 x 1 quad of `line` with word 1 `key` for every set bit `b` (at least 1)
    /// of `bits`: the bulk path of lines whose faces share a key. It writes to the output
    /// directly, not through the buffer: on inputs made of such lines (a checkerboard) the
    /// buffer's copy is a large share of the time. One capacity check for the line, then per
    /// quad a bit scan, one add on both words at once and one 8-byte store. In
    /// `key << 32 | first`, subtracting `1 << shift` and adding `b << shift` leaves `key` in
    /// the high half: word 0 of every face fits in its 32 bits, so the sum carries back
    /// whatever the subtraction borrowed.
    #[inline(always)]
    pub(crate) fn push_bits(&mut self, mut bits: u64, line: UnitLine, key: u32) {
        let shift = line.shift;
        let base = line.quad(1, key).to_u64().wrapping_sub(1 << shift);
        let count = bits.count_ones() as usize;
        self.out.reserve(count);
        // Written in place rather than through `Vec::extend`, whose loop the compiler inlines
        // here or not (then three more instructions a quad, outside this instruction set)
        // depending on unrelated code.
        let spare = self.out.spare_capacity_mut();
        let count = count.min(spare.len());
        // A counted loop over the spare entries with the bit scan inline: `zip` with
        // `bits::ones` checks both ends per quad.
        for quad in &mut spare[..count] {
            let b = u64::from(bits.trailing_zeros());
            bits &= bits.wrapping_sub(1);
            let both = base.wrapping_add(b << shift);
            quad.write(PackedQuad::from_u64(both));
        }
        #[expect(unsafe_code, reason = "marks the quads written above as the vector's")]
        // SAFETY: `reserve` made room for `count` quads, and the loop wrote the first `count`
        // spare entries.
        unsafe {
            self.out.set_len(self.out.len() + count);
        }
    }

    /// Appends the buffered quads to the output and empties the buffer.
    ///
    /// A slice of at most [`FLUSHED_AT_ONCE`] quads is appended as that many, a copy of
    /// constant length that compiles to a few vector moves, and the output is then cut back
    /// to the quads written; only larger slices take a call to `memcpy`. Small chunks (8^3)
    /// flush a few quads a slice, and `memcpy`'s size dispatch, called for each, costs more
    /// than the copy and mispredicts (see also `masks::copy_lines`).
    #[inline(always)]
    pub(crate) fn flush(&mut self) {
        let (len, end) = (self.len.min(4096), self.out.len() + self.len);
        if len > FLUSHED_AT_ONCE {
            self.out.extend_from_slice(&self.buf[..len]);
        } else {
            self.out.extend_from_slice(&self.buf[..FLUSHED_AT_ONCE]);
            self.out.truncate(end);
        }
        self.len = 0;
    }
}

impl<const A: usize> SliceFaces<'_, A> {
    /// The front lines around line `l`.
    #[inline(always)]
    pub(crate) fn front_lines(&self, l: usize) -> Front {
        (
            self.front[masked::<64>(l - 1)],
            self.front[l],
            self.front[masked::<64>(l + 1)],
        )
    }

    /// The id of the face at line `l`, bit `b`.
    #[inline(always)]
    pub(crate) fn id(&self, l: usize, b: usize) -> u32 {
        let i = self.base + l * self.stride_l + b * self.stride_b;
        u32::from(self.voxels.get(i).copied().unwrap_or(0))
    }

    /// The ids of line `l`, as the per-face loops read them (see [`LineIds::id`]).
    #[inline(always)]
    pub(crate) fn line_ids(&self, l: usize) -> LineIds<'_> {
        let start = self.base + l * self.stride_l;
        if Axis::<A>::LAYOUT == 2 {
            return LineIds::Strided {
                voxels: self.voxels,
                start,
                stride: self.stride_b,
            };
        }
        // Past the padded edge a 64-id row holds the next row's ids, never read as faces;
        // only the array's last rows can fall short, and they hold no face either.
        const AIR: [u16; 64] = [0; 64];
        let row = self
            .voxels
            .get(start..start + 64)
            .and_then(|r| <&[u16; 64]>::try_from(r).ok())
            .unwrap_or(&AIR);
        LineIds::Row(row)
    }

    /// The 64 ids of line `l` from bit `offset` (-1 or 0) on, for the directions whose lines
    /// are rows in memory (the ±Y and ±Z faces); `None` for the ±X faces and where the row
    /// would run past the ids.
    #[inline(always)]
    pub(crate) fn row_ids(&self, l: usize, offset: isize) -> Option<&[u16; 64]> {
        if Axis::<A>::LAYOUT == 2 {
            return None;
        }
        let start = (self.base + l * self.stride_l).checked_add_signed(offset)?;
        self.voxels.get(start..start + 64)?.try_into().ok()
    }

    /// Asks the CPU to fetch the ids of line `l` (a row of 64 ids, two cache lines) ahead of
    /// their use, for the ±Y faces: their lines' rows lie a slab apart (8 KiB at 62^3), a
    /// stride the hardware prefetchers do not follow, and the output written meanwhile evicts
    /// them from the nearer caches. A no-op for the other directions and off x86-64.
    #[inline(always)]
    pub(crate) fn prefetch_line(&self, l: usize) {
        if Axis::<A>::LAYOUT != 1 {
            return;
        }
        #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
        {
            let start = self.base + l * self.stride_l;
            for i in [start, start + 32] {
                if let Some(id) = self.voxels.get(i) {
                    safe_arch::prefetch_t0(id);
                }
            }
        }
        #[cfg(not(all(target_arch = "x86_64", target_feature = "sse")))]
        let _ = l;
    }

    /// The key of the face at line `l`, bit `b`: its id and, with `AO`, its 4 corner values.
    #[inline(always)]
    pub(crate) fn key<const AO: bool>(&self, l: usize, b: usize) -> u32 {
        self.id(l, b) << PackedQuad::BLOCK_SHIFT
            | self.ao::<AO>(self.front_lines(l), b) << PackedQuad::AO_SHIFT
    }

    /// The key of the face at line `l`, bit `b`, from where `K` says (see
    /// [`FROM_TABLE`](super::keys::FROM_TABLE)): the stored key, the one key of a one-id
    /// chunk, or the face's id (AO off).
    #[inline(always)]
    pub(crate) fn key_of<const K: u8>(&self, keys: &Keys, l: usize, b: usize) -> u32 {
        match K {
            FROM_ONE => keys.one,
            FROM_IDS => self.id(l, b) << PackedQuad::BLOCK_SHIFT,
            _ => keys.key(l, b),
        }
    }

    /// Line `l` of the slice's equal-id `along` mask (see [`EqualIds::along`]); 0 without
    /// masks.
    #[inline(always)]
    pub(crate) fn equal_along(&self, l: usize) -> u64 {
        self.equal
            .map_or(0, |e| e.along(Axis::<A>::LAYOUT, self.n, l))
    }

    /// Line `l` of the slice's equal-id `across` mask (see [`EqualIds::across`]); 0 without
    /// masks.
    #[inline(always)]
    pub(crate) fn equal_across(&self, l: usize) -> u64 {
        self.equal
            .map_or(0, |e| e.across(Axis::<A>::LAYOUT, self.n, l))
    }

    /// The packed AO byte of the face at bit `b` of a line with front lines `front` (all 3s
    /// without `AO`): 9 bits of the front lines index the direction's table.
    #[inline(always)]
    pub(crate) fn ao<const AO: bool>(&self, (f0, f1, f2): Front, b: usize) -> u32 {
        if !AO {
            return PackedQuad::AO_UNOCCLUDED;
        }
        let s = masked::<64>(b - 1);
        let code = ((f0 >> s) & 7) | ((f1 >> s) & 7) << 3 | ((f2 >> s) & 7) << 6;
        u32::from(self.facing.ao_table[code as usize])
    }

    /// Word 0 of a quad at line `l`, bit `b`, spanning `lines` lines and `bits` bits.
    ///
    /// Each field holds its value minus one (all at least 1) in bits of its own, so the
    /// fields add without carries: the slice's field and the four ones taken off are one
    /// constant per slice, and each other field costs a shift and an add.
    #[inline(always)]
    pub(crate) fn position_size(&self, l: usize, b: usize, lines: usize, bits: usize) -> u32 {
        let ones = (1 << Axis::<A>::SHIFT_L)
            + (1 << Axis::<A>::SHIFT_B)
            + (1 << Axis::<A>::SIZE_SHIFT_L)
            + (1 << Axis::<A>::SIZE_SHIFT_B);
        let slice = (self.n as u32).wrapping_sub(1) << Axis::<A>::SHIFT_N;
        slice
            .wrapping_sub(ones)
            .wrapping_add((l as u32) << Axis::<A>::SHIFT_L)
            .wrapping_add((b as u32) << Axis::<A>::SHIFT_B)
            .wrapping_add((lines as u32) << Axis::<A>::SIZE_SHIFT_L)
            .wrapping_add((bits as u32) << Axis::<A>::SIZE_SHIFT_B)
    }

    /// Where the 1 x 1 quads of line `l` go.
    #[inline(always)]
    pub(crate) fn unit_line(&self, l: usize) -> UnitLine {
        UnitLine {
            first: self.position_size(l, 1, 1, 1),
            shift: Axis::<A>::SHIFT_B,
        }
    }

    /// Fails if the id of `key` is unknown (not below [`known_below`](Self::known_below)),
    /// naming it and the face's position.
    #[inline(always)]
    pub(crate) fn check(&self, key: u32, l: usize, b: usize) -> Result<(), MeshError> {
        let id = key >> PackedQuad::BLOCK_SHIFT;
        if id < self.known_below {
            return Ok(());
        }
        let mut position = [0u32; 3];
        let [axis_n, axis_l, axis_b] = Axis::<A>::AXES;
        position[axis_n as usize] = self.n as u32;
        position[axis_l as usize] = l as u32;
        position[axis_b as usize] = b as u32;
        Err(MeshError::UnknownBlock {
            id: BlockId(id as u16),
            position,
        })
    }

    /// Pushes the quad at line `l`, bit `b`, spanning `lines` lines and `bits` bits, with word 1
    /// `word` (its id was checked already).
    #[inline(always)]
    pub(crate) fn push(
        &self,
        out: &mut Quads<'_>,
        (l, b, lines, bits): (usize, usize, usize, usize),
        word: u32,
    ) {
        out.push(PackedQuad {
            position_size: self.position_size(l, b, lines, bits),
            face_ao_block: word,
        });
    }
}

#[cfg(test)]
mod tests {
    use alloc::vec;

    use super::*;

    /// The one-add trick at its edges, against the one encoder of 1 x 1 quads: word 0 of
    /// bit 1 is 0 (the subtraction borrows from the key), the highest key and word bits, and
    /// both bit shifts the bulk paths use.
    #[test]
    fn push_bits_keeps_key_and_word_apart() {
        let word0_bits = (1 << (PackedQuad::HEIGHT_SHIFT + PackedQuad::FIELD_BITS)) - 1;
        let cases = [
            (0u32, PackedQuad::X_SHIFT, 0u32),
            (0, PackedQuad::Y_SHIFT, 0x0123_4567),
            (
                word0_bits & !(PackedQuad::FIELD_MASK << PackedQuad::X_SHIFT),
                PackedQuad::X_SHIFT,
                u32::MAX,
            ),
            (
                PackedQuad::FIELD_MASK << PackedQuad::Z_SHIFT,
                PackedQuad::Y_SHIFT,
                1 << PackedQuad::BLOCK_SHIFT,
            ),
        ];
        for (first, shift, key) in cases {
            let bits = 0x8000_0000_0000_0002u64 | 0x0F0F << 20;
            let mut buf = [PackedQuad::default(); 4096];
            let mut out = vec![PackedQuad::default()];
            let mut quads = Quads::new(&mut buf, &mut out);
            quads.push_bits(bits, UnitLine { first, shift }, key);
            let want: Vec<PackedQuad> = (1..64u32)
                .filter(|b| bits >> b & 1 == 1)
                .map(|b| UnitLine { first, shift }.quad(b as usize, key))
                .collect();
            assert_eq!(out[1..], want[..], "first {first:#x} shift {shift}");
        }
    }
}
