//! Every class of malformed glTF is refused by its named error, never a panic; every feature
//! left out is a named warning. The broken files are made here from the real Duck sample
//! (one rule broken at a time) and from small hand-made files.

#[path = "support/glb.rs"]
mod glb;
#[path = "support/samples.rs"]
mod samples;

use glb::Glb;
use serde_json::json;
use voxel_scene::props::{
    Limit, PrimitiveAt, PropError, PropLimits, PropModel, PropWarning, load_prop_bytes,
    load_prop_file,
};

fn load(bytes: &[u8]) -> Result<PropModel, PropError> {
    load_prop_bytes(bytes, &PropLimits::default())
}

fn duck() -> Option<Glb> {
    samples::sample_gltf("Duck.glb").map(|b| Glb::parse(&b))
}

const DUCK_AT: PrimitiveAt = PrimitiveAt {
    mesh: 0,
    primitive: 0,
};

/// Asserts the message names every part, and returns the error.
fn refused(result: Result<PropModel, PropError>, parts: &[&str]) -> PropError {
    let err = match result {
        Ok(_) => panic!("accepted; expected an error naming {parts:?}"),
        Err(e) => e,
    };
    let message = err.to_string();
    for part in parts {
        assert!(message.contains(part), "{message:?} does not name {part:?}");
    }
    err
}

#[test]
fn the_rebuilt_duck_still_loads() {
    let Some(d) = duck() else { return };
    assert_eq!(load(&d.bytes()).unwrap().vertex_count(), 2399);
}

#[test]
fn empty_and_random_bytes_are_refused() {
    assert!(matches!(load(&[]), Err(PropError::Empty)));
    let mut x = 0x9e37_79b9u32;
    let random: Vec<u8> = (0..4096)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x as u8
        })
        .collect();
    assert!(matches!(load(&random), Err(PropError::Json { .. })));
    let mut glb_random = b"glTF".to_vec();
    glb_random.extend(&random);
    assert!(matches!(load(&glb_random), Err(PropError::BadGlb { .. })));
    refused(load(b"{\"asset\": "), &["bad glTF JSON", "line 1"]);
}

#[test]
fn every_cut_of_the_duck_is_refused_as_truncated() {
    let Some(bytes) = samples::sample_gltf("Duck.glb") else {
        return;
    };
    for cut in (1..bytes.len())
        .step_by(97)
        .chain([1, 11, 12, 19, 20, bytes.len() - 1])
    {
        match load(&bytes[..cut]) {
            Err(PropError::GlbTruncated { .. }) => {}
            other => panic!("cut at {cut}: expected truncation, got {other:?}"),
        }
    }
    let mut longer = bytes.clone();
    longer.extend([0; 4]);
    refused(load(&longer), &["bad GLB", "144032"]);
}

#[test]
fn bad_json_in_a_glb_is_refused() {
    let Some(bytes) = samples::sample_gltf("Duck.glb") else {
        return;
    };
    let mut bad = bytes.clone();
    bad[20] = b'[';
    refused(load(&bad), &["bad glTF JSON"]);
}

#[test]
fn an_accessor_out_of_its_view_is_refused() {
    let Some(mut d) = duck() else { return };
    d.json["accessors"][1]["byteOffset"] = json!(12);
    let err = refused(
        load(&d.bytes()),
        &["accessor 1", "past the end of its buffer view"],
    );
    assert!(matches!(
        err,
        PropError::AccessorOutOfBounds {
            accessor: 1,
            end: 28800,
            view_length: 28788,
            ..
        }
    ));
}

#[test]
fn a_view_out_of_its_buffer_and_a_short_buffer_are_refused() {
    let Some(mut d) = duck() else { return };
    d.json["bufferViews"][3]["byteLength"] = json!(999_999);
    assert!(matches!(
        load(&d.bytes()),
        Err(PropError::ViewOutOfBuffer {
            view: 3,
            buffer: 0,
            ..
        })
    ));
    let Some(mut d) = duck() else { return };
    d.json["buffers"][0]["byteLength"] = json!(999_999);
    assert!(matches!(
        load(&d.bytes()),
        Err(PropError::BufferTooShort {
            buffer: 0,
            declared: 999_999,
            ..
        })
    ));
}

