//! Sun shadows and sky visibility by rays through block occupancy: the one rule the GPU
//! (`gpu_backend`'s shadow pass) and the CPU reference (`voxel_reference`) both trace.
//!
//! **Occupancy.** A ray asks an [`Occupancy`] whether a block cell is solid. The cell is in
//! camera-relative block coordinates: block position less the camera's block (the GPU never
//! sees a large world coordinate). Only the cells of the camera-centred grid
//! ([`GRID_CELLS`]^3 one-block cells, [`in_grid`]) can be solid ([`GridClipped`]): the GPU
//! holds no occupancy outside it, so the CPU reference clips its world the same way, and
//! surfaces farther than the grid are unshadowed on both.
//!
//! **What the GPU marks, and why it equals the CPU's full occupancy.** The GPU fills its grid
//! from the opaque quads of the nodes the level-of-detail rule selects this frame, skirts
//! included: the solid cell behind every quad (at a node's level a cell is `2^level` blocks
//! on each axis). That marks the *shell* of every solid: each solid cell with a face open to
//! air. A DDA ray steps face to face (6-connected), so coming from air it enters a solid
//! through a face, and the cell it enters is a shell cell: a march that starts in air stops
//! at the same cell whether the solid's inside is marked or not. The start is in air because
//! the shaded point is first moved half a block out of its surface along the normal.
//!
//! **No light leaks at LOD borders.** The selected nodes tile space without overlap: every
//! cell is answered by exactly one level, the one drawn there. A node's skirts are its
//! border faces (the quads it draws when the neighbour across that side is at another level),
//! so the shell is closed across every border: the fine side's solids end in marked cells at
//! the border, the coarse side's too, and a ray crossing the border meets one or the other
//! before it can enter either solid. Without the skirts a coarse solid whose border face is
//! hidden by its coarse neighbour's data (which the fine node replaces) would have an open
//! side there; the test `a_wall_across_a_lod_border_shadows_the_floor_continuously` states the
//! property on a mixed-level occupancy, and the GPU image tests check it on resident nodes.
//!
//! **March** ([`march`]): Amanatides–Woo DDA from the shaded point, first offset along the
//! surface normal by [`ShadowSettings::normal_bias`] blocks (times the level's cell size the
//! caller passes, so a point on a coarse surface leaves its own coarse cell), then along the
//! ray. It stops at the first solid cell (occluded), after [`ShadowSettings::max_steps`]
//! cells, or beyond [`ShadowSettings::max_distance`] blocks for the sun ray and
//! [`ShadowSettings::sky_distance`] for the sky rays (unoccluded). The bounds are checked by
//! [`ShadowSettings::check`]. The grid is in blocks, so the renderers pass a cell
//! size of 1.
//!
//! **Sky visibility** ([`sky_visibility`]): the fraction of [`SKY_DIRECTIONS`] (straight up
//! and four directions 45° from it) whose march escapes; the hemisphere ambient is
//! multiplied by it, so a cave (every ray blocked) gets no sky light and open ground all of it.
//!
//! **Per surface point** ([`surface_visibility`]): both, packed in one word
//! ([`Visibility::pack`]) as the GPU's shadow pass writes it per pixel; the sun ray is not
//! marched where the surface faces away from the sun (its sun term is 0 anyway).
//!
//! **Why rays and not cascaded shadow maps.** The GPU machine is a compute part with few
//! raster units (about 0.26 G quads/s in the G-buffer pass), where fragment-heavy work runs
//! about 30 times slower than compute; a shadow map re-rasterises the scene once per
//! cascade, while the grid is filled and marched in compute only. [`ShadowSettings`]
//! switches both features so their cost can be measured.

use core::fmt;

/// Where a ray's cells are solid: the finest resident occupancy covering each cell.
pub trait Occupancy {
    /// Whether the block cell `cell` (camera-relative block coordinates) is solid.
    fn solid(&self, cell: [i32; 3]) -> bool;

    /// Whether brick `brick` (the [`BRICK`]^3 cells `brick * BRICK ..`, camera-relative) is
    /// known to hold no solid cell. `false` where it is not known: the march then steps
    /// through the brick cell by cell, to the same answer (a jump only saves the steps).
    fn brick_empty(&self, _brick: [i32; 3]) -> bool {
        false
    }
}

