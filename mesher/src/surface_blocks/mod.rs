//! Surface-block lists ([`DrawBlock`]) for far draws: every block of a chunk that shows at
//! least one face, 4 bytes each (Project Ascendant's far field, drawn as ray-box sprites).
//!
//! A `DrawBlock` stores its position in 4 bits per axis, so it addresses a 16^3 block. Chunks of
//! 8^3 and 16^3 are one such *sub-block*; 32^3 chunks are split into 2^3 of them and 62^3 chunks
//! into 4^3 (the last one on each axis 14 voxels wide). [`SurfaceBlocks`] holds the blocks of
//! every non-empty sub-block contiguously, sub-block after sub-block, and one
//! [`SubBlockRange`] per non-empty sub-block saying where its blocks start:
//!
//! ```text
//!  blocks:     [ b b b b | b b | b b b b b b | ... ]
//!  sub_blocks:   (0,0,0)   (1,0,0) (0,1,0)            coord, offset, count
//!  chunk-local position = sub-block coord * 16 + DrawBlock position
//! ```
//!
//! # Exposure
//!
//! The same rules as the visible faces of the blocky meshers, shared by [`crate::shells`]:
//!
//! - a voxel *hides* its neighbour's face when it is neither air nor transparent: the opaque
//!   classes (`Opaque`, `ClutterBearing`, `Smoothable`) hide, and so do ids the palette does
//!   not know (the convention of [`BlockClasses::any_transparent`]: without transparent
//!   materials the occupancy masks are the hiding masks);
//! - the face of voxel `v` towards neighbour `n` is exposed when `v` is not air, `n` does not
//!   hide, and `v` is not a transparent voxel of the same id as `n`: water shows no face to
//!   water but does to glass and to air, and stone next to water is exposed;
//! - a block is *exposed* when at least one of its six faces is.
//!
//! An exposed voxel with an unknown id is an error ([`MeshError::UnknownBlock`]); a buried one,
//! or one in the border, is never looked at.
//!
//! Exposure is computed on the padded row masks: with `S` the hiding mask of a row, the exposed
//! faces of its hiding voxels are six AND-NOTs of neighbouring rows (`S & !(S >> 1)` for +x,
//! `S & !S[y + 1]` for +y, ...), and a block is buried when the AND of its six neighbour rows is
//! set. Only transparent voxels with a non-hiding neighbour are checked one by one (is that
//! neighbour the same id?). Without transparent materials in the palette no voxel is read
//! before output; with them, one pass over the occupied rows builds the transparent mask
//! (vectorized compares against the palette's transparent ids when it has at most 8).

pub(crate) mod exposure;
pub mod occupancy;

use alloc::vec::Vec;
use core::ops::Range;

use voxel_core::formats::{DrawBlock, DrawBlockFields, DrawBlockFlags};
use voxel_core::{BlockId, MaterialClass, PaddedChunk};

use crate::{BlockClasses, MeshError};
use exposure::{ExposureScratch, nothing_exposed};
pub use occupancy::{hiding_mask, hiding_mask_words, transparent_mask};

/// Edge of one sub-block in voxels: the 16 positions a [`DrawBlock`] axis can address.
pub const SUB_BLOCK_EDGE: u32 = DrawBlock::MAX_POSITION + 1;

/// Where the [`DrawBlock`]s of one non-empty sub-block lie in [`SurfaceBlocks::blocks`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SubBlockRange {
    /// Which sub-block: each axis `0..ceil(edge / 16)` (0 for chunks of 8^3 and 16^3, 0..2
    /// for 32^3, 0..4 for 62^3). Its voxels start at chunk-local `coord * 16`.
    pub coord: [u8; 3],
    /// Index of its first block.
    pub offset: u32,
    /// Number of its blocks, at least 1.
    pub count: u32,
}

impl SubBlockRange {
    /// Chunk-local position of the sub-block's voxel `(0, 0, 0)`: `coord * 16`.
    #[inline]
    pub fn origin(&self) -> [u32; 3] {
        self.coord.map(|c| u32::from(c) * SUB_BLOCK_EDGE)
    }

    /// Its blocks' index range in [`SurfaceBlocks::blocks`].
    #[inline]
    pub fn range(&self) -> Range<usize> {
        self.offset as usize..self.offset as usize + self.count as usize
    }
}

