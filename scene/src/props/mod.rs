//! glTF 2.0 props: meshes drawn beside the voxels, loaded from `.glb` or `.gltf` into a
//! [`PropModel`] shaped for upload.
//!
//! # What is loaded
//!
//! - **Geometry.** Every mesh, at its file index; of each, the triangle-list primitives:
//!   `POSITION` (`VEC3` of `FLOAT`), `NORMAL` (normalized; flat normals generated, vertices
//!   unwelded, when absent, with a [`PropWarning::NormalsGenerated`]), `TEXCOORD_0` (`FLOAT` or
//!   normalized `UNSIGNED_BYTE` / `UNSIGNED_SHORT`) as interleaved 32-byte [`PropVertex`]es, and
//!   `u32` indices (made, `0..n`, for a non-indexed list). Sparse accessors and accessors
//!   without a buffer view (zeros) are read. A box per primitive ([`PropPrimitive::bounds`])
//!   and per model ([`PropModel::bounds`], over every placed instance).
//! - **Materials.** Base colour factor and texture (decoded to sRGB RGBA8, PNG with `png`,
//!   JPEG with `zune-jpeg`: see `texture`), its sampler, metallic and roughness factors,
//!   emissive factor and texture and `KHR_materials_emissive_strength`, alpha mode and
//!   cutoff, double-sidedness. Factors outside `0..=1` (or a negative strength) are clamped,
//!   as a renderer would. Each image is decoded once, and only images a base colour or
//!   emissive texture uses.
//! - **Placement.** The default scene (scene 0 without one, every root node without any
//!   scene) flattened: one [`PropInstance`] per node with a mesh, its matrix the node
//!   transforms (a matrix, or translation * rotation * scale) composed from the root down,
//!   in `f64`.
//! - **Buffers and images.** The GLB `BIN` chunk, `data:` URIs (base64), and, only for
//!   [`load_prop_file`], files beside the `.gltf` (never outside its folder).
//! - **Draco** (`KHR_draco_mesh_compression`), with the `draco` feature only: the stream
//!   decoded by `draco-oxide-decoder` (see `draco` for why it is opt-in), its points and
//!   indices checked against the counts the accessors declare, which the limits were checked
//!   against first.
//!
//! # What is reported, not loaded
//!
//! Each is a [`PropWarning`] in [`PropModel::warnings`]: extensions in `extensionsUsed` that
//! are not implemented (only `KHR_materials_emissive_strength` is; `KHR_texture_transform`
//! is parsed and each use named), primitives that are not triangle lists (skipped), vertex
//! attributes other than the three above, morph targets, skins, cameras, animations, texture
//! slots other than the base colour, a base colour texture on a coordinate set other than 0
//! (dropped), a missing default scene.
//!
//! # What is refused
//!
//! A [`PropError`] naming the problem and the object it is in: an empty file, a GLB file cut
//! short or with a bad header or chunk, JSON that does not parse (random bytes included) or
//! does not validate (a reference to an object that does not exist), a version other than
//! 2.x, an extension in `extensionsRequired` that is not implemented (Draco mesh compression
//! without the `draco` feature), a Draco stream that does not decode or disagrees with the
//! primitive's accessors, a buffer without data or shorter than its `byteLength`, a buffer view past its
//! buffer, an accessor (or its sparse part) past its view, a bad stride, an accessor type or
//! component type its use does not allow, a sparse index past the count, a primitive without
//! positions, attributes of different counts, a triangle list whose count is not a multiple
//! of 3, an index past the vertices, a NaN or infinite position, normal, texture coordinate
//! or transform, a node reached twice (cycles included), an image that is not PNG or JPEG or
//! does not decode, an external URI without a folder to resolve it in or one escaping it,
//! and anything past a hard limit of [`PropLimits`] (vertices, indices, texture pixels, node
//! depth, instances, external bytes), checked before the memory is allocated.
//!
//! ```
//! use voxel_scene::props::{PropLimits, load_prop_bytes};
//!
//! // A one-triangle glTF with its buffer in a data URI.
//! let json = r#"{"asset":{"version":"2.0"},
//!   "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
//!   "bufferViews":[{"buffer":0,"byteLength":36}],
//!   "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}],
//!   "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
//!   "nodes":[{"mesh":0,"translation":[0,0,-5]}],
//!   "scenes":[{"nodes":[0]}],"scene":0}"#;
//! let model = load_prop_bytes(json.as_bytes(), &PropLimits::default())?;
//! assert_eq!(model.vertex_count(), 3);
//! assert_eq!(model.instances[0].matrix[3], [0.0, 0.0, -5.0, 1.0]);
//! // No normals in the file: flat ones are made, and the model says so.
//! assert_eq!(model.meshes[0].primitives[0].vertices[0].normal, [0.0, 0.0, 1.0]);
//! assert_eq!(model.warnings.len(), 1);
//! # Ok::<(), voxel_scene::props::PropError>(())
//! ```