impl<F: Fn([i32; 3]) -> bool> Occupancy for F {
    fn solid(&self, cell: [i32; 3]) -> bool {
        self(cell)
    }
}

/// One-block cells per axis of the camera-centred occupancy grid: cells `-GRID_CELLS / 2 ..
/// GRID_CELLS / 2` on each axis, camera-relative (the GPU grid holds `GRID_CELLS^3` bits,
/// 2 MiB).
pub const GRID_CELLS: i32 = 256;

/// Whether camera-relative `cell` lies in the occupancy grid.
pub fn in_grid(cell: [i32; 3]) -> bool {
    cell.iter()
        .all(|&c| (-(GRID_CELLS / 2)..GRID_CELLS / 2).contains(&c))
}

/// An occupancy seen through the grid: solid only inside it ([`in_grid`]), as the GPU has it.
#[derive(Clone, Copy, Debug)]
pub struct GridClipped<O>(pub O);

impl<O: Occupancy> Occupancy for GridClipped<O> {
    fn solid(&self, cell: [i32; 3]) -> bool {
        in_grid(cell) && self.0.solid(cell)
    }

    /// Bricks outside the grid are empty (the grid is whole bricks: [`GRID_CELLS`] / 2 is a
    /// multiple of [`BRICK`]); inside it, what the occupancy knows.
    fn brick_empty(&self, brick: [i32; 3]) -> bool {
        !in_grid(brick.map(|b| b * BRICK)) || self.0.brick_empty(brick)
    }
}

/// Cells per axis of a brick: the unit [`Occupancy::brick_empty`] answers for, and the GPU
/// grid's memory block (8^3 cells, one bit per brick says whether it holds a marked cell).
pub const BRICK: i32 = 8;

/// Switches and bounds of the shadow and sky-visibility rays.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowSettings {
    /// Whether the sun is tested for occlusion (off: every surface facing it is lit).
    pub sun_shadows: bool,
    /// Whether the hemisphere ambient falls with sky visibility (off: visibility 1).
    pub sky_visibility: bool,
    /// Cells a ray visits at most.
    pub max_steps: u32,
    /// Blocks the sun ray travels at most.
    pub max_distance: f32,
    /// Blocks a sky ray travels at most: sky light is hidden by what is near (a roof, a
    /// cave), so these rays are shorter than the sun's.
    pub sky_distance: f32,
    /// Offset along the normal before marching, in cells of the surface's level.
    pub normal_bias: f32,
}

impl Default for ShadowSettings {
    /// Both features on, 128 cells, sun rays of 64 blocks, sky rays of 16, half a cell of
    /// bias. A ray that meets nothing costs its whole distance, so the distances set the
    /// trace's cost: 64 blocks holds the shadow of a 40-block cliff under a sun 35 degrees
    /// high; 16 blocks of sky ray darken caves and overhangs, not open valleys.
    fn default() -> Self {
        ShadowSettings {
            sun_shadows: true,
            sky_visibility: true,
            max_steps: 128,
            max_distance: 64.0,
            sky_distance: 16.0,
            normal_bias: 0.5,
        }
    }
}

impl ShadowSettings {
    /// Both features off (the bounds of the default): the image without shadows.
    pub const OFF: ShadowSettings = ShadowSettings {
        sun_shadows: false,
        sky_visibility: false,
        max_steps: 128,
        max_distance: 64.0,
        sky_distance: 16.0,
        normal_bias: 0.5,
    };

    /// Whether either feature is on (the renderers trace rays only then).
    pub fn enabled(&self) -> bool {
        self.sun_shadows || self.sky_visibility
    }
}

/// Why a [`ShadowSettings`] cannot be rendered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShadowSettingsError {
    /// `max_steps` is 0 or above [`MAX_STEPS_LIMIT`].
    Steps {
        /// The rejected value.
        max_steps: u32,
    },
    /// `max_distance` is not finite or not positive.
    Distance {
        /// The rejected value.
        max_distance: f32,
    },
    /// `sky_distance` is not finite or not positive.
    SkyDistance {
        /// The rejected value.
        sky_distance: f32,
    },
    /// `normal_bias` is not finite or is outside `0..=2` cells.
    Bias {
        /// The rejected value.
        normal_bias: f32,
    },
}

