//! Skirts: what a chunk adds on one side when the neighbour there is drawn at another level of
//! detail.
//!
//! A chunk is meshed against its neighbours at its own level (real padding), so faces between
//! two solid voxels on either side of a chunk border are never emitted. Where the neighbour is
//! drawn at another level, the geometry on the far side of the border is not the one the chunk
//! was culled against, and a crack could open. The *skirt* of a side closes it: the border
//! faces towards that side that the real padding hides, and the border blocks that only those
//! faces expose. A renderer draws a side's skirt only when the neighbour across it is drawn at
//! another level; the two levels' skirts then close each side of the border on its own (the
//! rule of the [module docs](super)), without re-meshing the chunk when the levels change.
//!
//! ```text
//!   side +X of a chunk, seen along z        skirt faces: voxel V hides, padding N hides
//!        V N                                 (normal mesh: nothing between V and N)
//!   ...[#][#]|      ─► +X skirt face on V's +X side
//!   ...[#][ ]|      ─► none: V already shows that face in the normal mesh
//!   ...[ ][#]|      ─► none: nothing to close
//! ```
//!
//! Skirt faces carry no ambient occlusion (`ao = 3` on every corner): they stand in for the
//! other level's geometry, whose occlusion is not known here. Transparent voxels get no skirt:
//! a crack in water shows the ground under it, not the sky.

use alloc::vec::Vec;

use voxel_core::formats::{
    DrawBlock, DrawBlockFields, DrawBlockFlags, PackedQuad, PackedQuadFields,
};
use voxel_core::{BlockId, FaceDirection, MaterialClass, PaddedChunk};

use crate::{BlockClasses, MeshError};

/// Per side (index `FaceDirection::index`), the transition quads and blocks of one chunk. See
/// the [module docs](self). Reusable: every extraction clears and keeps the capacity.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Skirts {
    quads: [Vec<PackedQuad>; 6],
    blocks: [Vec<DrawBlock>; 6],
}

impl Skirts {
    /// Empty skirts.
    pub fn new() -> Self {
        Self::default()
    }

    /// Empties every side, keeping capacity.
    pub fn clear(&mut self) {
        self.quads.iter_mut().for_each(Vec::clear);
        self.blocks.iter_mut().for_each(Vec::clear);
    }

    /// The skirt quads of `side`, all facing `side`.
    pub fn quads(&self, side: FaceDirection) -> &[PackedQuad] {
        &self.quads[usize::from(side.index())]
    }

    /// The skirt blocks of `side`: border blocks that no face of the normal mesh shows.
    pub fn blocks(&self, side: FaceDirection) -> &[DrawBlock] {
        &self.blocks[usize::from(side.index())]
    }

    /// Replaces the skirt blocks of side `index` (`FaceDirection::index`).
    pub(crate) fn set_blocks(&mut self, index: usize, blocks: &[DrawBlock]) {
        self.blocks[index].clear();
        self.blocks[index].extend_from_slice(blocks);
    }

    /// Skirt quads per side.
    pub fn quad_counts(&self) -> [u32; 6] {
        self.quads.each_ref().map(|q| q.len() as u32)
    }

    /// Skirt blocks per side.
    pub fn block_counts(&self) -> [u32; 6] {
        self.blocks.each_ref().map(|b| b.len() as u32)
    }
}

/// True when `id` hides its neighbours' faces: neither air nor transparent (ids the palette
/// does not know hide, the meshers' convention).
fn hides(classes: &BlockClasses, id: BlockId) -> bool {
    !id.is_air() && !classes.is_transparent(id)
}

/// The padded coordinate of chunk-local `(u, v)` on `side`'s border layer (`outside` false) or
/// on the padding layer beyond it (`outside` true).
fn border_cell(edge: u32, side: FaceDirection, u: u32, v: u32, outside: bool) -> [u32; 3] {
    let mut p = [0u32; 3];
    p[side.width_axis()] = u + 1;
    p[side.height_axis()] = v + 1;
    p[side.normal_axis()] = match (side.is_positive(), outside) {
        (true, false) => edge,
        (true, true) => edge + 1,
        (false, false) => 1,
        (false, true) => 0,
    };
    p
}

fn voxel(chunk: &PaddedChunk, p: [u32; 3]) -> BlockId {
    chunk.voxels()[chunk.index(p[0], p[1], p[2])]
}

/// The opaque id of the border voxel at `(u, v)` of `side` when the real padding hides its face
/// towards `side`; `None` otherwise. An id the palette does not know is an error: the skirt
/// would show it.
fn skirt_id(
    chunk: &PaddedChunk,
    classes: &BlockClasses,
    side: FaceDirection,
    u: u32,
    v: u32,
) -> Result<Option<BlockId>, MeshError> {
    let edge = chunk.size().edge();
    let inner = border_cell(edge, side, u, v, false);
    let id = voxel(chunk, inner);
    if !hides(classes, id) || !hides(classes, voxel(chunk, border_cell(edge, side, u, v, true))) {
        return Ok(None);
    }
    if classes.class(id).is_none() {
        return Err(MeshError::UnknownBlock {
            id,
            position: inner,
        });
    }
    Ok(Some(id))
}

