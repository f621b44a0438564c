//! glTF binary output: the document built with `gltf-json` and wrapped in a GLB container by
//! `gltf::binary::Glb`.
//!
//! One mesh in one node of one scene; one primitive per material (see [`crate::pbr`]), each
//! with `POSITION` (`f32` x 3, with the exact `min`/`max` the format requires), `NORMAL`
//! (`f32` x 3), `COLOR_0` (linear RGBA, `u16` normalised) and `u32` indices. Every attribute
//! and index list is a tightly packed buffer view of the single binary buffer (all are
//! multiples of 4 bytes, so every view is aligned as the format requires).

use std::borrow::Cow;
use std::collections::BTreeMap;

use gltf::json;
use json::validation::Checked::Valid;
use json::validation::USize64;

use crate::Error;
use crate::geometry::{Geometry, Primitive};
use crate::mesh::ChunkOutput;
use crate::pbr::PbrMaterial;

/// The extension named when a material emits more than its colour.
const EMISSIVE_STRENGTH: &str = "KHR_materials_emissive_strength";

/// Bytes a `.glb` can hold at most: its header stores the length in 32 bits.
pub const MAX_GLB_BYTES: u64 = u32::MAX as u64;

/// Bytes of a blocky quad in the binary chunk: 4 vertices of position and normal (`f32` x 3
/// each) and colour (`u16` x 4), and 6 `u32` indices.
const QUAD_BYTES: u64 = 4 * (12 + 12 + 8) + 6 * 4;
/// Bytes of a vertex (as above) and of a triangle's indices.
const VERTEX_BYTES: u64 = 12 + 12 + 8;
const TRIANGLE_BYTES: u64 = 3 * 4;

/// The fewest bytes a `.glb` of `chunks` can take: exact for the binary chunk of blocky quads
/// (each is 4 vertices and 6 indices), a lower bound for smooth surfaces (each vertex a
/// triangle uses is written at least once); the JSON and the headers come on top.
pub fn bytes_needed(chunks: &[ChunkOutput]) -> u64 {
    let mut bytes = 0u64;
    let mut used = Vec::new();
    for chunk in chunks {
        let quads = chunk.blocky.opaque.len() + chunk.blocky.transparent.len();
        bytes += quads as u64 * QUAD_BYTES;
        let smooth = &chunk.smooth;
        used.clear();
        used.resize(smooth.vertices().len(), false);
        for triangle in smooth.triangles() {
            bytes += TRIANGLE_BYTES;
            for v in triangle {
                if let Some(seen) = used.get_mut(v as usize) {
                    *seen = true;
                }
            }
        }
        bytes += used.iter().filter(|&&u| u).count() as u64 * VERTEX_BYTES;
    }
    bytes
}

/// Fails when a `.glb` of `chunks` cannot fit `limit` bytes ([`MAX_GLB_BYTES`] for real
/// runs): checked on the meshed chunks, before the triangles (some 19 times their bytes) are
/// built.
pub fn check_fits(chunks: &[ChunkOutput], limit: u64) -> Result<(), Error> {
    let needed = bytes_needed(chunks);
    if needed > limit {
        return Err(too_large(needed, "at least "));
    }
    Ok(())
}

fn too_large(bytes: u64, at_least: &str) -> Error {
    Error::TooLarge(format!(
        "the mesh needs {at_least}{bytes} bytes, more than a .glb can hold (4 GiB); use .obj, \
         a coarser --lod or a smaller input"
    ))
}

