// The dispatch sizes of the quad rasteriser (render::quad_raster), on the GPU so that the CPU
// never waits for the cull's counts:
// - qr_page_args: per quad page, one workgroup per drawn command (min(counts[p], C)), folded
//   into x and y below 65535 workgroups per dimension, with the page's first command slot; it
//   also zeroes the record's list counts (state words below QR_FIRST_STAT_WORD), since it is
//   the record's first dispatch and nothing in it reads them: a record then needs no clear in
//   the encoder, and the records of a frame's phases can share one compute pass;
// - qr_tile_args: one workgroup per tile entry the quads pass appended, folded the same way.

// Twin of render::quad_raster::ArgsParams.
struct ArgsParams {
    page_count: u32,
    commands_per_page: u32,
    // Words between two pages' PageArgs in page_args.
    page_stride: u32,
    tile_capacity: u32,
}

// Largest workgroup count of one dispatch dimension.
const MAX_GROUPS: u32 = 65535u;
// The state word counting tile entries (render::quad_raster::StateWord::TileCount).
const QR_TILE_COUNT: u32 = 0u;
// The first statistics word (render::quad_raster::FIRST_STAT_WORD): the words below it are the
// record's list counts.
const QR_FIRST_STAT_WORD: u32 = 8u;

@group(0) @binding(0) var<storage, read> counts: array<u32>;
@group(0) @binding(1) var<storage, read_write> page_args: array<u32>;
@group(0) @binding(2) var<uniform> params: ArgsParams;
@group(0) @binding(3) var<storage, read_write> state: array<atomic<u32>>;
@group(0) @binding(4) var<storage, read_write> tile_dispatch: array<u32>;

// (x, y) workgroups for n: x * y >= n, each at most MAX_GROUPS for every u32 n.
fn fold(n: u32) -> vec2<u32> {
    return vec2<u32>(min(n, MAX_GROUPS), n / MAX_GROUPS + u32(n % MAX_GROUPS != 0u));
}

@compute @workgroup_size(64)
fn qr_page_args(@builtin(global_invocation_id) id: vec3<u32>) {
    let p = id.x;
    if p == 0u {
        for (var word = 0u; word < QR_FIRST_STAT_WORD; word++) {
            atomicStore(&state[word], 0u);
        }
    }
    if p >= params.page_count {
        return;
    }
    let n = min(counts[p], params.commands_per_page);
    let g = fold(n);
    let at = p * params.page_stride;
    page_args[at] = g.x;
    page_args[at + 1u] = g.y;
    page_args[at + 2u] = 1u;
    page_args[at + 3u] = p * params.commands_per_page;
    page_args[at + 4u] = n;
    page_args[at + 5u] = p;
}

@compute @workgroup_size(1)
fn qr_tile_args() {
    let n = min(atomicLoad(&state[QR_TILE_COUNT]), params.tile_capacity);
    let g = fold(n);
    tile_dispatch[0] = g.x;
    tile_dispatch[1] = g.y;
    tile_dispatch[2] = 1u;
}
