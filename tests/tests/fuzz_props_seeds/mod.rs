//! Seeds of the `gltf_props` fuzz target: tiny hand-made glTF and GLB files, valid ones
//! reaching every feature the loader reads or reports, and one per class it refuses.

use serde_json::{Value, json};

use super::Seeds;

/// A 2 x 2 RGBA PNG (red, green / blue, half-transparent white), made by hand.
const PNG_2X2: [u8; 76] = [
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52,
    0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x06, 0x00, 0x00, 0x00, 0x72, 0xb6, 0x0d,
    0x24, 0x00, 0x00, 0x00, 0x13, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0xf8, 0xcf, 0xc0, 0xf0,
    0x1f, 0x0c, 0x81, 0x34, 0x08, 0x34, 0x00, 0x00, 0x49, 0x49, 0x09, 0x78, 0x9c, 0x51, 0x17, 0x92,
    0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82,
];

fn floats(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

fn base64(bytes: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in bytes.chunks(3) {
        let w = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for i in 0..4 {
            if i <= c.len() {
                s.push(char::from(T[(w >> (18 - 6 * i) & 63) as usize]));
            } else {
                s.push('=');
            }
        }
    }
    s
}

fn data_uri(bytes: &[u8]) -> String {
    format!("data:application/octet-stream;base64,{}", base64(bytes))
}

/// A GLB file of `json` and `bin`.
fn glb(json: &Value, bin: Option<&[u8]>) -> Vec<u8> {
    let mut j = serde_json::to_vec(json).expect("json");
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend(0u32.to_le_bytes());
    out.extend((j.len() as u32).to_le_bytes());
    out.extend(0x4E4F_534Au32.to_le_bytes());
    out.extend(&j);
    if let Some(bin) = bin {
        let mut b = bin.to_vec();
        while !b.len().is_multiple_of(4) {
            b.push(0);
        }
        out.extend((b.len() as u32).to_le_bytes());
        out.extend(0x004E_4942u32.to_le_bytes());
        out.extend(&b);
    }
    let len = out.len() as u32;
    out[8..12].copy_from_slice(&len.to_le_bytes());
    out
}

fn triangle_json(buffer: Value) -> Value {
    json!({
        "asset": {"version": "2.0"},
        "buffers": [buffer],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0, "translation": [0, 0, -5]}],
        "scenes": [{"nodes": [0]}], "scene": 0
    })
}

/// A textured quad: `u8` indices, normals, normalized `u16` texture coordinates, a PNG in
/// the BIN chunk, a masked double-sided emissive material, nested nodes with a matrix and TRS.
fn textured_quad() -> (Value, Vec<u8>) {
    let mut bin = floats(&[0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0.]); // 0..48
    bin.extend(floats(&[0., 0., 1.].repeat(4))); // 48..96
    for uv in [0u16, 65535, 65535, 65535, 65535, 0, 0, 0] {
        bin.extend(uv.to_le_bytes()); // 96..112
    }
    bin.extend([0u8, 1, 2, 0, 2, 3, 0, 0]); // 112..118, padded to 120
    bin.extend(PNG_2X2); // 120..196
    let json = json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "buffers": [{"byteLength": 196}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 16},
            {"buffer": 0, "byteOffset": 112, "byteLength": 6},
            {"buffer": 0, "byteOffset": 120, "byteLength": 76}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "normalized": true, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5121, "count": 6, "type": "SCALAR"}
        ],
        "images": [{"bufferView": 4, "mimeType": "image/png"}],
        "samplers": [{"magFilter": 9728, "minFilter": 9729, "wrapS": 33071, "wrapT": 33648}],
        "textures": [{"sampler": 0, "source": 0}],
        "materials": [{
            "pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0.25, 1],
                "baseColorTexture": {"index": 0}, "metallicFactor": 0.5, "roughnessFactor": 0.25},
            "emissiveFactor": [0.1, 0.2, 0.3],
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}},
            "alphaMode": "MASK", "alphaCutoff": 0.3, "doubleSided": true
        }],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
            "indices": 3, "material": 0}]}],
        "nodes": [
            {"children": [1], "matrix": [1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1]},
            {"children": [2], "translation": [1, 2, 3], "rotation": [0, std::f32::consts::FRAC_1_SQRT_2, 0, std::f32::consts::FRAC_1_SQRT_2],
             "scale": [2, 2, 2]},
            {"mesh": 0}
        ],
        "scenes": [{"nodes": [0]}], "scene": 0
    });
    (json, bin)
}

