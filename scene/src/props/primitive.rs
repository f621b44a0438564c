//! Triangle-list primitives: positions, normals (flat ones made where the file has none),
//! texture coordinate 0 and `u32` indices (made for non-indexed lists), every value checked.

use std::borrow::Cow;

use gltf::Document;
use gltf::json::mesh::{Mode, Semantic};
use gltf::json::validation::Checked;

use super::PropLimits;
use super::accessor::{Use, count, read};
use super::draco::decode_primitive;
use super::error::{Limit, PrimitiveAt, PropError};
use super::model::{Aabb, PropMesh, PropPrimitive, PropVertex};
use super::warning::PropWarning;

/// Running totals checked against the limits before anything is allocated.
#[derive(Debug, Default)]
pub(crate) struct Totals {
    pub(crate) vertices: u64,
    pub(crate) indices: u64,
}

impl Totals {
    fn add(
        &mut self,
        vertices: usize,
        indices: usize,
        limits: &PropLimits,
    ) -> Result<(), PropError> {
        let v = self.vertices.saturating_add(vertices as u64);
        if v > limits.max_vertices as u64 {
            return Err(PropError::Limit {
                limit: Limit::Vertices,
                allowed: limits.max_vertices as u64,
                requested: v,
            });
        }
        let i = self.indices.saturating_add(indices as u64);
        if i > limits.max_indices as u64 {
            return Err(PropError::Limit {
                limit: Limit::Indices,
                allowed: limits.max_indices as u64,
                requested: i,
            });
        }
        self.vertices = v;
        self.indices = i;
        Ok(())
    }
}

fn mode_name(mode: Mode) -> &'static str {
    match mode {
        Mode::Points => "POINTS",
        Mode::Lines => "LINES",
        Mode::LineLoop => "LINE_LOOP",
        Mode::LineStrip => "LINE_STRIP",
        Mode::Triangles => "TRIANGLES",
        Mode::TriangleStrip => "TRIANGLE_STRIP",
        Mode::TriangleFan => "TRIANGLE_FAN",
    }
}

fn semantic_name(s: &Semantic) -> String {
    match s {
        Semantic::Positions => "POSITION".to_owned(),
        Semantic::Normals => "NORMAL".to_owned(),
        Semantic::Tangents => "TANGENT".to_owned(),
        Semantic::Colors(n) => format!("COLOR_{n}"),
        Semantic::TexCoords(n) => format!("TEXCOORD_{n}"),
        Semantic::Joints(n) => format!("JOINTS_{n}"),
        Semantic::Weights(n) => format!("WEIGHTS_{n}"),
    }
}

/// Every mesh of the file, at its file index.
pub(crate) fn load_meshes(
    document: &Document,
    buffers: &[Cow<'_, [u8]>],
    limits: &PropLimits,
    warnings: &mut Vec<PropWarning>,
) -> Result<Vec<PropMesh>, PropError> {
    let mut totals = Totals::default();
    let mut meshes = Vec::new();
    for (m, mesh) in document.as_json().meshes.iter().enumerate() {
        let mut primitives = Vec::new();
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let at = PrimitiveAt {
                mesh: m,
                primitive: p,
            };
            let mode = match prim.mode {
                Checked::Valid(mode) => mode,
                Checked::Invalid => {
                    return Err(PropError::Invalid {
                        problems: vec![format!("{at}: invalid mode")],
                    });
                }
            };
            if mode != Mode::Triangles {
                warnings.push(PropWarning::PrimitiveModeSkipped {
                    at,
                    mode: mode_name(mode),
                });
                continue;
            }
            if prim.targets.as_ref().is_some_and(|t| !t.is_empty()) {
                warnings.push(PropWarning::MorphTargets { at });
            }
            let mut attrs = Attrs::default();
            for (semantic, accessor) in &prim.attributes {
                match semantic {
                    Checked::Valid(Semantic::Positions) => attrs.position = Some(accessor.value()),
                    Checked::Valid(Semantic::Normals) => attrs.normal = Some(accessor.value()),
                    Checked::Valid(Semantic::TexCoords(0)) => attrs.uv = Some(accessor.value()),
                    Checked::Valid(other) => warnings.push(PropWarning::IgnoredAttribute {
                        at,
                        attribute: semantic_name(other),
                    }),
                    Checked::Invalid => {}
                }
            }
            let indices = prim.indices.map(|i| i.value());
            let primitive =
                load_primitive(document, buffers, at, attrs, indices, limits, &mut totals)?;
            if primitive.normals_generated {
                warnings.push(PropWarning::NormalsGenerated { at });
            }
            primitives.push(PropPrimitive {
                material: prim.material.map(|i| i.value()),
                ..primitive
            });
        }
        meshes.push(PropMesh {
            name: mesh.name.clone(),
            primitives,
        });
    }
    Ok(meshes)
}

#[derive(Clone, Copy, Debug, Default)]
struct Attrs {
    position: Option<usize>,
    normal: Option<usize>,
    uv: Option<usize>,
}

fn finite<const N: usize>(
    values: &[f64],
    at: PrimitiveAt,
    attribute: &'static str,
) -> Result<Vec<[f32; N]>, PropError> {
    values
        .chunks_exact(N)
        .enumerate()
        .map(|(vertex, c)| {
            let v: [f32; N] = std::array::from_fn(|i| c[i] as f32);
            if v.iter().all(|x| x.is_finite()) {
                Ok(v)
            } else {
                Err(PropError::NonFinite {
                    at,
                    attribute,
                    vertex,
                })
            }
        })
        .collect()
}