/// Writes the skirt quads of every side of `chunk` into `out` (its blocks are cleared): per
/// side, the border faces the real padding hides, merged greedily per block id (rows along the
/// width axis first, then whole rows along the height axis).
///
/// # Errors
///
/// [`MeshError::UnknownBlock`] for a border voxel a skirt would show whose id has no material;
/// `out` is then empty.
///
/// ```
/// use mesher::BlockClasses;
/// use mesher::lod::{Skirts, skirt_quads};
/// use voxel_core::{BlockId, ChunkSize, FaceDirection, Material, MaterialPalette, PaddedChunk};
///
/// let mut palette = MaterialPalette::new();
/// let stone = palette.push(Material::opaque(90, 90, 90))?;
/// let classes = BlockClasses::from_palette(&palette);
/// // Solid everywhere, padding included: only skirts can show the border.
/// let chunk = PaddedChunk::from_fn(ChunkSize::S8, |_, _, _| stone);
/// let mut skirts = Skirts::new();
/// skirt_quads(&chunk, &classes, &mut skirts)?;
/// // One 8 x 8 quad per side.
/// assert_eq!(skirts.quad_counts(), [1; 6]);
/// assert_eq!(skirts.quads(FaceDirection::PosY)[0].decode()?.width, 8);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn skirt_quads(
    chunk: &PaddedChunk,
    classes: &BlockClasses,
    out: &mut Skirts,
) -> Result<(), MeshError> {
    out.clear();
    let result = FaceDirection::ALL.into_iter().try_for_each(|side| {
        side_quads(
            chunk,
            classes,
            side,
            &mut out.quads[usize::from(side.index())],
        )
    });
    if result.is_err() {
        out.clear();
    }
    result
}

fn side_quads(
    chunk: &PaddedChunk,
    classes: &BlockClasses,
    side: FaceDirection,
    out: &mut Vec<PackedQuad>,
) -> Result<(), MeshError> {
    let e = chunk.size().edge();
    let n = e as usize;
    // The side's mask, row v, column u.
    let mut ids: Vec<Option<BlockId>> = Vec::with_capacity(n * n);
    for v in 0..e {
        for u in 0..e {
            ids.push(skirt_id(chunk, classes, side, u, v)?);
        }
    }
    for v in 0..n {
        let mut u = 0;
        while u < n {
            let Some(id) = ids[v * n + u] else {
                u += 1;
                continue;
            };
            let width = ids[v * n + u..(v + 1) * n]
                .iter()
                .take_while(|&&c| c == Some(id))
                .count();
            let row_matches = |r: usize| {
                ids[r * n + u..r * n + u + width]
                    .iter()
                    .all(|&c| c == Some(id))
            };
            let height = 1 + (v + 1..n).take_while(|&r| row_matches(r)).count();
            for r in v..v + height {
                ids[r * n + u..r * n + u + width].fill(None);
            }
            let mut position = [0u32; 3];
            position[side.width_axis()] = u as u32;
            position[side.height_axis()] = v as u32;
            position[side.normal_axis()] = if side.is_positive() { e - 1 } else { 0 };
            out.push(PackedQuad::encode(&PackedQuadFields {
                position,
                width: width as u32,
                height: height as u32,
                face: side,
                ao: [3; 4],
                block: id,
            })?);
            u += width;
        }
    }
    Ok(())
}

/// Writes the skirt blocks of every side of `chunk` into `out` (its quads are cleared): per
/// side, the border blocks that show a face towards that side only when the neighbour there is
/// drawn at another level (the real padding hides that face) and show no face otherwise (all
/// six real neighbours hide them), so they are not in the chunk's
/// [`surface_blocks`](fn@crate::surface_blocks) list. Flags follow that list's rules
/// (`EMISSIVE`, `SMOOTH`; skirt blocks are opaque and buried, so never `TRANSPARENT` or
/// `HAS_CLUTTER`).
///
/// # Errors
///
/// [`MeshError::BadShape`] for chunks wider than 16 (a [`DrawBlock`] addresses one 16^3
/// sub-block, and skirt blocks are not grouped by sub-block); [`MeshError::UnknownBlock`] as
/// for [`skirt_quads`]. On error `out` is empty.
pub fn skirt_blocks(
    chunk: &PaddedChunk,
    classes: &BlockClasses,
    out: &mut Skirts,
) -> Result<(), MeshError> {
    out.clear();
    let e = chunk.size().edge();
    if e > DrawBlock::MAX_POSITION + 1 {
        return Err(MeshError::BadShape {
            reason: "skirt blocks need chunks of at most 16^3 (one DrawBlock sub-block)",
            value: e as usize,
        });
    }
    let result = FaceDirection::ALL.into_iter().try_for_each(|side| {
        let list = &mut out.blocks[usize::from(side.index())];
        for v in 0..e {
            for u in 0..e {
                let Some(id) = skirt_id(chunk, classes, side, u, v)? else {
                    continue;
                };
                let p = border_cell(e, side, u, v, false);
                let buried = FaceDirection::ALL.into_iter().all(|f| {
                    let q = f.normal();
                    let n = core::array::from_fn(|i| p[i].wrapping_add_signed(q[i]));
                    hides(classes, voxel(chunk, n))
                });
                if buried {
                    list.push(DrawBlock::encode(&DrawBlockFields {
                        position: p.map(|c| c - 1),
                        flags: block_flags(classes, id),
                        block: id,
                    })?);
                }
            }
        }
        Ok(())
    });
    if result.is_err() {
        out.clear();
    }
    result
}

/// The flags a buried opaque block carries in a surface-block list.
fn block_flags(classes: &BlockClasses, id: BlockId) -> DrawBlockFlags {
    let mut flags = DrawBlockFlags::EMPTY;
    if classes.is_emissive(id) {
        flags = flags.union(DrawBlockFlags::EMISSIVE);
    }
    if classes.class(id) == Some(MaterialClass::Smoothable) {
        flags = flags.union(DrawBlockFlags::SMOOTH);
    }
    flags
}
