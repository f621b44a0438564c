// The raster far draws' indirect commands (render::far::raster): one non-indexed draw per
// far-list entry, compacted to slots 0..n, and n in count[0]. Entry point `draw_args_phase`
// takes the entries the last far_args range names (those one cull record appended);
// `draw_args_all` takes every entry of the frame so far (the transparent layer's draws).
// Slots n..capacity are written as empty draws, so the multi-draw without a count buffer draws
// exactly the same. node.wgsl and far_blocks.wgsl come before this body.

// Vertices per block: 6 (sprite) or 18 (cube).
override VERTICES_PER_BLOCK: u32 = 6u;
// Largest workgroup count of one dispatch dimension (the dispatch folds into y past it).
const MAX_GROUPS: u32 = 65535u;

struct DrawArgs {
    vertex_count: u32,
    instance_count: u32,
    first_vertex: u32,
    first_instance: u32,
}

// [x, y, z workgroups, first entry, end entry], written by far_args.
@group(0) @binding(0) var<storage, read> range: array<u32>;
@group(0) @binding(1) var<storage, read> far_list: array<vec2<u32>>;
@group(0) @binding(2) var<storage, read> nodes: array<NodeRecord>;
@group(0) @binding(3) var<storage, read_write> args: array<DrawArgs>;
@group(0) @binding(4) var<storage, read_write> count: array<u32>;

fn write_args(slot: u32, start: u32) {
    let capacity = arrayLength(&args);
    if slot >= capacity {
        return;
    }
    let end = min(range[4], arrayLength(&far_list));
    let n = min(end - min(start, end), capacity);
    if slot == 0u {
        count[0] = n;
    }
    var a = DrawArgs(0u, 0u, 0u, 0u);
    if slot < n {
        let entry = start + slot;
        let e = far_list[entry];
        a = DrawArgs(far_block_total(nodes[e.x], e.y) * VERTICES_PER_BLOCK, 1u, 0u, entry);
    }
    args[slot] = a;
}

@compute @workgroup_size(64)
fn draw_args_phase(@builtin(global_invocation_id) id: vec3<u32>) {
    write_args(id.y * MAX_GROUPS * 64u + id.x, range[3]);
}

@compute @workgroup_size(64)
fn draw_args_all(@builtin(global_invocation_id) id: vec3<u32>) {
    write_args(id.y * MAX_GROUPS * 64u + id.x, 0u);
}
