//! [`EqualIds`]: for every voxel that can show a face, whether its id equals the next voxel's
//! along x, y and z, in the slice layouts the face directions read: the equal-key masks of
//! the greedy pass with AO off, built for a whole chunk at once instead of face by face.
//!
//! With AO off a face's key is its id, so two neighbouring faces of a slice merge iff their
//! voxels' ids are equal. For a face direction whose slices are layout `L` (see
//! [`super::masks`]), the greedy pass needs per line `l` of slice `n`:
//!
//! - `along[l]` bit `b`: the voxel at bit `b` has the id of the voxel at bit `b + 1`;
//! - `across[l]` bit `b`: the voxel at line `l` has the id of the voxel at line `l + 1`.
//!
//! | faces | layout | along (bits) | across (lines) | stored as |
//! | ----- | ------ | ------------ | -------------- | --------- |
//! | ±Z    | A      | next x       | next y         | layout A |
//! | ±Y    | B      | next x       | next z         | layout A, read with slice and line swapped |
//! | ±X    | C      | next z       | next y         | layout C, bit transposed from A |
//!
//! A padded x-row of ids is contiguous, so each of a row's three comparisons is a SIMD
//! compare of the row with the ids one voxel further along x, y or z: 16 ids a register with
//! AVX2 ([`row_x86_v3`]), 8 with SSE2 ([`row_portable`]).
//!
//! Only *exposed* rows are compared: interior rows with a solid voxel that has a neighbour
//! which is not opaque. Faces lie on exposed voxels only, and every reader ANDs these masks
//! with the faces of the same voxel, so the entries of other rows are never read: they keep
//! whatever an earlier chunk left there. Layout C is transposed only for the B slices (`y`)
//! that hold an exposed row, for the same reason.
//!
//! # When the masks are built
//!
//! A row's compares cost about as much as keying a handful of faces one by one, so the masks
//! pay only where the exposed rows are dense: [`EqualIds::build`] first counts the exposed
//! voxels and opaque runs of an eighth of the rows and declines (the caller then keys the faces)
//! where they are few ([`masks_pay`]). From 16^3 up, layout C's transposes are skipped in the
//! same way when the chunk has few ±X faces a B slice ([`layout_c_pays`]); those faces are then
//! keyed. At 8^3 a B slice's bits fit one word, transposed for about a keyed face's cost, and
//! layout C is always built ([`transpose_8_into`]).
//! An exposed row with an id the classes do not know on a voxel that can show a face also
//! declines: keying names the id.

use super::aligned::{Slice, Slices};
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
use super::bits::transpose_rows_x86_v3;
use super::bits::{buried, masked, ones, runs_equal, runs_reach, transpose8, transpose64};

/// Whether a chunk of padded edge `p` whose sampled exposed rows (see [`exposed_rows`]) hold
/// `sample` is meshed from the masks: its exposed rows must hold both many exposed voxels and
/// many ends of opaque runs (±X faces, and runs cut by the chunk's border). Rows that are one
/// solid run (two ends), as in the walls and floors of built models, are meshed faster keyed
/// however many voxels they expose.
///
/// The bounds come from meshing every chunk of the bench inputs both ways (x86-64-v3). At
/// 32^3 and 62^3, built models such as the samples `monu1` and `monu10` (about 2 run ends a
/// row) mesh slower from the masks even with many exposed voxels a row, while foliage,
/// terrain, random fills and the shaded Menger sponge (3.3 run ends a row and more) mesh
/// faster from them, and so do the rolling hillsides of the terrain area (the viewer's
/// terrain over 8 x 8 chunks of 32^3: 2.8 to 4.4 run ends and 3.7 exposed voxels a row or
/// more). The bounds below, 2.8 and 3.5, take the hillsides and leave the built models keyed
/// but for a few chunks near the bound, where the two ways cost about the same. At 16^3 and
/// 8^3 the two ways are close on every input, and the looser rule there follows the same
/// split.
#[inline(always)]
const fn masks_pay(p: usize, sample: &Exposure) -> bool {
    let (rows, voxels, ends) = (sample.rows, sample.voxels, sample.run_ends);
    if rows == 0 {
        return false;
    }
    if p >= 34 {
        // At least 3.5 exposed voxels and 2.8 run ends a row.
        2 * voxels >= 7 * rows && 5 * ends >= 14 * rows
    } else {
        // At least 2 exposed voxels and 2.5 run ends a row.
        voxels >= 2 * rows && 2 * ends >= 5 * rows
    }
}

/// What the transposes of one B slice into layout C cost, in ±X faces keyed one by one (two
/// 64 x 64 bit transposes with their gathers, x86-64-v3, against a keyed ±X face with its
/// line), compared with the run ends the exposure pass counts. At 32^3 and below the two are
/// one transpose ([`transpose_pair_into`]), but halving the bound there makes no measurable
/// difference, so one bound serves every size.
pub(crate) const TRANSPOSE_IN_FACES: u32 = 40;

/// Whether layout C pays for a chunk of padded edge `p` with `run_ends` opaque-run ends (±X
/// faces) over `b_slices` B slices with an exposed row: from 16^3 up, more than
/// [`TRANSPOSE_IN_FACES`] a B slice. At 8^3 always: there a B slice's transpose is one
/// word's ([`transpose_8_into`]), about what one keyed ±X face costs.
#[inline(always)]
const fn layout_c_pays(p: usize, run_ends: u32, b_slices: u32) -> bool {
    p == 10 || run_ends > TRANSPOSE_IN_FACES * b_slices
}

