//! The `vertical_shells` body.

use mesher::{BlockClasses, MeshError, ShellRuns};
use voxel_core::{BlockId, ChunkSize, PaddedChunk};

use super::input::{ChunkInput, chunk_input, voxel_id};
use super::{chunk_positions, exposed_faces, id_at, unknown};

/// The exposed-face bits (bit `d`: face `FaceDirection::ALL[d]`) of every chunk voxel, index
/// `(x - 1) + e * ((y - 1) + e * (z - 1))` for padded `(x, y, z)`; 0 for a voxel that is not
/// exposed.
pub(super) fn face_bits(padded: &PaddedChunk, classes: &BlockClasses) -> Vec<u8> {
    chunk_positions(padded)
        .map(|pos| {
            exposed_faces(padded, classes, pos)
                .iter()
                .enumerate()
                .fold(0u8, |bits, (d, &shown)| bits | (u8::from(shown) << d))
        })
        .collect()
}

/// Index of padded chunk position `pos` in [`face_bits`].
pub(super) fn chunk_index(padded: &PaddedChunk, pos: [u32; 3]) -> usize {
    let e = padded.size().edge_usize();
    let [x, y, z] = pos.map(|a| a as usize - 1);
    x + e * (y + e * z)
}

/// A chunk of another size than `size` (a small one), to leave a reused buffer's scratch
/// holding something else first.
pub(super) fn other_chunk(size: ChunkSize) -> PaddedChunk {
    let other = if size == ChunkSize::S8 {
        ChunkSize::S16
    } else {
        ChunkSize::S8
    };
    PaddedChunk::from_fn(other, |x, y, z| voxel_id(((x ^ y ^ z) % 7) as u8))
}

/// `vertical_shells` on an arbitrary chunk ([`ChunkInput`]), in a fresh buffer and in one that
/// first held another chunk (same result). Against the per-voxel exposure rule:
///
/// - it fails exactly when an exposed voxel holds an unknown id, naming such a voxel that is
///   the lowest of its run (the one below is not an exposed voxel of that id), and leaves the
///   buffer empty;
/// - otherwise the runs cover every exposed voxel exactly once; each is `1..=edge - y` voxels
///   of one id, inside the chunk, maximal (the voxels just below and above are not exposed
///   voxels of its id), with `reserved` 0 and `sides` the OR of its voxels' exposed faces.
pub(crate) fn vertical_shells(data: &[u8]) {
    let Some(input) = chunk_input(data) else {
        return;
    };
    let ChunkInput {
        padded, classes, ..
    } = &input;
    let e = padded.size().edge();
    let faces = face_bits(padded, classes);
    let exposed = |pos: [u32; 3]| faces[chunk_index(padded, pos)];
    let shows_unknown =
        chunk_positions(padded).any(|p| exposed(p) != 0 && unknown(classes, id_at(padded, p)));

    let mut fresh = ShellRuns::new();
    let result = mesher::vertical_shells(padded, classes, &mut fresh);
    let mut reused = ShellRuns::new();
    // The other chunk's result does not matter, only that the buffer held it.
    let _ = mesher::vertical_shells(&other_chunk(padded.size()), classes, &mut reused);
    let again = mesher::vertical_shells(padded, classes, &mut reused);
    assert_eq!(result, again, "a reused buffer gives another result");
    assert_eq!(
        fresh.runs(),
        reused.runs(),
        "a reused buffer gives other runs"
    );

    match result {
        Ok(()) => {
            assert!(!shows_unknown, "an exposed unknown id was drawn");
            let mut covered = vec![false; faces.len()];
            for run in fresh.runs() {
                let (x, y, z, height) = (
                    u32::from(run.x),
                    u32::from(run.y),
                    u32::from(run.z),
                    u32::from(run.height),
                );
                assert!(x < e && z < e && height >= 1 && y + height <= e, "{run:?}");
                assert_eq!(run.wide, 0, "vertical shells are one column wide: {run:?}");
                let mut sides = 0u8;
                for py in y + 1..=y + height {
                    let pos = [x + 1, py, z + 1];
                    let bits = exposed(pos);
                    assert!(bits != 0, "{pos:?} of {run:?} is not exposed");
                    assert_eq!(id_at(padded, pos), BlockId(run.block), "{pos:?} of {run:?}");
                    let seen = std::mem::replace(&mut covered[chunk_index(padded, pos)], true);
                    assert!(!seen, "{pos:?} is in two runs");
                    sides |= bits;
                }
                assert_eq!(run.sides, sides, "side bits of {run:?}");
                // Maximal: padded y of the voxel below the run, and of the one above.
                for py in [y, y + height + 1] {
                    if (1..=e).contains(&py) {
                        let pos = [x + 1, py, z + 1];
                        assert!(
                            !(exposed(pos) != 0 && id_at(padded, pos) == BlockId(run.block)),
                            "{run:?} could grow to {pos:?}"
                        );
                    }
                }
            }
            let missed = chunk_positions(padded)
                .find(|&p| exposed(p) != 0 && !covered[chunk_index(padded, p)]);
            assert_eq!(missed, None, "an exposed voxel is in no run");
        }
        Err(MeshError::UnknownBlock { id, position }) => {
            assert!(unknown(classes, id), "{id:?} is known");
            assert!(position.iter().all(|a| (1..=e).contains(a)), "{position:?}");
            assert_eq!(id_at(padded, position), id, "the voxel at {position:?}");
            assert!(exposed(position) != 0, "{position:?} is not exposed");
            let [x, y, z] = position;
            if y > 1 {
                let below = [x, y - 1, z];
                assert!(
                    !(exposed(below) != 0 && id_at(padded, below) == id),
                    "{position:?} is not the lowest voxel of its run"
                );
            }
            assert!(fresh.is_empty(), "runs left after an error");
        }
        Err(other) => panic!("unexpected error {other:?}"),
    }
}
