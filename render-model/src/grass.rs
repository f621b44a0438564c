//! Grass clutter: how a [`ClutterUnit`] becomes two crossed quads (an "X" seen from above),
//! how wind bends them, how they fade out with distance, and the GPU records of the grass
//! pass. The WGSL twin (`gpu-backend`'s `grass.wgsl`) uses the same constants (a test there
//! compares them with naga) and the same operations; `voxel-reference` rasterises the quads
//! these functions give.
//!
//! # Geometry
//!
//! A unit at chunk-local `p` with up direction `n` (its decoded normal) and scale step `s` is a
//! blade `H = BLADE_HEIGHT * (1 + s / 15)` blocks tall and `W = BLADE_WIDTH_RATIO * H` wide.
//! Quad `q` (0 or 1) lies along the direction at angle `seed * PI / 16 + q * PI / 2` in the
//! plane across `n` ([`quad_direction`]); its corners run base left, base right, top right,
//! top left, with sprite coordinates `(0, 0), (1, 0), (1, 1), (0, 1)` (`y` up the blade).
//!
//! # Wind
//!
//! Only the top corners move: by `strength * WIND_SWAY * H * sin(phase + WIND_SPACE * (p.x +
//! p.z) + WIND_SEED * seed)` along [`WIND_DIRECTION`], where `phase` is
//! [`wind_phase`]`(seconds)`, the time reduced on the CPU in `f64` to `0..2 PI` over
//! [`WIND_PERIOD_S`] (so an `f32` on the GPU never holds a large time). The same time gives
//! the same image.
//!
//! # Fade by the error budget
//!
//! A blade whose height projects to `h_px = H * focal_px / distance` pixels (distance from the
//! eye to its base) is drawn at full size while `h_px >= FADE_FULL * budget_px` (8 budgets),
//! shrunk (height and width) by `(h_px - FADE_DROP * budget_px) / ((FADE_FULL - FADE_DROP) *
//! budget_px)` between, and dropped at `h_px <= FADE_DROP * budget_px` (4 budgets)
//! ([`blade_fade`]). Scaled by the level-of-detail error budget, so a coarser budget thins the
//! grass nearer, as it coarsens the voxels: a blade a few budgets tall covers a few pixels of
//! a tapering sliver, which alias to noise rather than read as grass, and leaving it out
//! errs by its few-pixel size over the ground it stands on. A chunk whose nearest point is so far that
//! its tallest possible blade is dropped is culled whole ([`chunk_fades_out`]). With
//! level-of-detail selection off the budget is [`DEFAULT_BUDGET_PX`].
//!
//! # Where clutter is placed
//!
//! The same fade says where clutter is worth storing. The tallest blade is dropped from
//! [`grass_reach`] `= MAX_BLADE_HEIGHT * focal_px / (FADE_DROP * budget_px)` blocks on (the
//! fade solved for its end), and the grass cull measures that distance to the chunk's cube
//! grown by [`CULL_GROW`] on every axis ([`chunk_grass_distance`]). So a level-0 chunk can
//! draw grass for an eye within `slack` blocks of a point `from` only if its cube lies nearer
//! to `from` than `grass_reach + slack + sqrt(3) * CULL_GROW` ([`may_draw_grass`]: the grown
//! cube lies within `sqrt(3) * CULL_GROW` of the cube, the eye within `slack` of `from`).
//! A streamer places clutter on the chunks this admits from its level-of-detail anchor, with
//! the anchor's hysteresis as the slack ([`chunk_may_draw_grass`]), and on no others: beyond,
//! every unit would be stored and never drawn.
//!
//! # Draw scheme
//!
//! No vertex or index buffers: one non-indexed indirect draw per chunk table slot, `12` vertices
//! per unit ([`VERTICES_PER_UNIT`]), `first_vertex = 12 * (first unit)` and `first_instance =
//! slot`. Vertex `v` is unit `v / 12`, quad `(v % 12) / 6`, corner `[0, 1, 2, 0, 2, 3][v % 6]`.
//!
//! [`ClutterUnit`]: voxel_core::formats::ClutterUnit

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use voxel_core::formats::ClutterUnitFields;

use crate::cull::LodParams;