/// The equal-id masks of one chunk (see the [module docs](self)). Scratch that keeps its
/// capacity between chunks.
#[derive(Clone, Debug)]
pub(crate) struct EqualIds {
    /// Layout A (slice z, line y, bit x): the next voxel along x has the same id.
    next_x_a: Slices,
    /// Layout A: the next voxel along y has the same id.
    next_y_a: Slices,
    /// Layout A: the next voxel along z has the same id.
    next_z_a: Slices,
    /// Layout C (slice x, line y, bit z): the next voxel along z has the same id.
    next_z_c: Slices,
    /// Layout C: the next voxel along y has the same id.
    next_y_c: Slices,
    /// Layout C was built: the ±X faces are merged by these masks (else they are keyed).
    has_c: bool,
    /// Per slab `z`, bit `y` set iff row `(y, z)` is exposed.
    exposed: Slice,
}

impl Default for EqualIds {
    fn default() -> Self {
        EqualIds {
            next_x_a: Slices::default(),
            next_y_a: Slices::default(),
            next_z_a: Slices::default(),
            next_z_c: Slices::default(),
            next_y_c: Slices::default(),
            has_c: false,
            exposed: [0; 64],
        }
    }
}

/// What [`EqualIds::build`] reads of a padded chunk of edge `p`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ChunkIds<'a> {
    /// Padded edge.
    pub p: usize,
    /// The `p^3` ids, x fastest.
    pub voxels: &'a [u16],
    /// Occupancy columns (bit `x` of `columns[y + p * z]`: the voxel is not air).
    pub columns: &'a [u64],
    /// Bit `z`: slab `z` has a solid voxel.
    pub slabs: u64,
    /// The opaque mask in layout A.
    pub opaque: &'a [Slice],
    /// Ids below this are known.
    pub known_below: u32,
}

impl EqualIds {
    /// Builds the masks of `chunk` with the portable row kernel ([`row_portable`];
    /// [`build_x86_v3`](Self::build_x86_v3) gives the same masks with AVX2).
    ///
    /// Returns false, with the masks unusable, when keying the faces one by one is the better
    /// way: the sampled exposed rows hold too few exposed voxels or opaque-run ends
    /// ([`masks_pay`]), an exposed row holds an id that is not below the classes' bound
    /// (keying names it), or the inputs do not fit together.
    #[inline(always)]
    pub(super) fn build(&mut self, chunk: &ChunkIds<'_>) -> bool {
        let Some((last, ys)) = self.prepare(chunk) else {
            return false;
        };
        let mut unknown = false;
        let u = &mut unknown;
        // Direct calls, not function pointers, so that each is inlined.
        let pass = match chunk.p {
            64 => compare_rows::<64, 0>(self, chunk, |r| row_portable(r, last, u)),
            34 => compare_rows::<32, 1>(self, chunk, |r| row_portable(r, last, u)),
            18 => compare_rows::<16, 1>(self, chunk, |r| row_portable(r, last, u)),
            _ => compare_rows::<16, 0>(self, chunk, |r| row_portable(r, last, u)),
        };
        !unknown && self.finish(chunk.p, ys, pass, |m, _| transpose64(m))
    }

    /// [`build`](Self::build) with the AVX2 row kernel ([`row_x86_v3`]): the same masks and
    /// answer. (On an x86-64 target without SSE, such as `x86_64-unknown-none`, which cannot
    /// hold AVX2 vectors, the portable kernel.)
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
    pub(super) fn build_x86_v3(&mut self, chunk: &ChunkIds<'_>) -> bool {
        #[cfg(target_feature = "sse2")]
        {
            use core::arch::x86_64::{_mm256_set1_epi16, _mm256_setzero_si256, _mm256_testz_si256};
            let Some((last, ys)) = self.prepare(chunk) else {
                return false;
            };
            let last = _mm256_set1_epi16(last as i16);
            // The OR of every row's saturating differences with the last known id: not zero
            // iff some id is above it.
            let mut excess = _mm256_setzero_si256();
            let e = &mut excess;
            let pass = match chunk.p {
                64 => compare_rows::<64, 0>(self, chunk, |r| row_x86_v3(r, last, e)),
                34 => compare_rows::<32, 1>(self, chunk, |r| row_x86_v3(r, last, e)),
                18 => compare_rows::<16, 1>(self, chunk, |r| row_x86_v3(r, last, e)),
                _ => compare_rows::<16, 0>(self, chunk, |r| row_x86_v3(r, last, e)),
            };
            _mm256_testz_si256(excess, excess) == 1
                && self.finish(chunk.p, ys, pass, |m, rows| transpose_rows_x86_v3(m, rows))
        }
        #[cfg(not(target_feature = "sse2"))]
        self.build(chunk)
    }

