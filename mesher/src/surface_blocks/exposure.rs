//! Which faces of a chunk's voxels are exposed, one padded row at a time, from the row masks.
//!
//! The rules are in the [`surface_blocks`](mod@crate::surface_blocks#exposure) module docs.
//! With `S` the hiding mask of a padded row (bit `px` set iff the voxel hides), the faces of the
//! hiding voxels of row `(py, pz)` are six AND-NOTs of shifted rows:
//!
//! ```text
//!   +x: S & !(S >> 1)      +y: S & !S[py + 1]      +z: S & !S[pz + 1]
//!   -x: S & !(S << 1)      -y: S & !S[py - 1]      -z: S & !S[pz - 1]
//! ```
//!
//! Transparent voxels are the only ones checked voxel by voxel, and only those with at least
//! one non-hiding neighbour: their face is exposed unless that neighbour holds the same id.
//! When the palette has no transparent material, `S` is the padded chunk's occupancy mask
//! itself and no voxel is read at all; otherwise `S` and the transparent mask `T` are built
//! once per chunk by one pass over the occupied rows: each row is compared with each
//! transparent id of the palette (byte compares the compiler vectorizes, packed into a mask by
//! a multiplication) when there are at most 8 of them, and looked up voxel by voxel otherwise.

use alloc::vec::Vec;

use voxel_core::{BlockId, ChunkSize, PaddedChunk};

use crate::BlockClasses;

/// Reusable masks for [`Exposure`]; keeps its capacity between chunks.
#[derive(Clone, Debug, Default)]
pub(crate) struct ExposureScratch {
    solid: Vec<u64>,
    transparent: Vec<u64>,
}

/// The exposure of one padded chunk's voxels, computed row by row on request.
pub(crate) struct Exposure<'a> {
    voxels: &'a [BlockId],
    solid: &'a [u64],
    /// `None` when the palette has no transparent material.
    transparent: Option<&'a [u64]>,
    p: usize,
    inner: u64,
}

/// Up to this many transparent ids, rows are classified by comparing them against each id.
const MAX_COMPARED_IDS: usize = 8;

/// Packs 64 bytes of 0 or 1 into the bits of a `u64`, byte `i` to bit `i`.
///
/// Each group of 8 bytes is multiplied by `0x0102_0408_1020_4080`: byte `i` of the group (bit
/// `8i`) lands on bit `56 + i` through the term `2^(8(7 - i) + i)`, and no two terms meet on a
/// bit, so the top byte is the packed group.
#[inline]
fn pack_bytes(bytes: &[u8; 64]) -> u64 {
    bytes.chunks_exact(8).enumerate().fold(0, |m, (i, group)| {
        let mut word = [0u8; 8];
        word.copy_from_slice(group);
        let packed = u64::from_le_bytes(word).wrapping_mul(0x0102_0408_1020_4080) >> 56;
        m | packed << (8 * i)
    })
}

/// Bit `x` set iff `row[x] == id` (`row` at most 64 long). Byte compares first, which the
/// compiler turns into vector compares, then [`pack_bytes`].
#[inline]
pub(crate) fn id_mask(row: &[BlockId], id: BlockId) -> u64 {
    let mut bytes = [0u8; 64];
    for (b, v) in bytes.iter_mut().zip(row) {
        *b = u8::from(*v == id);
    }
    pack_bytes(&bytes)
}

/// Bit `x` set iff `a[x] == b[x]` (at most 64 long); vectorized like [`id_mask`].
#[inline]
pub(crate) fn eq_mask(a: &[BlockId], b: &[BlockId]) -> u64 {
    let mut bytes = [0u8; 64];
    for (byte, (a, b)) in bytes.iter_mut().zip(a.iter().zip(b)) {
        *byte = u8::from(a == b);
    }
    pack_bytes(&bytes)
}

/// Bits `1..=e` of a padded row: the chunk's own voxels.
#[inline]
pub(crate) fn inner_mask(size: ChunkSize) -> u64 {
    ((1u64 << size.edge()) - 1) << 1
}

/// True when no voxel of the chunk can have an exposed face, known from the row masks alone:
/// the chunk is empty, or it is full and buried with no transparent material in the palette.
/// The early-out shared by the surface-block and shell extractions.
pub(crate) fn nothing_exposed(chunk: &PaddedChunk, classes: &BlockClasses) -> bool {
    chunk_is_empty(chunk) || (!classes.any_transparent() && chunk_is_full(chunk))
}

/// True if the chunk itself (not its border) holds no voxel: nothing can be exposed.
pub(crate) fn chunk_is_empty(chunk: &PaddedChunk) -> bool {
    let p = chunk.padded_edge();
    let inner = inner_mask(chunk.size());
    chunk.columns()[p..p * (p - 1)]
        .chunks_exact(p)
        .all(|plane| plane[1..p - 1].iter().all(|&row| row & inner == 0))
}

