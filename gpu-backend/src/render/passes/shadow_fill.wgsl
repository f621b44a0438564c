// The shadow grid fill: the camera-centred grid of GRID_CELLS^3 one-block cells, one bit each,
// marked from the opaque quads (skirts included) of every node the cull draws this frame:
// the solid cell behind each quad, 2^level blocks on each axis at the node's level
// (render_model::lighting::shadow states why that shell is enough and why it closes at LOD
// borders). One workgroup per table slot of the bound quad page (shadow_fill), and one per
// slot for the nodes' vertical shell runs (shadow_fill_shells: each run's box, which is its
// exposed voxels); the grid is cleared before. FORMATS_WGSL, node.wgsl, lod.wgsl and
// shadow_grid.wgsl (the grid's layout) come before this body.

// Twin of render_model::lighting::ShadowFillUniforms.
struct ShadowFillUniforms {
    lod: LodParams,
    camera_chunk: vec3<i32>,
    slot_bound: u32,
    camera_block: vec3<i32>,
    chunk_edge: u32,
    flags: u32,
    page: u32,
    page_capacity: u32,
    bound_capacity: u32,
}

// Twins of render_model::lighting::{SHADOW_FILL_LOD, shadow::GRID_CELLS} (a test compares).
const SHADOW_FILL_LOD: u32 = 1u;
const GRID_CELLS: i32 = 256;
const FILL_WORKGROUP: u32 = 64u;
// Slots per row of the folded dispatch.
const FILL_ROW: u32 = 65535u;

@group(0) @binding(0) var<uniform> u: ShadowFillUniforms;
@group(0) @binding(1) var<storage, read> table: array<MeshedChunkInfo>;
@group(0) @binding(2) var<storage, read_write> grid: array<atomic<u32>>;
@group(0) @binding(3) var<storage, read> quads: array<PackedQuad>;
@group(0) @binding(4) var<storage, read> nodes: array<NodeRecord>;
// The shell gigabuffer's one page (a zero word without shells).
@group(0) @binding(5) var<storage, read> shell_runs: array<ShellRun>;
// One bit per 8^3 brick of the grid (bit i of word i / 32 for brick i, the grid's brick
// order), set by shadow_bricks when the brick holds a marked cell: the trace skips the cell
// reads of empty bricks.
@group(0) @binding(6) var<storage, read_write> bricks: array<u32>;

// Marks the grid cells of the block box [lo, hi) (camera-relative blocks), clipped to the grid.
fn mark_box(lo: vec3<i32>, hi: vec3<i32>) {
    let half = GRID_CELLS / 2;
    let a = max(lo, vec3<i32>(-half)) + vec3<i32>(half);
    let b = min(hi, vec3<i32>(half)) + vec3<i32>(half);
    if any(b <= a) {
        return;
    }
    for (var z = a.z; z < b.z; z += 1) {
        for (var y = a.y; y < b.y; y += 1) {
            // The row's x cells, a word (8 cells of a brick) at a time.
            var x = a.x;
            while x < b.x {
                let g = vec3<i32>(x, y, z);
                let first = grid_bit(g);
                let n = min(8u - u32(x & 7), u32(b.x - x));
                atomicOr(&grid[grid_word(g)], ((1u << n) - 1u) << first);
                x += i32(n);
            }
        }
    }
}

// Where table slot `slot`'s node lies: its corner relative to the eye's block, its cell size
// in blocks, and whether it is drawn (the level-of-detail rule) and reaches the grid.
struct NodePlace {
    lo: vec3<i32>,
    cell: i32,
    inside: bool,
}