#[test]
fn a_wrong_component_type_is_refused() {
    let Some(mut d) = duck() else { return };
    d.json["accessors"][1]["componentType"] = json!(5123);
    refused(
        load(&d.bytes()),
        &["accessor 1", "POSITION", "VEC3 of UNSIGNED_SHORT"],
    );
    let Some(mut d) = duck() else { return };
    d.json["accessors"][3]["type"] = json!("VEC2");
    refused(load(&d.bytes()), &["accessor 3", "indices", "VEC2"]);
    let Some(mut d) = duck() else { return };
    d.json["accessors"][2]["componentType"] = json!(5121);
    refused(load(&d.bytes()), &["TEXCOORD_0", "UNSIGNED_BYTE"]);
    let Some(mut d) = duck() else { return };
    d.json["accessors"][1]["componentType"] = json!(1234);
    refused(load(&d.bytes()), &["invalid glTF", "componentType"]);
}

#[test]
fn an_index_out_of_the_vertex_range_is_refused() {
    let Some(mut d) = duck() else { return };
    let at = d.element_offset(3, 100, 2);
    d.bin.as_mut().unwrap()[at..at + 2].copy_from_slice(&2399u16.to_le_bytes());
    let err = refused(
        load(&d.bytes()),
        &["index 100 is 2399", "vertex count 2399"],
    );
    assert!(matches!(
        err,
        PropError::IndexOutOfRange {
            at: DUCK_AT,
            position: 100,
            index: 2399,
            vertex_count: 2399
        }
    ));
}

#[test]
fn nan_and_infinite_positions_are_refused() {
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let Some(mut d) = duck() else { return };
        let at = d.element_offset(1, 7, 12) + 4;
        d.bin.as_mut().unwrap()[at..at + 4].copy_from_slice(&bad.to_le_bytes());
        assert!(matches!(
            load(&d.bytes()),
            Err(PropError::NonFinite {
                at: DUCK_AT,
                attribute: "POSITION",
                vertex: 7
            })
        ));
    }
}

#[test]
fn a_missing_buffer_is_refused() {
    let Some(mut d) = duck() else { return };
    d.bin = None;
    refused(load(&d.bytes()), &["buffer 0 has no data"]);
}

#[test]
fn bad_image_bytes_are_refused() {
    let Some(mut d) = duck() else { return };
    let view = &d.json["bufferViews"][4];
    let at = view["byteOffset"].as_u64().unwrap() as usize;
    // Keep the signature, break the IHDR chunk.
    d.bin.as_mut().unwrap()[at + 12..at + 40].fill(0x5a);
    refused(load(&d.bytes()), &["image 0 does not decode"]);
    let Some(mut d) = duck() else { return };
    d.bin.as_mut().unwrap()[at..at + 8].copy_from_slice(b"RIFFWEBP");
    d.json["images"][0]["mimeType"] = json!("image/webp");
    assert!(matches!(
        load(&d.bytes()),
        Err(PropError::ImageFormat { image: 0, .. })
    ));
}

#[test]
fn node_cycles_and_second_parents_are_refused() {
    let Some(mut d) = duck() else { return };
    // 3 > 2 > 0 > 3.
    d.json["nodes"][0]["children"] = json!([3]);
    assert!(matches!(
        load(&d.bytes()),
        Err(PropError::NodeReachedTwice { node: 3 })
    ));
    let Some(mut d) = duck() else { return };
    d.json["nodes"][3]["children"] = json!([2, 0]);
    assert!(matches!(
        load(&d.bytes()),
        Err(PropError::NodeReachedTwice { node: 0 })
    ));
    let Some(mut d) = duck() else { return };
    d.json["nodes"][0]["children"] = json!([9]);
    refused(load(&d.bytes()), &["invalid glTF", "nodes[0].children[0]"]);
}

