//! glTF emission on a real device against the CPU reference (`voxel_reference::prop_raster`,
//! which adds the emissive colour as the G-buffer holds it, times the exposure): the duck
//! glowing by its emissive factor and strength, and by an emissive texture, matches its
//! reference and is brighter than the duck that does not glow; an emissive colour the
//! G-buffer cannot hold is refused by name. The tolerance is `props_support`'s.

mod props_support;

use gpu_backend::render::props::PropError;
use voxel_scene::props::PropModel;

use props_support::{camera_for, compare, cpu, drawn, gpu, placement, renderer, sample};

/// The duck with its material glowing `emissive * strength`, times its own base colour
/// texture as the emissive texture when `textured`.
fn glowing(mut model: PropModel, emissive: [f32; 3], strength: f32, textured: bool) -> PropModel {
    for m in &mut model.materials {
        m.emissive = emissive;
        m.emissive_strength = strength;
        if textured {
            m.emissive_texture = m.base_colour_texture;
        }
    }
    model
}

/// The mean of the sRGB channels over the pixels the prop covers.
fn mean_lit(rgba: &[u8], depth: &[f32]) -> f64 {
    let (sum, n) =
        depth
            .iter()
            .enumerate()
            .filter(|(_, d)| **d > 0.0)
            .fold((0u64, 0u64), |(s, n), (i, _)| {
                let p = &rgba[i * 4..i * 4 + 3];
                (s + p.iter().map(|&c| u64::from(c)).sum::<u64>(), n + 3)
            });
    sum as f64 / n.max(1) as f64
}

#[test]
fn an_emissive_duck_matches_its_cpu_reference_and_glows() {
    let Some(duck) = sample("Duck.glb") else {
        return;
    };
    assert!(
        duck.materials
            .iter()
            .all(|m| m.base_colour_texture.is_some()),
        "the duck is textured"
    );
    let cam = camera_for(&duck, 0);
    let mut plain = None;
    for (name, model) in [
        ("duck", duck.clone()),
        (
            "emissive-factor",
            glowing(duck.clone(), [0.9, 0.35, 0.1], 1.5, false),
        ),
        (
            "emissive-texture",
            glowing(duck.clone(), [1.0, 1.0, 1.0], 0.6, true),
        ),
    ] {
        let Some(mut r) = renderer(false) else {
            return;
        };
        let id = r.add_prop_model(&model).unwrap();
        r.create_prop(id, placement(0)).unwrap();
        let g = gpu(&mut r, &cam);
        let c = cpu(&model, placement(0), &cam);
        assert!(
            drawn(&c.depth) > 1000,
            "{name}: the reference draws the duck"
        );
        compare(name, &g, &c);
        let lit = mean_lit(&g.rgba, &g.depth);
        eprintln!("{name}: mean sRGB {lit:.1}");
        match plain {
            None => plain = Some(lit),
            Some(p) => assert!(lit > p + 20.0, "{name} glows: {lit:.1} against {p:.1}"),
        }
    }
}

#[test]
fn an_emissive_colour_past_the_gbuffer_s_range_is_refused_by_name() {
    let Some(duck) = sample("Duck.glb") else {
        return;
    };
    let Some(mut r) = renderer(false) else {
        return;
    };
    for strength in [1.0e6, f32::INFINITY] {
        let model = glowing(duck.clone(), [1.0, 0.5, 0.0], strength, false);
        match r.add_prop_model(&model) {
            Err(e @ PropError::Emission { .. }) => {
                let text = e.to_string();
                assert!(text.contains("emissive colour"), "{text}");
            }
            other => panic!("strength {strength}: {other:?}"),
        }
    }
}
