//! The hiding occupancy of a padded chunk as a flat bit set: what a far-draw renderer reads to
//! shade its surface blocks with the same ambient occlusion as the meshers.
//!
//! The blocky meshers' AO counts the *opaque* (hiding) voxels in front of a face corner
//! ([`crate::blocky`]'s AO rule), and those can lie in the neighbour chunks. A [`DrawBlock`]
//! list alone does not say which voxels around a block are solid, so the renderer keeps, beside
//! each chunk's list, one bit per padded voxel: `(e + 2)^3` bits, 1000 for an 8^3 chunk
//! (32 words, 128 bytes), 5832 for 16^3 (183 words).
//!
//! ```text
//!  bit i of the set = word i / 32, bit i % 32
//!  i = px + p * (py + p * pz),  p = e + 2   (PaddedChunk's voxel order)
//!  set iff the padded voxel is neither air nor transparent (unknown ids hide)
//! ```
//!
//! [`DrawBlock`]: voxel_core::formats::DrawBlock

use alloc::vec::Vec;

use voxel_core::PaddedChunk;

use crate::BlockClasses;

/// Writes the transparent occupancy of `chunk` into `out`, in the layout of [`hiding_mask`]:
/// bit set iff the padded voxel is transparent (water, glass). Far draws read it to show a
/// transparent block's face only where the meshers would: towards a voxel that neither hides
/// nor is transparent (they do not tell transparent ids apart there: water next to glass shows
/// no face between them, where the meshers would show one). Left empty when the padded chunk
/// has no transparent voxel (or the palette no transparent material).
pub fn transparent_mask(chunk: &PaddedChunk, classes: &BlockClasses, out: &mut Vec<u32>) {
    out.clear();
    if !classes.any_transparent() {
        return;
    }
    let p = chunk.padded_edge();
    let voxels = chunk.voxels();
    let mut any = false;
    let mut bits = alloc::vec![0u32; hiding_mask_words(chunk.size().edge())];
    for (row, &mask) in chunk.columns().iter().enumerate() {
        let mut rest = mask;
        while rest != 0 {
            let px = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            let i = px + p * row;
            if classes.is_transparent(voxels[i]) {
                bits[i / 32] |= 1 << (i % 32);
                any = true;
            }
        }
    }
    if any {
        *out = bits;
    }
}

/// Words of the bit set of a chunk of edge `edge`: `ceil((edge + 2)^3 / 32)`.
pub const fn hiding_mask_words(edge: u32) -> usize {
    let p = (edge + 2) as usize;
    (p * p * p).div_ceil(32)
}

/// Writes the hiding occupancy of `chunk` (see the [module docs](self)) into `out`, replacing
/// what it held: [`hiding_mask_words`] words.
///
/// ```
/// use mesher::BlockClasses;
/// use mesher::surface_blocks::{hiding_mask, hiding_mask_words};
/// use voxel_core::{BlockId, ChunkSize, Material, MaterialPalette, PaddedChunk};
///
/// let mut palette = MaterialPalette::new();
/// let stone = palette.push(Material::opaque(90, 90, 90))?;
/// let classes = BlockClasses::from_palette(&palette);
/// // Stone at padded (0, 0, 0) only: bit 0.
/// let chunk = PaddedChunk::from_fn(ChunkSize::S8, |x, y, z| {
///     if (x, y, z) == (0, 0, 0) { stone } else { BlockId::AIR }
/// });
/// let mut bits = Vec::new();
/// hiding_mask(&chunk, &classes, &mut bits);
/// assert_eq!(bits.len(), hiding_mask_words(8));
/// assert_eq!(bits[0], 1);
/// assert!(bits[1..].iter().all(|&w| w == 0));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn hiding_mask(chunk: &PaddedChunk, classes: &BlockClasses, out: &mut Vec<u32>) {
    let p = chunk.padded_edge();
    out.clear();
    out.resize(hiding_mask_words(chunk.size().edge()), 0);
    let voxels = chunk.voxels();
    let check_transparent = classes.any_transparent();
    for (row, &mask) in chunk.columns().iter().enumerate() {
        let mut rest = mask;
        while rest != 0 {
            let px = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            let i = px + p * row;
            if check_transparent && classes.is_transparent(voxels[i]) {
                continue;
            }
            out[i / 32] |= 1 << (i % 32);
        }
    }
}