impl fmt::Display for ShadowSettingsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ShadowSettingsError::Steps { max_steps } => {
                write!(
                    f,
                    "shadow max_steps {max_steps} is outside 1..={MAX_STEPS_LIMIT}"
                )
            }
            ShadowSettingsError::Distance { max_distance } => {
                write!(
                    f,
                    "shadow max_distance {max_distance} is not a positive finite number"
                )
            }
            ShadowSettingsError::SkyDistance { sky_distance } => {
                write!(
                    f,
                    "shadow sky_distance {sky_distance} is not a positive finite number"
                )
            }
            ShadowSettingsError::Bias { normal_bias } => {
                write!(f, "shadow normal_bias {normal_bias} is outside 0..=2 cells")
            }
        }
    }
}

impl std::error::Error for ShadowSettingsError {}

/// The most cells a ray may visit: bounds the lighting pass's cost per pixel.
pub const MAX_STEPS_LIMIT: u32 = 1024;

impl ShadowSettings {
    /// Checks that the bounds are usable: steps in `1..=MAX_STEPS_LIMIT`, positive finite
    /// distances, a bias in `0..=2` cells.
    pub fn check(&self) -> Result<(), ShadowSettingsError> {
        if self.max_steps == 0 || self.max_steps > MAX_STEPS_LIMIT {
            return Err(ShadowSettingsError::Steps {
                max_steps: self.max_steps,
            });
        }
        if !self.max_distance.is_finite() || self.max_distance <= 0.0 {
            return Err(ShadowSettingsError::Distance {
                max_distance: self.max_distance,
            });
        }
        if !self.sky_distance.is_finite() || self.sky_distance <= 0.0 {
            return Err(ShadowSettingsError::SkyDistance {
                sky_distance: self.sky_distance,
            });
        }
        if !self.normal_bias.is_finite() || !(0.0..=2.0).contains(&self.normal_bias) {
            return Err(ShadowSettingsError::Bias {
                normal_bias: self.normal_bias,
            });
        }
        Ok(())
    }
}

/// The sky-visibility directions, unit vectors: straight up and four at 45° from it.
pub const SKY_DIRECTIONS: [[f32; 3]; 5] = [
    [0.0, 1.0, 0.0],
    [
        core::f32::consts::FRAC_1_SQRT_2,
        core::f32::consts::FRAC_1_SQRT_2,
        0.0,
    ],
    [
        -core::f32::consts::FRAC_1_SQRT_2,
        core::f32::consts::FRAC_1_SQRT_2,
        0.0,
    ],
    [
        0.0,
        core::f32::consts::FRAC_1_SQRT_2,
        core::f32::consts::FRAC_1_SQRT_2,
    ],
    [
        0.0,
        core::f32::consts::FRAC_1_SQRT_2,
        -core::f32::consts::FRAC_1_SQRT_2,
    ],
];

/// Whether the ray from `origin` (camera-relative blocks), offset by `normal * normal_bias *
/// cell_size`, along unit `direction` reaches a solid cell within the settings' bounds (the
/// sun ray's distance, [`ShadowSettings::max_distance`]).
pub fn march(
    occupancy: &impl Occupancy,
    settings: &ShadowSettings,
    origin: [f32; 3],
    normal: [f32; 3],
    cell_size: f32,
    direction: [f32; 3],
) -> bool {
    march_within(
        occupancy,
        settings,
        origin,
        normal,
        cell_size,
        direction,
        settings.max_distance,
    )
}

