// Hi-Z occlusion test against a depth pyramid (gpu-backend/src/hiz): functions only, no
// bindings, to be prepended to a shader that tests boxes (the cull pass). Twin of
// gpu-backend/src/hiz/rect.rs (same clamping, same level choice, same texels, same min order):
// keep the two in step, operation by operation.
//
// CONTRACT. The including shader declares, at any group and binding it likes,
//
//     var hiz_texture: texture_2d<f32>;
//
// bound to DepthPyramid::texture_view() (all mips; sample type Float, not filterable:
// DepthPyramid::layout_entry gives the entry). Sizes and the level count come from
// textureDimensions (level 0) / textureNumLevels, so no uniform is needed. Every name declared here
// starts with `hiz_`; the includer must not declare other `hiz_` names.
//
// THE PYRAMID. Level 0 is max(1, W/2) x max(1, H/2) for a W x H screen, each level halves the
// one before (rounding down) to 1 x 1: a wgpu mip chain. Texel i of level m covers pixels
// [i * 2^(m+1), (i+1) * 2^(m+1)), except the last texel of a row (column), which also takes
// the pixels past that, to the screen edge. Each texel holds the minimum reversed-Z depth
// (farthest) of those pixels: 0 is sky (nothing drawn), 1 the near plane.
//
// API:
//   hiz_rect_visible(rect_min, rect_max, nearest_depth) -> bool
//       false (occluded) only when nearest_depth < hiz_rect_farthest(rect_min, rect_max);
//       a NaN nearest_depth is visible.
//   hiz_rect_farthest(rect_min, rect_max) -> f32
//       a lower bound of the depth of every screen pixel the rectangle touches: the minimum of
//       the (at most 2 x 2) texels of hiz_rect_level that cover them.
//   hiz_rect_level(pixels) -> u32, hiz_rect_pixels(rect_min, rect_max) -> HizPixels
//       the steps, exposed for callers that want to record them.
//
// RECTANGLES are in pixels, x right, y down, (0, 0) the top-left corner of the top-left
// pixel: a box's projected bounds. They need not be clamped or ordered:
//   - the corners are ordered per axis (an inverted rectangle is tested as the rectangle
//     between its corners: reject empty boxes before calling);
//   - pixel x is touched when floor(min.x) <= x <= floor(max.x) (a rectangle ending exactly on
//     a pixel edge also tests that pixel: conservative);
//   - pixels are clamped to the screen (to 0 ..= 2 * level-0 width - 1, which picks the same
//     texels as clamping to W - 1), so a rectangle partly off screen tests its on-screen part,
//     and one wholly off screen tests the nearest screen-edge pixels (reject those with the
//     frustum test first); infinities clamp like large values;
//   - NaN coordinates give an unspecified answer (still reading texels of the pyramid, never
//     out of bounds).
// A box that reaches the near plane has no meaningful rectangle: treat it as visible without
// calling.

// An inclusive range of screen pixels: lo <= hi per axis.
struct HizPixels {
    lo: vec2<u32>,
    hi: vec2<u32>,
}

// Size of level `level` (a mip chain rounds down: max(1, level-0 size >> level)). Computed
// rather than asked of textureDimensions(hiz_texture, level): with a level that differs
// between invocations, lavapipe (Mesa 22.3) answers every lane of a SIMD group with one lane's
// size, and the arithmetic is cheaper anyway.
fn hiz_level_size(level: u32) -> vec2<u32> {
    return max(textureDimensions(hiz_texture, 0u) >> vec2<u32>(level), vec2<u32>(1u));
}

// Levels of the pyramid.
fn hiz_level_count() -> u32 {
    return textureNumLevels(hiz_texture);
}

// The texel of `level` whose footprint holds pixel `p` (pixels past the last texel's start
// belong to the last texel). Twin of levels::texel_of_pixel.
fn hiz_texel_of_pixel(p: vec2<u32>, level: u32) -> vec2<u32> {
    return min(p >> vec2<u32>(level + 1u), hiz_level_size(level) - 1u);
}

// The pixels a rectangle touches, ordered and clamped (see RECTANGLES above).
fn hiz_rect_pixels(rect_min: vec2<f32>, rect_max: vec2<f32>) -> HizPixels {
    let bound = 2u * hiz_level_size(0u) - 1u;
    let boundf = vec2<f32>(bound);
    let lo = min(rect_min, rect_max);
    let hi = max(rect_min, rect_max);
    let lo_px = min(vec2<u32>(min(max(floor(lo), vec2<f32>(0.0)), boundf)), bound);
    let hi_px = min(vec2<u32>(min(max(floor(hi), vec2<f32>(0.0)), boundf)), bound);
    return HizPixels(lo_px, hi_px);
}

// Smallest shift s with (hi >> s) - (lo >> s) <= 1, for lo <= hi < 2^31. With
// 2^(g-1) <= hi - lo < 2^g it is g - 1 or g.
fn hiz_min_shift(lo: u32, hi: u32) -> u32 {
    let e = hi - lo;
    if e == 0u {
        return 0u;
    }
    let g = firstLeadingBit(e) + 1u;
    let s = g - 1u;
    return select(g, s, (hi >> s) - (lo >> s) <= 1u);
}

// The finest level at which `pixels` fall in at most 2 texels per axis (texel grid of
// 2^(level+1) pixels; the top level, 1 x 1, when none finer does).
fn hiz_rect_level(pixels: HizPixels) -> u32 {
    let shift = max(
        max(hiz_min_shift(pixels.lo.x, pixels.hi.x), hiz_min_shift(pixels.lo.y, pixels.hi.y)),
        1u,
    );
    return min(shift - 1u, hiz_level_count() - 1u);
}

// A lower bound of the depth of every pixel the rectangle touches (see the API above).
fn hiz_rect_farthest(rect_min: vec2<f32>, rect_max: vec2<f32>) -> f32 {
    let pixels = hiz_rect_pixels(rect_min, rect_max);
    let level = hiz_rect_level(pixels);
    let t0 = hiz_texel_of_pixel(pixels.lo, level);
    let t1 = hiz_texel_of_pixel(pixels.hi, level);
    let a = textureLoad(hiz_texture, t0, level).x;
    let b = textureLoad(hiz_texture, vec2<u32>(t1.x, t0.y), level).x;
    let c = textureLoad(hiz_texture, vec2<u32>(t0.x, t1.y), level).x;
    let d = textureLoad(hiz_texture, t1, level).x;
    return min(min(a, b), min(c, d));
}

// False (occluded) only when the object, whose largest (nearest) reversed-Z depth is
// `nearest_depth`, is farther than everything drawn in its rectangle.
fn hiz_rect_visible(rect_min: vec2<f32>, rect_max: vec2<f32>, nearest_depth: f32) -> bool {
    return !(nearest_depth < hiz_rect_farthest(rect_min, rect_max));
}
