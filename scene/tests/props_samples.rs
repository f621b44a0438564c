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
    assert!(tex.sampler.mipmaps);
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
/// `extensionsRequired`; their accessors have no buffer view), which this loader does not
/// decode: refused by name, as the specification asks of a loader without the extension.
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