/// Reusable output of [`surface_blocks`]: the blocks of a chunk that show at least one face,
/// grouped by 16^3 sub-block. [`clear`](Self::clear) and every extraction keep the capacity.
///
/// Within a sub-block, blocks are ordered z, then y, then x (x fastest); sub-blocks are ordered
/// the same way by their coordinate. Only non-empty sub-blocks are listed.
#[derive(Clone, Debug, Default)]
pub struct SurfaceBlocks {
    blocks: Vec<DrawBlock>,
    sub_blocks: Vec<SubBlockRange>,
    /// Exposed-voxel row masks of the chunk, index `y + edge * z` (chunk-local), bit `x + 1`.
    exposed: Vec<u64>,
    scratch: ExposureScratch,
}

impl SurfaceBlocks {
    /// An empty buffer.
    pub fn new() -> Self {
        Self::default()
    }

    /// Empties the lists, keeping capacity.
    pub fn clear(&mut self) {
        self.blocks.clear();
        self.sub_blocks.clear();
    }

    /// Every surface block, sub-block after sub-block.
    #[inline]
    pub fn blocks(&self) -> &[DrawBlock] {
        &self.blocks
    }

    /// The non-empty sub-blocks and where their blocks lie.
    #[inline]
    pub fn sub_blocks(&self) -> &[SubBlockRange] {
        &self.sub_blocks
    }

    /// The blocks of one listed sub-block.
    #[inline]
    pub fn sub_block(&self, range: &SubBlockRange) -> &[DrawBlock] {
        self.blocks.get(range.range()).unwrap_or(&[])
    }

    /// Number of surface blocks.
    #[inline]
    pub fn len(&self) -> usize {
        self.blocks.len()
    }

    /// True when no block is exposed.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.blocks.is_empty()
    }

    /// Every block with its chunk-local position (sub-block origin + packed position).
    pub fn iter_local(&self) -> impl Iterator<Item = ([u32; 3], DrawBlockFields)> + '_ {
        self.sub_blocks.iter().flat_map(move |range| {
            let origin = range.origin();
            self.sub_block(range).iter().map(move |block| {
                let fields = block.decode();
                let p = fields.position;
                (
                    [origin[0] + p[0], origin[1] + p[1], origin[2] + p[2]],
                    fields,
                )
            })
        })
    }
}

/// Lists the blocks of `chunk` that show at least one face, as [`DrawBlock`]s grouped by 16^3
/// sub-block (see the [module docs](mod@crate::surface_blocks)), replacing what `out` held.
///
/// Flags come from the material: `TRANSPARENT` for the transparent class, `EMISSIVE` for
/// `emission > 0`, `SMOOTH` for the smoothable class, and `HAS_CLUTTER` for a clutter-bearing
/// block whose top neighbour is air: the rule by which
/// [`place_clutter`](crate::clutter::place_clutter) places clutter (a clutter-bearing block
/// under water or glass shows its top face but grows no clutter).
///
/// Cost: one pass of word operations over the padded row masks (plus the transparent-mask pass
/// when the palette has transparent materials), then a class lookup per exposed voxel;
/// transparent voxels next to a non-hiding neighbour are checked voxel by voxel. An empty chunk,
/// and a full chunk whose face neighbours are all occupied when the palette has no transparent
/// material, return after a scan of the masks. No allocation once `out` has grown.
///
/// # Errors
///
/// [`MeshError::UnknownBlock`] for the first exposed voxel (in output order) whose id has no
/// material; `out` is then left empty. Unknown ids that are buried, or in the border, are not
/// errors (they hide their neighbours' faces, see the module docs).
///
/// ```
/// use mesher::{BlockClasses, SurfaceBlocks, surface_blocks};
/// use voxel_core::{BlockId, ChunkSize, Material, MaterialPalette, PaddedChunk};
///
/// let mut palette = MaterialPalette::new();
/// let stone = palette.push(Material::opaque(128, 128, 128))?;
/// let classes = BlockClasses::from_palette(&palette);
/// // One stone block at chunk-local (20, 3, 5) of a 32^3 chunk (padded (21, 4, 6)).
/// let chunk = PaddedChunk::from_fn(ChunkSize::S32, |x, y, z| {
///     if (x, y, z) == (21, 4, 6) { stone } else { BlockId::AIR }
/// });
/// let mut out = SurfaceBlocks::new();
/// surface_blocks(&chunk, &classes, &mut out)?;
/// assert_eq!(out.sub_blocks()[0].coord, [1, 0, 0]);
/// assert_eq!(out.blocks()[0].decode().position, [4, 3, 5]);
/// assert_eq!(out.iter_local().next().unwrap().0, [20, 3, 5]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn surface_blocks(
    chunk: &PaddedChunk,
    classes: &BlockClasses,
    out: &mut SurfaceBlocks,
) -> Result<(), MeshError> {
    out.clear();
    if nothing_exposed(chunk, classes) {
        return Ok(());
    }
    let result = extract(chunk, classes, out);
    if result.is_err() {
        out.clear();
    }
    result
}