/// The `.glb` bytes of `geometry`. Fails if it does not fit the format's 32-bit sizes.
pub fn to_glb(geometry: &Geometry) -> Result<Vec<u8>, Error> {
    let mut root = json::Root {
        asset: json::Asset {
            generator: Some(format!("voxmesh {}", env!("CARGO_PKG_VERSION"))),
            ..Default::default()
        },
        ..Default::default()
    };
    let mut bin: Vec<u8> = Vec::new();
    let buffer = json::Index::new(0);

    let materials: Vec<json::Index<json::Material>> = geometry
        .materials
        .iter()
        .map(|m| root.push(material(m)))
        .collect();
    if geometry
        .materials
        .iter()
        .any(|m| m.emissive_strength != 1.0)
    {
        root.extensions_used.push(EMISSIVE_STRENGTH.to_owned());
    }

    let mut primitives = Vec::new();
    for p in geometry.primitives.iter().filter(|p| !p.indices.is_empty()) {
        primitives.push(primitive(
            &mut root,
            &mut bin,
            buffer,
            p,
            materials[p.material],
        ));
    }
    let mesh = root.push(json::Mesh {
        extensions: None,
        extras: Default::default(),
        name: Some("voxmesh".to_owned()),
        primitives,
        weights: None,
    });
    let node = root.push(json::Node {
        mesh: Some(mesh),
        ..Default::default()
    });
    let scene = root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: None,
        nodes: vec![node],
    });
    root.scene = Some(scene);
    root.push(json::Buffer {
        byte_length: USize64::from(bin.len()),
        extensions: None,
        extras: Default::default(),
        name: None,
        uri: None,
    });

    let json = root.to_vec().expect("the glTF document serialises");
    // Header 12 bytes, two chunk headers of 8, both chunks padded to 4 bytes.
    let total = 12 + 8 + json.len().next_multiple_of(4) + 8 + bin.len().next_multiple_of(4);
    if total as u64 > MAX_GLB_BYTES {
        return Err(too_large(total as u64, ""));
    }
    let glb = gltf::binary::Glb {
        header: gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            length: total as u32,
        },
        json: Cow::Owned(json),
        bin: Some(Cow::Owned(bin)),
    };
    Ok(glb.to_vec().expect("writing to memory cannot fail"))
}

/// The glTF material of `m`.
fn material(m: &PbrMaterial) -> json::Material {
    let mut out = json::Material {
        alpha_mode: Valid(if m.blend {
            json::material::AlphaMode::Blend
        } else {
            json::material::AlphaMode::Opaque
        }),
        name: Some(name(m)),
        emissive_factor: json::material::EmissiveFactor(m.emissive),
        ..Default::default()
    };
    let pbr = &mut out.pbr_metallic_roughness;
    pbr.base_color_factor = json::material::PbrBaseColorFactor([1.0, 1.0, 1.0, m.alpha]);
    pbr.metallic_factor = json::material::StrengthFactor(m.metallic);
    pbr.roughness_factor = json::material::StrengthFactor(m.roughness);
    if m.emissive_strength != 1.0 {
        #[allow(
            clippy::needless_update,
            reason = "gltf features enabled elsewhere in a build add fields to this struct"
        )]
        let extensions = json::extensions::material::Material {
            emissive_strength: Some(json::extensions::material::EmissiveStrength {
                emissive_strength: json::extensions::material::EmissiveStrengthFactor(
                    m.emissive_strength,
                ),
            }),
            ..Default::default()
        };
        out.extensions = Some(extensions);
    }
    out
}

/// A readable material name: its kind and the values that set it apart.
fn name(m: &PbrMaterial) -> String {
    let mut parts = Vec::new();
    if m.blend {
        parts.push(format!("glass alpha {}", m.alpha));
    }
    if m.metallic > 0.0 {
        parts.push(format!("metal {}", m.metallic));
    }
    if m.emissive != [0.0; 3] {
        parts.push(format!("emissive x{}", m.emissive_strength));
    }
    if parts.is_empty() {
        parts.push("diffuse".to_owned());
    }
    parts.push(format!("roughness {}", m.roughness));
    parts.join(", ")
}