    /// Decides from an eighth of the rows whether the masks pay; if they do, finds the exposed
    /// rows of every slab (into `self.exposed`), decides whether layout C pays, sizes the
    /// scratch and returns the largest known id and the B slices (bit `y`) with an exposed
    /// row. `None`: keyed instead.
    #[inline(always)]
    fn prepare(&mut self, chunk: &ChunkIds<'_>) -> Option<(u16, u64)> {
        let p = chunk.p;
        if !(3..=64).contains(&p) || chunk.voxels.len() != p * p * p || chunk.columns.len() != p * p
        {
            return None;
        }
        let sample = exposed_rows::<true>(chunk, &mut self.exposed)?;
        if !masks_pay(p, &sample) {
            return None;
        }
        let all = exposed_rows::<false>(chunk, &mut self.exposed)?;
        self.has_c = layout_c_pays(p, all.run_ends, all.ys.count_ones());
        for v in [&mut self.next_x_a, &mut self.next_y_a, &mut self.next_z_a] {
            v.resize(p);
        }
        if self.has_c {
            self.next_z_c.resize(p);
            self.next_y_c.resize(p);
        }
        // Every id is below a bound past the 16-bit range.
        let last = chunk.known_below.checked_sub(1)?;
        Some((u16::try_from(last).unwrap_or(u16::MAX), all.ys))
    }

    /// Layout C from layout A, if it pays, for the B slices `ys` (those with an exposed row),
    /// with the bit transpose `transpose` (as
    /// [`Masks::build_with`](super::masks::Masks::build_with) takes it); false if the row pass
    /// failed (`None`).
    #[inline(always)]
    fn finish(
        &mut self,
        p: usize,
        ys: u64,
        pass: Option<()>,
        transpose: impl Fn(&mut [u64; 64], usize) + Copy,
    ) -> bool {
        if pass.is_none() {
            return false;
        }
        if self.has_c && p == 10 {
            let (a, c) = (
                [&self.next_z_a[..], &self.next_y_a[..]],
                [&mut self.next_z_c[..], &mut self.next_y_c[..]],
            );
            transpose_8_into(a, c);
        } else if self.has_c && p <= 34 {
            let (a, c) = (
                [&self.next_z_a[..], &self.next_y_a[..]],
                [&mut self.next_z_c[..], &mut self.next_y_c[..]],
            );
            transpose_pair_into(p, a, ys, c, transpose);
        } else if self.has_c {
            transpose_into(p, &self.next_z_a, ys, &mut self.next_z_c, transpose);
            transpose_into(p, &self.next_y_a, ys, &mut self.next_y_c, transpose);
        }
        true
    }

    /// Drops layout C, so that the ±X faces are keyed (to test both ways on one chunk).
    #[cfg(test)]
    pub(super) fn drop_layout_c(&mut self) {
        self.has_c = false;
    }

    /// Builds layout C of a chunk of padded edge `p` whose masks are built, whether it pays
    /// or not (to test it at every edge), for every B slice.
    #[cfg(test)]
    fn build_layout_c(&mut self, p: usize) {
        self.has_c = true;
        self.next_z_c.resize(p);
        self.next_y_c.resize(p);
        let ys = (u64::MAX >> (64 - (p - 2))) << 1;
        self.finish(p, ys, Some(()), |m, _| transpose64(m));
    }

    /// The ±X faces (layout C) are merged by these masks; otherwise they are keyed.
    #[inline(always)]
    pub(super) fn has_layout_c(&self) -> bool {
        self.has_c
    }

    /// Line `l` of slice `n` of the `along` masks of layout `layout` (0 = A, 1 = B, 2 = C, a
    /// constant of the direction): bit `b` set iff the voxel at line `l`, bit `b` has the id
    /// of the one at bit `b + 1`. Meaningful only where the voxel shows a face; 0 past the
    /// chunk. Layout B's line `z` of slice `y` is layout A's line `y` of slice `z`.
    #[inline(always)]
    pub(super) fn along(&self, layout: usize, n: usize, l: usize) -> u64 {
        match layout {
            0 => line(&self.next_x_a, n, l),
            1 => line(&self.next_x_a, l, n),
            _ => line(&self.next_z_c, n, l),
        }
    }

    /// Line `l` of slice `n` of the `across` masks of layout `layout`: bit `b` set iff the
    /// voxel at line `l`, bit `b` has the id of the one at line `l + 1` (as
    /// [`along`](Self::along)).
    #[inline(always)]
    pub(super) fn across(&self, layout: usize, n: usize, l: usize) -> u64 {
        match layout {
            0 => line(&self.next_y_a, n, l),
            1 => line(&self.next_z_a, l, n),
            _ => line(&self.next_y_c, n, l),
        }
    }
}

/// Line `l` of slice `n` of `masks`, or 0 past them.
#[inline(always)]
fn line(masks: &[Slice], n: usize, l: usize) -> u64 {
    masks.get(n).map_or(0, |slice| slice[masked::<64>(l)])
}

/// What [`exposed_rows`] counts.
#[derive(Clone, Copy, Debug)]
struct Exposure {
    /// Exposed rows.
    rows: u32,
    /// Exposed voxels.
    voxels: u32,
    /// The ends of the opaque runs of the rows looked at, within the chunk (two a run, cut at
    /// its border): the ±X faces, and those the chunk's border cuts.
    run_ends: u32,
    /// The B slices (bit `y`) with an exposed row.
    ys: u64,
}

