//! The march's brick jumps against the march without them: the same answer for every ray, on
//! random occupancies, directions, distances and step bounds (the jump only saves steps).

use proptest::prelude::*;

use super::{BRICK, GridClipped, Occupancy, ShadowSettings, march_within};

/// Solid cells in a 32^3 box at `-16..16` (bit per cell), with its bricks' emptiness known
/// or not.
struct Cells {
    bits: Vec<bool>,
    knows_bricks: bool,
}

const SIDE: i32 = 32;

impl Cells {
    fn index(cell: [i32; 3]) -> Option<usize> {
        let q = cell.map(|c| c + SIDE / 2);
        q.iter()
            .all(|&c| (0..SIDE).contains(&c))
            .then(|| (q[0] + SIDE * (q[1] + SIDE * q[2])) as usize)
    }
}

impl Occupancy for Cells {
    fn solid(&self, cell: [i32; 3]) -> bool {
        Cells::index(cell).is_some_and(|i| self.bits[i])
    }

    fn brick_empty(&self, brick: [i32; 3]) -> bool {
        if !self.knows_bricks {
            return false;
        }
        let lo = brick.map(|b| b * BRICK);
        (0..BRICK).all(|z| {
            (0..BRICK).all(|y| (0..BRICK).all(|x| !self.solid([lo[0] + x, lo[1] + y, lo[2] + z])))
        })
    }
}

fn unit(d: [f32; 3]) -> Option<[f32; 3]> {
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    (l > 1e-3).then(|| d.map(|c| c / l))
}

/// Occupancies with a few solid boxes (most bricks empty, some not), and rays from inside.
fn case() -> impl Strategy<Value = (Vec<bool>, [f32; 3], [f32; 3], f32, u32)> {
    let boxes = prop::collection::vec(
        (
            prop::array::uniform3(-16i32..16),
            prop::array::uniform3(1i32..6),
        ),
        0..6,
    );
    let axis = prop_oneof![Just(0.0f32), -1.0f32..1.0];
    (
        boxes,
        prop::array::uniform3(-15.9f32..15.9),
        [axis.clone(), axis.clone(), axis],
        0.5f32..60.0,
        1u32..200,
    )
        .prop_map(|(boxes, origin, dir, distance, steps)| {
            let mut bits = vec![false; (SIDE * SIDE * SIDE) as usize];
            for (lo, size) in boxes {
                for z in lo[2]..lo[2] + size[2] {
                    for y in lo[1]..lo[1] + size[1] {
                        for x in lo[0]..lo[0] + size[0] {
                            if let Some(i) = Cells::index([x, y, z]) {
                                bits[i] = true;
                            }
                        }
                    }
                }
            }
            (bits, origin, dir, distance, steps)
        })
}

/// The march's answer over `bits` without the jumps and with them.
fn both_answers(
    bits: Vec<bool>,
    settings: &ShadowSettings,
    origin: [f32; 3],
    dir: [f32; 3],
    distance: f32,
) -> (bool, bool) {
    let normal = [0.0, 1.0, 0.0];
    let stepping = Cells {
        bits: bits.clone(),
        knows_bricks: false,
    };
    let jumping = Cells {
        bits,
        knows_bricks: true,
    };
    (
        march_within(&stepping, settings, origin, normal, 1.0, dir, distance),
        march_within(&jumping, settings, origin, normal, 1.0, dir, distance),
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn jumping_empty_bricks_keeps_every_answer(
        (bits, origin, dir, distance, steps) in case()
    ) {
        let Some(dir) = unit(dir) else { return Ok(()) };
        let settings = ShadowSettings { max_steps: steps, ..ShadowSettings::default() };
        let (a, b) = both_answers(bits, &settings, origin, dir, distance);
        prop_assert_eq!(a, b);
    }
}

/// Directions and origins where crossings tie (equal components, cell-centre starts): the
/// order of tied crossings (lower axis first) decides the cells.
fn tied_case() -> impl Strategy<Value = (Vec<bool>, [f32; 3], [f32; 3], f32, u32)> {
    let component = prop::sample::select(vec![-1.0f32, -0.5, 0.0, 0.5, 1.0]);
    let start = (-15i32..15).prop_map(|c| c as f32 + 0.5);
    // Single cells as well as boxes: a tie decides whether the ray passes a lone cell.
    let cells = prop::collection::vec(prop::array::uniform3(-16i32..16), 0..40);
    (
        case(),
        cells,
        prop::array::uniform3(start),
        prop::array::uniform3(component),
    )
        .prop_map(|((mut bits, _, _, distance, steps), cells, origin, dir)| {
            for c in cells {
                if let Some(i) = Cells::index(c) {
                    bits[i] = true;
                }
            }
            (bits, origin, dir, distance, steps)
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn jumping_keeps_the_answer_where_crossings_tie(
        (bits, origin, dir, distance, steps) in tied_case()
    ) {
        let Some(dir) = unit(dir) else { return Ok(()) };
        let settings = ShadowSettings { max_steps: steps, normal_bias: 0.0, ..ShadowSettings::default() };
        let (a, b) = both_answers(bits, &settings, origin, dir, distance);
        prop_assert_eq!(a, b);
    }
}

#[test]
fn the_jump_crosses_an_empty_brick_to_a_wall_behind_it() {
    // A wall at x = 20 (three bricks on), the ray along a diagonal of no axis ties.
    let wall = |[x, _, _]: [i32; 3]| x == 20;
    struct Known<F>(F);
    impl<F: Fn([i32; 3]) -> bool> Occupancy for Known<F> {
        fn solid(&self, cell: [i32; 3]) -> bool {
            (self.0)(cell)
        }
        fn brick_empty(&self, brick: [i32; 3]) -> bool {
            brick[0] != 2
        }
    }
    let s = ShadowSettings::default();
    let dir = unit([1.0, 0.3, 0.2]).unwrap();
    let origin = [0.5, 0.5, 0.5];
    let up = [0.0, 1.0, 0.0];
    assert!(march_within(&Known(wall), &s, origin, up, 1.0, dir, 60.0));
    assert!(march_within(&wall, &s, origin, up, 1.0, dir, 60.0));
    // Short of the wall: unoccluded both ways.
    assert!(!march_within(&Known(wall), &s, origin, up, 1.0, dir, 15.0));
    // The grid clips: the brick past its edge is empty, so the jump leaves the grid.
    let clipped = GridClipped(Known(|_: [i32; 3]| false));
    assert!(!march_within(&clipped, &s, origin, up, 1.0, dir, 60.0));
}