/// Appends `p`'s data to `bin` and returns its glTF primitive.
fn primitive(
    root: &mut json::Root,
    bin: &mut Vec<u8>,
    buffer: json::Index<json::Buffer>,
    p: &Primitive,
    material: json::Index<json::Material>,
) -> json::mesh::Primitive {
    let (min, max) = bounds(&p.positions);
    let position = accessor(
        root,
        bin,
        buffer,
        &le_bytes(p.positions.as_flattened(), f32::to_le_bytes),
        AccessorKind::vec3_f32(p.positions.len(), Some((min, max))),
    );
    let normal = accessor(
        root,
        bin,
        buffer,
        &le_bytes(p.normals.as_flattened(), f32::to_le_bytes),
        AccessorKind::vec3_f32(p.normals.len(), None),
    );
    let colour = accessor(
        root,
        bin,
        buffer,
        &le_bytes(p.colours.as_flattened(), u16::to_le_bytes),
        AccessorKind {
            count: p.colours.len(),
            component: json::accessor::ComponentType::U16,
            type_: json::accessor::Type::Vec4,
            normalized: true,
            bounds: None,
            target: json::buffer::Target::ArrayBuffer,
        },
    );
    let indices = accessor(
        root,
        bin,
        buffer,
        &le_bytes(&p.indices, u32::to_le_bytes),
        AccessorKind {
            count: p.indices.len(),
            component: json::accessor::ComponentType::U32,
            type_: json::accessor::Type::Scalar,
            normalized: false,
            bounds: None,
            target: json::buffer::Target::ElementArrayBuffer,
        },
    );
    let mut attributes = BTreeMap::new();
    attributes.insert(Valid(json::mesh::Semantic::Positions), position);
    attributes.insert(Valid(json::mesh::Semantic::Normals), normal);
    attributes.insert(Valid(json::mesh::Semantic::Colors(0)), colour);
    json::mesh::Primitive {
        attributes,
        extensions: None,
        extras: Default::default(),
        indices: Some(indices),
        material: Some(material),
        mode: Valid(json::mesh::Mode::Triangles),
        targets: None,
    }
}

/// The little-endian bytes of `values` (the byte order glTF buffers use).
fn le_bytes<T: Copy, const N: usize>(values: &[T], to_le: fn(T) -> [u8; N]) -> Vec<u8> {
    let mut out = Vec::with_capacity(values.len() * N);
    for &v in values {
        out.extend_from_slice(&to_le(v));
    }
    out
}

/// Smallest and largest value per axis (the `POSITION` accessor's required `min`/`max`).
fn bounds(points: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    let mut min = [f32::INFINITY; 3];
    let mut max = [f32::NEG_INFINITY; 3];
    for p in points {
        for i in 0..3 {
            min[i] = min[i].min(p[i]);
            max[i] = max[i].max(p[i]);
        }
    }
    (min, max)
}

/// The shape of one accessor.
struct AccessorKind {
    count: usize,
    component: json::accessor::ComponentType,
    type_: json::accessor::Type,
    normalized: bool,
    bounds: Option<([f32; 3], [f32; 3])>,
    target: json::buffer::Target,
}

impl AccessorKind {
    fn vec3_f32(count: usize, bounds: Option<([f32; 3], [f32; 3])>) -> AccessorKind {
        AccessorKind {
            count,
            component: json::accessor::ComponentType::F32,
            type_: json::accessor::Type::Vec3,
            normalized: false,
            bounds,
            target: json::buffer::Target::ArrayBuffer,
        }
    }
}

/// Appends `data` (a multiple of 4 bytes) to `bin` as a buffer view of its own and returns an
/// accessor over it.
fn accessor(
    root: &mut json::Root,
    bin: &mut Vec<u8>,
    buffer: json::Index<json::Buffer>,
    data: &[u8],
    kind: AccessorKind,
) -> json::Index<json::Accessor> {
    debug_assert_eq!(data.len() % 4, 0);
    let view = root.push(json::buffer::View {
        buffer,
        byte_length: USize64::from(data.len()),
        byte_offset: Some(USize64::from(bin.len())),
        byte_stride: None,
        name: None,
        target: Some(Valid(kind.target)),
        extensions: None,
        extras: Default::default(),
    });
    bin.extend_from_slice(data);
    let (min, max) = match kind.bounds {
        Some((min, max)) => (
            Some(json::Value::from(min.to_vec())),
            Some(json::Value::from(max.to_vec())),
        ),
        None => (None, None),
    };
    root.push(json::Accessor {
        buffer_view: Some(view),
        byte_offset: None,
        count: USize64::from(kind.count),
        component_type: Valid(json::accessor::GenericComponentType(kind.component)),
        extensions: None,
        extras: Default::default(),
        type_: Valid(kind.type_),
        min,
        max,
        name: None,
        normalized: kind.normalized,
        sparse: None,
    })
}