#[test]
fn hard_limits_are_refused_by_name() {
    let Some(d) = duck() else { return };
    let bytes = d.bytes();
    let cases = [
        (
            PropLimits {
                max_vertices: 2398,
                ..PropLimits::default()
            },
            Limit::Vertices,
        ),
        (
            PropLimits {
                max_indices: 12635,
                ..PropLimits::default()
            },
            Limit::Indices,
        ),
        (
            PropLimits {
                max_texture_pixels: 512 * 511,
                ..PropLimits::default()
            },
            Limit::TexturePixels,
        ),
        (
            PropLimits {
                max_node_depth: 2,
                ..PropLimits::default()
            },
            Limit::NodeDepth,
        ),
        (
            PropLimits {
                max_instances: 0,
                ..PropLimits::default()
            },
            Limit::Instances,
        ),
    ];
    for (limits, which) in cases {
        match load_prop_bytes(&bytes, &limits) {
            Err(PropError::Limit { limit, .. }) => assert_eq!(limit, which),
            other => panic!("{which}: expected the limit, got {other:?}"),
        }
    }
    let err = load_prop_bytes(&bytes, &cases[0].0)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("2399") && err.contains("2398") && err.contains("max_vertices"),
        "{err}"
    );
    // A hostile count is refused before anything is allocated.
    let Some(mut d) = duck() else { return };
    d.json["accessors"][1]["count"] = json!(4_000_000_000u64);
    assert!(matches!(
        load(&d.bytes()),
        Err(PropError::Limit {
            limit: Limit::Vertices,
            ..
        })
    ));
}

#[test]
fn required_and_used_extensions() {
    let Some(mut d) = duck() else { return };
    d.json["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
    d.json["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
    refused(
        load(&d.bytes()),
        &["requires the extension KHR_mesh_quantization"],
    );
    let Some(mut d) = duck() else { return };
    d.json["extensionsUsed"] = json!(["KHR_lights_punctual", "KHR_materials_emissive_strength"]);
    let model = load(&d.bytes()).unwrap();
    assert!(model.warnings.contains(&PropWarning::UnsupportedExtension {
        name: "KHR_lights_punctual".into()
    }));
    assert_eq!(model.warnings.len(), 2, "{:?}", model.warnings);
}

#[test]
fn texture_transforms_other_texcoord_sets_and_slots_are_warned() {
    let Some(mut d) = duck() else { return };
    d.json["extensionsUsed"] = json!(["KHR_texture_transform"]);
    d.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] =
        json!({"KHR_texture_transform": {"scale": [2.0, 2.0]}});
    d.json["materials"][0]["normalTexture"] = json!({"index": 0});
    let model = load(&d.bytes()).unwrap();
    assert!(
        model
            .warnings
            .contains(&PropWarning::TextureTransform { material: 0 })
    );
    assert!(model.warnings.contains(&PropWarning::IgnoredTexture {
        material: 0,
        slot: "normalTexture"
    }));
    let Some(mut d) = duck() else { return };
    d.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = json!(1);
    let model = load(&d.bytes()).unwrap();
    assert!(model.warnings.contains(&PropWarning::TexCoordSet {
        material: 0,
        set: 1
    }));
    assert_eq!(model.materials[0].base_colour_texture, None);
}

#[test]
fn other_modes_skins_morph_targets_and_attributes_are_warned() {
    let Some(mut d) = duck() else { return };
    let prim = d.json["meshes"][0]["primitives"][0].clone();
    let mut points = prim.clone();
    points["mode"] = json!(0);
    let mut morph = prim.clone();
    morph["targets"] = json!([{"POSITION": 1}]);
    morph["attributes"]["TEXCOORD_1"] = json!(2);
    d.json["meshes"][0]["primitives"] = json!([points, morph]);
    d.json["animations"] = json!([]);
    let model = load(&d.bytes()).unwrap();
    let at1 = PrimitiveAt {
        mesh: 0,
        primitive: 1,
    };
    assert_eq!(model.meshes[0].primitives.len(), 1);
    assert_eq!(model.meshes[0].primitives[0].source_index, 1);
    for w in [
        PropWarning::PrimitiveModeSkipped {
            at: DUCK_AT,
            mode: "POINTS",
        },
        PropWarning::MorphTargets { at: at1 },
        PropWarning::IgnoredAttribute {
            at: at1,
            attribute: "TEXCOORD_1".into(),
        },
    ] {
        assert!(
            model.warnings.contains(&w),
            "{w} missing from {:?}",
            model.warnings
        );
    }
}

#[test]
fn missing_normals_are_generated_flat_and_warned() {
    let Some(mut d) = duck() else { return };
    let attrs = &mut d.json["meshes"][0]["primitives"][0]["attributes"];
    attrs.as_object_mut().unwrap().remove("NORMAL");
    let model = load(&d.bytes()).unwrap();
    let prim = &model.meshes[0].primitives[0];
    assert!(prim.normals_generated);
    assert!(
        model
            .warnings
            .contains(&PropWarning::NormalsGenerated { at: DUCK_AT })
    );
    // Unwelded: one vertex per index, each triangle's three sharing its face normal.
    assert_eq!(prim.vertices.len(), 12636);
    for tri in prim.indices.chunks_exact(3) {
        let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| prim.vertices[i as usize]);
        assert!(a.normal == b.normal && b.normal == c.normal);
    }
}