/// A blade's height at scale step 0, blocks.
pub const BLADE_HEIGHT: f32 = 0.45;
/// A blade's width over its height.
pub const BLADE_WIDTH_RATIO: f32 = 0.8;
/// How far the top of a blade sways at wind strength 1, in blade heights.
pub const WIND_SWAY: f32 = 0.25;
/// Phase change per block along x + z: neighbouring tufts sway out of step.
pub const WIND_SPACE: f32 = 0.35;
/// Phase change per seed step.
pub const WIND_SEED: f32 = 0.4;
/// The wind's period, seconds.
pub const WIND_PERIOD_S: f64 = 3.0;
/// The direction the wind pushes (unit length, horizontal).
pub const WIND_DIRECTION: [f32; 3] = [0.8, 0.0, 0.6];
/// A blade is drawn whole while its projected height is at least this many error budgets.
pub const FADE_FULL: f32 = 8.0;
/// A blade is dropped once its projected height is at most this many error budgets.
pub const FADE_DROP: f32 = 4.0;
/// The error budget, pixels, of the fade when level-of-detail selection is off.
pub const DEFAULT_BUDGET_PX: f32 = 1.0;
/// Vertices a unit is drawn with: two quads of two triangles.
pub const VERTICES_PER_UNIT: u32 = 12;
/// The largest scale step (`ClutterUnit::MAX_SCALE_STEP`).
const MAX_SCALE_STEP: f32 = 15.0;

/// The tallest blade, blocks (scale step 15).
pub const MAX_BLADE_HEIGHT: f32 = 2.0 * BLADE_HEIGHT;

/// A blade's height for scale step `step`, blocks.
pub fn blade_height(step: u8) -> f32 {
    BLADE_HEIGHT * (1.0 + f32::from(step) / MAX_SCALE_STEP)
}

/// The wind phase of time `seconds`: `2 PI * frac(seconds / WIND_PERIOD_S)`, reduced in
/// `f64` so any time gives an `f32` in `0..2 PI`. Not-finite times give phase 0.
pub fn wind_phase(seconds: f64) -> f32 {
    if !seconds.is_finite() {
        return 0.0;
    }
    let turns = (seconds / WIND_PERIOD_S).rem_euclid(1.0);
    (turns * std::f64::consts::TAU) as f32
}

/// What the grass quads of a frame depend on besides the unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrassFrame {
    /// [`wind_phase`] of the frame's time.
    pub wind_phase: f32,
    /// Wind strength: 0 is still, 1 sways by [`WIND_SWAY`].
    pub wind_strength: f32,
    /// Pixels per unit of tangent (`cull::lod::focal_px`).
    pub focal_px: f32,
    /// The error budget, pixels.
    pub budget_px: f32,
}

/// Direction of quad `quad` (0 or 1) of a unit with up direction `n` (unit length) and seed
/// `seed`: a unit vector across `n`.
pub fn quad_direction(n: Vec3, seed: u8, quad: u32) -> Vec3 {
    // A tangent frame of n: the axis least aligned with n, made perpendicular to it.
    let a = if n.y.abs() < 0.9 { Vec3::Y } else { Vec3::Z };
    let t = a.cross(n).normalize();
    let b = n.cross(t);
    let angle =
        f32::from(seed) * (std::f32::consts::PI / 16.0) + quad as f32 * std::f32::consts::FRAC_PI_2;
    t * angle.cos() + b * angle.sin()
}

/// The wind offset of a unit's top corners (chunk-local position `p`, seed `seed`, height
/// `height`) in `frame`.
pub fn wind_offset(p: Vec3, seed: u8, height: f32, frame: &GrassFrame) -> Vec3 {
    let phase = frame.wind_phase + WIND_SPACE * (p.x + p.z) + WIND_SEED * f32::from(seed);
    let sway = frame.wind_strength * WIND_SWAY * height * phase.sin();
    Vec3::from_array(WIND_DIRECTION) * sway
}

/// How much of a blade `height` blocks tall whose base is `distance` blocks from the eye is
/// drawn: 1 whole, 0 dropped, between: the factor its height and width shrink by (see the
/// [module docs](self)).
pub fn blade_fade(height: f32, distance: f32, frame: &GrassFrame) -> f32 {
    let px = height * frame.focal_px / distance.max(1e-6);
    let budget = frame.budget_px;
    if budget <= 0.0 {
        return 1.0;
    }
    ((px - FADE_DROP * budget) / ((FADE_FULL - FADE_DROP) * budget)).clamp(0.0, 1.0)
}

