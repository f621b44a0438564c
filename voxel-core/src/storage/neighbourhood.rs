//! [`PaddedChunk`] and [`gather_neighbourhood`]: a chunk plus its one-voxel border, the input of
//! every mesher.
//!
//! # Padding contract
//!
//! For a chunk of edge `e` the padded box has edge `p = e + 2` (64 for a 62^3 chunk, so a padded
//! row's occupancy is exactly one `u64`). The chunk's voxel `(x, y, z)` sits at padded
//! `(x + 1, y + 1, z + 1)`; padded coordinate 0 on an axis is the last layer (`e - 1`) of the
//! neighbour below on that axis, and padded `e + 1` is the first layer (`0`) of the neighbour
//! above. One padded row (fixed `py`, `pz`):
//!
//! ```text
//!  padded x:   0     1     2    ...    e    e+1
//!           +-----+-----+-----+-...-+-----+-----+
//!           |  W  | x=0 | x=1 |     |e - 1|  E  |     W = -x neighbour's x = e-1
//!           +-----+-----+-----+-...-+-----+-----+     E = +x neighbour's x = 0
//!  mask bit:   0     1     2           e    e+1
//! ```
//!
//! Which chunk supplies each row, seen along x (offsets are `(dy, dz)`; the W and E voxels of a
//! row come from the chunks one step further along -x and +x, so all 26 neighbours are read:
//! 6 faces, 12 edges, 8 corners):
//!
//! ```text
//!            pz = 0      pz = 1..=e     pz = e+1
//!          +----------+-------------+----------+
//! py = e+1 | (+1, -1) |   (+1,  0)  | (+1, +1) |
//!          +----------+-------------+----------+
//! py 1..=e | ( 0, -1) |   centre    | ( 0, +1) |
//!          +----------+-------------+----------+
//! py = 0   | (-1, -1) |   (-1,  0)  | (-1, +1) |
//!          +----------+-------------+----------+
//! ```
//!
//! Missing neighbours, and neighbours whose coordinate would leave the `i32` range, read as air.
//! Voxels are stored x fastest: index `px + p * (py + p * pz)`; occupancy masks one per padded
//! row, index `py + p * pz`, bit `px` set iff the padded voxel is not air.

use alloc::vec;
use alloc::vec::Vec;

use crate::{BlockId, ChunkCoord, ChunkSize, CoordError, LocalPos};

use super::{VoxelStorage, WorldMap};

/// A chunk with its one-voxel border: `(e + 2)^3` voxels and `(e + 2)^2` row masks. See the
/// [module docs](self) for the layout. Reusable: [`reset`](PaddedChunk::reset) and
/// [`gather_neighbourhood`] keep the buffers' capacity.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PaddedChunk {
    size: ChunkSize,
    voxels: Vec<BlockId>,
    columns: Vec<u64>,
}

impl PaddedChunk {
    /// An all-air padded chunk for chunks of `size`.
    pub fn new(size: ChunkSize) -> Self {
        let p = size.padded_edge();
        PaddedChunk {
            size,
            voxels: vec![BlockId::AIR; p * p * p],
            columns: vec![0; p * p],
        }
    }

    /// A padded chunk whose voxel at padded `(px, py, pz)` is `f(px, py, pz)`, each axis in
    /// `0..padded_edge`, called in storage order.
    pub fn from_fn(size: ChunkSize, mut f: impl FnMut(u32, u32, u32) -> BlockId) -> Self {
        let mut out = PaddedChunk::new(size);
        let p = size.padded_edge();
        for (c, row) in out.voxels.chunks_exact_mut(p).enumerate() {
            let (py, pz) = ((c % p) as u32, (c / p) as u32);
            let mut mask = 0;
            for (px, v) in row.iter_mut().enumerate() {
                *v = f(px as u32, py, pz);
                mask |= u64::from(!v.is_air()) << px;
            }
            out.columns[c] = mask;
        }
        out
    }

    /// Makes this an all-air padded chunk for `size`, keeping the buffers' capacity.
    pub fn reset(&mut self, size: ChunkSize) {
        self.resize(size);
        self.voxels.fill(BlockId::AIR);
        self.columns.fill(0);
    }