/// [`march`] over at most `max_distance` blocks (the sky rays pass
/// [`ShadowSettings::sky_distance`]).
///
/// Amanatides–Woo with the crossing times computed, not summed: the `j`-th crossing of a
/// cell boundary along axis `a` is at `first[a] + j * delta[a]`, so a run of crossings can be
/// counted without making them one by one. In a brick the occupancy knows is empty
/// ([`Occupancy::brick_empty`]) the march jumps to the first cell beyond it, counting the
/// crossings the cell-by-cell march would make there (for the step bound) in the order it
/// makes them (by time, ties to the lower axis, as the step picks its axis): the cells, the
/// step count and the answer are those of the march without the jump.
pub fn march_within(
    occupancy: &impl Occupancy,
    settings: &ShadowSettings,
    origin: [f32; 3],
    normal: [f32; 3],
    cell_size: f32,
    direction: [f32; 3],
    max_distance: f32,
) -> bool {
    let bias = settings.normal_bias * cell_size;
    let p = [0, 1, 2].map(|i| origin[i] + normal[i] * bias);
    let mut cell = p.map(|c| c.floor() as i32);
    let step = direction.map(|d| if d > 0.0 { 1 } else { -1 });
    // Ray length per cell along each axis, and to the first boundary.
    let delta = direction.map(|d| {
        if d != 0.0 {
            1.0 / d.abs()
        } else {
            f32::INFINITY
        }
    });
    let first = [0, 1, 2].map(|i| {
        if direction[i] == 0.0 {
            f32::INFINITY
        } else if direction[i] > 0.0 {
            (cell[i] as f32 + 1.0 - p[i]) * delta[i]
        } else {
            (p[i] - cell[i] as f32) * delta[i]
        }
    });
    // The time of crossing `j` (from 0) along axis `a`.
    let crossing = |a: usize, j: u32| {
        if direction[a] == 0.0 {
            f32::INFINITY
        } else {
            first[a] + j as f32 * delta[a]
        }
    };
    let mut crossed = [0u32; 3];
    let mut steps = 0u32;
    while steps < settings.max_steps {
        let brick = cell.map(|c| c.div_euclid(BRICK));
        if occupancy.brick_empty(brick) {
            // Crossings along each axis until the ray leaves the brick that way.
            let to_leave = [0, 1, 2].map(|a| {
                (if step[a] > 0 {
                    (brick[a] + 1) * BRICK - cell[a]
                } else {
                    cell[a] - brick[a] * BRICK + 1
                }) as u32
            });
            let leave = [0, 1, 2].map(|a| crossing(a, crossed[a] + to_leave[a] - 1));
            let exit = first_axis(leave);
            if leave[exit] > max_distance {
                return false;
            }
            for a in 0..3 {
                let made = if a == exit {
                    to_leave[a]
                } else {
                    // The crossings before the exit's: earlier, or as early on a lower axis.
                    let before = |t: f32| t < leave[exit] || (t == leave[exit] && a < exit);
                    (0..to_leave[a] - 1)
                        .take_while(|&m| before(crossing(a, crossed[a] + m)))
                        .count() as u32
                };
                cell[a] += step[a] * made as i32;
                crossed[a] += made;
                steps += made;
            }
            continue;
        }
        if occupancy.solid(cell) {
            return true;
        }
        let next = [0, 1, 2].map(|a| crossing(a, crossed[a]));
        let axis = first_axis(next);
        if next[axis] > max_distance {
            return false;
        }
        cell[axis] += step[axis];
        crossed[axis] += 1;
        steps += 1;
    }
    false
}

/// The axis of the earliest of three times, ties to the lower axis (the march's step rule).
fn first_axis(t: [f32; 3]) -> usize {
    if t[0] <= t[1] && t[0] <= t[2] {
        0
    } else if t[1] <= t[2] {
        1
    } else {
        2
    }
}

/// Whether one sky ray is blocked: [`march_within`] over the sky distance.
fn sky_ray(
    occupancy: &impl Occupancy,
    settings: &ShadowSettings,
    origin: [f32; 3],
    normal: [f32; 3],
    cell_size: f32,
    direction: [f32; 3],
) -> bool {
    march_within(
        occupancy,
        settings,
        origin,
        normal,
        cell_size,
        direction,
        settings.sky_distance,
    )
}

/// The sun's visibility at a point: 0 in shadow, 1 lit (always 1 with shadows off).
pub fn sun_visibility(
    occupancy: &impl Occupancy,
    settings: &ShadowSettings,
    origin: [f32; 3],
    normal: [f32; 3],
    cell_size: f32,
    sun_direction: [f32; 3],
) -> f32 {
    if !settings.sun_shadows {
        return 1.0;
    }
    if march(
        occupancy,
        settings,
        origin,
        normal,
        cell_size,
        sun_direction,
    ) {
        0.0
    } else {
        1.0
    }
}

