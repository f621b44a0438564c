// The shell cull: one indirect draw appended per chunk table slot whose node has shell runs
// and that the voxel cull draws (non-indexed, 18 vertices per run, first_vertex = 18 * its
// first run, first_instance = slot; compacted: the draw's index is stats[0], the draw count).
// A slot draws when its node is selected by the level-of-detail rule (lod.wgsl) at its own
// level (without selection: when it is level 0), its mesh box (which holds its runs' boxes) is inside the frustum, and, with
// occlusion culling, the voxel cull found it visible in this frame's late phase (its bit),
// and, with far draws (SHELL_CULL_FAR), it is not far-drawn by the voxel cull's rule (a node
// with far blocks whose cells span at most far_cell_px pixels at its box's nearest point).
// FORMATS_WGSL, node.wgsl and lod.wgsl come before this body.

// The same layout as GrassCullUniforms (render_model::grass; the pass fills it the same way).
struct ShellCullUniforms {
    planes: array<vec4<f32>, 6>,
    camera_chunk: vec3<i32>,
    slot_bound: u32,
    camera_offset: vec3<f32>,
    chunk_edge: f32,
    lod: LodParams,
    flags: u32,
    focal_px: f32,
    // GrassCullUniforms::budget_px: the far threshold here.
    far_cell_px: f32,
    pad: u32,
}

// Twins of render_model::grass::GRASS_CULL_LOD and GRASS_CULL_OCCLUSION.
const SHELL_CULL_LOD: u32 = 1u;
const SHELL_CULL_OCCLUSION: u32 = 2u;
const SHELL_CULL_FAR: u32 = 4u;
const VERTICES_PER_RUN: u32 = 18u;

@group(0) @binding(0) var<uniform> g: ShellCullUniforms;
@group(0) @binding(1) var<storage, read> table: array<MeshedChunkInfo>;
@group(0) @binding(2) var<storage, read> nodes: array<NodeRecord>;
// (vertex_count, instance_count, first_vertex, first_instance) per drawn node, compacted.
@group(0) @binding(3) var<storage, read_write> args: array<vec4<u32>>;
// The voxel cull's visibility bits (a bit per slot; one zero word without occlusion).
@group(0) @binding(4) var<storage, read> visible: array<u32>;
// 0: nodes drawn (the draw count), 1: runs drawn.
@group(0) @binding(5) var<storage, read_write> stats: array<atomic<u32>>;

fn shell_in_frustum(c: vec3<f32>, e: vec3<f32>) -> bool {
    for (var i = 0u; i < 6u; i += 1u) {
        let p = g.planes[i];
        if dot(p.xyz, c) + p.w + dot(abs(p.xyz), e) < 0.0 {
            return false;
        }
    }
    return true;
}

fn shell_slot_draws(slot: u32) -> bool {
    let info = table[slot];
    if nodes[slot].shell_count == 0u {
        return false;
    }
    let coord = vec3<i32>(info.chunk_x, info.chunk_y, info.chunk_z);
    // The voxel cull's rule: without level-of-detail selection only level 0 is drawn.
    if (g.flags & SHELL_CULL_LOD) != 0u {
        if !lod_selected(g.lod, coord, info.lod) {
            return false;
        }
    } else if info.lod != 0u {
        return false;
    }
    // The mesh box, in the node's voxels: scale to blocks, relative to the camera.
    let scale = f32(1u << min(info.lod, 15u));
    let rel = (coord << vec3<u32>(min(info.lod, 31u))) - g.camera_chunk;
    let origin = vec3<f32>(rel) * g.chunk_edge - g.camera_offset;
    let c = origin + vec3<f32>(info.centre_x, info.centre_y, info.centre_z) * scale;
    let box_extent = vec3<f32>(info.extent_x, info.extent_y, info.extent_z) * scale;
    let e = box_extent + vec3<f32>(0.01);
    if !shell_in_frustum(c, e) {
        return false;
    }
    // The voxel cull's far rule (cull.wgsl), on the same box: scale * focal / distance <=
    // far_cell_px, without a division.
    let far_drawn = (g.flags & SHELL_CULL_FAR) != 0u
        && (nodes[slot].flags & NODE_HAS_BLOCKS) != 0u
        && scale * g.focal_px <= g.far_cell_px * length(max(abs(c) - box_extent, vec3<f32>(0.0)));
    if far_drawn {
        return false;
    }
    if (g.flags & SHELL_CULL_OCCLUSION) != 0u
        && (visible[slot >> 5u] & (1u << (slot & 31u))) == 0u {
        return false;
    }
    return true;
}

@compute @workgroup_size(64)
fn shells_cull(@builtin(global_invocation_id) id: vec3<u32>) {
    let slot = id.x;
    if slot >= g.slot_bound {
        return;
    }
    if shell_slot_draws(slot) {
        let node = nodes[slot];
        let draw = atomicAdd(&stats[0], 1u);
        atomicAdd(&stats[1], node.shell_count);
        args[draw] = vec4<u32>(node.shell_count * VERTICES_PER_RUN, 1u, node.shell_offset * VERTICES_PER_RUN, slot);
    }
}
