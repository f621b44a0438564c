//! Whether every face of a chunk has one id: a one-material chunk (an occupancy grid, a
//! sculpt, a stone cave), or a chunk whose other ids are all hidden (a model filled with a
//! core material, stone with ores buried in it). With AO off every face then has one key, so
//! the greedy pass keys nothing and reads no id: the faces that merge are the neighbouring
//! ones. The search finds, first, whether any voxel has a face at all: with AO off a chunk
//! with none is done (small chunks of a terrain often are: their own voxels air, over a floor
//! in their padding), sooner than six walks that find no face.
//!
//! Only the voxels that have a face are read: those of the chunk (not its padding) that are
//! solid and have an air neighbour. A voxel with six solid neighbours shows no face, whatever
//! its id; a voxel of the padding shows none either (its faces are the next chunk's).

use super::aligned::Slice;
use super::bits::{buried, faces_of_id, masked, nonzero_lines, occupied_rows, ones};

/// Rows whose first and last solid voxels (and, where those differ from the chunk's id, whose
/// first and last voxels with a face) are compared with the chunk's id before every row is
/// scanned: on a chunk of several ids one of them nearly always differs, and the
/// scan is skipped. They are taken every `p * p / SAMPLES + 1` rows (about two per slab at
/// 62^3), a step that is not a multiple of `p`, so that they fall on different rows (y) of
/// their slabs rather than all on the bottom padding row, which shows no face. Only chunks of
/// padded edge [`SAMPLED_FROM`] and more are sampled.
const SAMPLES: usize = 128;

/// The smallest padded edge whose chunks are sampled before the scan, and whose hidden ids are
/// told apart from those with a face. Below it the samples cost more than the scans they
/// spare (an 8^3 chunk's samples are every row), and so does comparing rows one by one:
/// there every solid voxel of the chunk's slabs must have the id.
pub(crate) const SAMPLED_FROM: usize = 34;

/// What [`one_id`] finds about the ids of a chunk's voxels with a face.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FaceIds {
    /// No voxel has a face: the chunk has nothing to mesh.
    NoFace,
    /// Every voxel with a face has this id.
    One(u16),
    /// Not one id (or, below [`SAMPLED_FROM`], another id on a solid voxel without a face), or
    /// inputs that do not fit together: the faces are keyed.
    NotOne,
}

impl FaceIds {
    /// The one id, if there is one.
    pub(crate) fn one(self) -> Option<u16> {
        match self {
            FaceIds::One(id) => Some(id),
            FaceIds::NoFace | FaceIds::NotOne => None,
        }
    }
}

/// Whether every voxel with a face in the padded chunk `voxels` (edge `p`, occupancy `rows`
/// in layout A: bit `x` of line `y` of slab `z` is voxel `x + p * (y + p * z)`, lines from `p`
/// on zero; bit `z` of `slabs` set iff slab `z` has a solid voxel) has one id, and which. A
/// voxel has a face when it lies inside the chunk (coordinates `1..=p - 2`), is solid, and
/// one of its six neighbours is air; `rows` must be the opaque occupancy (no transparent
/// voxel). Below padded edge [`SAMPLED_FROM`] every solid voxel of slabs `1..=p - 2` must have
/// the id.
///
/// First the first voxel with a face is found (none: [`FaceIds::NoFace`], a chunk whose own
/// voxels are air or buried, such as one just above a floor, which holds the floor's top in
/// its padding). Then, from padded edge [`SAMPLED_FROM`] on, the ends of [`SAMPLES`] rows
/// spread over the chunk are compared with its id (a chunk of layered or painted materials
/// stops here); then, slab by slab, the ids of the slab's solid rows in one read where that
/// costs less, and otherwise (a slab with another id, or with rows that show no face) those
/// of every row with a face, of a row of 64 only the halves with one.
#[inline(always)]
pub(crate) fn one_id(voxels: &[u16], rows: &[Slice], p: usize, slabs: u64) -> FaceIds {
    if !(3..=64).contains(&p) || voxels.len() != p * p * p || rows.len() != p {
        return FaceIds::NotOne;
    }
    // Bits (and rows, and slabs) 1..=p - 2: the chunk without its padding.
    let inner = (u64::MAX >> (64 - (p - 2))) << 1;
    let slabs = slabs & inner;
    let first = ones(slabs)
        .flat_map(|z| (1..=p - 2).map(move |y| (y, z)))
        .map(|(y, z)| (y, z, faced_row(rows, inner, y, z)))
        .find(|&(_, _, f)| f != 0);
    match first {
        None => FaceIds::NoFace,
        Some(first) => same_id(voxels, rows, p, slabs, first).map_or(FaceIds::NotOne, FaceIds::One),
    }
}

