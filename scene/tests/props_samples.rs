//! The glTF prop loader on the shared samples (`../shared/data/gltf/`): the counts, textures,
//! materials and placed transforms each is known to hold.

#[path = "support/samples.rs"]
mod samples;

use voxel_scene::props::{
    AlphaMode, Filter, PropError, PropLimits, PropWarning, Wrap, load_prop_bytes,
};

fn load(name: &str) -> Option<Result<voxel_scene::props::PropModel, PropError>> {
    samples::sample_gltf(name).map(|b| load_prop_bytes(&b, &PropLimits::default()))
}

#[test]
fn the_duck_loads_with_its_counts_texture_and_nested_transforms() {
    let Some(result) = load("Duck.glb") else {
        return;
    };
    let model = result.unwrap_or_else(|e| panic!("Duck.glb: {e}"));
    assert_eq!(model.meshes.len(), 1);
    let prim = &model.meshes[0].primitives[0];
    assert_eq!(prim.vertices.len(), 2399);
    assert_eq!(prim.indices.len(), 12636);
    assert!(prim.has_uv && !prim.normals_generated);
    assert_eq!(prim.material, Some(0));
    // The accessor's min / max as the exporter wrote them (in f64), rounded to f32.
    assert_eq!(
        prim.bounds.min,
        [
            -69.29850006103516f64 as f32,
            9.929369926452637f64 as f32,
            -61.32819747924805f64 as f32
        ]
    );
    assert_eq!(
        prim.bounds.max,
        [
            96.17990112304688f64 as f32,
            163.97000122070312f64 as f32,
            53.92519760131836f64 as f32
        ]
    );
    for v in &prim.vertices {
        let n = v.normal;
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        assert!((len - 1.0).abs() < 1e-3, "{n:?}");
        assert!((0.0..=1.0).contains(&v.uv[0]) && (0.0..=1.0).contains(&v.uv[1]));
    }

    assert_eq!(model.materials.len(), 1);
    let m = &model.materials[0];
    assert_eq!(m.name.as_deref(), Some("blinn3-fx"));
    assert_eq!(m.base_colour, [1.0; 4]);
    assert_eq!((m.metallic, m.roughness), (0.0, 1.0));
    assert_eq!(m.alpha_mode, AlphaMode::Opaque);
    assert!(!m.double_sided);
    let tex = m.base_colour_texture.expect("a base colour texture");
    assert_eq!(tex.sampler.wrap_u, Wrap::Repeat);
    // minFilter 9986: NEAREST_MIPMAP_LINEAR.
    assert_eq!(
        (tex.sampler.mag, tex.sampler.min),
        (Filter::Linear, Filter::Nearest)
    );
    assert_eq!(tex.sampler.mip, Some(Filter::Linear));
    assert_eq!(model.textures.len(), 1);
    let t = &model.textures[tex.texture];
    assert_eq!((t.width, t.height, t.rgba.len()), (512, 512, 512 * 512 * 4));
    // The duck's texture is yellow where most of it is.
    let mean: Vec<f64> = (0..3)
        .map(|c| {
            t.rgba
                .iter()
                .skip(c)
                .step_by(4)
                .map(|&x| f64::from(x))
                .sum::<f64>()
                / (512.0 * 512.0)
        })
        .collect();
    assert!(
        mean[0] > 150.0 && mean[1] > 120.0 && mean[2] < 100.0,
        "{mean:?}"
    );

    // Node 3 (identity) > node 2 (scale 0.01) > node 0 (the mesh); node 1 holds the camera.
    assert_eq!(model.instances.len(), 1);
    let inst = model.instances[0];
    assert_eq!((inst.mesh, inst.node), (0, 0));
    let s = 0.01f32;
    assert_eq!(
        inst.matrix,
        [
            [s, 0.0, 0.0, 0.0],
            [0.0, s, 0.0, 0.0],
            [0.0, 0.0, s, 0.0],
            [0.0, 0.0, 0.0, 1.0]
        ]
    );
    let b = model.bounds.expect("placed");
    for i in 0..3 {
        assert!((b.min[i] - prim.bounds.min[i] * s).abs() < 1e-5);
        assert!((b.max[i] - prim.bounds.max[i] * s).abs() < 1e-5);
    }
    assert_eq!(model.warnings, [PropWarning::Camera { node: 1 }]);
}

/// Both boxes compress their geometry with Draco (`KHR_draco_mesh_compression` in
/// `extensionsRequired`; their accessors have no buffer view). Without the `draco` feature
/// the loader does not decode it: refused by name, as the specification asks of a loader
/// without the extension.
#[cfg(not(feature = "draco"))]
#[test]
fn the_draco_boxes_are_refused_naming_the_extension() {
    for name in ["Box.glb", "BoxTextured.glb"] {
        let Some(result) = load(name) else {
            return;
        };
        match result {
            Err(PropError::RequiredExtension { name: ext }) => {
                assert_eq!(ext, "KHR_draco_mesh_compression", "{name}");
            }
            other => panic!("{name}: expected the Draco refusal, got {other:?}"),
        }
    }
}

/// With the `draco` feature, both boxes decode: 24 vertices (4 per face, each with its
/// face's normal), 36 indices, a unit cube, under the Z-up to Y-up node matrix.
#[cfg(feature = "draco")]
#[test]
fn the_draco_boxes_decode_with_their_counts() {
    for (name, textured) in [("Box.glb", false), ("BoxTextured.glb", true)] {
        let Some(result) = load(name) else {
            return;
        };
        let model = result.unwrap_or_else(|e| panic!("{name}: {e}"));
        let prim = &model.meshes[0].primitives[0];
        assert_eq!(
            (prim.vertices.len(), prim.indices.len()),
            (24, 36),
            "{name}"
        );
        assert_eq!(prim.has_uv, textured, "{name}");
        for i in 0..3 {
            assert!(
                (prim.bounds.min[i] + 0.5).abs() < 1e-3,
                "{name}: {:?}",
                prim.bounds
            );
            assert!(
                (prim.bounds.max[i] - 0.5).abs() < 1e-3,
                "{name}: {:?}",
                prim.bounds
            );
        }
        for v in &prim.vertices {
            // Axis-aligned face normals.
            let n = v.normal;
            assert_eq!(
                n.iter().filter(|c| c.abs() > 0.999).count(),
                1,
                "{name}: {n:?}"
            );
        }
        assert_eq!(model.instances.len(), 1);
        assert_eq!(model.instances[0].node, 1);
        assert_eq!(
            model.instances[0].matrix,
            [
                [1.0, 0.0, 0.0, 0.0],
                [0.0, 0.0, -1.0, 0.0],
                [0.0, 1.0, 0.0, 0.0],
                [0.0, 0.0, 0.0, 1.0]
            ]
        );
        assert_eq!(model.materials.len(), 1);
        let m = &model.materials[0];
        if textured {
            let t = &model.textures[m.base_colour_texture.expect("texture").texture];
            assert_eq!((t.width, t.height), (256, 256), "{name}");
        } else {
            assert_eq!(m.base_colour, [0.8, 0.0, 0.0, 1.0]);
            assert_eq!(m.name.as_deref(), Some("Red"));
            assert!(model.textures.is_empty());
        }
        assert!(model.warnings.is_empty(), "{name}: {:?}", model.warnings);
    }
}
