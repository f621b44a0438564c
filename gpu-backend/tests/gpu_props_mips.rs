//! Prop texture mip levels on a real device: the duck wearing a 1-texel black and white
//! checkerboard, seen from far enough that the texture is minified several times, is drawn
//! averaged (neighbouring pixels close, as the CPU reference's mip-mapped sampling draws it)
//! and not aliased (as the same duck sampled from level 0 alone is). The tolerance is
//! `props_support`'s.

mod props_support;

use voxel_scene::props::{Filter, PropModel, PropTexture};

use props_support::{camera_at, compare, cpu, drawn, gpu, placement, renderer, sample};

/// The duck with its texture a `size` x `size` checkerboard of 1-texel checks, sampled
/// trilinearly with mip levels, or from level 0 alone (`mip` false).
fn checkered(mut model: PropModel, size: u32, mip: bool) -> PropModel {
    let rgba = (0..size * size)
        .flat_map(|i| {
            let v = if (i % size + i / size).is_multiple_of(2) {
                255
            } else {
                0
            };
            [v, v, v, 255]
        })
        .collect();
    model.textures = vec![PropTexture {
        image: 0,
        name: None,
        width: size,
        height: size,
        rgba,
    }];
    for m in &mut model.materials {
        if let Some(t) = &mut m.base_colour_texture {
            t.texture = 0;
            t.sampler.mag = Filter::Linear;
            t.sampler.min = Filter::Linear;
            t.sampler.mip = mip.then_some(Filter::Linear);
        }
        m.base_colour = [1.0; 4];
    }
    model
}

/// The mean largest channel difference between horizontally neighbouring pixels that both
/// show the prop, away from its silhouette (both neighbours' neighbours covered too).
fn roughness(rgba: &[u8], depth: &[f32], w: usize) -> f64 {
    let covered = |i: usize| depth.get(i).is_some_and(|d| *d > 0.0);
    let (mut sum, mut n) = (0u64, 0u64);
    for i in w + 1..depth.len().saturating_sub(w + 2) {
        let inside = [i - 1, i, i + 1, i + 2, i - w, i + w, i + 1 - w, i + 1 + w];
        if inside.iter().all(|&j| covered(j)) {
            let d = (0..3)
                .map(|c| rgba[i * 4 + c].abs_diff(rgba[(i + 1) * 4 + c]))
                .max()
                .unwrap_or(0);
            sum += u64::from(d);
            n += 1;
        }
    }
    sum as f64 / n.max(1) as f64
}

#[test]
fn a_minified_checkerboard_is_averaged_not_aliased() {
    let Some(duck) = sample("Duck.glb") else {
        return;
    };
    let cam = camera_at(&duck, 0, 1.8);
    let mut rough = Vec::new();
    for (name, mip) in [("mipmapped", true), ("level 0", false)] {
        let model = checkered(duck.clone(), 512, mip);
        let Some(mut r) = renderer(false) else {
            return;
        };
        let id = r.add_prop_model(&model).unwrap();
        r.create_prop(id, placement(0)).unwrap();
        let g = gpu(&mut r, &cam);
        let c = cpu(&model, placement(0), &cam);
        assert!(drawn(&c.depth) > 400, "{name}: the duck is in view");
        let (gr, cr) = (
            roughness(&g.rgba, &g.depth, props_support::W as usize),
            roughness(&c.rgba, &c.depth, props_support::W as usize),
        );
        eprintln!("{name}: neighbouring pixels differ by {gr:.1} (reference {cr:.1})");
        if mip {
            compare("checkerboard", &g, &c);
        }
        rough.push(gr);
    }
    assert!(rough[0] < 12.0, "mipmapped: averaged ({:.1})", rough[0]);
    assert!(
        rough[1] > 3.0 * rough[0],
        "level 0 alone aliases ({:.1} against {:.1})",
        rough[1],
        rough[0]
    );
}
