//! Opaque and transparent bit masks of a padded chunk, in the three layouts the face directions
//! read, and the uniform-chunk early exit.
//!
//! # Layouts
//!
//! A slice is the layer of voxels at one padded coordinate `n` along a face's normal axis. Each
//! layout stores, per slice, 64 *lines* of one `u64` each (lines at and past the padded edge `p`
//! are zero), so the faces of a slice are `cur[l] & !front[l]` line by line, and neighbouring
//! voxels are neighbouring bits or lines:
//!
//! | layout | slices | lines | bits | built from the occupancy columns by |
//! | ------ | ------ | ----- | ---- | ----------------------------------- |
//! | `A`    | z      | y     | x    | nothing for 62^3 chunks: it *is* the column order (`y + 64 * z`) |
//! | `B`    | y      | z     | x    | a word transpose (`B[y][z] = A[z][y]`) |
//! | `C`    | x      | y     | z    | a 64 x 64 bit transpose of each slice of `B` (`C[x][y]` bit `z` is `B[y][z]` bit `x`) |
//!
//! # Opaque and transparent masks
//!
//! When the palette has no transparent material ([`BlockClasses::any_transparent`] is false),
//! every non-air voxel is opaque (or unknown, which is an error once it shows a face), so the
//! opaque mask in layout `A` is the [`PaddedChunk`](voxel_core::PaddedChunk)'s occupancy columns
//! themselves: nothing is scanned.
//!
//! When it has some, the transparent mask is derived from the ids. With at most
//! [`FEW_TRANSPARENT`] transparent ids, a run of ids is first tested for containing any of them
//! at all (a SIMD compare-and-OR, no bit packing), and only runs that do are turned into bit
//! masks: each row of 64 ids whose occupancy is not zero in a 62^3 chunk, each slab of `p * p`
//! ids (contiguous) in a smaller one, whose rows are then cut out of the slab's mask (see
//! [`short_transparent`]). With more transparent ids, the class table is read for the occupied
//! voxels only. The opaque mask is then `occupancy & !transparent`. The
//! derivation also records whether two *different* transparent ids occur, since only then can
//! two transparent voxels show faces to each other.

use voxel_core::BlockId;

use super::aligned::Slices;
use super::bits::{masked, nonzero_lines, occupied_rows, ones, row_contains, row_equal};
use crate::BlockClasses;

/// Up to this many transparent ids in the palette, rows are classified with SIMD compares.
pub(crate) const FEW_TRANSPARENT: usize = 4;

pub(crate) use super::aligned::Slice;

/// The opaque lines of the front slice around line `l`.
pub(crate) type Front = (u64, u64, u64);

/// What the column masks say about a chunk before any face is looked at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Content {
    /// Every padded voxel is air: no faces.
    Empty,
    /// Every padded voxel is opaque: no faces.
    Buried,
    /// Anything else: mesh it.
    Surface,
}

/// The masks of one padded chunk in layouts `A`, `B`, `C` (see the [module docs](self)).
/// Scratch that keeps its capacity between chunks.
#[derive(Clone, Debug, Default)]
pub(crate) struct Masks {
    /// Padded edge of the chunk the masks were built for.
    pub p: usize,
    /// Opaque layout `A`; unused when the input columns are the opaque mask.
    opaque_a: Slices,
    opaque_b: Slices,
    opaque_c: Slices,
    trans_a: Slices,
    trans_b: Slices,
    trans_c: Slices,
    /// Bit `y`: line `y` of some slice of `opaque_c` may be non-zero (see [`bit_transpose`]).
    opaque_c_lines: u64,
    /// The same for `trans_c`.
    trans_c_lines: u64,
    /// Bit `y`: slice `y` of `opaque_b` may be non-zero (see [`word_transpose`]).
    opaque_b_slices: u64,
    /// The same for `trans_b`.
    trans_b_slices: u64,
    /// The input columns, viewed as 64-line slices, are the opaque mask.
    opaque_is_columns: bool,
    /// Some voxel is transparent.
    pub has_transparent: bool,
    /// Two different transparent ids occur, so transparent voxels can face each other.
    pub mixed_transparent: bool,
    /// [`Layouts::occupied`] of the opaque and the transparent mask.
    occupied: [[u64; 3]; 2],
}