/// The rest of [`one_id`] from the first voxel with a face, bit `first` of row `(y0, z0)`:
/// its id if every voxel with a face has it, else `None`. (`slabs`: those of the chunk
/// without its padding; the inputs fit together.)
#[inline(always)]
fn same_id(
    voxels: &[u16],
    rows: &[Slice],
    p: usize,
    slabs: u64,
    (y0, z0, first): (usize, usize, u64),
) -> Option<u16> {
    let e = p - 2;
    let inner = (u64::MAX >> (64 - e)) << 1;
    // A row's ids; for a 32^3 chunk 48 of them where the array has them (the faces lie in
    // bits 1..=32 only, and 48 ids fill three SIMD registers, see `faces_of_id`).
    let ids = |y: usize, z: usize| {
        let start = (y + p * z) * p;
        let len = if p == 34 && start + 48 <= voxels.len() {
            48
        } else {
            p
        };
        voxels.get(start..start + len)
    };
    let id = *ids(y0, z0)?.get(first.trailing_zeros() as usize)?;
    if p >= SAMPLED_FROM {
        // Row `y + p * z` every `stride` rows, `y` and `z` stepped along without a division.
        let stride = p * p / SAMPLES + 1;
        let (step_y, step_z) = (stride % p, stride / p);
        let (mut y, mut z) = (0, 0);
        for _ in 0..(p * p).div_ceil(stride) {
            if (1..=e).contains(&y) && (slabs >> (z & 63)) & 1 != 0 {
                // The row's solid ends first (two reads): they have a face, or lie in the
                // padding; only where they differ are the voxels with a face found.
                let start = (y + p * z) * p;
                let solid = rows.get(z).map_or(0, |slab| slab[y]);
                if solid != 0 && row_ends(voxels, start, solid) != (Some(id), Some(id)) {
                    let f = faced_row(rows, inner, y, z);
                    if f != 0 && row_ends(voxels, start, f) != (Some(id), Some(id)) {
                        return None;
                    }
                }
            }
            y += step_y;
            z += step_z;
            if y >= p {
                y -= p;
                z += 1;
            }
        }
    }
    // Lines 0 and 63 stay zero.
    let mut faced = [0u64; 64];
    // A row solid across, padding included: only such a row can be solid and show no face
    // (any other solid row has a voxel of the chunk next to an air one).
    let across = u64::MAX >> (64 - p);
    // Whether a slab's solid rows are read in one pass first (see below).
    let mut slab_at_once = true;
    for z in ones(slabs) {
        let here = rows.get(z)?;
        let solid_ids = |solid: core::ops::Range<usize>| {
            voxels.get((z * p + solid.start) * p..(z * p + solid.end) * p)
        };
        if p < SAMPLED_FROM {
            // Every solid voxel of the slab must have the id. Comparing rows one by one costs
            // more than keying these small chunks' faces saves.
            if holds_other(solid_ids(occupied_rows(&here[..p])?)?, id) {
                return None;
            }
            continue;
        }
        // In a chunk of one id, one read of a slab's solid rows answers for every voxel, and
        // costs less than comparing row by row. It is not taken where it would read rows
        // with no face (a filled model's inside, read for nothing, cache line by cache line),
        // nor, once a slab held another id, for the rest of the chunk (that id is a filled
        // model's core, and the next slab holds it too).
        if slab_at_once && !here.iter().fold(false, |any, &r| any | (r == across)) {
            if !holds_other(solid_ids(occupied_rows(&here[..p])?)?, id) {
                continue;
            }
            slab_at_once = false;
        }
        // Only the rows with a face are read: rows without one (inside a filled model) hold
        // nothing that counts, and reading them fetched every cache line of the chunk.
        faced_rows(rows.get(z - 1)?, here, rows.get(z + 1)?, inner, &mut faced);
        for y in ones(nonzero_lines(&faced) & inner) {
            let f = faced[y];
            let row = ids(y, z)?;
            if p == 64 {
                // Each half of a row of 64 ids is read only where it holds a face.
                for (half, ids) in row.chunks_exact(32).enumerate() {
                    let bits = f >> (32 * half) & u64::from(u32::MAX);
                    if bits != 0 && faces_of_id(ids, id, bits) != bits {
                        return None;
                    }
                }
            } else if faces_of_id(row, id, f) != f {
                return None;
            }
        }
    }
    Some(id)
}