fn extract(
    chunk: &PaddedChunk,
    classes: &BlockClasses,
    out: &mut SurfaceBlocks,
) -> Result<(), MeshError> {
    let SurfaceBlocks {
        blocks,
        sub_blocks,
        exposed,
        scratch,
    } = out;
    let size = chunk.size();
    let e = size.edge_usize();
    let p = chunk.padded_edge();
    let exposure = scratch.prepare(chunk, classes);
    exposed.clear();
    exposed.reserve(e * e);
    for pz in 1..=e {
        for py in 1..=e {
            exposed.push(exposure.row_exposed(py, pz));
        }
    }

    let voxels = chunk.voxels();
    let columns = chunk.columns();
    let sub = SUB_BLOCK_EDGE as usize;
    let per_axis = e.div_ceil(sub);
    for sz in 0..per_axis {
        for sy in 0..per_axis {
            for sx in 0..per_axis {
                let offset = blocks.len();
                let x0 = sx * sub;
                let width = sub.min(e - x0);
                let x_mask = ((1u64 << width) - 1) << (x0 + 1);
                for z in sz * sub..(sz * sub + sub).min(e) {
                    for y in sy * sub..(sy * sub + sub).min(e) {
                        let mut bits = exposed[y + e * z] & x_mask;
                        let (py, pz) = (y + 1, z + 1);
                        let above = columns[py + 1 + p * pz];
                        while bits != 0 {
                            let px = bits.trailing_zeros() as usize;
                            bits &= bits - 1;
                            let id = voxels[px + p * (py + p * pz)];
                            let air_above = (above >> px) & 1 == 0;
                            let flags = flags_of(classes, id, air_above).ok_or(
                                MeshError::UnknownBlock {
                                    id,
                                    position: [px as u32, py as u32, pz as u32],
                                },
                            )?;
                            blocks.push(DrawBlock::encode(&DrawBlockFields {
                                position: [
                                    (px - 1 - x0) as u32,
                                    (y - sy * sub) as u32,
                                    (z - sz * sub) as u32,
                                ],
                                flags,
                                block: id,
                            })?);
                        }
                    }
                }
                if blocks.len() > offset {
                    sub_blocks.push(SubBlockRange {
                        coord: [sx as u8, sy as u8, sz as u8],
                        offset: offset as u32,
                        count: (blocks.len() - offset) as u32,
                    });
                }
            }
        }
    }
    Ok(())
}

/// The [`DrawBlockFlags`] of an exposed block, or `None` for an id with no material. Written
/// without branches on the class: ids vary from voxel to voxel.
#[inline]
fn flags_of(classes: &BlockClasses, id: BlockId, air_above: bool) -> Option<DrawBlockFlags> {
    let class = classes.class(id)?;
    let flag = |on: bool, flag: DrawBlockFlags| u8::from(on) * flag.bits();
    let bits = flag(
        class == MaterialClass::Transparent,
        DrawBlockFlags::TRANSPARENT,
    ) | flag(classes.is_emissive(id), DrawBlockFlags::EMISSIVE)
        | flag(class == MaterialClass::Smoothable, DrawBlockFlags::SMOOTH)
        | flag(
            (class == MaterialClass::ClutterBearing) & air_above,
            DrawBlockFlags::HAS_CLUTTER,
        );
    DrawBlockFlags::from_bits(bits).ok()
}
