//! What the cull pass reads and writes per node beside the chunk table: the node side record
//! ([`NodeRecord`]) and the per-command draw record ([`DrawRecord`]).

use bytemuck::{Pod, Zeroable};

use crate::resident::ChunkRanges;

/// `NodeRecord::flags` bit: the node has far-draw blocks and a hiding mask.
pub const NODE_HAS_BLOCKS: u32 = 1;
/// `NodeRecord::flags` bit: a transparent mask of `mask_words` words follows the hiding mask.
pub const NODE_TRANSPARENT_MASK: u32 = 2;

/// Per table slot, what `MeshedChunkInfo` does not hold (twin of the WGSL `NodeRecord` in
/// `node.wgsl`, 64 bytes; a unit test checks the layout with naga): the smooth-quad range, the
/// far-draw blocks and their hiding mask, the skirt counts per side and the shell runs.
///
/// Skirt counts are packed two per word (side `2i` in the low 16 bits of word `i`, `2i + 1` in
/// the high ones): a side has at most `edge^2 <= 3844` skirt quads and at most 256 skirt blocks.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct NodeRecord {
    /// The smooth quads' first word in the smooth-quad gigabuffer (global).
    pub smooth_quad_offset: u32,
    /// Smooth quads.
    pub smooth_quad_count: u32,
    /// Their `SmoothQuadForm` tag.
    pub smooth_quad_form: u32,
    /// The draw blocks' first element in the draw-block gigabuffer (global), skirts excluded.
    pub block_offset: u32,
    /// Draw blocks, skirts excluded.
    pub block_count: u32,
    /// The hiding mask's first word in the draw-block gigabuffer (global).
    pub mask_offset: u32,
    /// The hiding mask's words (and the transparent mask's, when there is one).
    pub mask_words: u32,
    /// `NODE_*` bits.
    pub flags: u32,
    /// Skirt quads per side, packed (see above).
    pub opaque_skirts: [u32; 3],
    /// Skirt blocks per side, packed.
    pub block_skirts: [u32; 3],
    /// The shell runs' first element in the shell gigabuffer (global).
    pub shell_offset: u32,
    /// Shell runs.
    pub shell_count: u32,
}

const _: () = assert!(size_of::<NodeRecord>() == 64, "NodeRecord is 64 bytes");

/// Why a chunk's ranges do not fit a [`NodeRecord`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SkirtTooLarge {
    /// The side (`FaceDirection::index`).
    pub side: usize,
    /// Its count.
    pub count: u32,
}

impl std::fmt::Display for SkirtTooLarge {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "side {} has {} skirt elements; a node records at most 65535 per side",
            self.side, self.count
        )
    }
}

impl std::error::Error for SkirtTooLarge {}

fn pack(counts: [u32; 6]) -> Result<[u32; 3], SkirtTooLarge> {
    if let Some((side, &count)) = counts.iter().enumerate().find(|(_, c)| **c > 0xffff) {
        return Err(SkirtTooLarge { side, count });
    }
    Ok(std::array::from_fn(|i| {
        counts[2 * i] | counts[2 * i + 1] << 16
    }))
}

/// The count of `side` in a packed array.
pub fn skirt_count(words: [u32; 3], side: usize) -> u32 {
    (words[side >> 1] >> ((side & 1) * 16)) & 0xffff
}

impl NodeRecord {
    /// The record of a chunk uploaded at `ranges`. Blocks count only with a hiding mask (far
    /// draws need both).
    pub fn new(ranges: &ChunkRanges) -> Result<NodeRecord, SkirtTooLarge> {
        let blocks = ranges.draw_blocks.count + ranges.draw_block_skirts.iter().sum::<u32>();
        let has_blocks = blocks > 0 && ranges.hiding_mask.count > 0;
        Ok(NodeRecord {
            smooth_quad_offset: ranges.smooth_quads.offset,
            smooth_quad_count: ranges.smooth_quad_count,
            smooth_quad_form: ranges.smooth_quad_form as u32,
            block_offset: ranges.draw_blocks.offset,
            block_count: ranges.draw_blocks.count,
            mask_offset: ranges.hiding_mask.offset,
            mask_words: ranges.hiding_mask.count,
            flags: if has_blocks { NODE_HAS_BLOCKS } else { 0 }
                | if ranges.transparent_mask.count == ranges.hiding_mask.count
                    && ranges.transparent_mask.count > 0
                {
                    NODE_TRANSPARENT_MASK
                } else {
                    0
                },
            opaque_skirts: pack(ranges.opaque_skirts)?,
            block_skirts: pack(ranges.draw_block_skirts)?,
            shell_offset: ranges.shell_runs.offset,
            shell_count: ranges.shell_runs.count,
        })
    }
}

/// What the quad vertex shader reads per command (`records[instance_index]`), 16 bytes: the
/// chunk difference to the camera chunk in **level-0 chunks** (`chunk << level - camera chunk`,
/// wrapping `i32`) and the node's level, whose voxels are `2^level` blocks wide.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Pod, Zeroable)]
pub struct DrawRecord {
    /// Chunk difference x, y, z (level-0 chunks).
    pub chunk: [i32; 3],
    /// Level of detail.
    pub level: u32,
}

const _: () = assert!(size_of::<DrawRecord>() == 16, "DrawRecord is 16 bytes");

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skirt_counts_pack_two_per_word_and_refuse_overflow() {
        let words = pack([1, 2, 3, 4, 65535, 0]).unwrap();
        assert_eq!(
            (0..6).map(|s| skirt_count(words, s)).collect::<Vec<_>>(),
            [1, 2, 3, 4, 65535, 0]
        );
        assert_eq!(
            pack([0, 0, 0, 70000, 0, 0]),
            Err(SkirtTooLarge {
                side: 3,
                count: 70000
            })
        );
    }
}