fn node_place(slot: u32) -> NodePlace {
    var out: NodePlace;
    out.inside = false;
    let coord = vec3<i32>(table[slot].chunk_x, table[slot].chunk_y, table[slot].chunk_z);
    let level = min(table[slot].lod, 15u);
    var selected = level == 0u;
    if (u.flags & SHADOW_FILL_LOD) != 0u {
        selected = lod_selected(u.lod, coord, level);
    }
    if !selected {
        return out;
    }
    // Chunk differences beyond 2^20 are far outside the grid (and kept from overflowing when
    // scaled to blocks).
    let rel = (coord << vec3<u32>(level)) - u.camera_chunk;
    let far = vec3<i32>(1 << 20u);
    if any(rel > far) || any(rel < -far) {
        return out;
    }
    let edge = i32(u.chunk_edge);
    out.lo = rel * edge - u.camera_block;
    out.cell = 1 << level;
    let half = GRID_CELLS / 2;
    let size = edge * out.cell;
    out.inside = !(any(out.lo >= vec3<i32>(half)) || any(out.lo + vec3<i32>(size) <= vec3<i32>(-half)));
    return out;
}

@compute @workgroup_size(64)
fn shadow_fill(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let slot = wid.x + wid.y * FILL_ROW;
    if slot >= u.slot_bound {
        return;
    }
    let place = node_place(slot);
    if !place.inside {
        return;
    }
    let range = table[slot].opaque_quads;
    let total = face_layer_range_total(range);
    if total == 0u || range.offset / u.page_capacity != u.page {
        return;
    }
    let start = range.offset % u.page_capacity;
    if start > u.bound_capacity || total > u.bound_capacity - start {
        return;
    }
    let node_lo = place.lo;
    let cell = place.cell;
    for (var i = lid; i < total; i += FILL_WORKGROUP) {
        let q = quads[start + i];
        let face = packed_quad_face(q);
        if face > 5u {
            continue;
        }
        let lo = node_lo + vec3<i32>(packed_quad_position(q)) * cell;
        var extent = vec3<i32>(cell);
        extent[face_width_axis(face)] = i32(packed_quad_width(q)) * cell;
        extent[face_height_axis(face)] = i32(packed_quad_height(q)) * cell;
        mark_box(lo, lo + extent);
    }
}

// The shell runs of the node in slot wid (folded like shadow_fill): each run's box of
// exposed voxels, 2^level blocks a voxel.
@compute @workgroup_size(64)
fn shadow_fill_shells(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let slot = wid.x + wid.y * FILL_ROW;
    if slot >= u.slot_bound || nodes[slot].shell_count == 0u {
        return;
    }
    let place = node_place(slot);
    if !place.inside {
        return;
    }
    let first = nodes[slot].shell_offset;
    let count = nodes[slot].shell_count;
    if first >= arrayLength(&shell_runs) || count > arrayLength(&shell_runs) - first {
        return;
    }
    for (var i = lid; i < count; i += FILL_WORKGROUP) {
        let run = shell_runs[first + i];
        let lo = place.lo + vec3<i32>(shell_run_position(run)) * place.cell;
        let extent = vec3<i32>(i32(shell_run_width(run)), i32(shell_run_height(run)), 1) * place.cell;
        mark_box(lo, lo + extent);
    }
}

// The brick bits from the filled grid: one invocation per brick (its 16 words ORed), 32 per
// workgroup, which gather their bits into one word of `bricks` (so no clear is needed: every
// word is written whole). Dispatched after every fill of the frame (the pass orders them).
var<workgroup> wg_brick_bits: atomic<u32>;

@compute @workgroup_size(32)
fn shadow_bricks(
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(local_invocation_index) lid: u32,
) {
    let per_axis = u32(GRID_CELLS / 8);
    let word = wid.x;
    if lid == 0u {
        atomicStore(&wg_brick_bits, 0u);
    }
    workgroupBarrier();
    let base = (word * 32u + lid) * GRID_BRICK_WORDS;
    var marked = 0u;
    for (var w = 0u; w < GRID_BRICK_WORDS; w += 1u) {
        marked |= atomicLoad(&grid[base + w]);
    }
    if marked != 0u {
        atomicOr(&wg_brick_bits, 1u << lid);
    }
    workgroupBarrier();
    if lid == 0u && word < per_axis * per_axis * per_axis / 32u {
        bricks[word] = atomicLoad(&wg_brick_bits);
    }
}
