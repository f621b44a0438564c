//! The body of the `gltf_props` fuzz target: the glTF prop loader of `voxel-scene` on
//! arbitrary bytes (the whole input is a `.glb` or `.gltf` file).
//!
//! Compiled twice, like `bodies.rs`: by the target (`fuzz_targets/gltf_props.rs`) and by the
//! corpus replay test (`tests/tests/fuzz_corpus_replay.rs`). It checks properties, not just
//! "does not panic":
//!
//! - an error names something real: its message is not empty; a GLB truncation's offset and
//!   bytes available lie inside the input; an accessor out of bounds ends past its view; an
//!   index out of range is not below its vertex count; a limit's request exceeds it;
//! - a loaded model is consistent: every primitive is a triangle list (`3k` indices) whose
//!   indices are below its vertex count, every vertex value finite, every normal unit length
//!   or zero, every box exactly the box of its positions; material, texture and mesh indices
//!   point at what exists, every texture holds `4 * width * height` bytes; instance matrices
//!   are finite; the totals keep within the limits; the model's box holds every placed
//!   primitive's box;
//! - loading is deterministic: the same bytes give the same model.

use voxel_scene::props::{Aabb, PropError, PropLimits, PropModel, load_prop_bytes};

/// Small limits keep each run fast; the limits themselves are checked.
const LIMITS: PropLimits = PropLimits {
    max_vertices: 1 << 16,
    max_indices: 1 << 18,
    max_texture_pixels: 1 << 20,
    max_node_depth: 64,
    max_instances: 4096,
    max_external_bytes: 0,
};

fn check_error(data: &[u8], error: &PropError) {
    assert!(!error.to_string().is_empty());
    match error {
        PropError::GlbTruncated {
            offset, available, ..
        } => {
            assert!(*offset <= data.len(), "{error}");
            assert!(offset + available <= data.len(), "{error}");
        }
        PropError::AccessorOutOfBounds {
            end, view_length, ..
        } => assert!(*end > *view_length as u64, "{error}"),
        PropError::IndexOutOfRange {
            index,
            vertex_count,
            ..
        } => assert!(*index as usize >= *vertex_count, "{error}"),
        PropError::Limit {
            allowed, requested, ..
        } => assert!(requested > allowed, "{error}"),
        _ => {}
    }
}

fn contains(outer: &Aabb, inner: &Aabb, slack: f32) -> bool {
    (0..3).all(|i| {
        let s = slack * (1.0 + outer.min[i].abs().max(outer.max[i].abs()));
        outer.min[i] <= inner.min[i] + s && inner.max[i] <= outer.max[i] + s
    })
}

fn check_model(model: &PropModel) {
    assert!(model.vertex_count() <= LIMITS.max_vertices);
    assert!(model.index_count() <= LIMITS.max_indices);
    assert!(model.instances.len() <= LIMITS.max_instances);
    for p in model.primitives() {
        assert_eq!(p.indices.len() % 3, 0);
        assert!(p.indices.iter().all(|&i| (i as usize) < p.vertices.len()));
        for v in &p.vertices {
            let values = v.position.iter().chain(&v.normal).chain(&v.uv);
            assert!(values.into_iter().all(|x| x.is_finite()), "{v:?}");
            let n = v.normal;
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            assert!(len == 0.0 || (len - 1.0).abs() < 1e-3, "normal {n:?}");
        }
        if let Some(b) = Aabb::of_points(p.vertices.iter().map(|v| v.position)) {
            assert_eq!(b, p.bounds);
        }
        if let Some(m) = p.material {
            assert!(m < model.materials.len());
        }
        if p.normals_generated {
            assert_eq!(p.vertices.len(), p.indices.len());
        }
    }
    for m in &model.materials {
        if let Some(t) = m.base_colour_texture {
            assert!(t.texture < model.textures.len());
        }
        let unit = m
            .base_colour
            .iter()
            .chain(&m.emissive)
            .chain([&m.metallic, &m.roughness]);
        assert!(unit.into_iter().all(|x| (0.0..=1.0).contains(x)));
        assert!(m.emissive_strength >= 0.0 && m.emissive_strength.is_finite());
    }
    let mut pixels = 0u64;
    for t in &model.textures {
        assert_eq!(
            t.rgba.len() as u64,
            4 * u64::from(t.width) * u64::from(t.height)
        );
        pixels += u64::from(t.width) * u64::from(t.height);
    }
    assert!(pixels <= LIMITS.max_texture_pixels);
    for inst in &model.instances {
        assert!(inst.mesh < model.meshes.len());
        assert!(inst.matrix.iter().flatten().all(|x| x.is_finite()));
        let bounds = model
            .bounds
            .expect("a placed instance gives the model a box");
        for p in &model.meshes[inst.mesh].primitives {
            let b = p.bounds.transformed(&inst.matrix);
            if b.min.iter().chain(&b.max).all(|x| x.is_finite()) {
                assert!(
                    contains(&bounds, &b, 1e-5),
                    "{bounds:?} does not hold {b:?}"
                );
            }
        }
    }
}

/// Loads `data` as a prop and checks the result.
pub(crate) fn gltf_props(data: &[u8]) {
    let first = load_prop_bytes(data, &LIMITS);
    match &first {
        Err(e) => check_error(data, e),
        Ok(model) => check_model(model),
    }
    let second = load_prop_bytes(data, &LIMITS);
    match (&first, &second) {
        (Ok(a), Ok(b)) => assert_eq!(a, b, "loading is deterministic"),
        (Err(a), Err(b)) => assert_eq!(a.to_string(), b.to_string()),
        _ => panic!("two loads of the same bytes disagree"),
    }
}
