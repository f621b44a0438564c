//! glTF `BLEND` props on a real device against the CPU reference (`voxel_reference::
//! prop_raster`, which blends them over the opaque image after every opaque triangle,
//! depth-tested without writing depth): a half-transparent duck in front of an opaque one and
//! over the sky matches its reference, shows the duck behind through it, and differs from the
//! same duck drawn as a mask. The tolerance is `props_support`'s.

mod props_support;

use render_model::Lighting;
use render_model::props::PropPlacement;
use voxel_core::WorldPos;
use voxel_reference::prop_raster::{PlacedProp, render_props};
use voxel_scene::props::{AlphaMode, PropModel};

use props_support::{H, W, camera_for, compare, drawn, gpu, renderer, sample};

/// The duck with every material `mode` and its base colour's alpha `alpha`.
fn see_through(mut model: PropModel, mode: AlphaMode, alpha: f32) -> PropModel {
    for m in &mut model.materials {
        m.alpha_mode = mode;
        m.base_colour[3] = alpha;
    }
    model
}

/// At the origin voxel, moved by `(x, y, z)` blocks within it.
fn at(x: f32, y: f32, z: f32) -> PropPlacement {
    let local = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [x, y, z, 1.0],
    ];
    PropPlacement::new(WorldPos::new(0, 0, 0), local).unwrap()
}

#[test]
fn a_half_transparent_duck_blends_over_the_duck_behind_it() {
    let Some(duck) = sample("Duck.glb") else {
        return;
    };
    let cam = camera_for(&duck, 0);
    let b = duck.bounds.expect("placed geometry");
    let size = (0..3).map(|i| b.max[i] - b.min[i]).fold(0.0, f32::max);
    // The glass duck a little nearer the camera and to its left: it covers part of the
    // opaque duck and part of the sky.
    let (behind, front) = (at(0.0, 0.0, 0.0), at(-0.3 * size, 0.0, 0.45 * size));
    let glass = see_through(duck.clone(), AlphaMode::Blend, 0.5);
    let mask = see_through(duck.clone(), AlphaMode::Mask { cutoff: 0.5 }, 0.5);
    let mut frames = Vec::new();
    for (name, model) in [("blend", &glass), ("mask", &mask)] {
        let Some(mut r) = renderer(false) else {
            return;
        };
        let opaque = r.add_prop_model(&duck).unwrap();
        let see = r.add_prop_model(model).unwrap();
        r.create_prop(opaque, behind).unwrap();
        r.create_prop(see, front).unwrap();
        frames.push((name, gpu(&mut r, &cam)));
    }
    let want = render_props(
        &[
            PlacedProp {
                model: &duck,
                placement: behind,
            },
            PlacedProp {
                model: &glass,
                placement: front,
            },
        ],
        &cam,
        &Lighting::default(),
        W,
        H,
    );
    assert!(drawn(&want.depth) > 1000);
    let (_, blended) = &frames[0];
    let mask_frame = &frames[1].1;
    compare("blend", blended, &want);
    // `compare` checks the pixels the reference's depth covers; the glass writes no depth,
    // so its colour over the sky is checked here, by the same rule: every pixel off the
    // silhouettes (of the opaque duck and of the glass, whose coverage the mask frame's depth
    // shows) within 6 codes, but for 1 %.
    let covered = |i: usize| want.depth[i] > 0.0 || mask_frame.depth[i] > 0.0;
    let (mut compared, mut glass_over_sky, mut bad, mut differs) = (0, 0, 0, 0);
    for y in 1..H as i32 - 1 {
        for x in 1..W as i32 - 1 {
            let i = (y as u32 * W + x as u32) as usize;
            let band = (-1..=1).any(|dy| {
                (-1..=1).any(|dx| covered(((y + dy) as u32 * W + (x + dx) as u32) as usize))
                    != covered(i)
            });
            let (g, c, m) = (
                &blended.rgba[i * 4..i * 4 + 3],
                &want.rgba[i * 4..i * 4 + 3],
                &mask_frame.rgba[i * 4..i * 4 + 3],
            );
            differs += usize::from(g.iter().zip(m).any(|(a, b)| a.abs_diff(*b) > 16));
            if band {
                continue;
            }
            compared += 1;
            glass_over_sky += usize::from(mask_frame.depth[i] > 0.0 && want.depth[i] == 0.0);
            bad += usize::from(g.iter().zip(c).any(|(a, b)| a.abs_diff(*b) > 6));
            assert_eq!(
                blended.depth[i] > 0.0,
                want.depth[i] > 0.0,
                "depth written at {x},{y}"
            );
        }
    }
    eprintln!(
        "blend: {compared} pixels compared, {glass_over_sky} of glass over the sky, {bad} over 6, \
         {differs} differ from the mask"
    );
    assert!(glass_over_sky > 300, "glass over the sky in view");
    assert!(
        bad * 100 <= compared,
        "{bad} of {compared} pixels off the reference"
    );
    assert!(differs > 500, "a mask draws another image");
}
