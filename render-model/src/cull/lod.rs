//! Level-of-detail selection by one screen-space error budget: the rule, its hysteresis, and
//! the CPU twin of `lod.wgsl` (the same `f32` operations in the same order).
//!
//! # Levels and their error
//!
//! A node of level `k` covers `2^k x 2^k x 2^k` chunks of level 0 with one chunk of the same
//! edge whose voxels are `2^k` blocks wide (`mesher::lod`'s downsampling: a coarse voxel is
//! solid when any of its children is). Every point of its surface lies within
//! `sqrt(3) (2^k - 1)` blocks of the full-detail surface: a coarse voxel's faces are on its
//! cell's boundary, and the cell holds at least one solid child, which is at most `2^k - 1`
//! blocks from that boundary point *along each axis* (a lone child in the far corner of its
//! cell is that far from the near corner on all three at once). So level `k` **errs by
//! `e_k = sqrt(3) (2^k - 1)` blocks** (level 0 by nothing). Any displacement of length `e`
//! projects to at most `e f / d` pixels, whatever its direction, so this is the bound the
//! budget needs; the per-axis `2^k - 1` alone understates it (the 4096^2 view at 1 px missed
//! the image-error bar with it; BENCHMARKS.md has the budget sweep).
//!
//! # The rule
//!
//! Seen from a point at distance `d`, an error of `e` blocks spans at most `e * f / d` pixels,
//! with `f = (height / 2) / tan(fov_y / 2)` the focal length in pixels. With a budget of `B`
//! pixels a node *refines* (its eight children are drawn instead) when
//!
//! ```text
//!     e_k * f  >  B * max(d_k - h, 0)          d_k: distance from the anchor to the node's cube
//! ```
//!
//! and it is *selected* when it does not refine while its parent does (or it is at the top
//! level). Distances shrink by one level for the parent's larger cube and errors grow, so along
//! every path from the top level down exactly one node is selected: the drawn set covers space
//! once, with no overlap and no hole (where the chunks exist).
//!
//! # Hysteresis and the anchor
//!
//! Distances are measured from the **anchor**, not the camera. The anchor moves to the camera
//! only when the camera is more than `h` blocks away from it, and the rule subtracts `h` from
//! every distance: so for any camera within `h` of the anchor the real error of every selected
//! node stays within the budget (`d_camera >= d_anchor - h`), and between two anchor moves
//! nothing changes level, however the camera wanders. The selection depends only on the anchor
//! (never on the view direction), so turning the camera changes no level either.
//!
//! # Skirts
//!
//! A selected node draws the skirt of side `s` (`mesher::lod::skirts`) when its same-level
//! neighbour across `s` is not selected: that neighbour's space is drawn at another level. The
//! neighbour's selection is computed by the same rule from its cube alone, so the two sides of
//! every level border agree without looking each other up.
//!
//! # Far draws
//!
//! A selected node is drawn from its surface blocks (far draws) instead of its quads when its
//! cells, seen from the camera at the nearest point of its box, span at most `far_cell_px`
//! pixels. Far draws render each block as its exact cube (ray-box per pixel), so they add no
//! geometric error to their level: the switch is a cost decision, made per adapter by
//! measurement, not an accuracy one.

use bytemuck::{Pod, Zeroable};
use voxel_core::{ChunkCoord, FaceDirection};

/// The selection's inputs as `lod.wgsl` reads them (`LodParams`), 48 bytes; a unit test checks
/// the layout with naga.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct LodParams {
    /// The anchor's level-0 chunk.
    pub anchor_chunk: [i32; 3],
    /// The highest level nodes exist at (selected whenever they do not refine).
    pub top_level: u32,
    /// The anchor inside its chunk, blocks.
    pub anchor_offset: [f32; 3],
    /// The error budget, pixels.
    pub budget_px: f32,
    /// Pixels per unit of tangent: `(height / 2) / tan(fov_y / 2)`.
    pub focal_px: f32,
    /// Hysteresis distance, blocks.
    pub hysteresis: f32,
    /// Chunk edge, blocks.
    pub chunk_edge: f32,
    /// Zero.
    pub pad: u32,
}

const _: () = assert!(size_of::<LodParams>() == 48, "LodParams is 48 bytes");

/// `sqrt(3)`, the diagonal factor of the level error `e_k` (`lod.wgsl` spells the same `f32`).
const SQRT_3: f32 = 1.732_050_8;

