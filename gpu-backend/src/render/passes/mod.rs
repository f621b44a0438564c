//! The frame's passes, one file each with its shader of the same name beside it
//! (`gbuffer.rs` and `gbuffer.wgsl`), in frame order:
//!
//! | pass | file | what it records |
//! | ---- | ---- | --------------- |
//! | cull | [`cull`] | nodes to multi-draw-indirect commands: LOD selection, frustum, face directions, occlusion; the transparent layer back to front |
//! | quad raster | [`quad_raster`] | opaque greedy quads rasterised in compute into the 64-bit visibility buffer (compute opaque path) |
//! | far splat | [`far_splat`] | far-drawn nodes' blocks splatted in compute into the visibility buffers |
//! | far raster | [`far_raster`] | far-drawn nodes' blocks as sprites or camera-facing quads (raster far paths) |
//! | G-buffer | [`gbuffer`] | opaque greedy and smooth quads (and raster far blocks) into the G-buffer |
//! | Hi-Z | [`hiz`] | the depth pyramid of the early phase, for the late cull |
//! | grass | [`grass`] | clutter units as crossed quads into the G-buffer, culled with their chunks, swaying in the wind (after the opaque phases) |
//! | shells | [`shells`] | nodes' vertical shell runs as boxes synthesised in the vertex shader into the G-buffer, culled with their nodes (after the opaque phases) |
//! | prop cull | [`prop_cull`] | glTF prop instances: zero each batch's count, frustum and Hi-Z per instance, one indexed indirect draw per batch (after the opaque phases) |
//! | props | [`props`] | the batches' visible prop instances into the G-buffer |
//! | shadow | [`shadow`] | the camera-centred occupancy grid from the drawn nodes' quads, then per pixel the sun and sky visibility rays through it (with shadows on) |
//! | lighting | [`lighting`] | G-buffer and visibility buffers to display-linear HDR, sky and haze |
//! | transparent | [`transparent`] | transparent quads and far blocks blended into the HDR target |
//! | tonemap | [`tonemap`] | HDR to the sRGB output (or to `ldr` before anti-aliasing) |
//! | antialias | [`antialias`] | FXAA of `ldr` into the output |
//! | present | [`present`] | the output blitted into a window's swapchain image |
//!
//! Every pass records from one frame context ([`frame::FrameCtx`]: the device, the resident
//! nodes, the targets, the shared resources of [`shared`]) into a [`frame::Recorder`] (the
//! encoder, the open compute pass, the GPU timer), and opens its own timer scope. Passes hand
//! each other their outputs as arguments, so the frame's data flow reads in one place:
//! `Renderer::record_frame`. A new pass is one new file here (with its shader, named in
//! `crate::shaders`) and one line in that frame.
//!
//! [`targets`] holds the frame's textures, [`fullscreen`] what the full-screen passes share.

pub mod antialias;
pub mod cull;
pub mod far_raster;
pub mod far_splat;
pub mod frame;
pub mod fullscreen;
pub mod gbuffer;
pub mod grass;
pub mod hiz;
pub mod lighting;
pub mod present;
pub mod prop_cull;
pub mod props;
pub mod quad_raster;
pub mod shadow;
pub mod shared;
pub mod shells;
pub mod targets;
pub mod tonemap;
pub mod transparent;