/// Whether every blade of a chunk whose nearest point is `nearest` blocks from the eye is
/// dropped by the fade (the chunk is culled).
pub fn chunk_fades_out(nearest: f32, frame: &GrassFrame) -> bool {
    blade_fade(MAX_BLADE_HEIGHT, nearest, frame) <= 0.0
}

/// How far the grass cull grows a chunk's cube on every axis, blocks: the tallest blade
/// swaying its farthest (a unit's base lies in the cube, its blade may reach out of it).
pub const CULL_GROW: f32 = MAX_BLADE_HEIGHT * (1.0 + WIND_SWAY);

/// The distance from the eye, blocks, at which the tallest blade is dropped by the fade at
/// `focal_px` and `budget_px`: [`chunk_fades_out`] holds from there on. Infinite when the
/// budget is not positive (nothing fades).
pub fn grass_reach(focal_px: f32, budget_px: f32) -> f32 {
    if budget_px <= 0.0 {
        return f32::INFINITY;
    }
    MAX_BLADE_HEIGHT * focal_px / (FADE_DROP * budget_px)
}

/// The grass cull's distance from the eye to a chunk's cube grown by [`CULL_GROW`], blocks
/// (0 inside): `rel` is the chunk's coordinate less the eye's chunk, `offset` the eye inside
/// its chunk, `edge` the chunk edge. The CPU twin of `grass_cull.wgsl`'s `nearest`.
pub fn chunk_grass_distance(rel: [i32; 3], offset: [f32; 3], edge: f32) -> f32 {
    let half = 0.5 * edge;
    let e = half + CULL_GROW;
    let gap = |a: usize| (rel[a] as f32 * edge - offset[a] + half).abs() - e;
    Vec3::new(gap(0), gap(1), gap(2)).max(Vec3::ZERO).length()
}

/// The placement rule (see the [module docs](self)): whether a level-0 chunk whose cube lies
/// `distance` blocks from a point can draw grass for an eye within `slack` blocks of that
/// point, at `focal_px` and `budget_px`. False only where the grass cull drops the chunk for
/// every such eye.
pub fn may_draw_grass(distance: f64, slack: f64, focal_px: f32, budget_px: f32) -> bool {
    let grow = 3f64.sqrt() * f64::from(CULL_GROW);
    distance < f64::from(grass_reach(focal_px, budget_px)) + slack + grow
}

/// The placement rule from a level-of-detail anchor ([`may_draw_grass`] with the anchor's
/// hysteresis as the slack): whether level-0 chunk `coord` can draw grass for an eye within
/// `p.hysteresis` blocks of the anchor, at `p`'s budget and focal length.
pub fn chunk_may_draw_grass(p: &LodParams, coord: [i32; 3]) -> bool {
    may_draw_grass(
        f64::from(crate::cull::lod::node_distance(p, coord, 0)),
        f64::from(p.hysteresis),
        p.focal_px,
        p.budget_px,
    )
}

/// The corners of both quads of `unit` in `frame`: `[quad][corner]`, in the unit's chunk's
/// local space, with `eye` the eye in the same space (for the fade). A dropped blade gives
/// four equal corners per quad (nothing is rasterised).
pub fn unit_corners(unit: &ClutterUnitFields, eye: Vec3, frame: &GrassFrame) -> [[Vec3; 4]; 2] {
    let p = unit.position;
    let n = unit.normal.normalize_or(Vec3::Y);
    let fade = blade_fade(blade_height(unit.scale_step), (p - eye).length(), frame);
    let height = blade_height(unit.scale_step) * fade;
    let half = 0.5 * BLADE_WIDTH_RATIO * height;
    let top = n * height + wind_offset(p, unit.seed, height, frame);
    let mut out = [[p; 4]; 2];
    for (q, quad) in out.iter_mut().enumerate() {
        let d = quad_direction(n, unit.seed, q as u32) * half;
        *quad = [p - d, p + d, p + d + top, p - d + top];
    }
    out
}

/// Sprite coordinates of corner `k` (`y` up the blade).
pub fn corner_sprite(k: usize) -> [f32; 2] {
    [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]][k & 3]
}

