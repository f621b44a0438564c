//! The depth pyramid (Hi-Z) for two-phase occlusion culling: a compute-built min-depth mip
//! chain of the renderer's reversed-Z depth, the WGSL test a cull shader runs against it, and
//! CPU twins of both.
//!
//! ```text
//!  depth (Depth32Float, W x H) ─┐
//!  visibility (W*H x u64, opt) ─┴─► hiz_level0 ─► level 0 ─► hiz_reduce ─► … ─► level s ─► hiz_tail ─► … ─► 1 x 1
//!                                   (1 dispatch)   (R32Float mip chain,       (fifth level   (the last four
//!                                                   one dispatch per level)    from the end)  levels: 1 dispatch)
//!
//!  cull shader:  hiz.wgsl + `var hiz_texture: texture_2d<f32>` (DepthPyramid::texture_view())
//!                hiz_rect_visible(rect_min, rect_max, nearest_depth) -> bool
//! ```
//!
//! The rules (depth convention, level sizes, the rectangle test's decisions) and their CPU
//! twins are in [`render_model::hiz`]; this module builds the pyramid on the GPU and holds
//! the WGSL test.
//!
//! **Build** ([`DepthPyramid::record_build`]): one compute pass, one dispatch per level but
//! the last [`TAIL_LEVELS`], then one dispatch of one workgroup (`hiz_tail`) for those, each
//! kept in workgroup memory for the next (7 dispatches at 1920 x 1080 instead of 10: levels
//! 0-5, then 6-9; see [`DepthPyramid::build_dispatches`]). Each dispatch costs the CPU a
//! barrier and a driver call (on the NVIDIA driver, together about 14 k instructions), and
//! the small levels cannot fill a GPU anyway. No render pass, no uniforms (sizes from
//! `textureDimensions`). Level 0 reads
//! each pixel's depth with `textureLoad` and, when a visibility buffer is given, takes
//! `max(depth, bitcast<f32>(high word))` (the nearer of the two) before the minimum. The
//! visibility buffer is the splatting pass's `W * H` 64-bit `atomicMax` words, row-major
//! (`y * W + x`), read as `array<vec2<u32>>` (`x` = low word, payload; `y` = high word, the
//! `f32` bits of a reversed-Z depth, 0 = nothing). Without one, a one-word zero buffer is
//! bound and the shader skips it (`arrayLength < W * H`), so one pipeline serves both. Every
//! bind group is made in [`DepthPyramid::new`] except level 0's, which is made on first use
//! of a (depth view, visibility buffer) pair and cached (up to 4 pairs, compared by identity:
//! pass the same `TextureView` and `Buffer` objects each frame, not fresh views).
//!
//! **Cost, reasoned (not measured).** At 1920 x 1080 level 0 reads 8.3 MB of depth (+16.6 MB
//! of visibility words when given) and writes 2.1 MB; the other nine levels read 2.8 MB and
//! write 0.7 MB: about 14 MB without and 30 MB with a visibility buffer, some 5-10 µs of
//! H100 bandwidth. Reads are coalesced (neighbouring invocations read neighbouring pixel
//! pairs). The last levels (15 x 8 texels and smaller at 1080p) are far too small to fill a
//! GPU; they go to the tail's single workgroup, as AMD's single-pass downsampler does for its
//! last levels.
//!
//! **Test** (`hiz.wgsl`, documented there as an API: [`HIZ_FUNCTIONS`]): a shader prepends
//! it and declares `hiz_texture`; `hiz_rect_visible(rect_min, rect_max, nearest_depth)`
//! orders, floors and clamps the rectangle's pixels, picks the finest level at which they fall
//! in at most 2 x 2 texels, loads those (4 loads, repeated where fewer), and returns `false`
//! (occluded) only when `nearest_depth < min(texels)`. Rectangles: pixels, x right, y down;
//! inverted corners are tested as the rectangle between them; pixels off screen are clamped
//! to the nearest screen-edge pixel (a wholly off-screen rectangle tests the screen edge: reject
//! it with the frustum test first); NaN coordinates give an unspecified answer that still
//! reads inside the pyramid. Boxes reaching the near plane should be treated as visible
//! without calling.
//!
//! **Two-phase use** (Haar & Aaltonen; zeux/niagara), for the caller: draw what was visible
//! last frame; `record_build` from that depth; cull everything else with `hiz_rect_visible`
//! against the pyramid (bound with [`DepthPyramid::layout_entry`] and
//! [`DepthPyramid::texture_view`]) and draw what passes; rebuild if the next frame's first
//! phase tests against the pyramid too. The pyramid is per screen size: make a new one on
//! resize.
//!
//! [`HIZ_FUNCTIONS`]: crate::shaders::HIZ_FUNCTIONS

mod bindings;
mod error;
mod pyramid;
mod readback;

pub use bindings::{
    LEVEL0_DEPTH, LEVEL0_OUT, LEVEL0_VISIBILITY, PYRAMID_FORMAT, REDUCE_OUT, REDUCE_SOURCE,
    TAIL_LEVELS, TAIL_OUT, TAIL_SOURCE,
};
pub use error::HizError;
pub use pyramid::DepthPyramid;