/// The fraction of [`SKY_DIRECTIONS`] that escape (always 1 with sky visibility off).
pub fn sky_visibility(
    occupancy: &impl Occupancy,
    settings: &ShadowSettings,
    origin: [f32; 3],
    normal: [f32; 3],
    cell_size: f32,
) -> f32 {
    if !settings.sky_visibility {
        return 1.0;
    }
    let open = SKY_DIRECTIONS
        .iter()
        .filter(|&&d| !sky_ray(occupancy, settings, origin, normal, cell_size, d))
        .count();
    open as f32 / SKY_DIRECTIONS.len() as f32
}

/// The sun and sky visibility of one surface point (what the GPU's shadow pass writes per
/// pixel).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Visibility {
    /// The sun reaches the point (always with sun shadows off; never where the surface faces
    /// away from the sun).
    pub sun: bool,
    /// How many of [`SKY_DIRECTIONS`] escape (all with sky visibility off).
    pub sky_open: u32,
}

impl Visibility {
    /// Nothing blocked: what a point gets with both features off.
    pub const OPEN: Visibility = Visibility {
        sun: true,
        sky_open: SKY_DIRECTIONS.len() as u32,
    };

    /// The GPU word: bit 0 the sun, bits 1..4 the open sky directions.
    pub fn pack(self) -> u32 {
        u32::from(self.sun) | (self.sky_open << 1)
    }

    /// The inverse of [`pack`](Self::pack) (bits above 3 ignored; a count above 5 reads 5).
    pub fn unpack(word: u32) -> Visibility {
        Visibility {
            sun: word & 1 != 0,
            sky_open: ((word >> 1) & 7).min(SKY_DIRECTIONS.len() as u32),
        }
    }

    /// The sun term's factor: 1 or 0.
    pub fn sun_factor(self) -> f32 {
        if self.sun { 1.0 } else { 0.0 }
    }

    /// The hemisphere ambient's factor: the open fraction of the sky directions.
    pub fn sky_factor(self) -> f32 {
        self.sky_open as f32 / SKY_DIRECTIONS.len() as f32
    }
}

/// The visibility of the surface point `origin` (camera-relative blocks) with unit `normal`
/// (the rule in the [module docs](self)): the sun ray only where `dot(normal, sun) > 0`, the
/// sky rays always, each switched by `settings`; cells of one block. A point outside the
/// grid ([`in_grid`] of its cell) is [`Visibility::OPEN`]: the grid holds the shadows, and
/// the GPU spends nothing on the pixels beyond it.
pub fn surface_visibility(
    occupancy: &impl Occupancy,
    settings: &ShadowSettings,
    origin: [f32; 3],
    normal: [f32; 3],
    sun_direction: [f32; 3],
) -> Visibility {
    if !in_grid(origin.map(|c| c.floor() as i32)) {
        return Visibility::OPEN;
    }
    let l = sun_direction;
    let facing = normal[0] * l[0] + normal[1] * l[1] + normal[2] * l[2] > 0.0;
    let sun = if !settings.sun_shadows {
        true
    } else {
        facing && !march(occupancy, settings, origin, normal, 1.0, l)
    };
    let sky_open = if !settings.sky_visibility {
        SKY_DIRECTIONS.len() as u32
    } else {
        SKY_DIRECTIONS
            .iter()
            .filter(|&&d| !sky_ray(occupancy, settings, origin, normal, 1.0, d))
            .count() as u32
    };
    Visibility { sun, sky_open }
}

#[cfg(test)]
mod jump_tests;

#[cfg(test)]
mod tests {
    use super::*;

    /// A floor at y = -1 with a 1x4x1 pillar at x = 0, z = 0, and a roof at y = 6 over
    /// x in 5..30 (an overhang).
    struct Scene;
    impl Occupancy for Scene {
        fn solid(&self, [x, y, z]: [i32; 3]) -> bool {
            y == -1
                || (x == 0 && z == 0 && (0..4).contains(&y))
                || (y == 6 && (5..30).contains(&x) && (-10..10).contains(&z))
        }
    }

