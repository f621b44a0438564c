//! Whether every face of a chunk has one id: a one-material chunk (an occupancy grid, a
//! sculpt, a stone cave), or a chunk whose other ids are all hidden (a model filled with a
//! core material, stone with ores buried in it). With AO off every face then has one key, so
//! the greedy pass keys nothing and reads no id: the faces that merge are the neighbouring
//! ones.
//!
//! Only the voxels that have a face are read: those of the chunk (not its padding) that are
//! solid and have an air neighbour. A voxel with six solid neighbours shows no face, whatever
//! its id; a voxel of the padding shows none either (its faces are the next chunk's).

use super::bits::{buried, faces_of_id, nonzero_lines, occupied_rows, ones};

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
/// spare (an 8^3 chunk's are every row, and made AO off 7 % slower than AO on for the terrain
/// bench chunk at 8^3), and so does comparing rows one by one: there every solid voxel of
/// the chunk's slabs must have the id.
pub(crate) const SAMPLED_FROM: usize = 34;

/// The id of every voxel with a face in the padded chunk `voxels` (edge `p`, occupancy
/// `columns`: bit `x` of column `y + p * z` is voxel `x + p * (y + p * z)`; bit `z` of `slabs`
/// set iff slab `z` has a solid voxel), if they all have one, else `None` (also if no voxel
/// has a face, or the inputs do not fit together). A voxel has a face when it lies inside the
/// chunk (coordinates `1..=p - 2`), is solid, and one of its six neighbours is air; `columns`
/// must be the opaque occupancy (no transparent voxel). Below padded edge [`SAMPLED_FROM`]
/// every solid voxel of slabs `1..=p - 2` must have the id.
///
/// First, from padded edge [`SAMPLED_FROM`] on, the ends of [`SAMPLES`] rows spread over the
/// chunk are compared with the id of the first voxel with a face (a chunk of layered or
/// painted materials stops here); then every slab's ids, and in a slab with
/// another id, every row with a face.
#[inline(always)]
pub(crate) fn one_id(voxels: &[u16], columns: &[u64], p: usize, slabs: u64) -> Option<u16> {
    if !(3..=64).contains(&p) || voxels.len() != p * p * p || columns.len() != p * p {
        return None;
    }
    let e = p - 2;
    // Bits (and rows, and slabs) 1..=e: the chunk without its padding.
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
    let slabs = slabs & inner;
    let (y0, z0, first) = ones(slabs)
        .flat_map(|z| (1..=e).map(move |y| (y, z)))
        .map(|(y, z)| (y, z, faced_row(columns, p, inner, y, z)))
        .find(|&(_, _, f)| f != 0)?;
    let id = *ids(y0, z0)?.get(first.trailing_zeros() as usize)?;
    if p >= SAMPLED_FROM {
        // Row `y + p * z` every `stride` rows, `y` and `z` stepped along without a division.
        let stride = columns.len() / SAMPLES + 1;
        let (step_y, step_z) = (stride % p, stride / p);
        let (mut y, mut z) = (0, 0);
        for _ in 0..columns.len().div_ceil(stride) {
            if (1..=e).contains(&y) && (slabs >> (z & 63)) & 1 != 0 {
                // The row's solid ends first (two reads): they have a face, or lie in the
                // padding; only where they differ are the voxels with a face found.
                let c = y + p * z;
                let solid = columns.get(c).copied().unwrap_or(0);
                if solid != 0 && row_ends(voxels, c * p, solid) != (Some(id), Some(id)) {
                    let f = faced_row(columns, p, inner, y, z);
                    if f != 0 && row_ends(voxels, c * p, f) != (Some(id), Some(id)) {
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
    for z in ones(slabs) {
        // Most slabs hold no other id at all: one read of the ids of their solid rows answers
        // for every voxel. A voxel is neither air nor `id` iff neither it nor its XOR with
        // `id` is zero: iff their minimum is not. Those minima ORed together vectorise to
        // three operations per register of ids and one test.
        let rows = occupied_rows(columns.get(z * p..(z + 1) * p)?)?;
        let slab_ids = voxels.get((z * p + rows.start) * p..(z * p + rows.end) * p)?;
        if slab_ids.iter().fold(0u16, |acc, &v| acc | v.min(v ^ id)) == 0 {
            continue;
        }
        // Another id somewhere in the slab: it counts only where it has a face. Chunks below
        // `SAMPLED_FROM` stop here: their rows cost more to compare one by one than keying
        // their faces saves (foliage at 8^3: 2.8 % more instructions with AO off).
        if p < SAMPLED_FROM {
            return None;
        }
        // The slab's voxels with a face, row by row, from rows y - 1, y, y + 1 of the slab and
        // row y of the slabs around it: one pass over zipped slices with no branch, which the
        // compiler vectorises; then only the rows with a face are compared.
        let slab = |z: usize| columns.get(z * p..(z + 1) * p).unwrap_or(&[]);
        let (below, here, above) = (slab(z - 1), slab(z), slab(z + 1));
        let mut faced = [0u64; 64];
        let rows = (here.iter().zip(here.get(1..)?).zip(here.get(2..)?))
            .zip(below.get(1..)?)
            .zip(above.get(1..)?);
        for (f, ((((&before, &r), &after), &under), &over)) in faced[1..].iter_mut().zip(rows) {
            *f = r & inner & !buried(r, [before, after], [under, over]);
        }
        for y in ones(nonzero_lines(&faced)) {
            let f = faced[y];
            if faces_of_id(ids(y, z)?, id, f) != f {
                return None;
            }
        }
    }
    Some(id)
}

/// The ids at the lowest and highest set bit of `bits` in the row of `voxels` that starts at
/// index `start`.
#[inline(always)]
fn row_ends(voxels: &[u16], start: usize, bits: u64) -> (Option<u16>, Option<u16>) {
    let at = |x: u32| voxels.get(start + x as usize).copied();
    (at(bits.trailing_zeros()), at(63 - bits.leading_zeros()))
}

/// Bit `x`: voxel `(x, y, z)` of the chunk (`inner`: bits 1..=p - 2) is solid and has an air
/// neighbour, from the occupancy `columns` (`y` and `z` inside the chunk).
#[inline(always)]
fn faced_row(columns: &[u64], p: usize, inner: u64, y: usize, z: usize) -> u64 {
    let row = |y: usize, z: usize| columns.get(y + p * z).copied().unwrap_or(0);
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

    /// Occupancy columns of padded ids of edge `p`.
    fn columns_of(voxels: &[u16], p: usize) -> Vec<u64> {
        voxels
            .chunks_exact(p)
            .map(|row| {
                row.iter()
                    .enumerate()
                    .fold(0, |m, (x, &v)| m | u64::from(v != 0) << x)
            })
            .collect()
    }

    /// [`one_id`] with the slabs found from the columns.
    fn one_id_of(voxels: &[u16], p: usize) -> Option<u16> {
        let columns = columns_of(voxels, p);
        let slabs = columns.chunks(p).enumerate().fold(0, |m, (z, rows)| {
            m | u64::from(rows.iter().any(|&r| r != 0)) << z
        });
        one_id(voxels, &columns, p, slabs)
    }

    /// One id of every voxel with a face, found voxel by voxel (below [`SAMPLED_FROM`], of
    /// every solid voxel of the chunk's slabs).
    fn reference(voxels: &[u16], p: usize) -> Option<u16> {
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
        let first = *faced.first()?;
        if p < SAMPLED_FROM {
            // Every solid voxel of the chunk's slabs.
            let slabs = &voxels[p * p..p * p * (p - 1)];
            return slabs.iter().all(|&v| v == 0 || v == first).then_some(first);
        }
        faced.iter().all(|&v| v == first).then_some(first)
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
                    assert_eq!(reference(&voxels, p), Some(id), "{p} {from}");
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
                            if want.is_some() {
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
            let want = (p >= SAMPLED_FROM).then_some(5);
            assert_eq!(reference(&voxels, p), want, "{p}");
            assert_eq!(one_id_of(&voxels, p), want, "{p}");
            // One step deeper: the core voxel under the pit has a face.
            voxels[index(p / 2, p - 3, p / 2)] = 0;
            assert_eq!(reference(&voxels, p), None, "{p}");
            assert_eq!(one_id_of(&voxels, p), None, "{p}");
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
            assert_eq!(one_id_of(&voxels, p), Some(5), "{p}");
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
                    assert_eq!(want.is_none(), inside, "{p} at {at}");
                }
            }
        }
    }

    #[test]
    fn air_or_mismatched_inputs_have_no_one_id() {
        let p = 10;
        let air = vec![0u16; p * p * p];
        assert_eq!(one_id_of(&air, p), None, "all air");
        let mut one = air.clone();
        one[555] = 4;
        let columns = columns_of(&one, p);
        let slabs = 1 << 5;
        assert_eq!(one_id(&one, &columns, p, slabs), Some(4));
        assert_eq!(one_id(&one[1..], &columns, p, slabs), None, "ids too short");
        assert_eq!(
            one_id(&one, &columns[1..], p, slabs),
            None,
            "columns too short"
        );
        assert_eq!(one_id(&one, &columns, p + 1, slabs), None, "another edge");
        // Solid only in the padding: no face.
        let mut padding = air.clone();
        padding[0] = 4;
        assert_eq!(one_id_of(&padding, p), None, "padding only");
    }
}