/// Distance from the origin to the cube `[lo, lo + size]` (0 inside).
fn cube_distance(lo: [f32; 3], size: f32) -> f32 {
    let d: [f32; 3] = std::array::from_fn(|i| lo[i].max(-(lo[i] + size)).max(0.0));
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// The anchor-relative minimum corner of node `coord` of `level`, blocks: the chunk difference
/// in wrapping `i32`, then `f32`.
fn node_lo(p: &LodParams, coord: [i32; 3], level: u32) -> [f32; 3] {
    std::array::from_fn(|i| {
        let rel = (coord[i] << level).wrapping_sub(p.anchor_chunk[i]);
        rel as f32 * p.chunk_edge - p.anchor_offset[i]
    })
}

/// Distance from the anchor to node `coord` of `level`'s cube, blocks (0 inside): what the
/// selection measures.
pub fn node_distance(p: &LodParams, coord: [i32; 3], level: u32) -> f32 {
    cube_distance(
        node_lo(p, coord, level),
        p.chunk_edge * (1u32 << level.min(31)) as f32,
    )
}

/// True when node `coord` of `level` errs by more than the budget (its children are drawn).
pub fn refines(p: &LodParams, coord: [i32; 3], level: u32) -> bool {
    if level == 0 {
        return false;
    }
    let scale = (1u32 << level) as f32;
    let distance = cube_distance(node_lo(p, coord, level), p.chunk_edge * scale);
    let d = (distance - p.hysteresis).max(0.0);
    (scale - 1.0) * SQRT_3 * p.focal_px > p.budget_px * d
}

/// True when node `coord` of `level` is drawn (see the [module docs](self)).
pub fn selected(p: &LodParams, coord: [i32; 3], level: u32) -> bool {
    if refines(p, coord, level) {
        return false;
    }
    if level >= p.top_level {
        return true;
    }
    refines(p, coord.map(|c| c >> 1), level + 1)
}

/// Bit `f` (`FaceDirection::index`) set when the same-level neighbour across side `f` is not
/// selected, so the node draws that side's skirt.
pub fn skirt_mask(p: &LodParams, coord: [i32; 3], level: u32) -> u32 {
    let mut mask = 0;
    for face in FaceDirection::ALL {
        let n = face.normal();
        let neighbour = std::array::from_fn(|i| coord[i].wrapping_add(n[i]));
        if !selected(p, neighbour, level) {
            mask |= 1 << face.index();
        }
    }
    mask
}

/// The focal length in pixels of a vertical field of view over `height` pixels.
pub fn focal_px(fov_y: f64, height: u32) -> f32 {
    (f64::from(height) * 0.5 / (fov_y * 0.5).tan()) as f32
}

/// The user's side of the selection: the budget and its companions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LodSettings {
    /// The error budget, pixels (default 1). 0 selects level 0 everywhere: full detail.
    pub budget_px: f32,
    /// Hysteresis distance, blocks: how far the camera may move from the anchor before the
    /// selection moves with it (default 16).
    pub hysteresis: f32,
    /// Nodes whose cells span at most this many pixels are far-drawn from their surface blocks
    /// (when far draws are on and the node has them); 0 meshes every node.
    pub far_cell_px: f32,
}

impl Default for LodSettings {
    fn default() -> Self {
        LodSettings {
            budget_px: 1.0,
            hysteresis: 16.0,
            far_cell_px: 4.0,
        }
    }
}

/// Why a [`LodSettings`] was refused.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BadLodSetting {
    /// Which setting.
    pub name: &'static str,
    /// Its value.
    pub value: f32,
}

impl std::fmt::Display for BadLodSetting {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "LOD setting {} = {} must be finite and at least 0",
            self.name, self.value
        )
    }
}

impl std::error::Error for BadLodSetting {}

impl LodSettings {
    /// The settings if every value is finite and non-negative.
    pub fn validate(self) -> Result<LodSettings, BadLodSetting> {
        for (name, value) in [
            ("budget_px", self.budget_px),
            ("hysteresis", self.hysteresis),
            ("far_cell_px", self.far_cell_px),
        ] {
            if !value.is_finite() || value < 0.0 {
                return Err(BadLodSetting { name, value });
            }
        }
        Ok(self)
    }
}

/// Where level-of-detail distances are measured from, moved with hysteresis (see the
/// [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LodAnchor {
    /// Level-0 chunk.
    pub chunk: ChunkCoord,
    /// Offset inside the chunk, blocks.
    pub offset: [f32; 3],
}

