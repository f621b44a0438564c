//! How the streamed terrain's clutter looks: the units `mesher::place_clutter` placed on the
//! grass blocks are dressed as meadow grass, with a flower now and then; units of any other
//! clutter-bearing block as dry grass. The grass pass draws the kind's shape
//! (`render_model::grass::is_flower`) in the unit's tint.

use render_model::grass::is_flower;
use voxel_core::BlockId;
use voxel_core::formats::ClutterUnit;

/// Expected units per grass top face.
pub(super) const DENSITY: f32 = 2.0;

/// Flower head colours (RGBA8, red lowest): red, yellow, white, violet, blue.
const FLOWERS: [u32; 5] = [0xff2a2ad8, 0xff30d8ec, 0xfff0f0f0, 0xffd04c9a, 0xffe07a3c];

/// Dresses `units` in place: `grass` is the terrain's grass block. The placement's own
/// random bits choose (the 4-bit seed and the tint's variation), so the result is as
/// deterministic as the placement.
pub(super) fn dress(units: &mut [ClutterUnit], grass: BlockId) {
    for u in units {
        let kind = (u.settings & 0xff) as u8;
        let seed = (u.settings >> 12) as u8 & 0xf;
        let variation = u.tint;
        // The placement's tint is 255 less 5 random bits per channel: those bits, 0..32.
        let r = (255 - (variation & 0xff) as u8) & 31;
        let g = (255 - ((variation >> 8) & 0xff) as u8) & 31;
        let meadow = u16::from(kind / 4) == grass.0 % 64;
        // A flower on one meadow unit in 16 (variant 3 with an even seed of 8 values).
        let flower = meadow && is_flower(kind) && seed < 4;
        let kind = if flower {
            kind
        } else {
            (kind & !3) | (seed % 3)
        };
        u.settings = (u.settings & !0xff) | u16::from(kind);
        u.tint = if flower {
            FLOWERS[usize::from(seed) % FLOWERS.len()]
        } else if meadow {
            rgba(70 + r * 2, 135 + g * 2, 45)
        } else {
            rgba(165 + r * 2, 150 + g * 2, 80)
        };
    }
}

fn rgba(r: u8, g: u8, b: u8) -> u32 {
    u32::from(r) | u32::from(g) << 8 | u32::from(b) << 16 | 0xff << 24
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(kind: u8, seed: u8, tint: u32) -> ClutterUnit {
        ClutterUnit {
            settings: u16::from(kind) | u16::from(seed) << 12,
            tint,
            ..Default::default()
        }
    }

    #[test]
    fn meadows_grow_green_grass_and_some_flowers_dry_grass_none() {
        let grass = BlockId(1);
        let mut units: Vec<ClutterUnit> = (0..64u32)
            .map(|i| {
                unit(
                    4 + (i % 4) as u8,
                    (i / 4) as u8,
                    0xff00_0000 | ((255 - i % 31) * 0x0101),
                )
            })
            .collect();
        dress(&mut units, grass);
        let flowers = units.iter().filter(|u| is_flower(u.settings as u8)).count();
        assert_eq!(flowers, 4, "one in 16");
        for u in &units {
            let [r, g, b, _] = u.tint.to_le_bytes();
            if !is_flower(u.settings as u8) {
                assert!(g > r && g > b, "green grass: {r} {g} {b}");
            }
        }
        let mut dry: Vec<ClutterUnit> = (0..16).map(|s| unit(4 * 7 + 3, s, 0xff000000)).collect();
        dress(&mut dry, grass);
        assert!(dry.iter().all(|u| !is_flower(u.settings as u8)));
        assert!(dry.iter().all(|u| u.tint.to_le_bytes()[0] > 150));
    }
}
