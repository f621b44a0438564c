//! Whether the solid voxels of a chunk all have one id (a one-material chunk: an occupancy
//! grid, a sculpt, a stone cave). With AO off every face then has one key, so the greedy pass
//! keys nothing and reads no id: the faces that merge are the neighbouring ones.

/// Ids compared before the scan may stop: a vectorised fold over a block, then one branch.
const BLOCK: usize = 256;

/// The id of every solid (non-air) voxel of `voxels` if they all have the one of the voxel at
/// `first`, else `None` (also if `first` is out of range or air). `voxels[..first]` is air;
/// `last` is the last solid voxel, compared first: on a chunk of layered materials (terrain)
/// the lowest and the highest differ, and nothing is scanned.
#[inline(always)]
pub(crate) fn one_id(voxels: &[u16], first: usize, last: usize) -> Option<u16> {
    let rest = voxels.get(first..)?;
    let id = *rest.first().filter(|&&id| id != 0)?;
    if voxels.get(last) != Some(&id) {
        return None;
    }
    // A voxel is neither air nor `id` iff neither it nor its XOR with `id` is zero: iff
    // their minimum is not. Per block, those minima ORed together, which vectorises to
    // three operations per register of ids and one test.
    let only_id = |block: &[u16]| block.iter().fold(0u16, |acc, &v| acc | v.min(v ^ id)) == 0;
    let (blocks, tail) = rest.as_chunks::<BLOCK>();
    for block in blocks {
        if !only_id(block) {
            return None;
        }
    }
    if !only_id(tail) {
        return None;
    }
    Some(id)
}

#[cfg(test)]
mod tests {
    use alloc::vec;

    use super::*;

    /// Ids at the edges of the XOR-and-minimum test: the smallest and largest, the sign bit,
    /// ids that differ from another in one bit only.
    const IDS: [u16; 7] = [1, 2, 3, 0x7FFF, 0x8000, 0xFFFE, 0xFFFF];

    #[test]
    fn one_id_is_found_only_when_every_solid_voxel_has_it() {
        // Lengths of the arrays the mesher takes (10^3 to 64^3 ids), and one that ends inside
        // a block; the first solid voxel at the start, inside, and at a block's edge.
        for len in [1000, 5832, 39_304, 262_144, 1000 + BLOCK / 2] {
            for first in [0, 7, BLOCK - 1, BLOCK] {
                for id in IDS {
                    let mut voxels = vec![0u16; len];
                    for v in voxels[first..].iter_mut().step_by(3) {
                        *v = id;
                    }
                    let last = voxels.iter().rposition(|&v| v != 0).unwrap();
                    assert_eq!(one_id(&voxels, first, last), Some(id), "{len} {first} {id}");
                    // Another id anywhere after the first: at block edges, in the tail, last.
                    for at in [first + 1, BLOCK, 2 * BLOCK - 1, len - 2, len - 1] {
                        for other in IDS.iter().copied().filter(|&o| o != id) {
                            let mut with_other = voxels.clone();
                            with_other[at] = other;
                            let last = with_other.iter().rposition(|&v| v != 0).unwrap();
                            assert_eq!(
                                one_id(&with_other, first, last),
                                None,
                                "{len} {first} {id} {other} at {at}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn air_or_an_out_of_range_first_voxel_has_no_one_id() {
        let voxels = vec![0u16, 0, 5, 5];
        assert_eq!(one_id(&voxels, 2, 3), Some(5));
        assert_eq!(one_id(&voxels, 0, 3), None, "the first voxel is air");
        assert_eq!(one_id(&voxels, 4, 3), None, "past the end");
        assert_eq!(one_id(&voxels, 2, 1), None, "the last voxel is air");
        assert_eq!(
            one_id(&voxels, 2, 9),
            None,
            "the last voxel is past the end"
        );
    }
}