impl LodAnchor {
    /// Distance from this anchor to the point `(chunk, offset)` of a world of `edge`-block
    /// chunks, blocks (`f64`; chunk differences wrap in `i32` like every camera-relative
    /// placement).
    pub fn distance_to(&self, chunk: ChunkCoord, offset: [f32; 3], edge: u32) -> f64 {
        let d = [
            chunk.x.wrapping_sub(self.chunk.x),
            chunk.y.wrapping_sub(self.chunk.y),
            chunk.z.wrapping_sub(self.chunk.z),
        ];
        let v: [f64; 3] = std::array::from_fn(|i| {
            f64::from(d[i]) * f64::from(edge) + f64::from(offset[i]) - f64::from(self.offset[i])
        });
        (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
    }

    /// The anchor after the camera moved to `(chunk, offset)`: unchanged while the camera is
    /// within `hysteresis` blocks, else the camera's position.
    pub fn follow(
        self,
        chunk: ChunkCoord,
        offset: [f32; 3],
        edge: u32,
        hysteresis: f32,
    ) -> LodAnchor {
        if self.distance_to(chunk, offset, edge) > f64::from(hysteresis) {
            LodAnchor { chunk, offset }
        } else {
            self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params(budget: f32, top: u32) -> LodParams {
        LodParams {
            anchor_chunk: [0; 3],
            top_level: top,
            anchor_offset: [4.0; 3],
            budget_px: budget,
            focal_px: 800.0,
            hysteresis: 0.0,
            chunk_edge: 8.0,
            pad: 0,
        }
    }

    /// The level selected along the path from the top to the level-0 chunk `c0`.
    fn selected_levels(p: &LodParams, c0: [i32; 3]) -> Vec<u32> {
        (0..=p.top_level)
            .filter(|&k| selected(p, c0.map(|c| c >> k), k))
            .collect()
    }

    #[test]
    fn exactly_one_level_is_selected_along_every_path() {
        for budget in [0.0, 0.25, 1.0, 4.0, 1e6] {
            let p = params(budget, 6);
            for x in (-700..700).step_by(37) {
                for z in (-300..300).step_by(23) {
                    let levels = selected_levels(&p, [x, 1, z]);
                    assert_eq!(
                        levels.len(),
                        1,
                        "budget {budget}, chunk ({x}, 1, {z}): {levels:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn levels_follow_the_error_rule() {
        let p = params(1.0, 8);
        // Level 1 errs by sqrt(3) blocks: it needs d >= sqrt(3) focal / budget = 1385.6
        // blocks (the per-axis error alone would allow it from 800).
        let near = selected_levels(&p, [160, 0, 0])[0];
        let far = selected_levels(&p, [180, 0, 0])[0];
        assert_eq!(near, 0, "1276 blocks away");
        assert_eq!(far, 1, "1436 blocks away");
        assert_eq!(selected_levels(&params(0.0, 8), [5000, 0, 0]), vec![0]);
        assert_eq!(selected_levels(&params(1e9, 8), [1000, 0, 0]), vec![8]);
        // At distance 0 every error is unbounded: full detail around the anchor.
        assert_eq!(selected_levels(&params(1e9, 8), [0, 0, 0]), vec![0]);
        // The selected node's own error is within budget at its distance, its parent's is not.
        for x in [100, 300, 1000, 4000] {
            let k = selected_levels(&p, [x, 0, 0])[0];
            assert!(!refines(&p, [x >> k, 0, 0], k));
        }
    }

    #[test]
    fn skirts_face_exactly_the_neighbours_at_other_levels() {
        let p = params(1.0, 6);
        for x in -400..400 {
            let c0 = [x, 0, 3];
            let k = selected_levels(&p, c0)[0];
            let coord = c0.map(|c| c >> k);
            let mask = skirt_mask(&p, coord, k);
            // +X neighbour: its level-0 chunks are drawn at level k iff it is selected.
            let n0 = [(coord[0] + 1) << k, 0, 3];
            let nk = selected_levels(&p, n0)[0];
            assert_eq!(
                mask & 1 != 0,
                nk != k,
                "chunk {x}: level {k}, +X neighbour {nk}"
            );
        }
    }

    #[test]
    fn the_anchor_moves_only_past_the_hysteresis() {
        let a = LodAnchor {
            chunk: ChunkCoord::new(0, 0, 0),
            offset: [1.0; 3],
        };
        let near = a.follow(ChunkCoord::new(1, 0, 0), [1.0; 3], 8, 16.0);
        assert_eq!(near, a);
        let moved = a.follow(ChunkCoord::new(3, 0, 0), [1.0; 3], 8, 16.0);
        assert_eq!(moved.chunk, ChunkCoord::new(3, 0, 0));
        assert!(
            LodSettings {
                budget_px: f32::NAN,
                ..Default::default()
            }
            .validate()
            .is_err()
        );
    }

    #[test]
    fn hysteresis_keeps_the_error_within_budget_for_cameras_near_the_anchor() {
        let mut p = params(1.0, 6);
        p.hysteresis = 16.0;
        // A camera 16 blocks from the anchor, toward the nodes.
        let mut cam = p;
        cam.anchor_offset = [4.0 + 16.0, 4.0, 4.0];
        cam.hysteresis = 0.0;
        for x in 0..600 {
            let k = selected_levels(&p, [x, 0, 0])[0];
            // Seen from the moved camera the selected node does not refine: within budget.
            assert!(!refines(&cam, [x >> k, 0, 0], k), "chunk {x} level {k}");
        }
    }
}