    /// Sets the size and buffer lengths without clearing (the gather overwrites everything).
    fn resize(&mut self, size: ChunkSize) {
        let p = size.padded_edge();
        self.size = size;
        self.voxels.resize(p * p * p, BlockId::AIR);
        self.columns.resize(p * p, 0);
    }

    /// The size of the chunk at the centre.
    #[inline]
    pub fn size(&self) -> ChunkSize {
        self.size
    }

    /// Padded edge: chunk edge + 2.
    #[inline]
    pub fn padded_edge(&self) -> usize {
        self.size.padded_edge()
    }

    /// The padded voxels, x fastest: index with [`index`](Self::index).
    #[inline]
    pub fn voxels(&self) -> &[BlockId] {
        &self.voxels
    }

    /// The padded row masks, index `py + padded_edge * pz`, bit `px` set iff not air.
    #[inline]
    pub fn columns(&self) -> &[u64] {
        &self.columns
    }

    /// Linear index of padded `(px, py, pz)`: `px + p * (py + p * pz)`. Does not check the
    /// axes; use [`get`](Self::get) for a checked read.
    #[inline]
    pub fn index(&self, px: u32, py: u32, pz: u32) -> usize {
        let p = self.padded_edge();
        px as usize + p * (py as usize + p * pz as usize)
    }

    fn check(&self, pos: [u32; 3]) -> Result<(), CoordError> {
        let p = self.padded_edge() as u32;
        if pos.iter().any(|&a| a >= p) {
            return Err(CoordError::LocalOutOfChunk { pos, edge: p });
        }
        Ok(())
    }

    /// The voxel at padded `(px, py, pz)`, or an error naming the padded edge.
    pub fn get(&self, px: u32, py: u32, pz: u32) -> Result<BlockId, CoordError> {
        self.check([px, py, pz])?;
        Ok(self.voxels[self.index(px, py, pz)])
    }

    /// Writes the voxel at padded `(px, py, pz)`, keeping its row mask, and returns the old id.
    pub fn set(&mut self, px: u32, py: u32, pz: u32, id: BlockId) -> Result<BlockId, CoordError> {
        self.check([px, py, pz])?;
        let i = self.index(px, py, pz);
        let c = py as usize + self.padded_edge() * pz as usize;
        let bit = 1u64 << px;
        self.columns[c] = (self.columns[c] & !bit) | (u64::from(!id.is_air()) << px);
        Ok(core::mem::replace(&mut self.voxels[i], id))
    }

    /// Sets the whole padding layer on one side to air: padded coordinate 0 (negative
    /// directions) or `edge + 1` (positive directions) along the face's axis, edges and corners
    /// of that layer included.
    ///
    /// Meshers then treat that neighbour as empty and emit the chunk's border faces on that
    /// side. LOD meshing uses it where a neighbour is drawn at another level of detail, so each
    /// side of the border is closed on its own and no crack can open between them.
    pub fn clear_padding_face(&mut self, face: crate::FaceDirection) {
        let p = self.padded_edge();
        let layer = if face.is_positive() { p - 1 } else { 0 };
        match face.normal_axis() {
            0 => {
                let bit = !(1u64 << layer);
                for (row, mask) in self.voxels.chunks_exact_mut(p).zip(self.columns.iter_mut()) {
                    row[layer] = BlockId::AIR;
                    *mask &= bit;
                }
            }
            axis => {
                for c in 0..p * p {
                    let (py, pz) = (c % p, c / p);
                    if (if axis == 1 { py } else { pz }) == layer {
                        self.voxels[c * p..(c + 1) * p].fill(BlockId::AIR);
                        self.columns[c] = 0;
                    }
                }
            }
        }
    }

    /// The mask of padded row `(py, pz)`, or an error naming the padded edge.
    pub fn column(&self, py: u32, pz: u32) -> Result<u64, CoordError> {
        self.check([0, py, pz])?;
        Ok(self.columns[py as usize + self.padded_edge() * pz as usize])
    }
}

