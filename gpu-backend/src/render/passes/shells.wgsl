// The shell pass: vertical shell runs (ShellRun) drawn as boxes into the G-buffer, synthesised
// from vertex_index alone. render_common.wgsl, node.wgsl and far_ao.wgsl come before this body.
//
// No vertex or index buffers: vertex v of a draw is run v / 18 of the bound shell page
// (first_vertex = 18 * the node's first run), on axis (v % 18) / 6 of its box the face toward
// the eye (a box is convex: the face away from the eye on each axis is a back face), corner
// [0, 1, 2, 0, 2, 3][v % 6] of that face (shell_run_corner: the corners of the greedy quad
// covering the same side, counter-clockwise from outside); instance_index is the chunk table
// slot (first_instance), whose records give the node's chunk, level and hiding mask. A face
// whose side bit is clear is a degenerate triangle outside the clip volume.
//
// Ambient occlusion per pixel: the fragment finds the voxel of the run under it and takes
// the meshers' AO of that voxel's face at that point (far_ao.wgsl's face_ao, from the node's
// hiding mask, which the node carries when meshed with far blocks); without a mask (heightmap
// boxes) a side with its foot at the box's lowest voxel shades that voxel as the meshers shade
// a step's side, and every other face is 3 (unoccluded). Faces grow in their plane by the G-buffer pass's hair against T-junction
// pinholes (DILATION_PX, MIN_DILATION).

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<storage, read> materials: array<GpuMaterial>;
@group(1) @binding(0) var<storage, read> shells: array<ShellRun>;
@group(1) @binding(1) var<storage, read> chunks: array<MeshedChunkInfo>;
@group(1) @binding(2) var<storage, read> nodes: array<NodeRecord>;
// The draw-block gigabuffer's one page (hiding masks), or one zero word without far blocks.
@group(1) @binding(3) var<storage, read> masks: array<u32>;

const VERTICES_PER_RUN: u32 = 18u;
const DILATION_PX: f32 = 1.0 / 64.0;
const MIN_DILATION: f32 = 1.0 / 4096.0;

struct ShellVaryings {
    @builtin(position) position: vec4<f32>,
    // The point in the node's voxel units (chunk-local), interpolated.
    @location(0) voxel: vec3<f32>,
    // The run's box, node voxel units.
    @location(1) @interpolate(flat) lo: vec3<f32>,
    @location(2) @interpolate(flat) hi: vec3<f32>,
    @location(3) @interpolate(flat) block: u32,
    @location(4) @interpolate(flat) face: u32,
    @location(5) @interpolate(flat) slot: u32,
    // 1 when the face has its foot at the box's lowest voxel (ShellRun's feet), else 0.
    @location(6) @interpolate(flat) foot: u32,
}

@vertex
fn vs_shell(@builtin(vertex_index) vertex: u32, @builtin(instance_index) slot: u32) -> ShellVaryings {
    let run = shells[vertex / VERTICES_PER_RUN];
    let info = chunks[slot];
    let level = min(info.lod, 15u);
    let scale = f32(1u << level);
    let coord = vec3<i32>(info.chunk_x, info.chunk_y, info.chunk_z);
    let rel = (coord << vec3<u32>(level)) - frame.camera_chunk;
    let origin = vec3<f32>(rel) * frame.chunk_edge - frame.camera_offset;
    let lo = vec3<f32>(shell_run_position(run));
    let hi = lo + vec3<f32>(f32(shell_run_width(run)), f32(shell_run_height(run)), 1.0);
    // The box's centre relative to the eye picks the face of this vertex's axis: the positive
    // one when the eye is on the positive side (FACE_* pairs: 2 * axis + 1 is the negative).
    let box_centre = origin + 0.5 * (lo + hi) * scale;
    let axis = (vertex % VERTICES_PER_RUN) / 6u;
    let face = 2u * axis + u32(box_centre[axis] >= 0.0);
    let corner = array<u32, 6>(0u, 1u, 2u, 0u, 2u, 3u)[vertex % 6u];
    var out: ShellVaryings;
    out.slot = slot;
    out.face = face;
    out.block = shell_run_block(run);
    out.foot = u32(shell_run_has_foot(run, face));
    if !shell_run_has_side(run, face) {
        // Every vertex of the face at one point behind the eye: nothing rasterises.
        out.position = vec4<f32>(0.0, 0.0, -1.0, 1.0);
        return out;
    }
    let cell = vec3<f32>(shell_run_corner(run, face, corner));
    let centre = 0.5 * (vec3<f32>(shell_run_corner(run, face, 0u)) + vec3<f32>(shell_run_corner(run, face, 2u)));
    var local = cell * scale;
    let pixel = 2.0 * length(frame.up) / f32(frame.height);
    let hair = max(length(origin + local) * pixel * DILATION_PX, MIN_DILATION);
    local += sign(cell - centre) * hair;
    out.position = frame.view_proj * vec4<f32>(origin + local, 1.0);
    out.voxel = local / scale;
    out.lo = lo;
    out.hi = hi;
    return out;
}

// The hiding mask being read (set from the node before any `hides`).
var<private> mask_offset: u32;
var<private> mask_words: u32;

// Whether the node's padded voxel p hides its neighbours (far_ao.wgsl calls it).
fn hides(p: vec3<i32>, edge: i32) -> bool {
    let q = edge + 2;
    if any(p < vec3<i32>(0)) || any(p >= vec3<i32>(q)) {
        return false;
    }
    let i = u32(p.x + q * (p.y + q * p.z));
    let word = min(i >> 5u, max(mask_words, 1u) - 1u);
    return ((masks[mask_offset + word] >> (i & 31u)) & 1u) != 0u;
}

struct ShellOut {
    // sRGB albedo (exact palette bytes), alpha = AO / 3 (as gbuffer_texels writes it).
    @location(0) albedo_ao: vec4<f32>,
    // Octahedral 16+16 normal, block id.
    @location(1) normal_material: vec2<u32>,
}

@fragment
fn fs_shell(in: ShellVaryings) -> ShellOut {
    let n = face_normal(in.face);
    var ao = 3.0;
    let node = nodes[in.slot];
    if node.mask_words > 0u {
        mask_offset = node.mask_offset;
        mask_words = node.mask_words;
        // The voxel under the point: inside the box on the face's plane axes, the box's own
        // layer on its normal axis.
        let inside = clamp(in.voxel, in.lo, in.hi - vec3<f32>(1e-4));
        var v = vec3<i32>(floor(inside));
        let axis = face_normal_axis(in.face);
        let w = face_width_axis(in.face);
        let h = face_height_axis(in.face);
        let layer = select(in.lo[axis], in.hi[axis] - 1.0, face_is_positive(in.face));
        v[axis] = i32(layer);
        let uv = vec2<f32>(inside[w] - f32(v[w]), inside[h] - f32(v[h]));
        ao = face_ao(v + vec3<i32>(1), in.face, uv, i32(frame.chunk_edge));
    } else if in.foot != 0u {
        // A heightmap box's side at a step (no hiding mask): the meshers' AO of a side face
        // whose front voxel below is solid and whose front voxels beside and above are air,
        // 1 at the foot to 3 one voxel up.
        ao = 1.0 + 2.0 * clamp(in.voxel.y - in.lo.y, 0.0, 1.0);
    }
    let m = material_of(in.block);
    var out: ShellOut;
    out.albedo_ao = vec4<f32>(material_srgba(m).rgb, clamp(ao / 3.0, 0.0, 1.0));
    out.normal_material = vec2<u32>(oct32_encode(normalize(vec3<f32>(n))), in.block);
    return out;
}