/// The clutter kind's shape: kinds with `kind % 4 == 3` are flowers (a stem with a head of
/// the unit's tint), the others grass blades (tinted).
pub fn is_flower(kind: u8) -> bool {
    kind % 4 == 3
}

/// Whether sprite point `s` (0..1 on both axes) of a blade or flower is covered, and the
/// colour there as a multiple of the unit's tint (`None`: not covered). A blade is a
/// triangle tapering to its tip, darker at its base; a flower a thin green stem under a round
/// head of the tint.
pub fn sprite_colour(kind: u8, s: [f32; 2], tint: [f32; 3]) -> Option<[f32; 3]> {
    let [x, y] = s;
    let dx = (x - 0.5).abs();
    if is_flower(kind) {
        let head = ((x - 0.5) * (x - 0.5) + (y - 0.78) * (y - 0.78)).sqrt();
        if head < FLOWER_HEAD_RADIUS {
            return Some(tint);
        }
        if dx < FLOWER_STEM_HALF_WIDTH && y < 0.78 {
            return Some(FLOWER_STEM);
        }
        return None;
    }
    // Half the blade's width at height y: the base spans most of the quad, the tip a point.
    if dx > 0.5 * (1.0 - y) {
        return None;
    }
    let shade = BLADE_BASE_SHADE + (1.0 - BLADE_BASE_SHADE) * y;
    Some(tint.map(|c| c * shade))
}

/// Radius of a flower's head, in sprite units.
pub const FLOWER_HEAD_RADIUS: f32 = 0.2;
/// Half the width of a flower's stem, in sprite units.
pub const FLOWER_STEM_HALF_WIDTH: f32 = 0.06;
/// A flower stem's colour (sRGB, 0..1).
pub const FLOWER_STEM: [f32; 3] = [0.25, 0.5, 0.15];
/// A blade's brightness at its base, relative to its tip.
pub const BLADE_BASE_SHADE: f32 = 0.55;

/// The grass cull's uniforms (twin of `GrassCullUniforms` in `grass/cull.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GrassCullUniforms {
    /// Camera-relative frustum planes (as `CullView::planes`).
    pub planes: [[f32; 4]; 6],
    /// The chunk holding the eye.
    pub camera_chunk: [i32; 3],
    /// Slots to test.
    pub slot_bound: u32,
    /// The eye inside its chunk, blocks.
    pub camera_offset: [f32; 3],
    /// Chunk edge, blocks.
    pub chunk_edge: f32,
    /// The level-of-detail selection the voxel cull uses (`GRASS_CULL_LOD` set).
    pub lod: LodParams,
    /// `GRASS_CULL_*` bits.
    pub flags: u32,
    /// Pixels per unit of tangent.
    pub focal_px: f32,
    /// The fade's error budget, pixels.
    pub budget_px: f32,
    /// Zero.
    pub pad: u32,
}

/// [`GrassCullUniforms::flags`]: the level-of-detail selection decides which level-0 chunks
/// are drawn.
pub const GRASS_CULL_LOD: u32 = 1;
/// [`GrassCullUniforms::flags`]: occlusion culling ran; a chunk's visibility bit says whether
/// the voxel cull drew it.
pub const GRASS_CULL_OCCLUSION: u32 = 2;
/// [`GrassCullUniforms::flags`], in the shell cull (which shares the layout): far draws are
/// on, so a node with far-draw blocks whose cells span at most `budget_px` pixels (the far
/// threshold there) is drawn by the far path, not by its runs, as the voxel cull decides.
pub const SHELL_CULL_FAR: u32 = 4;

/// The grass draw's uniforms (twin of `GrassUniforms` in `grass.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GrassUniforms {
    /// [`GrassFrame::wind_phase`].
    pub wind_phase: f32,
    /// [`GrassFrame::wind_strength`].
    pub wind_strength: f32,
    /// [`GrassFrame::focal_px`].
    pub focal_px: f32,
    /// [`GrassFrame::budget_px`].
    pub budget_px: f32,
}

