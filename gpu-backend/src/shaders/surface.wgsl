// What the surface passes share (G-buffer, transparent, raster far draws): greedy PackedQuads
// and smooth BlockVertex quads pulled by index (no vertex buffers), their bindings, the
// G-buffer texels and the forward-lit colour of a surface point. render_common.wgsl comes
// before this body, FORMATS_WGSL before that.
//
// Quads: the shared index buffer holds 4q + (0, 1, 2, 0, 2, 3); draws start at index 0 with
// base_vertex = 4 * (in-page index of the first quad), so vertex_index >> 2 is the quad in the
// bound page and vertex_index & 3 the corner slot. records[instance_index] is the draw's
// DrawRecord (first_instance = its index): the node's level-0 chunk difference to the camera
// chunk and its level of detail, whose voxels are 2^level blocks wide.

@group(0) @binding(0) var<uniform> frame: FrameUniforms;
@group(0) @binding(1) var<storage, read> materials: array<GpuMaterial>;

// Twin of cull::DrawRecord (a unit test checks the layout with naga).
struct DrawRecord {
    chunk_x: i32,
    chunk_y: i32,
    chunk_z: i32,
    level: u32,
}

@group(1) @binding(0) var<storage, read> quads: array<PackedQuad>;
@group(1) @binding(1) var<storage, read> records: array<DrawRecord>;
// The opaque visibility buffer (64-bit words as (payload, depth bits) pairs) when the frame
// has one (FRAME_SPLAT): the transparent quads are hidden behind what it holds.
@group(1) @binding(9) var<storage, read> opaque_visibility: array<vec2<u32>>;

// One smooth chunk: its level-0 chunk difference to the camera chunk and where its vertices and
// quads live (twin of render::SmoothDraw, written by the cull pass).
struct SmoothDraw {
    chunk_x: i32,
    chunk_y: i32,
    chunk_z: i32,
    vertex_offset: u32,
    // The chunk's first word in the smooth-quad page, and its form (SMOOTH_QUADS_*).
    quad_offset: u32,
    quad_count: u32,
    quad_form: u32,
    // Level of detail: positions scale by 2^level.
    level: u32,
}

@group(1) @binding(2) var<storage, read> smooth_vertices: array<BlockVertex>;
// Smooth quads as the mesher wrote them (compact records, u16 or u32 indices), as words.
@group(1) @binding(3) var<storage, read> smooth_quads: array<u32>;
@group(1) @binding(4) var<storage, read> smooth_draws: array<SmoothDraw>;

// How far vs_quad grows a quad in its plane, in pixels at the quad's distance, and the least
// it grows it, blocks (see vs_quad). Rasterisers snap to 1/256 pixel or finer, so 1/64 pixel
// closes T-junction pinholes; more would move edges: a pixel centre within the hair of a
// crease sees the wrong face.
const DILATION_PX: f32 = 1.0 / 64.0;
const MIN_DILATION: f32 = 1.0 / 4096.0;

struct SurfaceVaryings {
    @builtin(position) position: vec4<f32>,
    @location(0) @interpolate(flat) block: u32,
    // Ambient occlusion, 0..=3, interpolated across the triangle.
    @location(1) ao: f32,
    // Constant over a greedy quad, per vertex on smooth surfaces.
    @location(2) normal: vec3<f32>,
}

// Camera-relative position of chunk-local point `local` of chunk `rel` (already chunk -
// camera chunk): every term is small, so nothing large is ever an f32.
fn relative_position(rel: vec3<i32>, local: vec3<f32>) -> vec4<f32> {
    let p = (vec3<f32>(rel) * frame.chunk_edge - frame.camera_offset) + local;
    return frame.view_proj * vec4<f32>(p, 1.0);
}

// The corner of its quad that vertex `vertex` of the bound page is: slot `vertex & 3`, after
// the AO diagonal flip of mesher::blocky::triangle_indices (split along corners 1-3 when they
// are brighter, by renaming corner slot k to corner (k + 1) & 3).
fn quad_corner(vertex: u32) -> u32 {
    let q = quads[vertex >> 2u];
    let flip = packed_quad_ao(q, 1u) + packed_quad_ao(q, 3u) > packed_quad_ao(q, 0u) + packed_quad_ao(q, 2u);
    return ((vertex & 3u) + u32(flip)) & 3u;
}