/// Three layouts of one mask, as the directions read them.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Layouts<'a> {
    /// Layout A, B and C, each `p` slices.
    pub by: [&'a [Slice]; 3],
    /// Per layout, bit `n` set iff slice `n` has a set bit: slices without one show no face.
    pub occupied: [u64; 3],
}

/// Which slices of each layout have a set bit, from layout A alone: slab `z` of A (layout A's
/// slice), line `y` of any slab (layout B's slice `y`), bit `x` of any line (layout C's slice).
///
/// Reads lines `0..p` of each slab only: the rest are zero, and in a short chunk nothing
/// writes them, so reading them would fetch cold cache lines (3 a slab at 32^3) for nothing.
#[inline(always)]
fn occupied_slices(a: &[Slice], p: usize) -> [u64; 3] {
    let mut any_line = [0u64; 64];
    let mut slabs = 0u64;
    for (z, slab) in a.iter().enumerate() {
        let mut any = 0u64;
        for (acc, &line) in any_line.iter_mut().zip(&slab[..p]) {
            *acc |= line;
            any |= line;
        }
        slabs |= u64::from(any != 0) << (z & 63);
    }
    let bits = any_line.iter().fold(0, |acc, &line| acc | line);
    [slabs, nonzero_lines(&any_line), bits]
}

/// Layout A of the transparent mask of a 62^3 chunk (padded edge 64, at most
/// [`FEW_TRANSPARENT`] transparent `ids`) into `trans_a`, row by row: a row whose occupancy is
/// not zero is tested for each id with a compare-and-OR ([`row_contains`]), and only the ids
/// it holds are turned into bits. Returns which of the ids occur (bit `k` for `ids[k]`).
#[inline(always)]
fn row_transparent(voxels: &[u16], columns: &[u64], ids: &[BlockId], trans_a: &mut [Slice]) -> u32 {
    let mut seen = 0u32;
    let slabs = voxels.as_chunks::<64>().0.chunks_exact(64);
    for ((rows, cols), lines) in slabs.zip(columns.chunks_exact(64)).zip(trans_a) {
        for ((row, &occ), line) in rows.iter().zip(cols).zip(lines) {
            let mut t = 0;
            if occ != 0 {
                for (k, id) in ids.iter().enumerate() {
                    if row_contains(row, id.0) {
                        seen |= 1 << k;
                        t |= row_equal(row, id.0);
                    }
                }
            }
            *line = t;
        }
    }
    seen
}

/// Words of a slab's flat id-match mask in [`short_transparent`]: a 34^3 chunk's slab of
/// 34 x 34 ids takes 18 whole words and a tail word, and the last row's bits may end in the
/// tail word, so the word after it (never written) reads as zero.
const SLAB_WORDS: usize = 20;

/// Layout A of the transparent mask of a chunk of padded edge `P` below 64 (at most
/// [`FEW_TRANSPARENT`] transparent `ids`; `columns`, its occupancy) into `trans_a`'s lines
/// `0..P`; returns which of the ids occur (bit `k` for `ids[k]`).
///
/// Slab by slab, since a slab's `P * P` ids are contiguous: a slab that holds none of an id
/// costs one compare-and-OR over its rows from the first non-air one to the last
/// ([`row_contains`]). Otherwise its ids are matched 64 at a time into a flat mask (bit `i`
/// of word `i / 64` for id `i` of the slab) and each row's `P` bits, which start at bit
/// `P * y`, are cut out of it. Row by row, a 34-id row would cost two scans of an odd length
/// each, several times the work of its share of the flat match.
#[inline(always)]
fn short_transparent<const P: usize>(
    voxels: &[u16],
    columns: &[u64],
    ids: &[BlockId],
    trans_a: &mut [Slice],
) -> u32 {
    debug_assert!(P < 64 && P * P <= 64 * (SLAB_WORDS - 1));
    let row_bits = (1u64 << P) - 1;
    let mut flat = [0u64; SLAB_WORDS];
    let mut seen = 0u32;
    let slabs = voxels.chunks_exact(P * P).zip(columns.chunks_exact(P));
    for ((slab, rows), lines) in slabs.zip(trans_a.iter_mut()) {
        lines[..P].fill(0);
        // Only the rows from the slab's first non-air row to its last can hold the ids: the
        // others are not read (the sky above a terrain, the air around a model).
        let Some(rows) = occupied_rows(rows) else {
            continue;
        };
        let solid = slab.get(rows.start * P..rows.end * P).unwrap_or(slab);
        for (k, id) in ids.iter().enumerate() {
            if !row_contains(solid, id.0) {
                continue;
            }
            seen |= 1 << k;
            let (whole, tail) = slab.as_chunks::<64>();
            for (word, ids) in flat.iter_mut().zip(whole) {
                *word = row_equal(ids, id.0);
            }
            flat[whole.len()] = row_equal(tail, id.0);
            for (y, line) in lines[..P].iter_mut().enumerate() {
                let bit = P * y;
                let pair = u128::from(flat[bit / 64]) | u128::from(flat[bit / 64 + 1]) << 64;
                *line |= (pair >> (bit % 64)) as u64 & row_bits;
            }
        }
    }
    seen
}