/// The voxels with a face of slab `here` (layout A lines), line by line, from the slabs
/// `below` and `above` it: a solid voxel of bits `inner` with an air neighbour. Lines 1 to 62
/// of fixed arrays, so that the compiler vectorises the pass with no branch; lines past the
/// chunk's are not masked here (the caller takes lines `1..=p - 2` only).
#[inline(always)]
fn faced_rows(below: &Slice, here: &Slice, above: &Slice, inner: u64, faced: &mut Slice) {
    let lines = (here[1..63].iter().zip(&here[..62]).zip(&here[2..]))
        .zip(&below[1..63])
        .zip(&above[1..63]);
    for (f, ((((&r, &before), &after), &under), &over)) in faced[1..63].iter_mut().zip(lines) {
        *f = r & inner & !buried(r, [before, after], [under, over]);
    }
}

/// True if `ids` holds an id that is neither air nor `id`. A voxel is neither iff neither it
/// nor its XOR with `id` is zero: iff their minimum is not. Those minima ORed together
/// vectorise to three operations per register of ids and one test.
#[inline(always)]
fn holds_other(ids: &[u16], id: u16) -> bool {
    ids.iter().fold(0u16, |acc, &v| acc | v.min(v ^ id)) != 0
}

/// The ids at the lowest and highest set bit of `bits` in the row of `voxels` that starts at
/// index `start`.
#[inline(always)]
fn row_ends(voxels: &[u16], start: usize, bits: u64) -> (Option<u16>, Option<u16>) {
    let at = |x: u32| voxels.get(start + x as usize).copied();
    (at(bits.trailing_zeros()), at(63 - bits.leading_zeros()))
}

/// Bit `x`: voxel `(x, y, z)` of the chunk (`inner`: bits 1..=p - 2) is solid and has an air
/// neighbour, from the occupancy `rows` in layout A (`y` and `z` inside the chunk).
#[inline(always)]
fn faced_row(rows: &[Slice], inner: u64, y: usize, z: usize) -> u64 {
    let row = |y: usize, z: usize| rows.get(z).map_or(0, |slab| slab[masked::<64>(y)]);
    let r = row(y, z);
    let sides = [row(y - 1, z), row(y + 1, z)];
    r & inner & !buried(r, sides, [row(y, z - 1), row(y, z + 1)])
}

#[cfg(test)]
mod tests {
    use alloc::vec;
    use alloc::vec::Vec;

    use super::*;

    /// Ids at the edges of the faces' compare: the smallest and largest, the sign bit, ids
    /// that differ from another in one bit only.
    const IDS: [u16; 7] = [1, 2, 3, 0x7FFF, 0x8000, 0xFFFE, 0xFFFF];

    /// Occupancy of padded ids of edge `p`, in layout A (slab `z`, line `y`, bit `x`).
    fn rows_of(voxels: &[u16], p: usize) -> Vec<Slice> {
        voxels
            .chunks_exact(p * p)
            .map(|slab| {
                let mut lines = [0u64; 64];
                for (line, row) in lines.iter_mut().zip(slab.chunks_exact(p)) {
                    *line = row
                        .iter()
                        .enumerate()
                        .fold(0, |m, (x, &v)| m | u64::from(v != 0) << x);
                }
                lines
            })
            .collect()
    }

    /// [`one_id`] with the slabs found from the rows.
    fn one_id_of(voxels: &[u16], p: usize) -> FaceIds {
        let rows = rows_of(voxels, p);
        let slabs = rows.iter().enumerate().fold(0, |m, (z, lines)| {
            m | u64::from(lines.iter().any(|&r| r != 0)) << z
        });
        one_id(voxels, &rows, p, slabs)
    }

    /// What [`one_id`] finds, found voxel by voxel (below [`SAMPLED_FROM`], the one id of
    /// every solid voxel of the chunk's slabs).
    fn reference(voxels: &[u16], p: usize) -> FaceIds {
        let at = |x: usize, y: usize, z: usize| voxels[x + p * (y + p * z)];
        let inside = 1..p - 1;
        let mut faced = Vec::new();
        for z in inside.clone() {
            for y in inside.clone() {
                for x in inside.clone() {
                    let near = [
                        at(x - 1, y, z),
                        at(x + 1, y, z),
                        at(x, y - 1, z),
                        at(x, y + 1, z),
                        at(x, y, z - 1),
                        at(x, y, z + 1),
                    ];
                    if at(x, y, z) != 0 && near.contains(&0) {
                        faced.push(at(x, y, z));
                    }
                }
            }
        }
        let Some(&first) = faced.first() else {
            return FaceIds::NoFace;
        };
        let one = if p < SAMPLED_FROM {
            // Every solid voxel of the chunk's slabs.
            let slabs = &voxels[p * p..p * p * (p - 1)];
            slabs.iter().all(|&v| v == 0 || v == first)
        } else {
            faced.iter().all(|&v| v == first)
        };
        if one {
            FaceIds::One(first)
        } else {
            FaceIds::NotOne
        }
    }

