//! Per-frame GPU records: the frame uniforms and the smooth-chunk draw records.

use bytemuck::{Pod, Zeroable};

use voxel_core::ChunkSize;

use crate::camera::Camera;
use crate::lighting::{Lighting, LightingUniforms};

/// The uniforms every renderer shader reads (twin of the WGSL `FrameUniforms` in
/// `gpu-backend`'s `render_common.wgsl`; a test there checks the layout with naga). 272 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct FrameUniforms {
    /// Camera-relative view-projection, column-major ([`Camera::view_projection`]).
    pub view_proj: [[f32; 4]; 4],
    /// The eye inside its chunk, blocks.
    pub camera_offset: [f32; 3],
    /// Chunk edge, blocks.
    pub chunk_edge: f32,
    /// The chunk holding the eye.
    pub camera_chunk: [i32; 3],
    /// Materials uploaded (larger block ids read entry 0).
    pub material_count: u32,
    /// Smooth vertex positions decode over `0..=smooth_extent`.
    pub smooth_extent: f32,
    /// Subtracted from decoded smooth positions to make them chunk-local.
    pub smooth_origin: f32,
    /// Output width, pixels.
    pub width: u32,
    /// Output height, pixels.
    pub height: u32,
    /// Light and sky.
    pub lighting: LightingUniforms,
    /// The view direction (world axes).
    pub forward: [f32; 3],
    /// Near plane, blocks.
    pub near: f32,
    /// Screen right, scaled by the tangent of half the horizontal field of view: the ray
    /// through pixel `(x, y)` is `forward + u * right + v * up` with `u, v` in `-1..1`.
    pub right: [f32; 3],
    /// `FRAME_*` bits.
    pub flags: u32,
    /// Screen up, scaled by the tangent of half the vertical field of view.
    pub up: [f32; 3],
    /// Zero.
    pub pad: u32,
}

const _: () = assert!(size_of::<FrameUniforms>() == 272);

/// `FrameUniforms::flags` bit: far draws were splatted into the visibility buffers this frame,
/// and the lighting pass resolves them.
pub const FRAME_SPLAT: u32 = 1;

/// `FrameUniforms::flags` bit: the shadow pass wrote this frame's per-pixel sun and sky
/// visibility (`lighting::shadow::Visibility` words), and the lighting pass shades with it.
pub const FRAME_SHADOWS: u32 = 2;

/// What [`FrameUniforms::new`] needs besides the camera and lighting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameShape {
    /// Output width, pixels.
    pub width: u32,
    /// Output height, pixels.
    pub height: u32,
    /// Chunk size of the scene (the eye is split into a chunk and an offset by it).
    pub chunk_size: ChunkSize,
    /// Materials uploaded.
    pub material_count: u32,
    /// Smooth vertex extent.
    pub smooth_extent: f32,
    /// Smooth vertex origin.
    pub smooth_origin: f32,
    /// `FRAME_*` bits.
    pub flags: u32,
}

impl FrameUniforms {
    /// The uniforms of one frame.
    pub fn new(camera: &Camera, lighting: &Lighting, shape: &FrameShape) -> Self {
        let eye = camera.eye(shape.chunk_size);
        let basis = camera.basis();
        let (half_w, half_h) = camera.half_extents(shape.width, shape.height);
        let f32s = |v: [f64; 3], scale: f64| v.map(|c| (c * scale) as f32);
        FrameUniforms {
            view_proj: camera.view_projection(shape.width, shape.height),
            camera_offset: eye.offset,
            chunk_edge: shape.chunk_size.edge() as f32,
            camera_chunk: [eye.chunk.x, eye.chunk.y, eye.chunk.z],
            material_count: shape.material_count,
            smooth_extent: shape.smooth_extent,
            smooth_origin: shape.smooth_origin,
            width: shape.width,
            height: shape.height,
            lighting: LightingUniforms::new(lighting),
            forward: f32s(basis.forward, 1.0),
            near: camera.near as f32,
            right: f32s(basis.right, half_w),
            flags: shape.flags,
            up: f32s(basis.up, half_h),
            pad: 0,
        }
    }
}

/// One chunk's smooth layer as the smooth draw reads it (twin of the WGSL `SmoothDraw`),
/// 32 bytes. Written by the cull pass for each visible smooth chunk (from the chunk's
/// `NodeRecord`: `MeshedChunkInfo` has no smooth-quad range).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct SmoothDraw {
    /// Level-0 chunk difference to the camera chunk (wrapping), x, y, z.
    pub chunk: [i32; 3],
    /// First vertex in the smooth-vertex page (quad indices are relative to it).
    pub vertex_offset: u32,
    /// First word of the chunk's quads in the smooth-quad page.
    pub quad_offset: u32,
    /// Quads.
    pub quad_count: u32,
    /// The quads' form: a `SmoothQuadForm` tag (`SMOOTH_QUADS_*` in WGSL).
    pub quad_form: u32,
    /// Level of detail: positions scale by `2^level`.
    pub level: u32,
}

const _: () = assert!(size_of::<SmoothDraw>() == 32);
