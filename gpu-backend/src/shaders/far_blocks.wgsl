// Shared by the far draws (splat.wgsl, far_raster.wgsl, far_draw_args.wgsl): which blocks a
// far-list entry draws. node.wgsl comes before this body.

// Blocks a far node draws: its blocks plus the skirt blocks of the sides in `skirts`.
fn far_block_total(node: NodeRecord, skirts: u32) -> u32 {
    var n = node.block_count;
    for (var f = 0u; f < 6u; f += 1u) {
        if ((skirts >> f) & 1u) != 0u {
            n += skirt_count(node.block_skirts, f);
        }
    }
    return n;
}

// The draw-block index of the node's `b`-th drawn block: its blocks, then the skirt blocks of
// each side in `skirts` (every side's skirt is stored, side after side, after the blocks).
fn block_index(node: NodeRecord, skirts: u32, b: u32) -> u32 {
    if b < node.block_count {
        return node.block_offset + b;
    }
    var rest = b - node.block_count;
    var at = node.block_offset + node.block_count;
    for (var f = 0u; f < 6u; f += 1u) {
        let n = skirt_count(node.block_skirts, f);
        if ((skirts >> f) & 1u) != 0u {
            if rest < n {
                return at + rest;
            }
            rest -= n;
        }
        at += n;
    }
    return at;
}
