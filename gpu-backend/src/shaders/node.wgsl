// What the renderer keeps per table slot beside MeshedChunkInfo (twin of cull::NodeRecord, a
// unit test checks the layout with naga): the smooth-quad range, the far-draw blocks and their
// hiding mask, the per-side skirt counts and the shell runs. 64 bytes.
struct NodeRecord {
    // The smooth quads' first word in the smooth-quad gigabuffer (global), count and form.
    smooth_quad_offset: u32,
    smooth_quad_count: u32,
    smooth_quad_form: u32,
    // The draw blocks (global element offset in the draw-block gigabuffer), without skirts.
    block_offset: u32,
    block_count: u32,
    // The hiding mask's first word (draw-block gigabuffer, global) and its word count (the
    // transparent mask's too, when NODE_TRANSPARENT_MASK says one follows).
    mask_offset: u32,
    mask_words: u32,
    // NODE_* bits.
    flags: u32,
    // Skirt quads (at the end of each opaque face group) and skirt blocks (after the blocks,
    // side after side) per side: side 2i in the low 16 bits of word i, side 2i + 1 high.
    opaque_skirts: array<u32, 3>,
    block_skirts: array<u32, 3>,
    // The shell runs (global element offset in the shell gigabuffer) and their count.
    shell_offset: u32,
    shell_count: u32,
}

// The node has far-draw blocks and a hiding mask.
const NODE_HAS_BLOCKS: u32 = 1u;
// A transparent mask of mask_words words follows the hiding mask.
const NODE_TRANSPARENT_MASK: u32 = 2u;

// Count of side `side` in a pair-packed array of six u16.
fn skirt_count(words: array<u32, 3>, side: u32) -> u32 {
    return (words[side >> 1u] >> ((side & 1u) * 16u)) & 0xffffu;
}