mod accessor;
mod buffers;
mod draco;
mod error;
mod glb;
mod material;
mod model;
mod nodes;
mod primitive;
mod texture;
mod uri;
mod warning;

use std::path::Path;

pub use error::{Limit, PrimitiveAt, PropError};
pub use model::{
    Aabb, AlphaMode, Filter, PropInstance, PropMaterial, PropMesh, PropModel, PropPrimitive,
    PropSampler, PropTexture, PropVertex, TextureRef, Wrap, transform_point,
};
pub use warning::PropWarning;

use buffers::Base;

/// Extensions whose content this loader applies.
#[cfg(not(feature = "draco"))]
pub const SUPPORTED_EXTENSIONS: &[&str] = &["KHR_materials_emissive_strength"];

/// Extensions whose content this loader applies (with Draco decoding: feature `draco`).
#[cfg(feature = "draco")]
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_materials_emissive_strength",
    "KHR_draco_mesh_compression",
];

/// Hard limits against hostile files, each refused by name ([`PropError::Limit`]) before
/// the memory it would take is allocated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PropLimits {
    /// Vertices stored, summed over every primitive (after flat normals unweld).
    pub max_vertices: usize,
    /// Indices, summed over every primitive.
    pub max_indices: usize,
    /// Texels of the decoded textures, summed.
    pub max_texture_pixels: u64,
    /// Deepest node hierarchy (a root is depth 1).
    pub max_node_depth: usize,
    /// Placed meshes.
    pub max_instances: usize,
    /// Bytes of external buffer and image files, summed.
    pub max_external_bytes: u64,
}

impl Default for PropLimits {
    /// 16 M vertices, 64 M indices, 64 M texels (256 MB of RGBA8), depth 256, 1 M instances,
    /// 1 GiB of external files: far beyond a prop, far below what exhausts a machine.
    fn default() -> Self {
        PropLimits {
            max_vertices: 1 << 24,
            max_indices: 1 << 26,
            max_texture_pixels: 1 << 26,
            max_node_depth: 256,
            max_instances: 1 << 20,
            max_external_bytes: 1 << 30,
        }
    }
}

/// Loads a `.glb` or `.gltf` from bytes. Buffers and images must be in the file (GLB `BIN`
/// chunk or `data:` URIs); an external reference is [`PropError::ExternalUri`].
pub fn load_prop_bytes(bytes: &[u8], limits: &PropLimits) -> Result<PropModel, PropError> {
    load(bytes, Base::None, limits)
}

/// Loads a `.glb` or `.gltf` file, resolving external buffers and images beside it (and
/// refusing any outside its folder, [`PropError::UriEscapes`]).
pub fn load_prop_file(path: &Path, limits: &PropLimits) -> Result<PropModel, PropError> {
    let bytes = std::fs::read(path).map_err(|source| PropError::Read {
        path: path.to_owned(),
        source,
    })?;
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    load(&bytes, Base::Folder(folder), limits)
}