    const UP: [f32; 3] = [0.0, 1.0, 0.0];

    fn sun() -> [f32; 3] {
        let d: [f32; 3] = [-1.0, 1.0, 0.0];
        let l = (2.0f32).sqrt();
        d.map(|c| c / l)
    }

    #[test]
    fn the_pillar_shadows_the_floor_behind_it_and_not_beside_it() {
        let s = ShadowSettings::default();
        // Sun towards -x: the shadow lies at +x, 4 blocks long.
        for x in 1..=3 {
            let p = [x as f32 + 0.5, 0.0, 0.5];
            assert_eq!(
                sun_visibility(&Scene, &s, p, UP, 1.0, sun()),
                0.0,
                "x = {x}"
            );
        }
        assert_eq!(
            sun_visibility(&Scene, &s, [6.5, 0.0, 0.5], UP, 1.0, sun()),
            1.0
        );
        assert_eq!(
            sun_visibility(&Scene, &s, [2.5, 0.0, 2.5], UP, 1.0, sun()),
            1.0
        );
    }

    #[test]
    fn shadows_off_lights_everything() {
        let s = ShadowSettings {
            sun_shadows: false,
            ..ShadowSettings::default()
        };
        assert_eq!(
            sun_visibility(&Scene, &s, [2.5, 0.0, 0.5], UP, 1.0, sun()),
            1.0
        );
    }

    #[test]
    fn under_the_overhang_is_darker_than_open_ground() {
        let s = ShadowSettings::default();
        let under = sky_visibility(&Scene, &s, [15.5, 0.0, 0.5], UP, 1.0);
        let open = sky_visibility(&Scene, &s, [-20.5, 0.0, 0.5], UP, 1.0);
        assert_eq!(open, 1.0);
        assert_eq!(under, 0.0);
        let off = ShadowSettings {
            sky_visibility: false,
            ..s
        };
        assert_eq!(sky_visibility(&Scene, &off, [15.5, 0.0, 0.5], UP, 1.0), 1.0);
    }

    #[test]
    fn the_march_stops_at_its_distance_bound() {
        let s = ShadowSettings {
            sky_distance: 3.0,
            ..ShadowSettings::default()
        };
        // The roof is 6 blocks above: beyond the bound, the ray escapes.
        assert_eq!(sky_visibility(&Scene, &s, [15.5, 0.0, 0.5], UP, 1.0), 1.0);
        // The sun ray has its own bound: the roof shadows the floor below it.
        let sun_up = sun_visibility(&Scene, &s, [15.5, 0.0, 0.5], UP, 1.0, UP);
        assert_eq!(sun_up, 0.0);
        let short = ShadowSettings {
            max_distance: 3.0,
            ..ShadowSettings::default()
        };
        assert_eq!(
            sun_visibility(&Scene, &short, [15.5, 0.0, 0.5], UP, 1.0, UP),
            1.0
        );
    }

    #[test]
    fn a_coarse_surface_is_biased_out_of_its_own_cell() {
        // A coarse surface point on top of a 4-block cell at y in -4..0: without a bias
        // scaled by the level's cell size the ray starts inside solid data.
        struct Coarse;
        impl Occupancy for Coarse {
            fn solid(&self, [_, y, _]: [i32; 3]) -> bool {
                (-4..0).contains(&y)
            }
        }
        let s = ShadowSettings::default();
        let p = [1.5, -0.01, 1.5];
        assert_eq!(sun_visibility(&Coarse, &s, p, UP, 0.0, UP), 0.0);
        assert_eq!(sun_visibility(&Coarse, &s, p, UP, 4.0, UP), 1.0);
    }