/// Which neighbour (0 = below, 1 = the centre chunk, 2 = above) and which source layer a padded
/// coordinate reads.
#[inline]
fn axis(p: usize, e: usize) -> (usize, u32) {
    if p == 0 {
        (0, e as u32 - 1)
    } else if p == e + 1 {
        (2, 0)
    } else {
        (1, p as u32 - 1)
    }
}

/// Fills `out` with chunk `centre` of `world` and its one-voxel border from the 26 neighbouring
/// chunks (see the [module docs](self) for the layout). Missing chunks, and neighbour
/// coordinates past the `i32` range, read as air. `out` takes the world's chunk size and keeps
/// its capacity, so one buffer serves any number of gathers.
///
/// Rows are copied with [`VoxelStorage::copy_row`] and their occupancy comes from
/// [`VoxelStorage::column_mask`] shifted by one; only the two border voxels of each row are read
/// one by one.
pub fn gather_neighbourhood<C: VoxelStorage>(
    world: &WorldMap<C>,
    centre: ChunkCoord,
    out: &mut PaddedChunk,
) {
    let size = world.size();
    out.resize(size);
    let e = size.edge_usize();
    let p = size.padded_edge();

    let mut near: [[[Option<&C>; 3]; 3]; 3] = [[[None; 3]; 3]; 3];
    for (dz, plane) in near.iter_mut().enumerate() {
        for (dy, line) in plane.iter_mut().enumerate() {
            for (dx, slot) in line.iter_mut().enumerate() {
                let offset = [dx as i32 - 1, dy as i32 - 1, dz as i32 - 1];
                *slot = centre
                    .checked_offset(offset)
                    .ok()
                    .and_then(|c| world.get(c));
            }
        }
    }

    let border = |chunk: Option<&C>, x: usize, y: u32, z: u32| -> BlockId {
        let pos = LocalPos {
            x: x as u8,
            y: y as u8,
            z: z as u8,
        };
        chunk.and_then(|c| c.get(pos).ok()).unwrap_or(BlockId::AIR)
    };

    let rows = out.voxels.chunks_exact_mut(p);
    for ((c, row), mask_out) in rows.enumerate().zip(out.columns.iter_mut()) {
        let (dy, sy) = axis(c % p, e);
        let (dz, sz) = axis(c / p, e);
        let line = &near[dz][dy];
        let inner = &mut row[1..=e];
        let mut mask = match line[1] {
            Some(chunk) if chunk.copy_row(sy, sz, inner).is_ok() => {
                chunk.column_mask(sy, sz).unwrap_or(0) << 1
            }
            _ => {
                inner.fill(BlockId::AIR);
                0
            }
        };
        let west = border(line[0], e - 1, sy, sz);
        let east = border(line[2], 0, sy, sz);
        row[0] = west;
        row[e + 1] = east;
        mask |= u64::from(!west.is_air()) | (u64::from(!east.is_air()) << (e + 1));
        *mask_out = mask;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::FaceDirection;

    #[test]
    fn clearing_a_padding_face_empties_exactly_that_layer() {
        for size in ChunkSize::ALL {
            for face in FaceDirection::ALL {
                let mut padded = PaddedChunk::from_fn(size, |_, _, _| BlockId(3));
                padded.clear_padding_face(face);
                let p = padded.padded_edge() as u32;
                let layer = if face.is_positive() { p - 1 } else { 0 };
                for pz in 0..p {
                    for py in 0..p {
                        let mut mask = 0u64;
                        for px in 0..p {
                            let on_layer = [px, py, pz][face.normal_axis()] == layer;
                            let id = padded.get(px, py, pz).unwrap();
                            assert_eq!(id.is_air(), on_layer, "{size:?} {face:?} ({px},{py},{pz})");
                            mask |= u64::from(!id.is_air()) << px;
                        }
                        assert_eq!(
                            padded.column(py, pz).unwrap(),
                            mask,
                            "{size:?} {face:?} row mask"
                        );
                    }
                }
            }
        }
    }
}
