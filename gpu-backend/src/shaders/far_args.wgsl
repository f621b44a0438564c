// One thread between a cull record and its splat: the splat's workgroup counts and far-list
// range, from the far list's length and where the previous splat of the frame stopped
// (range[4], cleared with the frame). Twin of render::far's dispatch layout:
// [x, y, z workgroups, first entry, end entry].

// The statistics word counting the far list (cull::CullStats::FAR_LIST_WORD).
const STAT_FAR_LIST: u32 = 9u;
// Largest workgroup count of one dispatch dimension.
const MAX_GROUPS: u32 = 65535u;

@group(0) @binding(0) var<storage, read_write> stats: array<atomic<u32>>;
@group(0) @binding(1) var<storage, read_write> range: array<u32>;
@group(0) @binding(2) var<storage, read> far_list: array<vec2<u32>>;

@compute @workgroup_size(1)
fn far_args() {
    let end = min(atomicLoad(&stats[STAT_FAR_LIST]), arrayLength(&far_list));
    let start = min(range[4], end);
    let n = end - start;
    range[0] = min(n, MAX_GROUPS);
    range[1] = (n + MAX_GROUPS - 1u) / MAX_GROUPS;
    range[2] = 1u;
    range[3] = start;
    range[4] = end;
}