impl Masks {
    /// [`build_with`](Self::build_with) the portable transpose, for the tests.
    #[cfg(test)]
    pub(super) fn build(
        &mut self,
        p: usize,
        voxels: &[u16],
        columns: &[u64],
        classes: &BlockClasses,
    ) -> Content {
        self.build_with(p, voxels, columns, classes, |m, _| {
            super::bits::transpose64(m)
        })
    }

    /// Builds the masks of a padded chunk of edge `p` from its ids (x fastest) and occupancy
    /// columns (index `y + p * z`), with the bit transpose `transpose` (`transpose(m, rows)`:
    /// the 64 x 64 transpose of `m`, whose words from `rows` on are zero), the entry's copy
    /// for its instruction set. Returns [`Content::Empty`] or [`Content::Buried`] without
    /// building anything when the columns already say there is no face.
    #[inline(always)]
    pub(super) fn build_with(
        &mut self,
        p: usize,
        voxels: &[u16],
        columns: &[u64],
        classes: &BlockClasses,
        transpose: impl Fn(&mut [u64; 64], usize) + Copy,
    ) -> Content {
        self.p = p;
        let full_row = u64::MAX >> (64 - p);
        let (any, all) = columns
            .iter()
            .fold((0u64, u64::MAX), |(any, all), &c| (any | c, all & c));
        if any == 0 {
            return Content::Empty;
        }

        self.has_transparent = false;
        self.mixed_transparent = false;
        if classes.any_transparent() {
            self.derive_transparent(p, voxels, columns, classes);
        }
        if all == full_row && !self.has_transparent {
            return Content::Buried;
        }

        // Layout A of the opaque mask: the columns themselves when possible.
        self.opaque_is_columns = p == 64 && !self.has_transparent;
        if !self.opaque_is_columns {
            self.opaque_a.resize(p);
            let slabs = columns.chunks_exact(p).zip(self.opaque_a.iter_mut());
            if self.has_transparent {
                for ((slab, out), t) in slabs.zip(self.trans_a.iter()) {
                    for ((o, &c), &t) in out.iter_mut().zip(slab).zip(t) {
                        *o = c & !t;
                    }
                }
            } else {
                for (slab, out) in slabs {
                    copy_lines(out, slab, p);
                }
            }
        }
        let opaque_a: &[Slice] = if self.opaque_is_columns {
            bytemuck::cast_slice(columns)
        } else {
            &self.opaque_a
        };
        self.occupied[0] = occupied_slices(opaque_a, p);
        let b_slices = self.occupied[0][1];
        word_transpose(
            p,
            opaque_a,
            &mut self.opaque_b,
            b_slices,
            &mut self.opaque_b_slices,
        );
        bit_transpose(
            p,
            &self.opaque_b,
            b_slices,
            &mut self.opaque_c,
            &mut self.opaque_c_lines,
            transpose,
        );
        if self.has_transparent {
            self.occupied[1] = occupied_slices(&self.trans_a, p);
            let b_slices = self.occupied[1][1];
            word_transpose(
                p,
                &self.trans_a,
                &mut self.trans_b,
                b_slices,
                &mut self.trans_b_slices,
            );
            let (b, c, lines) = (&self.trans_b, &mut self.trans_c, &mut self.trans_c_lines);
            bit_transpose(p, b, b_slices, c, lines, transpose);
        }
        Content::Surface
    }