    #[test]
    fn a_wall_across_a_lod_border_shadows_the_floor_continuously() {
        // Finest resident data covering each cell: 1-block cells for x < 8, 2-block cells
        // (the coarse node's rounding of the same wall at z = 0) for x >= 8.
        struct Border;
        impl Occupancy for Border {
            fn solid(&self, [x, y, z]: [i32; 3]) -> bool {
                let wall = if x < 8 { z == 0 } else { z.div_euclid(2) == 0 };
                y == -1 || ((0..16).contains(&x) && (0..4).contains(&y) && wall)
            }
        }
        let s = ShadowSettings::default();
        let l = core::f32::consts::FRAC_1_SQRT_2;
        for x in 1..15 {
            let p = [x as f32 + 0.5, 0.0, -1.5];
            let v = sun_visibility(&Border, &s, p, UP, 1.0, [0.0, l, l]);
            assert_eq!(v, 0.0, "light leaks at x = {x}");
        }
    }

    #[test]
    fn bad_settings_get_named_errors() {
        let d = ShadowSettings::default();
        assert_eq!(d.check(), Ok(()));
        let zero = ShadowSettings { max_steps: 0, ..d };
        assert_eq!(
            zero.check(),
            Err(ShadowSettingsError::Steps { max_steps: 0 })
        );
        let far = ShadowSettings {
            max_distance: f32::INFINITY,
            ..d
        };
        assert!(matches!(
            far.check(),
            Err(ShadowSettingsError::Distance { .. })
        ));
        let sky = ShadowSettings {
            sky_distance: 0.0,
            ..d
        };
        assert_eq!(
            sky.check(),
            Err(ShadowSettingsError::SkyDistance { sky_distance: 0.0 })
        );
        let bias = ShadowSettings {
            normal_bias: -1.0,
            ..d
        };
        assert!(matches!(
            bias.check(),
            Err(ShadowSettingsError::Bias { .. })
        ));
    }

    #[test]
    fn the_grid_clips_the_occupancy() {
        let clipped = GridClipped(|[_, y, _]: [i32; 3]| y == -1);
        assert!(clipped.solid([0, -1, 0]));
        assert!(clipped.solid([-GRID_CELLS / 2, -1, GRID_CELLS / 2 - 1]));
        assert!(!clipped.solid([GRID_CELLS / 2, -1, 0]));
        assert!(!clipped.solid([0, -1, -GRID_CELLS / 2 - 1]));
    }

    #[test]
    fn visibility_words_round_trip() {
        for sun in [false, true] {
            for sky_open in 0..=5 {
                let v = Visibility { sun, sky_open };
                assert_eq!(Visibility::unpack(v.pack()), v);
            }
        }
        assert_eq!(Visibility::unpack(u32::MAX).sky_open, 5);
        assert_eq!(Visibility::OPEN.sky_factor(), 1.0);
    }

    #[test]
    fn a_surface_point_gets_both_rays_and_the_switches() {
        let s = ShadowSettings::default();
        let shadowed = surface_visibility(&Scene, &s, [2.5, 0.0, 0.5], UP, sun());
        assert!(!shadowed.sun);
        let under = surface_visibility(&Scene, &s, [15.5, 0.0, 0.5], UP, sun());
        assert_eq!(under.sky_open, 0);
        let open = surface_visibility(&Scene, &s, [-20.5, 0.0, 0.5], UP, sun());
        assert_eq!(open, Visibility::OPEN);
        // Facing away from the sun: no sun, whatever the occupancy.
        let down = surface_visibility(&Scene, &s, [-20.5, 0.0, 0.5], [0.0, -1.0, 0.0], sun());
        assert!(!down.sun);
        assert_eq!(
            surface_visibility(&Scene, &ShadowSettings::OFF, [15.5, 0.0, 0.5], UP, sun()),
            Visibility::OPEN
        );
        assert!(!ShadowSettings::OFF.enabled());
        // Beyond the grid: open, even under a roof over everything.
        let roofed = |[_, y, _]: [i32; 3]| y == 6;
        let inside = [0.5, 0.0, GRID_CELLS as f32 / 2.0 - 0.5];
        let beyond = [0.5, 0.0, GRID_CELLS as f32 / 2.0 + 0.5];
        assert_eq!(surface_visibility(&roofed, &s, inside, UP, UP).sky_open, 0);
        assert_eq!(
            surface_visibility(&roofed, &s, beyond, UP, UP),
            Visibility::OPEN
        );
        assert!(s.enabled());
    }
}