impl From<&GrassFrame> for GrassUniforms {
    fn from(f: &GrassFrame) -> GrassUniforms {
        GrassUniforms {
            wind_phase: f.wind_phase,
            wind_strength: f.wind_strength,
            focal_px: f.focal_px,
            budget_px: f.budget_px,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    fn unit(p: Vec3, seed: u8, step: u8) -> ClutterUnitFields {
        ClutterUnitFields {
            position: p,
            normal: Vec3::Y,
            kind: 0,
            scale_step: step,
            seed,
            uv: Vec2::ZERO,
            uv_size: Vec2::splat(15.0 / 255.0),
            tint: [255; 4],
        }
    }

    fn frame(phase: f32, strength: f32) -> GrassFrame {
        GrassFrame {
            wind_phase: phase,
            wind_strength: strength,
            focal_px: 300.0,
            budget_px: 1.0,
        }
    }

    #[test]
    fn wind_moves_only_the_top_corners() {
        let u = unit(Vec3::new(3.5, 4.0, 2.25), 5, 7);
        let eye = Vec3::new(3.0, 6.0, -2.0);
        let still = unit_corners(&u, eye, &frame(0.0, 0.0));
        let windy = unit_corners(&u, eye, &frame(1.0, 1.0));
        for q in 0..2 {
            assert_eq!(still[q][0], windy[q][0]);
            assert_eq!(still[q][1], windy[q][1]);
            assert!((still[q][2] - windy[q][2]).length() > 0.01);
            assert!((still[q][3] - windy[q][3]).length() > 0.01);
        }
    }

    #[test]
    fn the_same_time_gives_the_same_quads() {
        let u = unit(Vec3::new(1.5, 2.0, 7.75), 9, 3);
        let f = frame(wind_phase(12.25), 1.0);
        let g = frame(wind_phase(12.25 + WIND_PERIOD_S * 1000.0), 1.0);
        let a = unit_corners(&u, Vec3::ZERO, &f);
        let b = unit_corners(&u, Vec3::ZERO, &g);
        for q in 0..2 {
            for k in 0..4 {
                assert!((a[q][k] - b[q][k]).length() < 1e-4);
            }
        }
        assert_eq!(wind_phase(f64::NAN), 0.0);
        assert!((0.0..std::f32::consts::TAU + 1e-6).contains(&wind_phase(-7.0)));
    }

    #[test]
    fn the_quads_cross_and_stand_on_the_unit() {
        let u = unit(Vec3::new(0.5, 1.0, 0.5), 0, 0);
        let c = unit_corners(&u, Vec3::new(0.5, 1.5, -3.0), &frame(0.0, 0.0));
        let d0 = (c[0][1] - c[0][0]).normalize();
        let d1 = (c[1][1] - c[1][0]).normalize();
        assert!(d0.dot(d1).abs() < 1e-6, "quads are perpendicular");
        assert!((c[0][2].y - 1.0 - BLADE_HEIGHT).abs() < 1e-6);
        assert!(((c[0][1] - c[0][0]).length() - BLADE_WIDTH_RATIO * BLADE_HEIGHT).abs() < 1e-6);
        assert_eq!(0.5 * (c[0][0] + c[0][1]), u.position);
    }

    #[test]
    fn blades_fade_by_projected_size_against_the_budget() {
        let f = frame(0.0, 0.0);
        let h = blade_height(0);
        // Whole at 8 budgets or more, dropped at 4 budgets or less, halfway at 6.
        let at = |px: f32| h * f.focal_px / px;
        assert_eq!(blade_fade(h, at(8.0), &f), 1.0);
        assert_eq!(blade_fade(h, at(4.0), &f), 0.0);
        assert!((blade_fade(h, at(6.0), &f) - 0.5).abs() < 1e-5);
        assert_eq!(blade_fade(h, at(2.0), &f), 0.0);
        let coarse = GrassFrame {
            budget_px: 2.0,
            ..f
        };
        assert_eq!(
            blade_fade(h, at(8.0), &coarse),
            0.0,
            "a coarser budget drops it"
        );
        let zero_budget = GrassFrame {
            budget_px: 0.0,
            ..f
        };
        assert_eq!(blade_fade(h, 1e6, &zero_budget), 1.0);
        // A chunk is culled exactly when its tallest blade would be dropped.
        let far = MAX_BLADE_HEIGHT * f.focal_px / (FADE_DROP * f.budget_px);
        assert!(chunk_fades_out(far * 1.01, &f));
        assert!(!chunk_fades_out(far * 0.99, &f));
        // A dropped blade has no area.
        let u = unit(Vec3::ZERO, 0, 0);
        let c = unit_corners(&u, Vec3::new(0.0, 0.0, at(3.9)), &f);
        assert!(c.iter().flatten().all(|&p| p == Vec3::ZERO));
    }

    #[test]
    fn the_reach_is_where_the_tallest_blade_fades_out() {
        for (focal, budget) in [(64.0, 1.0), (935.0, 1.0), (935.0, 1.19), (300.0, 4.0)] {
            let f = GrassFrame {
                focal_px: focal,
                budget_px: budget,
                ..frame(0.0, 0.0)
            };
            let reach = grass_reach(focal, budget);
            assert!(chunk_fades_out(reach * 1.0001, &f), "{focal} {budget}");
            assert!(!chunk_fades_out(reach * 0.9999, &f), "{focal} {budget}");
        }
        assert_eq!(grass_reach(100.0, 0.0), f32::INFINITY);
        assert!(
            may_draw_grass(1e30, 0.0, 100.0, 0.0),
            "no budget: nothing fades"
        );
    }

    /// Eyes within the slack of an anchor and chunks around it (a fixed pseudo-random
    /// sweep): every chunk the cull keeps for some eye is one the placement rule admits from
    /// the anchor, and the rule admits little beyond (within one chunk's diagonal and the
    /// slack of a kept one).
    #[test]
    fn placement_admits_every_chunk_the_cull_can_draw() {
        let edge = 16.0f32;
        let (focal, budget, slack) = (120.0f32, 1.0f32, 16.0f64);
        let f = GrassFrame {
            focal_px: focal,
            budget_px: budget,
            ..frame(0.0, 0.0)
        };
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 33) as f64 / f64::from(1u32 << 31)) * 2.0 - 1.0
        };
        let (mut kept, mut admitted) = (0, 0);
        for _ in 0..200 {
            // The anchor at the origin chunk's (8, 8, 8); the eye within the slack of it.
            let anchor = [8.0f64; 3];
            let dir = Vec3::new(next() as f32, next() as f32, next() as f32).normalize_or(Vec3::X);
            let eye = [0, 1, 2].map(|a| anchor[a] + f64::from(dir[a]) * slack * next().abs());
            for x in -5..=5 {
                for y in -2..=2 {
                    for z in -5..=5 {
                        let rel = [x, y, z];
                        // The eye's chunk and offset (it may have left the anchor's chunk).
                        let chunk = eye.map(|e| (e / f64::from(edge)).floor() as i32);
                        let offset = [0, 1, 2]
                            .map(|a| (eye[a] - f64::from(chunk[a]) * f64::from(edge)) as f32);
                        let from_eye = [0, 1, 2].map(|a| rel[a] - chunk[a]);
                        let drawn =
                            !chunk_fades_out(chunk_grass_distance(from_eye, offset, edge), &f);
                        let gap = |a: usize| {
                            let lo = f64::from(rel[a]) * f64::from(edge) - anchor[a];
                            lo.max(-(lo + f64::from(edge))).max(0.0)
                        };
                        let distance = (gap(0).powi(2) + gap(1).powi(2) + gap(2).powi(2)).sqrt();
                        let placed = may_draw_grass(distance, slack, focal, budget);
                        assert!(
                            !drawn || placed,
                            "chunk {rel:?} drawn from {eye:?} but not placed"
                        );
                        kept += usize::from(drawn);
                        admitted += usize::from(placed);
                        if placed {
                            let reach = f64::from(grass_reach(focal, budget));
                            assert!(distance < reach + slack + 2.0, "{distance}");
                        }
                    }
                }
            }
        }
        assert!(
            kept > 1000 && admitted > kept,
            "{kept} kept, {admitted} admitted"
        );
    }

    #[test]
    fn blades_taper_and_flowers_have_heads() {
        let t = [0.2, 0.8, 0.3];
        assert!(sprite_colour(0, [0.5, 0.05], t).is_some());
        assert!(sprite_colour(0, [0.05, 0.9], t).is_none());
        assert!(sprite_colour(0, [0.5, 0.99], t).is_some());
        assert_eq!(sprite_colour(3, [0.5, 0.78], t), Some(t));
        assert_eq!(sprite_colour(3, [0.5, 0.3], t), Some(FLOWER_STEM));
        assert!(sprite_colour(3, [0.2, 0.3], t).is_none());
        assert!(is_flower(7) && !is_flower(4));
    }
}