fn normalize(n: [f32; 3]) -> [f32; 3] {
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len > 0.0 && len.is_finite() {
        n.map(|c| c / len)
    } else {
        [0.0; 3]
    }
}

/// The unit normal of triangle `a, b, c` (counter-clockwise front), zero when degenerate.
fn face_normal(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> [f32; 3] {
    let u: [f32; 3] = std::array::from_fn(|i| b[i] - a[i]);
    let v: [f32; 3] = std::array::from_fn(|i| c[i] - a[i]);
    normalize([
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ])
}

fn load_primitive(
    document: &Document,
    buffers: &[Cow<'_, [u8]>],
    at: PrimitiveAt,
    attrs: Attrs,
    indices: Option<usize>,
    limits: &PropLimits,
    totals: &mut Totals,
) -> Result<PropPrimitive, PropError> {
    let position = attrs.position.ok_or(PropError::MissingPositions { at })?;
    let vertex_count = count(document, position);
    let index_count = indices.map_or(vertex_count, |i| count(document, i));
    // Flat normals unweld: one vertex per index.
    let stored_vertices = if attrs.normal.is_some() {
        vertex_count
    } else {
        index_count
    };
    totals.add(stored_vertices, index_count, limits)?;
    if !index_count.is_multiple_of(3) {
        return Err(PropError::TriangleCount {
            at,
            count: index_count,
        });
    }
    for (attribute, accessor) in [("NORMAL", attrs.normal), ("TEXCOORD_0", attrs.uv)] {
        if let Some(a) = accessor {
            let n = count(document, a);
            if n != vertex_count {
                return Err(PropError::AttributeCount {
                    at,
                    attribute,
                    count: n,
                    positions: vertex_count,
                });
            }
        }
    }
    // Decoded after the limits were checked against the accessors' counts, which the
    // decoded data must then match.
    let draco = decode_primitive(document, buffers, at)?;
    if let Some(d) = &draco
        && d.points != vertex_count
    {
        return Err(PropError::Draco {
            at,
            problem: format!(
                "the stream decodes {} points, the POSITION accessor says {vertex_count}",
                d.points
            ),
        });
    }
    let values = |accessor: usize, name: &'static str, use_: Use, n: usize| match draco
        .as_ref()
        .and_then(|d| d.values(name, n, at))
    {
        Some(decoded) => decoded,
        None => read(document, buffers, accessor, use_),
    };
    let positions: Vec<[f32; 3]> = finite(
        &values(position, "POSITION", Use::Vec3("POSITION"), 3)?,
        at,
        "POSITION",
    )?;
    let normals: Option<Vec<[f32; 3]>> = match attrs.normal {
        Some(a) => Some(finite(
            &values(a, "NORMAL", Use::Vec3("NORMAL"), 3)?,
            at,
            "NORMAL",
        )?),
        None => None,
    };
    let uvs: Option<Vec<[f32; 2]>> = match attrs.uv {
        Some(a) => Some(finite(
            &values(a, "TEXCOORD_0", Use::TexCoord, 2)?,
            at,
            "TEXCOORD_0",
        )?),
        None => None,
    };
    let index_list: Vec<u32> = match (&draco, indices) {
        (Some(d), _) => {
            if d.indices.len() != index_count {
                return Err(PropError::Draco {
                    at,
                    problem: format!(
                        "the stream decodes {} indices, the primitive says {index_count}",
                        d.indices.len()
                    ),
                });
            }
            d.indices.clone()
        }
        (None, Some(i)) => read(document, buffers, i, Use::Indices)?
            .into_iter()
            .map(|v| v as u32)
            .collect(),
        (None, None) => (0..vertex_count as u32).collect(),
    };
    for (position, &index) in index_list.iter().enumerate() {
        if index as usize >= vertex_count {
            return Err(PropError::IndexOutOfRange {
                at,
                position,
                index,
                vertex_count,
            });
        }
    }
    let uv_of = |v: usize| uvs.as_ref().map_or([0.0; 2], |u| u[v]);
    let (vertices, indices) = match &normals {
        Some(normals) => (
            (0..vertex_count)
                .map(|v| PropVertex {
                    position: positions[v],
                    normal: normalize(normals[v]),
                    uv: uv_of(v),
                })
                .collect::<Vec<_>>(),
            index_list,
        ),
        None => {
            let mut vertices = Vec::with_capacity(index_list.len());
            for tri in index_list.chunks_exact(3) {
                let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| i as usize);
                let normal = face_normal(positions[a], positions[b], positions[c]);
                for v in [a, b, c] {
                    vertices.push(PropVertex {
                        position: positions[v],
                        normal,
                        uv: uv_of(v),
                    });
                }
            }
            let indices = (0..vertices.len() as u32).collect();
            (vertices, indices)
        }
    };
    let bounds = Aabb::of_points(vertices.iter().map(|v| v.position)).unwrap_or(Aabb {
        min: [0.0; 3],
        max: [0.0; 3],
    });
    Ok(PropPrimitive {
        source_index: at.primitive,
        vertices,
        indices,
        material: None,
        bounds,
        has_uv: uvs.is_some(),
        normals_generated: normals.is_none(),
    })
}
