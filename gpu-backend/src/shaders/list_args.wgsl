// One thread between the opaque cull records and an ordered record over the transparent list:
// the ordered record's workgroup counts (64 slots each) from the list's length. Twin of
// cull::CullPass::record_ordered_with's indirect dispatches: [x, y, z] workgroups.

// The statistics word counting the transparent list (cull::CullStats::TRANSPARENT_LIST_WORD).
const STAT_TRANSPARENT_LIST: u32 = 13u;
const SLOTS_PER_GROUP: u32 = 64u;
const MAX_GROUPS: u32 = 65535u;

@group(0) @binding(0) var<storage, read_write> stats: array<atomic<u32>>;
@group(0) @binding(1) var<storage, read_write> args: array<u32>;
@group(0) @binding(2) var<storage, read> list: array<u32>;

@compute @workgroup_size(1)
fn transparent_args() {
    let n = min(atomicLoad(&stats[STAT_TRANSPARENT_LIST]), arrayLength(&list));
    let groups = (n + SLOTS_PER_GROUP - 1u) / SLOTS_PER_GROUP;
    args[0] = min(groups, MAX_GROUPS);
    args[1] = (groups + MAX_GROUPS - 1u) / MAX_GROUPS;
    args[2] = 1u;
}
