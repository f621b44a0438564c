// The shadow grid's memory layout, shared by its fill and its trace. The grid is GRID_CELLS^3
// one-bit cells (grid coordinates 0..GRID_CELLS, the camera-relative cell plus GRID_CELLS / 2),
// stored as bricks of 8^3 cells, 16 words (64 bytes) each, bricks in x, y, z order. A brick
// keeps the cells a ray visits next close in memory whichever axis it steps along (a row
// layout puts each y or z step 32 or 8192 bytes away). Within a brick, cell (x, y, z) is bit
// x + 8 y + 64 z: a word holds 8 cells along x for 4 along y.
// The including shader defines GRID_CELLS.

const GRID_BRICK_WORDS: u32 = 16u;

// The word index and the bit of grid cell g (each component in 0..GRID_CELLS).
fn grid_word(g: vec3<i32>) -> u32 {
    let bricks = u32(GRID_CELLS / 8);
    let b = vec3<u32>(g >> vec3<u32>(3u));
    let l = vec3<u32>(g & vec3<i32>(7));
    let brick = b.x + (b.y + b.z * bricks) * bricks;
    return brick * GRID_BRICK_WORDS + (l.y >> 2u) + 2u * l.z;
}

fn grid_bit(g: vec3<i32>) -> u32 {
    return u32(g.x & 7) + 8u * u32(g.y & 3);
}
