//! Whether the solid voxels of a chunk all have one id (a one-material chunk: an occupancy
//! grid, a sculpt, a stone cave). With AO off every face then has one key, so the greedy pass
//! keys nothing and reads no id: the faces that merge are the neighbouring ones.

use super::bits::{occupied_rows, ones};

/// Rows whose first and last solid voxels are compared with the chunk's first before any
/// slab is scanned: on a chunk of several ids one of them nearly always differs, and the scan
/// (a read of every id) is skipped. They are taken every `p * p / SAMPLES + 1` rows (about two
/// per slab at 62^3), a step that is not a multiple of `p`, so that they fall on different
/// rows (y) of their slabs rather than all on the bottom padding row, which is mostly air.
/// Only chunks of padded edge [`SAMPLED_FROM`] and more are sampled.
const SAMPLES: usize = 128;

/// The smallest padded edge whose chunks are sampled before the scan. Below it the samples
/// cost more than the scans they spare: an 8^3 chunk's are every row, and made AO off 7 %
/// slower than AO on for the terrain bench chunk at 8^3. Without them, AO off runs 8 % to
/// 10 % fewer instructions at 8^3 and 2 % to 5 % fewer at 16^3 on the sphere, Menger sponge,
/// flat maze and `monu` models (callgrind; foliage, where the first slab's scan stops, the same).
const SAMPLED_FROM: usize = 34;

/// The id of every solid (non-air) voxel of the padded chunk `voxels` (edge `p`, occupancy
/// `columns`: bit `x` of column `y + p * z` is voxel `x + p * (y + p * z)`; bit `z` of `slabs`
/// set iff slab `z` has a solid voxel) if they all have one, else `None` (also if every voxel
/// is air, or the inputs do not fit together).
///
/// First, from padded edge [`SAMPLED_FROM`] on, the first and last solid voxel of the chunk
/// and of [`SAMPLES`] rows spread over it are compared (a chunk of layered or painted
/// materials stops here); then the ids of every slab with a solid voxel are scanned, a slab at
/// a time, from its first solid row to its last.
#[inline(always)]
pub(crate) fn one_id(voxels: &[u16], columns: &[u64], p: usize, slabs: u64) -> Option<u16> {
    if p == 0 || p > 64 || voxels.len() != p * p * p || columns.len() != p * p || slabs == 0 {
        return None;
    }
    let solid_ends = |c: usize| {
        let row = columns.get(c).copied().unwrap_or(0);
        let at = |x: u32| voxels.get(c * p + x as usize).copied();
        (at(row.trailing_zeros()), at(63 - row.leading_zeros()))
    };
    // The first and last row with a solid voxel, in the first and last slab with one.
    let slab_rows = |z: u32| columns.chunks_exact(p).nth(z as usize).unwrap_or(&[]);
    let (first_slab, last_slab) = (slabs.trailing_zeros(), 63 - slabs.leading_zeros());
    let first_row = first_slab as usize * p + slab_rows(first_slab).iter().position(|&c| c != 0)?;
    let last_row = last_slab as usize * p + slab_rows(last_slab).iter().rposition(|&c| c != 0)?;
    let id = solid_ends(first_row).0?;
    if p >= SAMPLED_FROM {
        let stride = columns.len() / SAMPLES + 1;
        let rows = (0..columns.len()).step_by(stride).chain([last_row]);
        for c in rows.filter(|&c| columns[c] != 0) {
            if solid_ends(c) != (Some(id), Some(id)) {
                return None;
            }
        }
    }
    // A voxel is neither air nor `id` iff neither it nor its XOR with `id` is zero: iff
    // their minimum is not. Per slab, those minima ORed together, which vectorises to three
    // operations per register of ids and one test. Only the rows from the slab's first solid
    // row to its last are read: where a slab has few solid rows (a floor seen edge on, a flat
    // maze), reading all its ids made this scan cost more than keying the faces with AO on.
    for z in ones(slabs) {
        let rows = occupied_rows(columns.get(z * p..(z + 1) * p)?)?;
        let ids = voxels.get((z * p + rows.start) * p..(z * p + rows.end) * p)?;
        if ids.iter().fold(0u16, |acc, &v| acc | v.min(v ^ id)) != 0 {
            return None;
        }
    }
    Some(id)
}