    /// Fills `trans_a` (layout A) and the two flags.
    #[inline(always)]
    fn derive_transparent(
        &mut self,
        p: usize,
        voxels: &[u16],
        columns: &[u64],
        classes: &BlockClasses,
    ) {
        let ids = classes.transparent_ids();
        self.trans_a.resize(p);
        if ids.len() <= FEW_TRANSPARENT {
            let seen = match p {
                64 => row_transparent(voxels, columns, ids, &mut self.trans_a),
                34 => short_transparent::<34>(voxels, columns, ids, &mut self.trans_a),
                18 => short_transparent::<18>(voxels, columns, ids, &mut self.trans_a),
                _ => short_transparent::<10>(voxels, columns, ids, &mut self.trans_a),
            };
            self.has_transparent = seen != 0;
            self.mixed_transparent = seen.count_ones() > 1;
            return;
        }
        // Many transparent ids: the class table, for the occupied voxels. The first
        // transparent id seen, to tell whether two different ones occur.
        let mut first: Option<u16> = None;
        let slabs = voxels.chunks_exact(p * p).zip(columns.chunks_exact(p));
        for ((slab, cols), out) in slabs.zip(self.trans_a.iter_mut()) {
            for ((row, &occ), t_out) in slab.chunks_exact(p).zip(cols).zip(out.iter_mut()) {
                let mut t = 0;
                for x in ones(occ) {
                    let id = row.get(x).copied().unwrap_or(0);
                    if classes.is_transparent(BlockId(id)) {
                        t |= 1 << x;
                        match first {
                            None => first = Some(id),
                            Some(f) if f != id => self.mixed_transparent = true,
                            Some(_) => {}
                        }
                    }
                }
                *t_out = t;
            }
        }
        self.has_transparent = first.is_some();
    }

    /// The opaque mask in all three layouts; `columns` are the input columns (layout A when the
    /// chunk is 62^3 and has no transparent voxel).
    pub(super) fn opaque<'a>(&'a self, columns: &'a [u64]) -> Layouts<'a> {
        let a: &[Slice] = if self.opaque_is_columns {
            bytemuck::cast_slice(columns)
        } else {
            &self.opaque_a
        };
        Layouts {
            by: [a, &self.opaque_b, &self.opaque_c],
            occupied: self.occupied[0],
        }
    }

    /// The transparent mask in all three layouts, if any voxel is transparent.
    pub(super) fn transparent(&self) -> Option<Layouts<'_>> {
        self.has_transparent.then_some(Layouts {
            by: [&self.trans_a, &self.trans_b, &self.trans_c],
            occupied: self.occupied[1],
        })
    }
}

/// Copies lines `0..p` of `from` into `to`. For the padded edges below 64 the length is a
/// constant, so the copy is a few vector moves in place of a call to `memcpy`, whose size
/// dispatch costs more than such a short copy (small chunks make many of them). Each arm
/// copies word by word ([`copy_words`]): with `copy_from_slice` in every arm, the compiler
/// merges the arms into one copy of variable length, which is the `memcpy` call again.
#[inline(always)]
fn copy_lines(to: &mut [u64], from: &[u64], p: usize) {
    match p {
        10 => copy_words::<10>(to, from),
        18 => copy_words::<18>(to, from),
        34 => copy_words::<34>(to, from),
        _ => to[..p].copy_from_slice(&from[..p]),
    }
}

/// Copies the first `N` words of `from` into `to`, word by word (see [`copy_lines`]).
#[inline(always)]
fn copy_words<const N: usize>(to: &mut [u64], from: &[u64]) {
    let (Some(to), Some(from)) = (to.first_chunk_mut::<N>(), from.first_chunk::<N>()) else {
        unreachable!("a slice holds the padded edge's lines");
    };
    for (t, &f) in to.iter_mut().zip(from) {
        *t = f;
    }
}

/// Layout B from layout A: `out[y][z] = a[z][y]`, where `nonempty` (bit `y`: line `y` of
/// some slab of `a` is not zero, see [`occupied_slices`]) says which slices of `out` have a
/// set bit.
///
/// The empty ones are not gathered: they are zeroed, and not even that when `written` (bit
/// `y`: slice `y` may hold a set bit, kept across chunks) says they are zero already, as the
/// slices above a terrain's surface and most of a water mask's are from one chunk to the
/// next. Left unread and unwritten, their cache lines stay out of the cache.
#[inline(always)]
fn word_transpose(p: usize, a: &[Slice], out: &mut Slices, nonempty: u64, written: &mut u64) {
    if out.len() != p {
        // Resized: slices kept from another size are not tracked.
        *written = u64::MAX;
    }
    out.resize(p);
    // Slice by slice of the output: `p` strided reads, one contiguous write.
    for (y, slot) in out.iter_mut().enumerate() {
        let bit = 1u64 << (y & 63);
        if nonempty & bit != 0 {
            for (word, slab) in slot.iter_mut().zip(a) {
                *word = slab[masked::<64>(y)];
            }
        } else if *written & bit != 0 {
            slot[..p].fill(0);
        }
    }
    *written = nonempty;
}

