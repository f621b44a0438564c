//! `KHR_draco_mesh_compression`, behind the `draco` feature: a primitive's Draco stream
//! decoded by `draco-oxide-decoder` (pure Rust), its attributes found by the unique ids the
//! extension names, and checked against the counts the primitive's accessors declare (which
//! the vertex and index limits were checked against before decoding).
//!
//! Without the feature, [`decode_primitive`] finds nothing to decode: a file that requires
//! the extension is refused earlier by name, and one that only uses it has uncompressed
//! fallback accessors, which are read instead (with a warning for the extension).

use std::borrow::Cow;

use gltf::Document;

use super::error::{PrimitiveAt, PropError};

/// A decoded Draco primitive: every attribute per point, and the triangle list.
#[derive(Debug, Default)]
pub(crate) struct Decoded {
    /// Points (vertices) decoded.
    pub(crate) points: usize,
    /// Triangle list.
    pub(crate) indices: Vec<u32>,
    /// `(glTF attribute name, components, values per point)`.
    pub(crate) attributes: Vec<(String, usize, Vec<f64>)>,
}

impl Decoded {
    /// The values of `attribute` (`components` per point, flattened), `None` when the
    /// extension does not compress it.
    pub(crate) fn values(
        &self,
        attribute: &str,
        components: usize,
        at: PrimitiveAt,
    ) -> Option<Result<Vec<f64>, PropError>> {
        let (_, n, values) = self
            .attributes
            .iter()
            .find(|(name, ..)| name == attribute)?;
        if *n != components {
            return Some(Err(PropError::Draco {
                at,
                problem: format!("{attribute} decodes with {n} components, not {components}"),
            }));
        }
        Some(Ok(values.clone()))
    }
}

/// The Draco data of primitive `at`, when it has the extension (and the feature is on).
#[cfg(feature = "draco")]
pub(crate) fn decode_primitive(
    document: &Document,
    buffers: &[Cow<'_, [u8]>],
    at: PrimitiveAt,
) -> Result<Option<Decoded>, PropError> {
    use draco_oxide_core::attribute::ComponentDataType as C;

    let Some(prim) = document
        .as_json()
        .meshes
        .get(at.mesh)
        .and_then(|m| m.primitives.get(at.primitive))
    else {
        return Ok(None);
    };
    let Some(ext) = prim
        .extensions
        .as_ref()
        .and_then(|e| e.others.get("KHR_draco_mesh_compression"))
    else {
        return Ok(None);
    };
    let bad = |problem: String| PropError::Draco { at, problem };
    let view = ext
        .get("bufferView")
        .and_then(gltf::json::Value::as_u64)
        .ok_or_else(|| bad("the extension has no bufferView".to_owned()))?;
    let ids = ext
        .get("attributes")
        .and_then(gltf::json::Value::as_object)
        .ok_or_else(|| bad("the extension has no attributes".to_owned()))?;
    let bytes = super::buffers::view_bytes(document, buffers, view as usize)?;
    let mesh = draco_oxide_decoder::decode_mesh(bytes).map_err(|e| bad(e.to_string()))?;
    let mut out = Decoded::default();
    let positions = mesh
        .get_attributes()
        .iter()
        .find(|a| {
            ids.get("POSITION")
                .and_then(gltf::json::Value::as_u64)
                .is_some_and(|id| a.get_id().as_usize() as u64 == id)
        })
        .ok_or_else(|| bad("no POSITION attribute in the stream".to_owned()))?;
    out.points = positions.len();
    for (name, id) in ids {
        let Some(id) = id.as_u64() else {
            return Err(bad(format!("attribute {name} has a non-integer id")));
        };
        let Some(a) = mesh
            .get_attributes()
            .iter()
            .find(|a| a.get_id().as_usize() as u64 == id)
        else {
            return Err(bad(format!(
                "attribute {name} (id {id}) is not in the stream"
            )));
        };
        if a.len() != out.points {
            return Err(bad(format!(
                "attribute {name} covers {} points, POSITION {}",
                a.len(),
                out.points
            )));
        }
        let ty = a.get_component_type();
        let (n, size) = (a.get_num_components(), ty.size());
        let raw = a.get_data_as_bytes();
        let map = a.point_map_as_slice();
        let mut values = Vec::with_capacity(out.points.saturating_mul(n));
        for p in 0..out.points {
            let value = match map {
                Some(m) => m.get(p).map(|&v| usize::from(v)),
                None => Some(p),
            }
            .ok_or_else(|| bad(format!("attribute {name}: point {p} has no value")))?;
            for c in 0..n {
                let offset = (value * n + c) * size;
                let b = raw
                    .get(offset..offset + size)
                    .ok_or_else(|| bad(format!("attribute {name}: value {value} is missing")))?;
                let le = |k: usize| b.get(k).copied().unwrap_or(0);
                values.push(match ty {
                    C::U8 => f64::from(le(0)),
                    C::I8 => f64::from(le(0) as i8),
                    C::U16 => f64::from(u16::from_le_bytes([le(0), le(1)])),
                    C::I16 => f64::from(i16::from_le_bytes([le(0), le(1)])),
                    C::U32 => f64::from(u32::from_le_bytes([le(0), le(1), le(2), le(3)])),
                    C::I32 => f64::from(i32::from_le_bytes([le(0), le(1), le(2), le(3)])),
                    C::F32 => f64::from(f32::from_le_bytes([le(0), le(1), le(2), le(3)])),
                    other => return Err(bad(format!("attribute {name}: {other:?} components"))),
                });
            }
        }
        out.attributes.push((name.clone(), n, values));
    }
    for face in mesh.get_faces() {
        for &p in face {
            out.indices.push(usize::from(p) as u32);
        }
    }
    Ok(Some(out))
}

/// Without the `draco` feature there is nothing to decode (see the module docs).
#[cfg(not(feature = "draco"))]
pub(crate) fn decode_primitive(
    _document: &Document,
    _buffers: &[Cow<'_, [u8]>],
    _at: PrimitiveAt,
) -> Result<Option<Decoded>, PropError> {
    Ok(None)
}
