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
//! **Depth convention.** Reversed-Z (`near / view_z`: 1 at the near plane, 0 at infinity,
//! cleared to 0 = sky). Each texel holds the **minimum** depth it covers, the farthest thing
//! drawn there, so an object whose nearest depth is below a texel is behind everything in it.
//!
//! **Levels.** For a `W x H` screen, level 0 is `max(1, W/2) x max(1, H/2)` and level `m` is
//! `max(1, w_{m-1}/2) x max(1, h_{m-1}/2)`, rounding **down**, to 1 x 1: exactly the mips wgpu
//! gives a texture of level 0's size ([`level_sizes`]). Texel `i` of a level covers source
//! indices (pixels for level 0) `2i ..= 2i + 1` per axis, and the **last** texel of a row or
//! column also takes the odd index left over (`2i ..= 2i + 2`: [`footprint`]). In pixels,
//! texel `(i, j)` of level `m` covers `[i * 2^(m+1), (i + 1) * 2^(m+1))` on each axis, the last
//! one reaching to the screen edge ([`pixel_span`]), and holds the minimum over exactly those
//! pixels (a unit test checks this on random sizes from the definition).
//!
//! *Why not `ceil(W/2)` levels.* A chain that rounds up (`ceil(w/2)`, the last texel covering
//! one index where the size is odd) does not fit one wgpu texture: mip sizes round down, so
//! on a 37-wide screen (level 0: 19) level 1 would need 10 texels where mip 1 has 9. Storing
//! it would take a texture padded to powers of two (up to 4x the texels; 1024 x 1024 instead
//! of 960 x 540 at 1080p) plus a uniform carrying the real sizes to every shader that reads
//! it. Rounding down and letting the last texel take the odd row (Turitzin's
//! non-power-of-two Hi-Z) keeps level = mip, no padding, and every size derived from level
//! 0's `textureDimensions` by a shift. The bound is as conservative; only the last row and
//! column of texels of a level are wider (under 2x) at odd sizes, so a rectangle at the
//! screen's right or bottom edge may be tested a little more coarsely.
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
//! **CPU twins.** [`pyramid_reference`] (and [`merge_visibility_reference`] for level 0's
//! inputs) makes the build's decisions, and [`rect_test_reference`] /
//! [`rect_visible_reference`] the test's, with the same `f32` operations in the same order:
//! every step is a `floor`, a `min`, a `max`, a comparison or an exact conversion, so the GPU
//! agrees bit for bit (for inputs without NaN; `-0.0` and `0.0` may come out either way and
//! compare equal). The GPU tests (`tests/gpu_hiz.rs`) check both on lavapipe.
//!
//! ```
//! use gpu_backend::hiz::{pyramid_reference, rect_visible_reference};
//!
//! // An 8 x 4 screen: a wall at depth 0.5 on the left half, sky on the right.
//! let depth: Vec<f32> = (0..32).map(|p| if p % 8 < 4 { 0.5 } else { 0.0 }).collect();
//! let levels = pyramid_reference(&depth, 8, 4)?;
//! assert_eq!(levels.len(), 3); // 4 x 2, 2 x 1, 1 x 1
//! // A box at depth 0.25 (farther than the wall) behind the wall is occluded ...
//! assert!(!rect_visible_reference(&levels, 8, 4, [0.5, 0.5], [3.5, 3.5], 0.25)?);
//! // ... one in front of it is not, nor is one that reaches the sky.
//! assert!(rect_visible_reference(&levels, 8, 4, [0.5, 0.5], [3.5, 3.5], 0.75)?);
//! assert!(rect_visible_reference(&levels, 8, 4, [2.5, 0.5], [5.5, 1.5], 0.25)?);
//! # Ok::<(), gpu_backend::hiz::HizError>(())
//! ```
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
mod levels;
mod pyramid;
mod readback;
mod rect;
mod reference;
#[cfg(test)]
mod test_rng;

pub use bindings::{
    LEVEL0_DEPTH, LEVEL0_OUT, LEVEL0_VISIBILITY, PYRAMID_FORMAT, REDUCE_OUT, REDUCE_SOURCE,
    TAIL_LEVELS, TAIL_OUT, TAIL_SOURCE,
};
pub use error::HizError;
pub use levels::{MAX_SCREEN_EDGE, footprint, half, level_sizes, pixel_span, texel_of_pixel};
pub use pyramid::DepthPyramid;
pub use rect::{RectTest, rect_test_reference, rect_visible_reference};
pub use reference::{merge_visibility_reference, pyramid_reference};