/// Layout C from layout B: for each slice `y`, transpose the bit matrix (lines z, bits x) into
/// lines x, bits z, stored at `out[x][y]`. `nonempty` (bit `y`: slice `y` of `b` has a set
/// bit) is the one [`word_transpose`] took.
///
/// Writing line `y` of all 64 slices of `out` is 64 stores a slice apart; for an empty slice
/// of `b` they store zeros, which a scratch reused from the last chunk often holds already
/// (terrain leaves the slices above its surface empty, water most of the transparent mask).
/// So `lines` remembers which lines `y` may hold a set bit, and an empty slice `y` whose line
/// is known clear costs nothing.
#[inline(always)]
fn bit_transpose(
    p: usize,
    b: &[Slice],
    nonempty: u64,
    out: &mut Slices,
    lines: &mut u64,
    transpose: impl Fn(&mut [u64; 64], usize),
) {
    if out.len() != p {
        // Resized: lines of slices kept from another size are not tracked.
        *lines = u64::MAX;
    }
    out.resize(p);
    const ZERO: Slice = [0; 64];
    // The matrix to transpose: only its first `p` lines are copied in, so the rest must be
    // zero, and stay zero, as a transpose of bits `0..p` leaves them.
    let mut work: Slice = [0; 64];
    for (y, slice) in b.iter().enumerate() {
        let bit = 1u64 << (y & 63);
        let empty = nonempty & bit == 0;
        if empty && *lines & bit == 0 {
            continue;
        }
        let m = if empty {
            *lines &= !bit;
            &ZERO
        } else {
            copy_lines(&mut work, slice, p);
            transpose(&mut work, p);
            debug_assert!(work[p..].iter().all(|&line| line == 0));
            *lines |= bit;
            &work
        };
        for (x, slot) in out.iter_mut().enumerate() {
            slot[masked::<64>(y)] = m[masked::<64>(x)];
        }
    }
}

#[cfg(test)]
mod tests {
    use alloc::vec;
    use alloc::vec::Vec;

    use voxel_core::{Material, MaterialClass, MaterialPalette};

    use super::*;

    /// A palette of 2 opaque ids (1, 2) and `transparent` transparent ones (3, 4, ...).
    fn classes(transparent: usize) -> BlockClasses {
        let mut palette = MaterialPalette::new();
        for _ in 0..2 {
            palette.push(Material::opaque(90, 90, 90)).unwrap();
        }
        for _ in 0..transparent {
            let glass = Material::opaque(200, 220, 230).with_class(MaterialClass::Transparent);
            palette.push(glass).unwrap();
        }
        BlockClasses::from_palette(&palette)
    }

    /// Layout A of the transparent and opaque masks and the two flags, against each voxel's
    /// class, at every edge, for palettes of 1 to [`FEW_TRANSPARENT`] transparent ids (the
    /// slab-wise path below 64, the row-wise one at 64) and one more (the class-table path).
    /// Transparent ids sit at the ends of slabs and of the flat masks' words; one chunk holds
    /// only the last transparent id, one holds two different ones.
    #[test]
    fn transparent_and_opaque_masks_follow_each_voxel_s_class() {
        let mut rng = voxel_scene::rng::Rng::new(11);
        let mut masks = Masks::default();
        for p in [10, 18, 34, 64, 34] {
            for transparent in [1, 2, FEW_TRANSPARENT, FEW_TRANSPARENT + 1] {
                let classes = classes(transparent);
                let last = 2 + transparent as u16;
                for case in 0..3 {
                    let mut voxels: Vec<u16> = (0..p * p * p)
                        .map(|_| match (rng.below(3), case) {
                            (0, _) => 0,
                            (1, _) => 1 + rng.below(2) as u16,
                            (_, 0) => 3 + rng.below(transparent as u64) as u16,
                            (_, _) => 2,
                        })
                        .collect();
                    if case >= 1 {
                        // Only the last transparent id, at the first and last voxel of each
                        // slab and at a word boundary of the first slab.
                        for z in 0..p {
                            voxels[z * p * p] = last;
                            voxels[(z + 1) * p * p - 1] = last;
                        }
                        voxels[64] = last;
                    }
                    if case == 2 {
                        voxels[p * p * p / 2] = 3;
                    }
                    check(&mut masks, p, &voxels, &classes);
                    let want_mixed = match case {
                        0 => transparent > 1,
                        1 => false,
                        _ => last != 3,
                    };
                    assert_eq!(masks.mixed_transparent, want_mixed, "edge {p}, case {case}");
                }
            }
        }
    }

