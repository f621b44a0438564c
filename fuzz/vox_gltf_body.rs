//! The body of the `vox_gltf` fuzz target: `.vox` bytes through voxmesh's stages (load, mesh,
//! triangles, `.glb` and `.obj` writers) to bytes the `gltf` crate reads back.
//!
//! Compiled twice, like `bodies.rs`: by the target (`fuzz_targets/vox_gltf.rs`) and by the
//! corpus replay test (`tests/tests/fuzz_corpus_replay.rs`). Input: byte 0 picks the mode
//! (faces, greedy, smooth), ambient occlusion, `--lod` 0 or 1 and the scale (1, 1/16 or
//! 1,000,000, the command line's largest); the rest is the `.vox` file. Files the loader
//! refuses are `vox_loader`'s concern and return at once. For every file it loads, it checks:
//!
//! - meshing a loaded scene never fails (every id it holds is in its palette);
//! - `voxmesh::finite::check` passes: every number the outputs will hold is finite;
//! - the `.glb` is read back by `gltf` (`Gltf::from_slice`), its JSON holds no `null` (what
//!   `serde_json` writes for an infinite or NaN float) and only finite numbers; every material
//!   factor is finite and in its range (emissive strength at least 1); every `POSITION` and
//!   `NORMAL` float of the binary chunk is finite, every position lies within its accessor's
//!   `min`/`max`, every index is below the vertex count;
//! - the `.obj` and `.mtl` hold only finite numbers (every token that parses as a float),
//!   and as many `v` lines as the `.glb` has vertices.

use voxel_core::ChunkSize;
use voxel_scene::vox::{VoxOptions, load_vox_with};
use voxmesh::cli::Mode;
use voxmesh::geometry::{self, GeometryOptions};
use voxmesh::{finite, glb, mesh, obj};

/// Voxels a fuzzed scene may place (keeps each run fast).
const MAX_VOXELS: usize = 1 << 14;

/// Every number in a JSON value is finite and nothing is `null`.
fn check_json(value: &serde_json::Value, path: &str) {
    match value {
        serde_json::Value::Null => panic!("{path} is null (a float that was not finite?)"),
        serde_json::Value::Number(n) => {
            let f = n.as_f64().expect("JSON numbers are f64");
            assert!(f.is_finite(), "{path} = {f}");
        }
        serde_json::Value::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                check_json(item, &format!("{path}[{i}]"));
            }
        }
        serde_json::Value::Object(fields) => {
            for (key, item) in fields {
                check_json(item, &format!("{path}.{key}"));
            }
        }
        serde_json::Value::Bool(_) | serde_json::Value::String(_) => {}
    }
}

/// The `f32` triples of `accessor` in `blob`.
fn vec3s(accessor: &gltf::Accessor<'_>, blob: &[u8]) -> Vec<[f32; 3]> {
    let view = accessor.view().expect("a buffer view");
    let start = view.offset() + accessor.offset();
    let bytes = &blob[start..start + accessor.count() * 12];
    bytes
        .chunks_exact(12)
        .map(|v| {
            std::array::from_fn(|i| f32::from_le_bytes(v[4 * i..4 * i + 4].try_into().unwrap()))
        })
        .collect()
}

/// See the [module docs](self).
pub(crate) fn vox_gltf(data: &[u8]) {
    let Some((&flags, vox)) = data.split_first() else {
        return;
    };
    let mode = match flags % 3 {
        0 => Mode::Faces,
        1 => Mode::Greedy,
        _ => Mode::Smooth,
    };
    let ao = flags & 0x04 != 0;
    let lod = u32::from(flags >> 3 & 1);
    let scale = [1.0, 1.0 / 16.0, 1e6, 1.0][usize::from(flags >> 4 & 3)];
    let Ok(scene) = load_vox_with(vox, &VoxOptions::new(ChunkSize::S16, MAX_VOXELS)) else {
        return;
    };
    if scene.voxel_count == 0 {
        return;
    }
    let classes = mesh::classes_for(&scene.palette, mode);
    let world = mesh::downsample(scene.world, &classes, lod)
        .unwrap_or_else(|e| panic!("downsampling a loaded scene: {e}"));
    let chunks = mesh::mesh_world(&world, &classes, mode, ao, &|| {})
        .unwrap_or_else(|e| panic!("meshing a loaded scene: {e}"));
    let options = GeometryOptions {
        edge: ChunkSize::S16.edge(),
        cell: scale * f64::from(1u32 << lod),
        ambient_occlusion: ao,
    };
    let geometry = geometry::build(&chunks, &scene.materials, &options, &|| {});
    finite::check(&geometry).unwrap_or_else(|e| panic!("{e}"));
    let needed = glb::bytes_needed(&chunks);
    let bytes = glb::to_glb(&geometry).unwrap_or_else(|e| panic!("{e}"));
    assert!(needed <= bytes.len() as u64, "{needed} > {}", bytes.len());

    let gltf = gltf::Gltf::from_slice(&bytes).unwrap_or_else(|e| panic!("gltf refuses it: {e}"));
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let json: serde_json::Value =
        serde_json::from_slice(&bytes[20..20 + json_len]).expect("the JSON chunk parses");
    check_json(&json, "$");
    for material in gltf.document.materials() {
        let pbr = material.pbr_metallic_roughness();
        for v in pbr
            .base_color_factor()
            .into_iter()
            .chain([pbr.metallic_factor(), pbr.roughness_factor()])
            .chain(material.emissive_factor())
        {
            assert!(v.is_finite() && (0.0..=1.0).contains(&v), "{v}");
        }
        if let Some(strength) = material.emissive_strength() {
            assert!(strength.is_finite() && strength >= 1.0, "{strength}");
        }
    }
    let blob = gltf.blob.as_deref().unwrap_or(&[]);
    let mut vertices = 0;
    for mesh in gltf.document.meshes() {
        for primitive in mesh.primitives() {
            let position = primitive.get(&gltf::Semantic::Positions).expect("POSITION");
            let points = vec3s(&position, blob);
            let (Some(min), Some(max)) = (position.min(), position.max()) else {
                panic!("POSITION without min and max");
            };
            let bound = |v: &gltf::json::Value| -> Vec<f32> {
                v.as_array()
                    .expect("an array")
                    .iter()
                    .map(|c| c.as_f64().expect("a number") as f32)
                    .collect()
            };
            let (min, max) = (bound(&min), bound(&max));
            for p in &points {
                for i in 0..3 {
                    assert!(
                        p[i].is_finite() && min[i] <= p[i] && p[i] <= max[i],
                        "{p:?}"
                    );
                }
            }
            let normal = primitive.get(&gltf::Semantic::Normals).expect("NORMAL");
            for n in vec3s(&normal, blob) {
                assert!(n.iter().all(|c| c.is_finite()), "{n:?}");
            }
            let indices = primitive.indices().expect("indices");
            let view = indices.view().expect("a buffer view");
            let start = view.offset() + indices.offset();
            for index in blob[start..start + 4 * indices.count()].chunks_exact(4) {
                let index = u32::from_le_bytes(index.try_into().unwrap()) as usize;
                assert!(index < points.len(), "index {index} of {}", points.len());
            }
            vertices += points.len();
        }
    }

    let (obj, mtl) = obj::write_obj(&geometry, "fuzz.mtl");
    for text in [&obj, &mtl] {
        for token in text.split_whitespace() {
            if let Ok(v) = token.parse::<f64>() {
                assert!(v.is_finite(), "{token} in the OBJ output");
            }
        }
    }
    let v_lines = obj.lines().filter(|l| l.starts_with("v ")).count();
    assert_eq!(v_lines, vertices);
}