// Corner `vertex & 3` of quad `vertex >> 2` of the bound page, in the chunk of the draw's
// record. `grow`: see vs_quad.
fn quad_vertex(vertex: u32, instance: u32, grow: bool) -> SurfaceVaryings {
    let q = quads[vertex >> 2u];
    let corner = quad_corner(vertex);
    let record = records[instance];
    let rel = vec3<i32>(record.chunk_x, record.chunk_y, record.chunk_z);
    let scale = f32(1u << min(record.level, 15u));
    let cell = vec3<f32>(packed_quad_corner(q, corner));
    var local = cell * scale;
    if grow {
        // The normal axis of (corner - centre) is 0, so sign() keeps the quad in its plane.
        let centre = 0.5 * (vec3<f32>(packed_quad_corner(q, 0u)) + vec3<f32>(packed_quad_corner(q, 2u)));
        let origin = vec3<f32>(rel) * frame.chunk_edge - frame.camera_offset;
        // One pixel spans distance * 2 tan(fov_y / 2) / height blocks; |up| = tan(fov_y / 2).
        let pixel = 2.0 * length(frame.up) / f32(frame.height);
        let hair = max(length(origin + local) * pixel * DILATION_PX, MIN_DILATION);
        local += sign(cell - centre) * hair;
    }
    var out: SurfaceVaryings;
    out.position = relative_position(rel, local);
    out.block = packed_quad_block(q);
    out.ao = f32(packed_quad_ao(q, corner));
    out.normal = vec3<f32>(face_normal(packed_quad_face(q)));
    return out;
}

// Vertex `vertex % 6` of smooth quad `vertex / 6` of the draw `instance`.
fn smooth_vertex(vertex: u32, instance: u32) -> SurfaceVaryings {
    let draw = smooth_draws[instance];
    let q = vertex / 6u;
    // Triangles (a, b, c) and (a, c, d) of the quad's corners.
    let slot = array<u32, 6>(0u, 1u, 2u, 0u, 2u, 3u)[vertex % 6u];
    // The corner's words (FORMATS_WGSL): the second is read for compact records only, and
    // clamped to the page in case the chunk ends it.
    let w = draw.quad_offset + smooth_quad_word(draw.quad_form, q, slot);
    let next = min(w + 1u, arrayLength(&smooth_quads) - 1u);
    let index = smooth_quad_corner(draw.quad_form, q, slot, smooth_quads[w], smooth_quads[next]);
    let v = smooth_vertices[draw.vertex_offset + index];
    let scale = f32(1u << min(draw.level, 15u));
    let local = (block_vertex_position(v, frame.smooth_extent) - vec3<f32>(frame.smooth_origin)) * scale;
    let n = block_vertex_normal(v);
    var out: SurfaceVaryings;
    out.position = relative_position(vec3<i32>(draw.chunk_x, draw.chunk_y, draw.chunk_z), local);
    out.block = block_vertex_block(v);
    out.ao = 3.0;
    out.normal = n;
    return out;
}

struct GBufferOut {
    // sRGB albedo (exact palette bytes), alpha = AO / 3.
    @location(0) albedo_ao: vec4<f32>,
    // Octahedral 16+16 normal, block id.
    @location(1) normal_material: vec2<u32>,
}

// The G-buffer texels of a surface point of block `block` (AO 0..=3, normal not yet unit).
fn gbuffer_texels(block: u32, ao: f32, normal: vec3<f32>) -> GBufferOut {
    let m = material_of(block);
    var out: GBufferOut;
    out.albedo_ao = vec4<f32>(material_srgba(m).rgb, clamp(ao / 3.0, 0.0, 1.0));
    out.normal_material = vec2<u32>(oct32_encode(normalize(normal)), block);
    return out;
}

// A transparent surface point at fragment position `position` lit (forward) with the
// lighting model's transparent-layer rule (lighting::surface) and seen through the haze:
// premultiplied colour and coverage, for a premultiplied-alpha blend. `inside`: blocks from the
// point to the opaque surface behind it along the view ray.
fn transparent_colour(block: u32, ao: f32, normal: vec3<f32>, position: vec4<f32>, inside: f32) -> vec4<f32> {
    let m = surface_material(material_of(block));
    let seen = eye_ray(vec2<u32>(floor(position.xy)), position.z);
    let layer = transparent_layer(m, normalize(normal), ao, seen.dir, inside);
    return haze_layer(layer, seen.dir, seen.distance);
}