/// A hand-made `.gltf` with a sparse accessor, no indices, and a node with TRS.
fn sparse_gltf(uri: &str) -> serde_json::Value {
    json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": 44, "uri": uri}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 2},
            {"buffer": 0, "byteOffset": 40, "byteLength": 4}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
            {"componentType": 5126, "count": 3, "type": "VEC3",
             "sparse": {"count": 1,
                "indices": {"bufferView": 1, "componentType": 5123},
                "values": {"bufferView": 2}}}
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}}]}],
        "nodes": [{"mesh": 0, "translation": [1, 2, 3], "scale": [2, 2, 2],
                   "rotation": [0, std::f32::consts::FRAC_1_SQRT_2, 0, std::f32::consts::FRAC_1_SQRT_2]}],
        "scenes": [{"nodes": [0]}]
    })
}

fn sparse_bin() -> Vec<u8> {
    let mut bin = Vec::new();
    for v in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        bin.extend(v.to_le_bytes());
    }
    bin.extend(2u16.to_le_bytes());
    bin.extend([0, 0]);
    // Only one float of the sparse value fits 4 bytes: a VEC3 needs 12. Sized below.
    bin.extend(1.0f32.to_le_bytes());
    bin
}

#[test]
fn sparse_accessors_trs_and_generated_indices() {
    // The sparse VEC3 value needs 12 bytes: the hand-made view of 4 is out of bounds ...
    let data = |bin: &[u8]| {
        let mut s = String::from("data:application/octet-stream;base64,");
        const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        for c in bin.chunks(3) {
            let w = (u32::from(c[0]) << 16)
                | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
                | u32::from(*c.get(2).unwrap_or(&0));
            for i in 0..=c.len() {
                s.push(T[(w >> (18 - 6 * i) & 63) as usize] as char);
            }
        }
        s
    };
    let bin = sparse_bin();
    let gltf = sparse_gltf(&data(&bin));
    assert!(matches!(
        load(gltf.to_string().as_bytes()),
        Err(PropError::AccessorOutOfBounds {
            accessor: 1,
            part: "sparse values",
            ..
        })
    ));
    // ... and with room for it, vertex 2's normal is replaced: (0, 0, 1) there, zeros else.
    let mut bin = bin;
    bin.truncate(40);
    for v in [0.0f32, 0.0, 1.0] {
        bin.extend(v.to_le_bytes());
    }
    let mut gltf = sparse_gltf(&data(&bin));
    gltf["buffers"][0]["byteLength"] = json!(52);
    gltf["bufferViews"][2]["byteLength"] = json!(12);
    let model = load(gltf.to_string().as_bytes()).unwrap();
    let prim = &model.meshes[0].primitives[0];
    assert_eq!(prim.indices, [0, 1, 2]);
    assert_eq!(prim.vertices[2].normal, [0.0, 0.0, 1.0]);
    assert_eq!(prim.vertices[0].normal, [0.0; 3]);
    // T * R(90 degrees about y) * S(2): x goes to -z, scaled by 2, then moved.
    let m = model.instances[0].matrix;
    let p = voxel_scene::props::transform_point(&m, [1.0, 0.0, 0.0]);
    for (got, want) in p.iter().zip([1.0, 2.0, 1.0]) {
        assert!((got - want).abs() < 1e-5, "{p:?}");
    }
    assert_eq!(model.warnings, [PropWarning::NoDefaultScene]);
    // A sparse index past the count.
    let mut bad = bin.clone();
    bad[36..38].copy_from_slice(&3u16.to_le_bytes());
    gltf["buffers"][0]["uri"] = json!(data(&bad));
    assert!(matches!(
        load(gltf.to_string().as_bytes()),
        Err(PropError::SparseIndexOutOfRange {
            accessor: 1,
            index: 3,
            count: 3
        })
    ));
}