#[cfg(test)]
mod tests {
    use alloc::vec;
    use alloc::vec::Vec;

    use super::*;

    /// Ids at the edges of the XOR-and-minimum test: the smallest and largest, the sign bit,
    /// ids that differ from another in one bit only.
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
    fn one_id_of(voxels: &[u16], columns: &[u64], p: usize) -> Option<u16> {
        let slabs = columns.chunks(p).enumerate().fold(0, |m, (z, rows)| {
            m | u64::from(rows.iter().any(|&r| r != 0)) << z
        });
        one_id(voxels, columns, p, slabs)
    }

    /// One id of every solid voxel, read one by one.
    fn reference(voxels: &[u16]) -> Option<u16> {
        let mut solid = voxels.iter().copied().filter(|&v| v != 0);
        let first = solid.next()?;
        solid.all(|v| v == first).then_some(first)
    }

    #[test]
    fn one_id_is_found_only_when_every_solid_voxel_has_it() {
        for p in [10, 18, 34, 64] {
            let len = p * p * p;
            // Solid voxels from the start, or from inside the second slab, or a lone voxel.
            for (from, step) in [(0, 3), (p * p + 7, 5), (len / 2 + 1, len)] {
                for id in IDS {
                    let mut voxels = vec![0u16; len];
                    for v in voxels[from..].iter_mut().step_by(step) {
                        *v = id;
                    }
                    let columns = columns_of(&voxels, p);
                    assert_eq!(one_id_of(&voxels, &columns, p), Some(id), "{p} {from} {id}");
                    assert_eq!(reference(&voxels), Some(id));
                    // Another id anywhere: the first solid voxel, a sampled row's ends, a
                    // row no sample reads, inside a slab, the last voxel.
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
                            let columns = columns_of(&with_other, p);
                            assert_eq!(
                                one_id_of(&with_other, &columns, p),
                                reference(&with_other),
                                "{p} {from} {id} {other} at {at}"
                            );
                        }
                    }
                }
            }
        }
    }

    /// Slabs with two solid rows (`y` = 3 and 7, every `z`, as in a flat maze seen edge on),
    /// where only the rows from the first solid one to the last are read: another id at
    /// either end of that range, or between, is found.
    #[test]
    fn another_id_at_the_ends_of_a_slab_s_solid_rows_is_found() {
        for p in [10, 18, 34, 64] {
            let mut voxels = vec![0u16; p * p * p];
            for z in 0..p {
                for y in [3, 7] {
                    voxels[(z * p + y) * p..][..p].fill(5);
                }
            }
            let columns = columns_of(&voxels, p);
            assert_eq!(one_id_of(&voxels, &columns, p), Some(5), "{p}");
            for z in [0, p / 2, p - 1] {
                let row = |y: usize| (z * p + y) * p;
                for at in [row(3), row(3) + p - 1, row(5) + 1, row(7), row(7) + p - 1] {
                    let mut with_other = voxels.clone();
                    with_other[at] = 6;
                    let columns = columns_of(&with_other, p);
                    assert_eq!(one_id_of(&with_other, &columns, p), None, "{p} at {at}");
                }
            }
        }
    }

    #[test]
    fn air_or_mismatched_inputs_have_no_one_id() {
        let p = 10;
        let air = vec![0u16; p * p * p];
        assert_eq!(one_id_of(&air, &columns_of(&air, p), p), None, "all air");
        let mut one = air.clone();
        one[555] = 4;
        let columns = columns_of(&one, p);
        assert_eq!(one_id_of(&one, &columns, p), Some(4));
        assert_eq!(one_id_of(&one[1..], &columns, p), None, "ids too short");
        assert_eq!(one_id_of(&one, &columns[1..], p), None, "columns too short");
        assert_eq!(one_id_of(&one, &columns, p + 1), None, "another edge");
    }
}