/// The exposed rows of `chunk` into `out` (bit `y` of `out[z]`): interior rows with a solid
/// voxel that has a neighbour which is not opaque, since only such voxels show faces. With
/// `SAMPLE`, only the rows with `(y + z) % 8 == 2` are looked at (a diagonal pattern, which
/// layered or walled models do not line up with, as they do with every eighth slab). `None`
/// if the inputs do not fit together.
#[inline(always)]
fn exposed_rows<const SAMPLE: bool>(chunk: &ChunkIds<'_>, out: &mut Slice) -> Option<Exposure> {
    let p = chunk.p;
    let inner = (u64::MAX >> (64 - (p - 2))) << 1;
    *out = [0; 64];
    let mut count = Exposure {
        rows: 0,
        voxels: 0,
        run_ends: 0,
        ys: 0,
    };
    for z in ones(chunk.slabs & inner) {
        let opaque = chunk.opaque;
        let (slab, below, above) = (opaque.get(z)?, opaque.get(z - 1)?, opaque.get(z + 1)?);
        let columns = chunk.columns.get(z * p..(z + 1) * p)?;
        let mut exposed = 0u64;
        // Rows 1..p - 1, or every eighth of them from the first with (y + z) % 8 == 2.
        let (first, step) = if SAMPLE {
            (1 + (9 - z % 8) % 8, 8)
        } else {
            (1, 1)
        };
        for y in (first..p - 1).step_by(step) {
            let solid = columns[y] & inner;
            // Voxels all of whose 6 neighbours are opaque show no face.
            let o = slab[y];
            let hidden = buried(
                o,
                [slab[masked::<64>(y - 1)], slab[masked::<64>(y + 1)]],
                [below[y], above[y]],
            );
            let shown = (solid & !hidden).count_ones();
            count.voxels += shown;
            exposed |= u64::from(shown != 0) << y;
            // The ends of the row's opaque runs within the chunk, cut at its border: the
            // bits where the row differs from itself shifted by one.
            let o = o & inner;
            count.run_ends += (o ^ (o << 1)).count_ones();
        }
        count.rows += exposed.count_ones();
        count.ys |= exposed;
        out[z] = exposed;
    }
    Some(count)
}

/// The four runs of `N` ids one row's masks compare: the row from some voxel on, and the ids
/// one voxel further along x, y and z. The ids past a row's end belong to the next rows and
/// give bits no face reads.
pub(crate) struct RowRuns<'a, const N: usize> {
    /// The row's ids.
    pub row: &'a [u16; N],
    /// The ids from the row's second voxel on.
    pub next_x: &'a [u16; N],
    /// The row at `y + 1`.
    pub next_y: &'a [u16; N],
    /// The row at `z + 1`.
    pub next_z: &'a [u16; N],
}