#[test]
fn external_files_resolve_beside_the_gltf_and_never_outside() {
    let dir = std::env::temp_dir().join(format!("props-external-{}", std::process::id()));
    let inner = dir.join("model");
    std::fs::create_dir_all(&inner).unwrap();
    let mut bin = Vec::new();
    for v in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        bin.extend(v.to_le_bytes());
    }
    std::fs::write(inner.join("tri angle.bin"), &bin).unwrap();
    std::fs::write(dir.join("outside.bin"), &bin).unwrap();
    let gltf = |uri: &str| {
        json!({
            "asset": {"version": "2.0"},
            "buffers": [{"byteLength": 36, "uri": uri}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
            "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0
        })
        .to_string()
    };
    let path = inner.join("tri.gltf");
    std::fs::write(&path, gltf("tri%20angle.bin")).unwrap();
    let model = load_prop_file(&path, &PropLimits::default()).unwrap();
    assert_eq!(model.vertex_count(), 3);
    // The same file from bytes has nowhere to look.
    assert!(matches!(
        load(gltf("tri%20angle.bin").as_bytes()),
        Err(PropError::ExternalUri { .. })
    ));
    for uri in [
        "../outside.bin",
        "/etc/hostname",
        "file:///etc/hostname",
        "%2E%2E/outside.bin",
    ] {
        std::fs::write(&path, gltf(uri)).unwrap();
        match load_prop_file(&path, &PropLimits::default()) {
            Err(PropError::UriEscapes { uri: u, .. }) => assert_eq!(u, uri),
            other => panic!("{uri}: expected a refusal, got {other:?}"),
        }
    }
    let limits = PropLimits {
        max_external_bytes: 35,
        ..PropLimits::default()
    };
    std::fs::write(&path, gltf("tri%20angle.bin")).unwrap();
    assert!(matches!(
        load_prop_file(&path, &limits),
        Err(PropError::Limit {
            limit: Limit::ExternalBytes,
            requested: 36,
            ..
        })
    ));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_version_other_than_2_is_refused() {
    let Some(mut d) = duck() else { return };
    d.json["asset"]["version"] = json!("1.0");
    refused(load(&d.bytes()), &["\"1.0\"", "2.x"]);
}

/// Found by the `gltf_props` fuzz target: `gltf-json`'s own validation indexed `accessors`
/// with a `POSITION` index past the end and panicked.
#[test]
fn a_position_accessor_past_the_end_is_refused_not_a_panic() {
    let Some(mut d) = duck() else { return };
    d.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(99);
    refused(load(&d.bytes()), &["invalid glTF", "accessor 99"]);
}

#[test]
fn material_factors_outside_their_range_are_refused_by_name() {
    let cases: [(&str, serde_json::Value, &str); 5] = [
        (
            "pbrMetallicRoughness",
            json!({ "baseColorFactor": [1.5, 0.5, 0.5, 1.0] }),
            "baseColorFactor[0]",
        ),
        (
            "pbrMetallicRoughness",
            json!({ "roughnessFactor": -0.25 }),
            "roughnessFactor",
        ),
        (
            "emissiveFactor",
            json!([0.0, 2.0, 0.0]),
            "emissiveFactor[1]",
        ),
        ("alphaCutoff", json!(-1.0), "alphaCutoff"),
        (
            "extensions",
            json!({ "KHR_materials_emissive_strength": { "emissiveStrength": -3.0 } }),
            "emissiveStrength",
        ),
    ];
    for (key, value, factor) in cases {
        let Some(mut d) = duck() else { return };
        d.json["materials"][0][key] = value;
        if key == "alphaCutoff" {
            d.json["materials"][0]["alphaMode"] = json!("MASK");
        }
        if key == "extensions" {
            d.json["extensionsUsed"] = json!(["KHR_materials_emissive_strength"]);
        }
        let err = refused(load(&d.bytes()), &["material 0", factor]);
        assert!(
            matches!(err, PropError::BadMaterialFactor { material: 0, .. }),
            "{factor}: {err:?}"
        );
    }
}