    /// Layouts B and C are layout A transposed, bit by bit, and the occupied slices are those
    /// with a set bit, for a run of chunks built with one scratch: chunks with air above some
    /// row `y` (empty B slices, skipped) follow fuller ones and the other way round, and the
    /// size changes, so a slice skipped as empty must not keep an earlier chunk's bits.
    #[test]
    fn layouts_b_and_c_transpose_layout_a_across_chunks_on_one_scratch() {
        let mut rng = voxel_scene::rng::Rng::new(5);
        let mut masks = Masks::default();
        let classes = classes(1);
        let runs = [
            (34, 34),
            (34, 9),
            (34, 30),
            (34, 2),
            (64, 20),
            (64, 64),
            (64, 3),
        ];
        for (p, top) in runs
            .into_iter()
            .chain([(18, 18), (18, 4), (34, 12), (34, 34)])
        {
            let voxels: Vec<u16> = (0..p * p * p)
                .map(|i| {
                    if (i / p) % p >= top {
                        0
                    } else {
                        rng.below(4) as u16
                    }
                })
                .collect();
            let columns: Vec<u64> = voxels
                .chunks_exact(p)
                .map(|row| (0..p).fold(0u64, |m, x| m | u64::from(row[x] != 0) << x))
                .collect();
            assert_eq!(
                masks.build(p, &voxels, &columns, &classes),
                Content::Surface
            );
            let layouts = [Some(masks.opaque(&columns)), masks.transparent()];
            for (kind, layouts) in layouts.into_iter().flatten().enumerate() {
                let [a, b, c] = layouts.by;
                let mut occupied = [0u64; 3];
                for (z, slab) in a.iter().enumerate().take(p) {
                    for (y, &line) in slab.iter().enumerate().take(p) {
                        for (x, c_slice) in c.iter().enumerate().take(p) {
                            let bit = line >> x & 1;
                            let at = (p, top, kind, x, y, z);
                            assert_eq!(b[y][z] >> x & 1, bit, "B: edge, top, mask, x, y, z {at:?}");
                            assert_eq!(
                                c_slice[y] >> z & 1,
                                bit,
                                "C: edge, top, mask, x, y, z {at:?}"
                            );
                            if bit != 0 {
                                occupied[0] |= 1 << z;
                                occupied[1] |= 1 << y;
                                occupied[2] |= 1 << x;
                            }
                        }
                    }
                }
                assert_eq!(
                    layouts.occupied, occupied,
                    "edge {p}, top {top}, mask {kind}"
                );
            }
        }
    }

    /// Builds `masks` for `voxels` and checks layout A and `has_transparent` voxel by voxel.
    fn check(masks: &mut Masks, p: usize, voxels: &[u16], classes: &BlockClasses) {
        let columns: Vec<u64> = voxels
            .chunks_exact(p)
            .map(|row| (0..p).fold(0u64, |m, x| m | u64::from(row[x] != 0) << x))
            .collect();
        assert_eq!(masks.build(p, voxels, &columns, classes), Content::Surface);
        let opaque = masks.opaque(&columns).by[0];
        let empty = vec![[0u64; 64]; p];
        let transparent = masks.transparent().map_or(&empty[..], |t| t.by[0]);
        let mut any = false;
        for z in 0..p {
            for y in 0..p {
                for x in 0..p {
                    let id = BlockId(voxels[x + p * (y + p * z)]);
                    let is_t = classes.is_transparent(id);
                    any |= is_t;
                    let at = |slices: &[Slice]| (slices[z][y] >> x) & 1 == 1;
                    assert_eq!(at(transparent), is_t, "edge {p}, ({x}, {y}, {z}) id {id:?}");
                    assert_eq!(at(opaque), id.0 != 0 && !is_t, "edge {p}, ({x}, {y}, {z})");
                }
            }
            assert!(transparent[z][p..].iter().all(|&line| line == 0));
        }
        assert_eq!(masks.has_transparent, any, "edge {p}");
    }
}