/// True if every voxel of the chunk and every face neighbour of one is occupied. When the
/// palette has no transparent material that means every voxel is buried.
pub(crate) fn chunk_is_full(chunk: &PaddedChunk) -> bool {
    let p = chunk.padded_edge();
    let inner = inner_mask(chunk.size());
    let full = inner | 1 | (1u64 << (p - 1));
    chunk
        .columns()
        .chunks_exact(p)
        .enumerate()
        .all(|(pz, plane)| {
            let z_border = pz == 0 || pz == p - 1;
            plane.iter().enumerate().all(|(py, &row)| {
                let y_border = py == 0 || py == p - 1;
                let need = match (z_border, y_border) {
                    (true, true) => 0,
                    (false, false) => full,
                    _ => inner,
                };
                row & need == need
            })
        })
}

impl ExposureScratch {
    /// Prepares the hiding and transparent masks of `chunk`.
    pub(crate) fn prepare<'a>(
        &'a mut self,
        chunk: &'a PaddedChunk,
        classes: &BlockClasses,
    ) -> Exposure<'a> {
        let p = chunk.padded_edge();
        let voxels = chunk.voxels();
        let columns = chunk.columns();
        let inner = inner_mask(chunk.size());
        if !classes.any_transparent() {
            return Exposure {
                voxels,
                solid: columns,
                transparent: None,
                p,
                inner,
            };
        }
        self.solid.clear();
        self.solid.extend_from_slice(columns);
        self.transparent.clear();
        self.transparent.resize(columns.len(), 0);
        // With few transparent ids (the usual case: water, glass, ice), whole-row compares
        // against each; otherwise one table lookup per occupied voxel.
        let few = classes.transparent_ids();
        let few = (few.len() <= MAX_COMPARED_IDS).then_some(few);
        let rows = voxels.chunks_exact(p).zip(columns);
        let masks = self.solid.iter_mut().zip(self.transparent.iter_mut());
        for ((row, &occupied), (solid, transparent)) in rows.zip(masks) {
            if occupied == 0 {
                continue;
            }
            let t = match few {
                Some(ids) => ids.iter().fold(0, |t, &id| t | id_mask(row, id)),
                None => row.iter().enumerate().fold(0, |t, (x, &id)| {
                    t | (u64::from(classes.is_transparent(id)) << x)
                }),
            };
            *transparent = t & occupied;
            *solid = occupied & !t;
        }
        Exposure {
            voxels,
            solid: &self.solid,
            transparent: Some(&self.transparent),
            p,
            inner,
        }
    }
}

impl Exposure<'_> {
    /// The exposed faces of the chunk voxels in padded row `(py, pz)`, both in `1..=e`: one
    /// mask per face direction in `FaceDirection::ALL` order (+x, -x, +y, -y, +z, -z), bit
    /// `px` set iff voxel `(px, py, pz)` shows that face. Only bits `1..=e` can be set.
    #[inline]
    pub(crate) fn row_faces(&self, py: usize, pz: usize) -> [u64; 6] {
        let p = self.p;
        let r = py + p * pz;
        let s = self.solid[r];
        let neighbours = [
            s >> 1,
            s << 1,
            self.solid[r + 1],
            self.solid[r - 1],
            self.solid[r + p],
            self.solid[r - p],
        ];
        let own = s & self.inner;
        let mut faces = neighbours.map(|n| own & !n);
        let Some(transparent) = self.transparent else {
            return faces;
        };
        let all_hidden = neighbours.iter().fold(u64::MAX, |acc, n| acc & n);
        let mut candidates = transparent[r] & self.inner & !all_hidden;
        let offsets = [
            1,
            -1,
            p as isize,
            -(p as isize),
            (p * p) as isize,
            -((p * p) as isize),
        ];
        while candidates != 0 {
            let px = candidates.trailing_zeros() as usize;
            candidates &= candidates - 1;
            let index = px + p * r;
            let id = self.voxels[index];
            for ((face, &neighbour), &offset) in faces.iter_mut().zip(&neighbours).zip(&offsets) {
                let other = self.voxels[index.wrapping_add_signed(offset)];
                let shown = (neighbour >> px) & 1 == 0 && other != id;
                *face |= u64::from(shown) << px;
            }
        }
        faces
    }

    /// The union of [`row_faces`](Self::row_faces): bit `px` set iff the voxel shows any face.
    #[inline]
    pub(crate) fn row_exposed(&self, py: usize, pz: usize) -> u64 {
        self.row_faces(py, pz).iter().fold(0, |acc, f| acc | f)
    }
}
