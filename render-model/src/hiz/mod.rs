//! The depth pyramid's rules (Hi-Z for two-phase occlusion culling) and the CPU twins of its
//! build and its test. `gpu_backend::hiz` builds the pyramid on the GPU and holds the WGSL
//! test a cull shader runs against it; both make exactly the decisions made here.
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
//! **CPU twins.** [`pyramid_reference`] (and [`merge_visibility_reference`] for level 0's
//! inputs) makes the build's decisions, and [`rect_test_reference`] /
//! [`rect_visible_reference`] the test's, with the same `f32` operations in the same order:
//! every step is a `floor`, a `min`, a `max`, a comparison or an exact conversion, so the GPU
//! agrees bit for bit (for inputs without NaN; `-0.0` and `0.0` may come out either way and
//! compare equal). `gpu-backend`'s GPU tests (`tests/gpu_hiz.rs`) check both on lavapipe.
//!
//! ```
//! use render_model::hiz::{pyramid_reference, rect_visible_reference};
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
//! # Ok::<(), render_model::hiz::ScreenError>(())
//! ```
//!

mod error;
mod levels;
mod rect;
mod reference;
#[cfg(test)]
mod test_rng;

pub use error::ScreenError;
pub use levels::{
    MAX_SCREEN_EDGE, check_screen, footprint, half, level_sizes, pixel_span, texel_of_pixel,
};
pub use rect::{RectTest, rect_test_reference, rect_visible_reference};
pub use reference::{merge_visibility_reference, pyramid_reference};