/// The `gltf` crate's validation, less three rules: `POSITION` accessors without `min` /
/// `max` (which the specification asks for) are accepted, since the loader computes the
/// bounds from the positions themselves and several exporters omit them; extensions in
/// `extensionsRequired` are checked by the loader against what it implements, not against
/// what `gltf-json` parses; and accessors without a buffer view are accepted (read as zeros,
/// or replaced by a Draco stream's data, the case the rule would refuse).
fn validate(root: gltf::json::Root) -> Result<gltf::Document, PropError> {
    use gltf::json::validation::{Error, Validate};
    // `gltf-json` 1.4.1's primitive check indexes `accessors` with the `POSITION` index
    // before the reference check runs, and panics on one past the end (found by the
    // `gltf_props` fuzz target): those indices are checked here first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, index) in &prim.attributes {
                if index.value() >= root.accessors.len() {
                    let name = match semantic {
                        gltf::json::validation::Checked::Valid(s) => format!("{s:?}"),
                        gltf::json::validation::Checked::Invalid => "an attribute".to_owned(),
                    };
                    return Err(PropError::Invalid {
                        problems: vec![format!(
                            "meshes[{m}].primitives[{p}].attributes: {name} refers to accessor \
                             {}, which does not exist",
                            index.value()
                        )],
                    });
                }
            }
        }
    }
    let mut problems = Vec::new();
    root.validate(&root, gltf::json::Path::new, &mut |path, error| {
        let path = path().to_string();
        let missing_ok = path.ends_with("[\"POSITION\"].min")
            || path.ends_with("[\"POSITION\"].max")
            || (path.starts_with("accessors[") && path.ends_with("].bufferView"));
        let waived = (missing_ok && error == Error::Missing)
            || (path.starts_with("extensionsRequired") && error == Error::Unsupported);
        if !waived && problems.len() < 8 {
            problems.push(format!("{path}: {error}"));
        }
    });
    if !problems.is_empty() {
        return Err(PropError::Invalid { problems });
    }
    Ok(gltf::Document::from_json_without_validation(root))
}

fn load(bytes: &[u8], base: Base<'_>, limits: &PropLimits) -> Result<PropModel, PropError> {
    if bytes.is_empty() {
        return Err(PropError::Empty);
    }
    let (json, bin) = if glb::is_glb(bytes) {
        let g = glb::split(bytes)?;
        (g.json, g.bin)
    } else {
        (bytes, None)
    };
    let root = gltf::json::Root::from_slice(json).map_err(|e| PropError::Json {
        message: e.to_string(),
    })?;
    // Before validation, which would only say "unsupported".
    for name in &root.extensions_required {
        if !SUPPORTED_EXTENSIONS.contains(&name.as_str()) {
            return Err(PropError::RequiredExtension { name: name.clone() });
        }
    }
    if !root.asset.version.starts_with("2.") {
        return Err(PropError::Version {
            found: root.asset.version.clone(),
        });
    }
    let document = validate(root)?;
    let mut warnings = Vec::new();
    for name in document.extensions_used() {
        if !SUPPORTED_EXTENSIONS.contains(&name) {
            warnings.push(PropWarning::UnsupportedExtension {
                name: name.to_owned(),
            });
        }
    }
    let animations = document.as_json().animations.len();
    if animations > 0 {
        warnings.push(PropWarning::Animations { count: animations });
    }
    let mut external_total = 0u64;
    let buffers = buffers::load_buffers(&document, bin, base, limits, &mut external_total)?;
    let materials = material::load_materials(
        &document,
        &buffers,
        base,
        limits,
        &mut warnings,
        &mut external_total,
    )?;
    let meshes = primitive::load_meshes(&document, &buffers, limits, &mut warnings)?;
    let instances = nodes::flatten(&document, limits, &mut warnings)?;
    let bounds = instances
        .iter()
        .flat_map(|i| {
            meshes
                .get(i.mesh)
                .into_iter()
                .flat_map(|m| m.primitives.iter())
                .map(|p| p.bounds.transformed(&i.matrix))
        })
        .reduce(Aabb::union);
    Ok(PropModel {
        meshes,
        materials: materials.materials,
        textures: materials.textures,
        instances,
        bounds,
        warnings,
    })
}