    /// Sparse fills (every voxel has a face) with another id put anywhere: the first solid
    /// voxel, the middle one, a row no sample reads, a third of the way in, the last voxel
    /// (padding: no face).
    #[test]
    fn one_id_is_found_only_when_every_voxel_with_a_face_has_it() {
        let mut found = 0;
        let mut refused = 0;
        for p in [10, 18, 34, 64] {
            let len = p * p * p;
            // Solid voxels from the start, or from inside the second slab, or a lone voxel.
            for (from, step) in [(0, 3), (p * p + 7, 5), (len / 2 + p * (p / 2) + p / 2, len)] {
                for id in IDS {
                    let mut voxels = vec![0u16; len];
                    for v in voxels[from..].iter_mut().step_by(step) {
                        *v = id;
                    }
                    assert_eq!(one_id_of(&voxels, p), reference(&voxels, p));
                    assert_eq!(reference(&voxels, p), FaceIds::One(id), "{p} {from}");
                    let solid: Vec<usize> = (0..len).filter(|&i| voxels[i] != 0).collect();
                    let unsampled = p * (len / p / SAMPLES / 2) + 3;
                    for at in [
                        solid[0],
                        solid[solid.len() / 2],
                        unsampled,
                        len / 3,
                        len - 1,
                    ] {
                        for other in IDS.iter().copied().filter(|&o| o != id) {
                            let mut with_other = voxels.clone();
                            with_other[at] = other;
                            let want = reference(&with_other, p);
                            let got = one_id_of(&with_other, p);
                            assert_eq!(got, want, "{p} {from} {id} {other} at {at}");
                            if want.one().is_some() {
                                found += 1;
                            } else {
                                refused += 1;
                            }
                        }
                    }
                }
            }
        }
        assert!(
            found > 100 && refused > 100,
            "{found} found, {refused} refused"
        );
    }