/// The seeds, by name.
pub(crate) fn gltf_props_seeds() -> Seeds {
    let tri = floats(&[0., 0., 0., 1., 0., 0., 0., 1., 0.]);
    let mut seeds: Seeds = vec![
        (
            "triangle-data-uri",
            triangle_json(json!({"byteLength": 36, "uri": data_uri(&tri)}))
                .to_string()
                .into_bytes(),
        ),
        (
            "triangle-glb",
            glb(&triangle_json(json!({"byteLength": 36})), Some(&tri)),
        ),
    ];
    let (quad, bin) = textured_quad();
    seeds.push(("textured-quad-glb", glb(&quad, Some(&bin))));
    let mut embedded = quad.clone();
    embedded["buffers"][0]["uri"] = json!(data_uri(&bin));
    seeds.push(("textured-quad-data-uri", embedded.to_string().into_bytes()));

    // Sparse normals over a view-less accessor, no indices, no scene.
    let mut sparse_bin = tri.clone();
    sparse_bin.extend(2u16.to_le_bytes());
    sparse_bin.extend([0, 0]);
    sparse_bin.extend(floats(&[0., 0., 1.]));
    let sparse = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": 52}],
        "bufferViews": [
            {"buffer": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 2},
            {"buffer": 0, "byteOffset": 40, "byteLength": 12}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
            {"componentType": 5126, "count": 3, "type": "VEC3", "sparse": {"count": 1,
                "indices": {"bufferView": 1, "componentType": 5123}, "values": {"bufferView": 2}}}
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}}]}],
        "nodes": [{"mesh": 0}]
    });
    seeds.push(("sparse-no-scene-glb", glb(&sparse, Some(&sparse_bin))));

    // What is reported: other modes, attributes, morph targets, a skin, a camera, an
    // unknown extension, a texture transform, animations.
    let mut warned = quad.clone();
    warned["extensionsUsed"] = json!(["KHR_texture_transform", "KHR_lights_punctual"]);
    let prim = warned["meshes"][0]["primitives"][0].clone();
    let mut lines = prim.clone();
    lines["mode"] = json!(1);
    let mut morph = prim.clone();
    morph["targets"] = json!([{"POSITION": 0}]);
    morph["attributes"]["TEXCOORD_1"] = json!(2);
    morph["attributes"]["COLOR_0"] = json!(0);
    warned["meshes"][0]["primitives"] = json!([lines, morph]);
    warned["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] =
        json!({"KHR_texture_transform": {"offset": [0.5, 0]}});
    warned["materials"][0]["normalTexture"] = json!({"index": 0});
    warned["cameras"] = json!([{"type": "perspective", "perspective": {"yfov": 1, "znear": 0.1}}]);
    warned["nodes"][1]["camera"] = json!(0);
    seeds.push(("warnings-glb", glb(&warned, Some(&bin))));

    // Refused, one class each.
    let mut cycle = quad.clone();
    cycle["nodes"][2]["children"] = json!([0]);
    seeds.push(("refused-node-cycle", glb(&cycle, Some(&bin))));
    let mut out_of_range = bin.clone();
    out_of_range[113] = 9;
    seeds.push((
        "refused-index-out-of-range",
        glb(&quad, Some(&out_of_range)),
    ));
    let mut nan = bin.clone();
    nan[4..8].copy_from_slice(&f32::NAN.to_le_bytes());
    seeds.push(("refused-nan-position", glb(&quad, Some(&nan))));
    let mut bad_png = bin.clone();
    bad_png[140..150].fill(0x5a);
    seeds.push(("refused-bad-image", glb(&quad, Some(&bad_png))));
    let mut oob = quad.clone();
    oob["accessors"][0]["byteOffset"] = json!(4);
    seeds.push(("refused-accessor-out-of-view", glb(&oob, Some(&bin))));
    let mut wrong = quad.clone();
    wrong["accessors"][0]["componentType"] = json!(5123);
    seeds.push(("refused-wrong-component-type", glb(&wrong, Some(&bin))));
    let mut draco = quad.clone();
    draco["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    draco["extensionsUsed"] = json!(["KHR_draco_mesh_compression"]);
    seeds.push(("refused-required-extension", glb(&draco, Some(&bin))));
    let whole = glb(&quad, Some(&bin));
    seeds.push(("refused-truncated-glb", whole[..whole.len() - 7].to_vec()));
    seeds.push(("refused-no-bin", glb(&quad, None)));
    seeds.push(("refused-empty", Vec::new()));
    seeds.push((
        "refused-bad-json",
        b"{\"asset\": {\"version\": 2.0".to_vec(),
    ));
    seeds
}