/// The row pass of [`EqualIds::build`] over the exposed rows of `chunk`, with the row kernel
/// `kernel` (the three masks of a run: bit `i` set iff the id of the run's voxel `i` equals
/// the next one's along x, y and z), comparing the `N` ids of a row from voxel `FROM` on
/// (`N` a multiple of 16 that reaches at least voxel `p - 2`, the last one that shows a
/// face). `None` if a row's ids run past the array (never for a padded chunk's interior
/// rows: see the bound below).
///
/// Faces lie on voxels `1..p - 1` only, so a 34-id row is compared from voxel 1 as 32 ids (2
/// AVX2 registers a run, not 3) and an 18-id row as 16 (1, not 2); bit 0 and the bits past
/// voxel `p - 2` of such masks are zero or other rows' (no face reads them).
#[inline(always)]
fn compare_rows<const N: usize, const FROM: usize>(
    eq: &mut EqualIds,
    chunk: &ChunkIds<'_>,
    mut kernel: impl FnMut(&RowRuns<'_, N>) -> [u64; 3],
) -> Option<()> {
    let p = chunk.p;
    debug_assert!(FROM <= 1 && FROM + N >= p - 1 && N <= 64 && N.is_multiple_of(16));
    // The furthest id read: the next-z run of the last interior row, `N` ids from its start.
    debug_assert!((p - 1) * p * p + (p - 2) * p + FROM + N <= chunk.voxels.len());
    for (z, &rows) in eq.exposed.iter().enumerate().take(p) {
        if rows == 0 {
            continue;
        }
        let (x_out, y_out, z_out) = (
            eq.next_x_a.get_mut(z)?,
            eq.next_y_a.get_mut(z)?,
            eq.next_z_a.get_mut(z)?,
        );
        for y in ones(rows) {
            let start = (y + p * z) * p + FROM;
            // One bounds check for the four runs (the furthest starts `p * p` on; no sum
            // here overflows: `start` is below `p^3`).
            let span = chunk.voxels.get(start..start + p * p + N)?;
            let run =
                |from: usize| -> Option<&[u16; N]> { span.get(from..from + N)?.try_into().ok() };
            let runs = RowRuns {
                row: run(0)?,
                next_x: run(1)?,
                next_y: run(p)?,
                next_z: run(p * p)?,
            };
            let [next_x, next_y, next_z] = kernel(&runs);
            x_out[y] = next_x << FROM;
            y_out[y] = next_y << FROM;
            z_out[y] = next_z << FROM;
        }
    }
    Some(())
}

/// The portable row kernel: [`runs_equal`] (SSE2 where the target has it); sets `unknown` if
/// an id of the run is above `last`, the largest known id (as [`row_x86_v3`] tests, so that
/// both decline the same chunks).
#[inline(always)]
fn row_portable<const N: usize>(r: &RowRuns<'_, N>, last: u16, unknown: &mut bool) -> [u64; 3] {
    *unknown |= runs_reach(r.row, last) != 0;
    [
        runs_equal(r.row, r.next_x),
        runs_equal(r.row, r.next_y),
        runs_equal(r.row, r.next_z),
    ]
}

/// The AVX2 row kernel: 16 ids a register, two registers' compares packed to 32 mask bits
/// per `vpmovmskb`. ORs the saturating difference of every id of the run with `last` (the
/// largest known id, in every lane) into `excess`, which stays zero iff no id is above it;
/// the ids past the row's end (other rows') are tested too, which can only decline a chunk
/// the portable kernel would build.
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
#[inline]
fn row_x86_v3<const N: usize>(
    r: &RowRuns<'_, N>,
    last: core::arch::x86_64::__m256i,
    excess: &mut core::arch::x86_64::__m256i,
) -> [u64; 3] {
    use core::arch::x86_64::{_mm256_cmpeq_epi16, _mm256_or_si256, _mm256_subs_epu16};
    for k in 0..N / 16 {
        *excess = _mm256_or_si256(*excess, _mm256_subs_epu16(lanes(r.row, k), last));
    }
    let equal =
        |other: &[u16; N]| lane_bits::<N>(|k| _mm256_cmpeq_epi16(lanes(r.row, k), lanes(other, k)));
    [equal(r.next_x), equal(r.next_y), equal(r.next_z)]
}

/// Register `k` of a run of `N` ids: its ids `16 k .. 16 k + 16`, one 32-byte load.
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
#[inline]
fn lanes<const N: usize>(run: &[u16; N], k: usize) -> core::arch::x86_64::__m256i {
    let registers: &[[u16; 16]] = bytemuck::cast_slice(run);
    bytemuck::cast(registers[k % registers.len()])
}

/// One mask bit per id from registers of all-ones or all-zero lanes, `lane(k)` for the ids
/// `16 k ..`: two registers at a time are packed to bytes (`packs` interleaves them by
/// 128-bit lane, a.lo, b.lo, a.hi, b.hi, and a permute restores id order) and their 32 bits
/// taken with one `vpmovmskb`.
#[cfg(all(target_arch = "x86_64", target_feature = "sse2"))]
#[target_feature(enable = "avx2,bmi1,bmi2,lzcnt,popcnt")]
#[inline]
fn lane_bits<const N: usize>(lane: impl Fn(usize) -> core::arch::x86_64::__m256i) -> u64 {
    use core::arch::x86_64::{
        _mm256_movemask_epi8, _mm256_packs_epi16, _mm256_permute4x64_epi64, _mm256_setzero_si256,
    };
    // Pairs of registers, unrolled: `N / 16` is a constant.
    let mut mask = 0u64;
    for pair in 0..N.div_ceil(32) {
        let k = 2 * pair;
        let high = if k + 1 < N / 16 {
            lane(k + 1)
        } else {
            _mm256_setzero_si256()
        };
        let packed = _mm256_permute4x64_epi64::<0b11_01_10_00>(_mm256_packs_epi16(lane(k), high));
        mask |= u64::from(_mm256_movemask_epi8(packed) as u32) << ((16 * k) & 63);
    }
    mask
}

/// Layout C from layout A, as [`transpose_into`], of two masks at once, for a chunk of 8^3
/// (padded edge 10): the 8 x 8 bits of each B slice's voxels a word, a row a byte, one
/// [`transpose8`] each. (Through [`transpose_pair_into`]'s 64 x 64 matrices, zeroed and
/// transposed whole, an 8^3 chunk would pay for 64 lines where it has 8.) Every line `1..9` of
/// slices `1..9` is written, of B slices with an exposed row or not (nothing reads the
/// others).
#[inline(always)]
fn transpose_8_into(a: [&[Slice]; 2], out: [&mut [Slice]; 2]) {
    for (a, out) in a.into_iter().zip(out) {
        // Word y - 1, byte z - 1: bits 1..9 of line y of A slice z.
        let mut m = [0u64; 8];
        for (z, slice) in a.iter().skip(1).take(8).enumerate() {
            for (word, &line) in m.iter_mut().zip(&slice[1..9]) {
                *word |= ((line >> 1) & 0xFF) << (8 * z);
            }
        }
        for word in &mut m {
            *word = transpose8(*word);
        }
        // Now word y - 1, byte x - 1 holds bits z - 1 of line y of C slice x.
        for (x, slice) in out.iter_mut().skip(1).take(8).enumerate() {
            for (line, &word) in slice[1..9].iter_mut().zip(&m) {
                *line = ((word >> (8 * x)) & 0xFF) << 1;
            }
        }
    }
}

/// Layout C from layout A, as [`transpose_into`], of two masks at once, for a chunk of
/// 32^3 or smaller: only the voxels inside the chunk show faces, and their bits of a B
/// slice, at most 32 x 32, are read, so the bits of both masks fit one 64 x 64 transpose
/// side by side (the first's in the low 32 bits of the rows, the second's in the high ones,
/// which come out as rows 32 to 63). Lines of slices 0 and `p - 1`, and bits 0 and `p - 1`,
/// are not written or are zero: no face lies there.
#[inline(always)]
fn transpose_pair_into(
    p: usize,
    a: [&[Slice]; 2],
    ys: u64,
    out: [&mut [Slice]; 2],
    transpose: impl Fn(&mut [u64; 64], usize),
) {
    debug_assert!(p <= 34);
    let [first, second] = a;
    let [first_out, second_out] = out;
    let interior = |line: u64| (line >> 1) & 0xFFFF_FFFF;
    // Both are `p` slices long (`prepare` sized them); their interior ones are `1..p - 1`.
    let (first, second) = (&first[1..p - 1], &second[1..p - 1]);
    let (first_out, second_out) = (&mut first_out[1..p - 1], &mut second_out[1..p - 1]);
    // Rows `p - 2..` of every matrix are zero when it is transposed: set once here, and
    // again after each block (the transpose fills them). Rows below are written per block.
    let mut ms = [[0u64; 64]; 8];
    // Eight B slices at a time, the words of a slice's lines `8 k .. 8 k + 8`: the masks'
    // slices lie 512 bytes apart, so line `y` of each of the four masks' 32 slices falls in
    // 8 of the L1 cache's 64 sets, and taken one `y` at a time the 128 lines evict each
    // other before the next `y` reads them again.
    for block in 0..8 {
        let block_ys = (ys >> (8 * block)) & 0xFF;
        if block_ys == 0 {
            continue;
        }
        let lines = 8 * block..8 * block + 8;
        for m in &mut ms {
            m[first.len()..].fill(0);
        }
        for (z, (one, two)) in first.iter().zip(second).enumerate() {
            let (one, two) = (&one[lines.clone()], &two[lines.clone()]);
            for ((m, &one), &two) in ms.iter_mut().zip(one).zip(two) {
                // Row z - 1: the interior bits of line y of slice z, of the first masks in
                // the low half and of the second in the high half.
                m[masked::<64>(z)] = interior(one) | interior(two) << 32;
            }
        }
        for k in ones(block_ys) {
            transpose(&mut ms[masked::<8>(k)], 32);
        }
        // Row x - 1 of the low half now holds the first masks' bits z - 1, row x + 31 the
        // second's. Lines of the block that are not in `ys` take what their rows gave:
        // nothing reads them.
        let outs = first_out.iter_mut().zip(second_out.iter_mut());
        for (x, (one, two)) in outs.enumerate() {
            let (one, two) = (&mut one[lines.clone()], &mut two[lines.clone()]);
            for ((one, two), m) in one.iter_mut().zip(two).zip(&ms) {
                *one = m[masked::<64>(x)] << 1;
                *two = m[masked::<64>(x + 32)] << 1;
            }
        }
    }
}

/// Layout C from layout A for the B slices `ys`: `out[x][y]` bit `z` is `a[z][y]` bit `x`
/// (layout B's slice `y` gathered from A, then a 64 x 64 bit transpose). The other slices'
/// lines of `out` are left as they are. For a chunk of 62^3 (at 32^3 and below,
/// [`transpose_pair_into`]).
#[inline(always)]
fn transpose_into(
    p: usize,
    a: &[Slice],
    ys: u64,
    out: &mut [Slice],
    transpose: impl Fn(&mut [u64; 64], usize),
) {
    for y in ones(ys) {
        let mut m = [0u64; 64];
        for (word, slab) in m.iter_mut().zip(a) {
            *word = slab[y];
        }
        transpose(&mut m, p);
        for (x, line) in out.iter_mut().enumerate().take(p) {
            line[y] = m[masked::<64>(x)];
        }
    }
}

#[cfg(test)]
mod tests {
    use alloc::vec;
    use alloc::vec::Vec;

    use voxel_scene::rng::Rng;

    use super::*;

    /// A padded chunk of edge `p` for the tests: ids, occupancy columns, opaque mask in
    /// layout A (ids at or above `transparent_from` are transparent), and occupied slabs.
    struct TestChunk {
        p: usize,
        voxels: Vec<u16>,
        columns: Vec<u64>,
        opaque: Vec<Slice>,
        slabs: u64,
    }

    impl TestChunk {
        fn new(p: usize, voxels: Vec<u16>, transparent_from: u16) -> Self {
            let mask = |keep: &dyn Fn(u16) -> bool| -> Vec<u64> {
                voxels
                    .chunks_exact(p)
                    .map(|row| (0..p).fold(0, |m, x| m | u64::from(keep(row[x])) << x))
                    .collect()
            };
            let columns = mask(&|id| id != 0);
            let opaque_rows = mask(&|id| id != 0 && id < transparent_from);
            let mut opaque = vec![[0u64; 64]; p];
            for (z, slab) in opaque.iter_mut().enumerate() {
                slab[..p].copy_from_slice(&opaque_rows[z * p..(z + 1) * p]);
            }
            let slabs = (0..p).fold(0, |s, z| {
                s | u64::from(columns[z * p..(z + 1) * p].iter().any(|&c| c != 0)) << z
            });
            TestChunk {
                p,
                voxels,
                columns,
                opaque,
                slabs,
            }
        }

        fn ids(&self, known_below: u32) -> ChunkIds<'_> {
            ChunkIds {
                p: self.p,
                voxels: &self.voxels,
                columns: &self.columns,
                slabs: self.slabs,
                opaque: &self.opaque,
                known_below,
            }
        }

        fn id(&self, [x, y, z]: [usize; 3]) -> u16 {
            self.voxels[x + self.p * (y + self.p * z)]
        }

        /// A solid interior voxel with a neighbour that is not opaque.
        fn exposed(&self, at: [usize; 3], transparent_from: u16) -> bool {
            let p = self.p;
            let opaque = |v: [usize; 3]| {
                let id = self.id(v);
                id != 0 && id < transparent_from
            };
            if at.iter().any(|&a| a == 0 || a >= p - 1) || self.id(at) == 0 {
                return false;
            }
            (0..3).any(|axis| {
                [at[axis] - 1, at[axis] + 1].iter().any(|&c| {
                    let mut n = at;
                    n[axis] = c;
                    !opaque(n)
                })
            })
        }
    }

    /// Random ids: air with probability `air` in 8, else one of `ids` (1 ..= ids).
    fn noise(p: usize, seed: u64, air: u64, ids: u16) -> Vec<u16> {
        let mut rng = Rng::new(seed);
        (0..p * p * p)
            .map(|_| {
                if rng.below(8) < air {
                    0
                } else {
                    1 + rng.below(u64::from(ids)) as u16
                }
            })
            .collect()
    }

    /// Both kernels (the AVX2 one where this CPU runs it) on `chunk`: the answer of each,
    /// and the masks of the portable one.
    fn build_both(chunk: &TestChunk, known_below: u32) -> (EqualIds, bool) {
        let mut portable = EqualIds::default();
        let built = portable.build(&chunk.ids(known_below));
        #[cfg(target_arch = "x86_64")]
        if crate::instruction_set::x86_v3_or_skip("EqualIds::build_x86_v3") {
            let mut wide = EqualIds::default();
            #[expect(
                unsafe_code,
                reason = "calls the AVX2 build on a CPU checked to have it"
            )]
            // SAFETY: `X86V3.is_supported()` found every feature `build_x86_v3` is compiled
            // for.
            let wide_built = unsafe { wide.build_x86_v3(&chunk.ids(known_below)) };
            assert_eq!(wide_built, built, "both kernels give the same answer");
            if built {
                assert_eq!(wide.has_c, portable.has_c);
                let p = chunk.p;
                for layout in 0..3 {
                    for n in 0..p {
                        for l in 0..p {
                            for (a, b) in [
                                (wide.along(layout, n, l), portable.along(layout, n, l)),
                                (wide.across(layout, n, l), portable.across(layout, n, l)),
                            ] {
                                // Entries are meaningful at exposed voxels only: compared
                                // where the voxel of the layout's line and bit is exposed.
                                let exposed = (0..p).fold(0u64, |m, b| {
                                    let at = match layout {
                                        0 => [b, l, n],
                                        1 => [b, n, l],
                                        _ => [n, l, b],
                                    };
                                    m | u64::from(chunk.exposed(at, u16::MAX)) << b
                                });
                                if layout < 2 || wide.has_c {
                                    assert_eq!(a & exposed, b & exposed, "layout {layout}");
                                }
                            }
                        }
                    }
                }
            }
        }
        (portable, built)
    }

    /// Every mask bit of every exposed voxel, in all three layouts, against the ids, at every
    /// padded edge; dense fills of few ids (the masks are built), with and without
    /// transparent ids, and with ids at the ends of the 16-bit range.
    #[test]
    fn masks_match_the_ids_of_every_exposed_voxel() {
        for p in [10, 18, 34, 64] {
            for (case, (air, ids, transparent_from)) in [(2, 2, u16::MAX), (4, 3, 3), (2, 1, 2)]
                .into_iter()
                .enumerate()
            {
                let mut voxels = noise(p, (p * 10 + case) as u64, air, ids);
                if case == 0 {
                    // The largest ids: a signed compare or saturating pack would fail here.
                    for (i, v) in voxels.iter_mut().enumerate().filter(|(i, _)| i % 7 == 0) {
                        *v = [0x7FFF, 0x8000, 0xFFFF][i % 3];
                    }
                }
                let chunk = TestChunk::new(p, voxels, transparent_from);
                let (mut eq, built) = build_both(&chunk, u32::MAX);
                assert!(built, "edge {p} case {case}: a dense fill builds its masks");
                let what = alloc::format!("edge {p} case {case}");
                // A B slice's transposes cost the same at every edge: the larger chunks'
                // slices hold enough ±X faces for them. Where they do not pay, layout C is
                // built here, to test it at every edge.
                assert!(eq.has_layout_c() || p < 34, "{what}: layout C");
                if !eq.has_layout_c() {
                    eq.build_layout_c(p);
                }
                for z in 1..p - 1 {
                    for y in 1..p - 1 {
                        for x in 1..p - 1 {
                            if !chunk.exposed([x, y, z], transparent_from) {
                                continue;
                            }
                            let id = chunk.id([x, y, z]);
                            let same = |dx: usize, dy: usize, dz: usize| {
                                u64::from(chunk.id([x + dx, y + dy, z + dz]) == id)
                            };
                            let bit = |line: u64, b: usize| (line >> b) & 1;
                            // Layout A: slice z, line y, bit x.
                            assert_eq!(bit(eq.along(0, z, y), x), same(1, 0, 0), "{what}");
                            assert_eq!(bit(eq.across(0, z, y), x), same(0, 1, 0), "{what}");
                            // Layout B: slice y, line z, bit x.
                            assert_eq!(bit(eq.along(1, y, z), x), same(1, 0, 0), "{what}");
                            assert_eq!(bit(eq.across(1, y, z), x), same(0, 0, 1), "{what}");
                            // Layout C: slice x, line y, bit z.
                            assert_eq!(bit(eq.along(2, x, y), z), same(0, 0, 1), "{what}");
                            assert_eq!(bit(eq.across(2, x, y), z), same(0, 1, 0), "{what}");
                        }
                    }
                }
            }
        }
    }

    /// The exposed rows and their counts against each voxel's 6 neighbours, at every edge:
    /// fills from nearly solid (voxels exposed by one air neighbour, along any axis) to
    /// sparse, with transparent ids (exposed to them, and exposed themselves).
    #[test]
    fn exposed_rows_are_those_with_a_voxel_next_to_one_not_opaque() {
        for p in [10, 18, 34, 64] {
            for (case, air) in [0u64, 1, 4, 7].into_iter().enumerate() {
                let transparent_from = 3;
                let chunk = TestChunk::new(p, noise(p, 7 + case as u64, air, 3), transparent_from);
                let mut rows = [0u64; 64];
                let count = exposed_rows::<false>(&chunk.ids(u32::MAX), &mut rows).unwrap();
                let opaque = |x: usize, y: usize, z: usize| {
                    let id = chunk.id([x, y, z]);
                    id != 0 && id < transparent_from
                };
                let (mut want_rows, mut want_voxels, mut want_x) = (0, 0, 0);
                for (z, &got) in rows.iter().enumerate().take(p) {
                    let mut want = 0u64;
                    for y in 0..p {
                        let shown = (0..p)
                            .filter(|&x| chunk.exposed([x, y, z], transparent_from))
                            .count() as u32;
                        want |= u64::from(shown != 0) << y;
                        want_voxels += shown;
                        // The ends of opaque runs within the chunk's interior (x in 1..p - 1).
                        if (1..p - 1).contains(&y) && (1..p - 1).contains(&z) {
                            let inside = |x: usize| (1..p - 1).contains(&x) && opaque(x, y, z);
                            for x in (1..p - 1).filter(|&x| inside(x)) {
                                want_x += u32::from(!inside(x + 1)) + u32::from(!inside(x - 1));
                            }
                        }
                    }
                    assert_eq!(got, want, "edge {p} air {air}/8 slab {z}");
                    want_rows += want.count_ones();
                }
                let got = (count.rows, count.voxels, count.run_ends);
                assert_eq!(
                    got,
                    (want_rows, want_voxels, want_x),
                    "edge {p} air {air}/8"
                );
                // The sample looks at an eighth of the rows: about an eighth of the counts.
                let mut sampled = [0u64; 64];
                let sample = exposed_rows::<true>(&chunk.ids(u32::MAX), &mut sampled).unwrap();
                assert!(sample.rows <= count.rows / 8 + p as u32, "edge {p}");
                assert!(
                    sampled.iter().zip(&rows).all(|(s, r)| s & !r == 0),
                    "edge {p}"
                );
            }
        }
    }

    /// Few exposed voxels a row (isolated voxels and thin lines) decline; so does an unknown
    /// id on any voxel of an exposed row that can show a face, the first and last of the row
    /// included (both kernels alike); a chunk with few ±X faces builds without layout C (from
    /// 16^3 up).
    #[test]
    fn sparse_chunks_and_unknown_ids_decline() {
        for p in [10, 18, 34, 64] {
            // One voxel in every other row: one exposed voxel a row.
            let mut sparse = vec![0u16; p * p * p];
            for z in 1..p - 1 {
                for y in (1..p - 1).step_by(2) {
                    sparse[(y + z) % (p - 2) + 1 + p * (y + p * z)] = 1;
                }
            }
            let (_, built) = build_both(&TestChunk::new(p, sparse, u16::MAX), u32::MAX);
            assert!(!built, "edge {p}: sparse");

            let dense = noise(p, p as u64, 2, 2);
            let (_, built) = build_both(&TestChunk::new(p, dense.clone(), u16::MAX), 3);
            assert!(built, "edge {p}: ids 1 and 2, both known");
            for at in [
                p * p + p + 1,
                p * p * (p / 2) + p * (p / 2) + p / 2,
                p * p + p + p - 2,
            ] {
                let mut unknown = dense.clone();
                unknown[at] = 3;
                let chunk = TestChunk::new(p, unknown, u16::MAX);
                let (_, built) = build_both(&chunk, 3);
                assert!(!built, "edge {p}: unknown id at {at}");
            }

            // One slab of rows of runs of three voxels: many exposed voxels and ±X faces a
            // row, but one row a B slice, so too few ±X faces a B slice for layout C (but at
            // 8^3, where it always pays).
            let mut layered = vec![0u16; p * p * p];
            for y in 1..p - 1 {
                for x in (1..p - 1).filter(|x| x % 5 < 3) {
                    layered[x + p * (y + p)] = 1 + (x % 2) as u16;
                }
            }
            let (eq, built) = build_both(&TestChunk::new(p, layered, u16::MAX), u32::MAX);
            assert!(built, "edge {p}: layered");
            assert_eq!(eq.has_layout_c(), p == 10, "edge {p}: one row a B slice");

            // Rows of solid runs (two ±X faces each) decline however many voxels they expose.
            let mut walls = vec![0u16; p * p * p];
            for z in (1..p - 1).step_by(2) {
                for y in 1..p - 1 {
                    for x in 1..p - 1 {
                        walls[x + p * (y + p * z)] = 1 + ((y + z) % 3) as u16;
                    }
                }
            }
            let (_, built) = build_both(&TestChunk::new(p, walls, u16::MAX), u32::MAX);
            assert!(!built, "edge {p}: walls");
        }
    }
}