    /// Filled chunks (solid across, padding included, so that most rows show no face) cut by
    /// tunnels of air along x, y and z, with other ids dropped anywhere: on buried voxels, on
    /// the tunnels' walls, in the padding. Each must give the voxel-by-voxel answer.
    #[test]
    fn filled_chunks_cut_by_tunnels_give_the_reference_answer() {
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = |below: usize| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 33) as usize % below
        };
        let (mut found, mut refused) = (0, 0);
        for p in [10, 18, 34, 64] {
            let index = |[x, y, z]: [usize; 3]| x + p * (y + p * z);
            for _ in 0..64 {
                let mut voxels = vec![5u16; p * p * p];
                let mut tunnels = Vec::new();
                for _ in 0..1 + next(4) {
                    let axis = next(3);
                    let mut at = [next(p), next(p), next(p)];
                    for _ in 0..next(p) {
                        voxels[index(at)] = 0;
                        tunnels.push(at);
                        at[axis] = (at[axis] + 1) % p;
                    }
                }
                // Half of the other ids anywhere (mostly buried), half next to a tunnel.
                for k in 0..next(4) {
                    let at = match tunnels.get(next(tunnels.len().max(1))) {
                        Some(&(mut at)) if k % 2 == 0 => {
                            let axis = next(3);
                            at[axis] = (at[axis] + 1) % p;
                            index(at)
                        }
                        _ => next(voxels.len()),
                    };
                    if voxels[at] != 0 {
                        voxels[at] = [6, 0x8005, 0xFFFF][next(3)];
                    }
                }
                let want = reference(&voxels, p);
                assert_eq!(one_id_of(&voxels, p), want, "edge {p}");
                if want.one().is_some() {
                    found += 1;
                } else {
                    refused += 1;
                }
            }
        }
        assert!(
            found > 40 && refused > 40,
            "{found} found, {refused} refused"
        );
    }

    /// A solid block of one id with a core of another: the core shows no face until one of its
    /// voxels touches air; ids in the padding show none. (Below [`SAMPLED_FROM`] the core is
    /// refused.)
    #[test]
    fn hidden_ids_and_the_padding_s_do_not_count() {
        for p in [10, 18, 34, 64] {
            let index = |x: usize, y: usize, z: usize| x + p * (y + p * z);
            let mut voxels = vec![5u16; p * p * p];
            // A core two voxels in from the chunk's faces, and other ids in the padding.
            for z in 3..p - 3 {
                for y in 3..p - 3 {
                    voxels[index(3, y, z)..index(p - 3, y, z)].fill(6);
                }
            }
            voxels[index(0, 4, 4)] = 7;
            voxels[index(p - 1, p - 1, p - 1)] = 8;
            // A pit from the top face down to just above the core (rows 3 to p - 4).
            for y in p - 2..p {
                voxels[index(p / 2, y, p / 2)] = 0;
            }
            let want = if p >= SAMPLED_FROM {
                FaceIds::One(5)
            } else {
                FaceIds::NotOne
            };
            assert_eq!(reference(&voxels, p), want, "{p}");
            assert_eq!(one_id_of(&voxels, p), want, "{p}");
            // One step deeper: the core voxel under the pit has a face.
            voxels[index(p / 2, p - 3, p / 2)] = 0;
            assert_eq!(reference(&voxels, p), FaceIds::NotOne, "{p}");
            assert_eq!(one_id_of(&voxels, p), FaceIds::NotOne, "{p}");
        }
    }

    /// Slabs with two solid rows (`y` = 3 and 7, every `z`, as in a flat maze seen edge on):
    /// another id at either end of a row, or between the rows, is found where it has a face.
    #[test]
    fn another_id_at_the_ends_of_a_slab_s_solid_rows_is_found() {
        for p in [10, 18, 34, 64] {
            let mut voxels = vec![0u16; p * p * p];
            for z in 0..p {
                for y in [3, 7] {
                    voxels[(z * p + y) * p..][..p].fill(5);
                }
            }
            assert_eq!(one_id_of(&voxels, p), FaceIds::One(5), "{p}");
            for z in [0, 1, p / 2, p - 2, p - 1] {
                let row = |y: usize| (z * p + y) * p;
                for at in [row(3), row(3) + 1, row(3) + p - 2, row(5) + 1, row(7) + 2] {
                    let mut with_other = voxels.clone();
                    with_other[at] = 6;
                    let want = reference(&with_other, p);
                    assert_eq!(one_id_of(&with_other, p), want, "{p} at {at}");
                    // Rows 3, 5 and 7 lie inside, and an id there (solid or in the air between
                    // the rows) has an air neighbour.
                    // (Below `SAMPLED_FROM` the padding of the chunk's slabs counts too.)
                    let x_inside = (1..p - 1).contains(&(at % p)) || p < SAMPLED_FROM;
                    let inside = (1..p - 1).contains(&z) && x_inside;
                    assert_eq!(want == FaceIds::NotOne, inside, "{p} at {at}");
                }
            }
        }
    }

    /// No voxel with a face (all air, solid in the padding only, everything solid but a
    /// voxel of the padding that touches none of the chunk's), or inputs that do not fit.
    #[test]
    fn chunks_without_a_face_and_mismatched_inputs_have_no_one_id() {
        for p in [10, 18, 34, 64] {
            let index = |x: usize, y: usize, z: usize| x + p * (y + p * z);
            let air = vec![0u16; p * p * p];
            assert_eq!(one_id_of(&air, p), FaceIds::NoFace, "{p}: all air");
            assert_eq!(reference(&air, p), FaceIds::NoFace, "{p}: all air");
            // The padding's slab below the chunk, and its row below the chunk in every slab.
            let mut padding = air.clone();
            padding[..p * p].fill(4);
            for z in 0..p {
                padding[index(0, 0, z)..index(0, 1, z)].fill(4);
            }
            assert_eq!(one_id_of(&padding, p), FaceIds::NoFace, "{p}: padding only");
            assert_eq!(reference(&padding, p), FaceIds::NoFace, "{p}: padding only");
            let mut buried = vec![4u16; p * p * p];
            buried[index(0, 0, p / 2)] = 0;
            assert_eq!(one_id_of(&buried, p), FaceIds::NoFace, "{p}: buried");
            assert_eq!(reference(&buried, p), FaceIds::NoFace, "{p}: buried");
            // One step in, that air voxel touches the chunk.
            buried[index(1, 0, p / 2)] = 0;
            assert_eq!(one_id_of(&buried, p), FaceIds::One(4), "{p}: one face");
        }
        let p = 10;
        let mut one = vec![0u16; p * p * p];
        one[555] = 4;
        let rows = rows_of(&one, p);
        let slabs = 1 << 5;
        assert_eq!(one_id(&one, &rows, p, slabs), FaceIds::One(4));
        let not_one = FaceIds::NotOne;
        assert_eq!(one_id(&one[1..], &rows, p, slabs), not_one, "ids too short");
        assert_eq!(
            one_id(&one, &rows[1..], p, slabs),
            not_one,
            "rows too short"
        );
        assert_eq!(one_id(&one, &rows, p + 1, slabs), not_one, "another edge");
    }
}
