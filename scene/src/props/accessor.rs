//! Accessors read with every bound checked: the type and component type against what the
//! use allows, the stride, the last element against the end of its view, sparse indices
//! against the count. Elements are read byte by byte (little-endian), so misaligned data is
//! read correctly rather than refused.

use std::borrow::Cow;

use gltf::Document;
use gltf::json::accessor::{ComponentType, Type};
use gltf::json::validation::Checked;

use super::buffers::view_bytes;
use super::error::PropError;

/// What an accessor is read as.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Use {
    /// `POSITION` or `NORMAL`: `VEC3` of `FLOAT`.
    Vec3(&'static str),
    /// `TEXCOORD_0`: `VEC2` of `FLOAT`, or of normalized `UNSIGNED_BYTE` / `UNSIGNED_SHORT`.
    TexCoord,
    /// Indices: `SCALAR` of `UNSIGNED_BYTE`, `UNSIGNED_SHORT` or `UNSIGNED_INT`.
    Indices,
}

impl Use {
    fn name(self) -> &'static str {
        match self {
            Use::Vec3(name) => name,
            Use::TexCoord => "TEXCOORD_0",
            Use::Indices => "indices",
        }
    }

    fn expected(self) -> &'static str {
        match self {
            Use::Vec3(_) => "VEC3 of FLOAT",
            Use::TexCoord => "VEC2 of FLOAT, or of normalized UNSIGNED_BYTE or UNSIGNED_SHORT",
            Use::Indices => {
                "SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, not normalized"
            }
        }
    }

    fn components(self) -> usize {
        match self {
            Use::Vec3(_) => 3,
            Use::TexCoord => 2,
            Use::Indices => 1,
        }
    }

    fn accepts(self, ty: Type, component: ComponentType, normalized: bool) -> bool {
        use ComponentType as C;
        match self {
            Use::Vec3(_) => ty == Type::Vec3 && component == C::F32 && !normalized,
            Use::TexCoord => {
                ty == Type::Vec2
                    && match component {
                        C::F32 => !normalized,
                        C::U8 | C::U16 => normalized,
                        _ => false,
                    }
            }
            Use::Indices => {
                ty == Type::Scalar && matches!(component, C::U8 | C::U16 | C::U32) && !normalized
            }
        }
    }
}

fn component_size(c: ComponentType) -> usize {
    match c {
        ComponentType::I8 | ComponentType::U8 => 1,
        ComponentType::I16 | ComponentType::U16 => 2,
        ComponentType::U32 | ComponentType::F32 => 4,
    }
}

fn type_name(t: Type) -> &'static str {
    match t {
        Type::Scalar => "SCALAR",
        Type::Vec2 => "VEC2",
        Type::Vec3 => "VEC3",
        Type::Vec4 => "VEC4",
        Type::Mat2 => "MAT2",
        Type::Mat3 => "MAT3",
        Type::Mat4 => "MAT4",
    }
}

fn component_name(c: ComponentType) -> &'static str {
    match c {
        ComponentType::I8 => "BYTE",
        ComponentType::U8 => "UNSIGNED_BYTE",
        ComponentType::I16 => "SHORT",
        ComponentType::U16 => "UNSIGNED_SHORT",
        ComponentType::U32 => "UNSIGNED_INT",
        ComponentType::F32 => "FLOAT",
    }
}

/// One component as `f64` (exact for every type): normalized integers mapped to `0..=1`.
fn decode(c: ComponentType, normalized: bool, b: &[u8]) -> f64 {
    let raw = match (c, b) {
        (ComponentType::U8, &[x, ..]) => f64::from(x),
        (ComponentType::I8, &[x, ..]) => f64::from(x as i8),
        (ComponentType::U16, &[x, y, ..]) => f64::from(u16::from_le_bytes([x, y])),
        (ComponentType::I16, &[x, y, ..]) => f64::from(i16::from_le_bytes([x, y])),
        (ComponentType::U32, &[x, y, z, w, ..]) => f64::from(u32::from_le_bytes([x, y, z, w])),
        (ComponentType::F32, &[x, y, z, w, ..]) => f64::from(f32::from_le_bytes([x, y, z, w])),
        _ => 0.0,
    };
    if !normalized {
        return raw;
    }
    match c {
        ComponentType::U8 => raw / 255.0,
        ComponentType::U16 => raw / 65535.0,
        ComponentType::I8 => (raw / 127.0).max(-1.0),
        ComponentType::I16 => (raw / 32767.0).max(-1.0),
        _ => raw,
    }
}

/// The element count of accessor `index` (0 for a missing one, which validation excludes).
pub(crate) fn count(document: &Document, index: usize) -> usize {
    document
        .as_json()
        .accessors
        .get(index)
        .map_or(0, |a| usize::try_from(a.count.0).unwrap_or(usize::MAX))
}

/// The components of accessor `index` read as `use_`, flattened (`count * components`
/// values). The caller has checked `count` against its limits.
pub(crate) fn read(
    document: &Document,
    buffers: &[Cow<'_, [u8]>],
    index: usize,
    use_: Use,
) -> Result<Vec<f64>, PropError> {
    let invalid = || PropError::Invalid {
        problems: vec![format!("accessor {index} does not exist or is invalid")],
    };
    let a = document
        .as_json()
        .accessors
        .get(index)
        .ok_or_else(invalid)?;
    let (Checked::Valid(ty), Checked::Valid(component)) = (&a.type_, &a.component_type) else {
        return Err(invalid());
    };
    let (ty, component) = (*ty, component.0);
    if !use_.accepts(ty, component, a.normalized) {
        let normalized = if a.normalized { " (normalized)" } else { "" };
        return Err(PropError::WrongAccessorType {
            accessor: index,
            used_as: use_.name(),
            found: format!(
                "{} of {}{normalized}",
                type_name(ty),
                component_name(component)
            ),
            expected: use_.expected(),
        });
    }
    let n = use_.components();
    let size = component_size(component);
    let element = n * size;
    let count = count(document, index);
    let total = count.checked_mul(n).ok_or(PropError::AccessorOutOfBounds {
        accessor: index,
        part: "elements",
        end: u64::MAX,
        view_length: 0,
    })?;
    let mut out = Vec::new();
    match a.buffer_view {
        Some(view) => {
            let bytes = view_bytes(document, buffers, view.value())?;
            let declared = document
                .as_json()
                .buffer_views
                .get(view.value())
                .and_then(|v| v.byte_stride)
                .map_or(0, |s| s.0);
            let stride = if declared == 0 { element } else { declared };
            if stride < element || stride > 252 {
                return Err(PropError::BadStride {
                    view: view.value(),
                    stride,
                    element,
                });
            }
            let offset = a.byte_offset.map_or(0, |o| o.0);
            if count > 0 {
                let end = (count as u64 - 1)
                    .checked_mul(stride as u64)
                    .and_then(|x| x.checked_add(offset))
                    .and_then(|x| x.checked_add(element as u64))
                    .unwrap_or(u64::MAX);
                if end > bytes.len() as u64 {
                    return Err(PropError::AccessorOutOfBounds {
                        accessor: index,
                        part: "elements",
                        end,
                        view_length: bytes.len(),
                    });
                }
            }
            out.reserve_exact(total);
            for e in 0..count {
                let start = offset as usize + e * stride;
                for c in 0..n {
                    let at = start + c * size;
                    out.push(decode(component, a.normalized, &bytes[at..at + size]));
                }
            }
        }
        // No view: every element is zero until sparse values replace some.
        None => out.resize(total, 0.0),
    }
    if let Some(sparse) = &a.sparse {
        let Checked::Valid(index_type) = &sparse.indices.component_type else {
            return Err(invalid());
        };
        let index_type = index_type.0;
        let isize_ = component_size(index_type);
        let entries = usize::try_from(sparse.count.0).unwrap_or(usize::MAX);
        let indices = view_bytes(document, buffers, sparse.indices.buffer_view.value())?;
        let values = view_bytes(document, buffers, sparse.values.buffer_view.value())?;
        let check = |bytes: &[u8], offset: u64, each: usize, part| {
            let end = (entries as u64)
                .checked_mul(each as u64)
                .and_then(|x| x.checked_add(offset))
                .unwrap_or(u64::MAX);
            if end > bytes.len() as u64 {
                Err(PropError::AccessorOutOfBounds {
                    accessor: index,
                    part,
                    end,
                    view_length: bytes.len(),
                })
            } else {
                Ok(offset as usize)
            }
        };
        let i0 = check(
            indices,
            sparse.indices.byte_offset.0,
            isize_,
            "sparse indices",
        )?;
        let v0 = check(
            values,
            sparse.values.byte_offset.0,
            element,
            "sparse values",
        )?;
        for k in 0..entries {
            let at = i0 + k * isize_;
            let target = decode(index_type, false, &indices[at..at + isize_]) as u32;
            if target as usize >= count {
                return Err(PropError::SparseIndexOutOfRange {
                    accessor: index,
                    index: target,
                    count,
                });
            }
            for c in 0..n {
                let at = v0 + k * element + c * size;
                out[target as usize * n + c] =
                    decode(component, a.normalized, &values[at..at + size]);
            }
        }
    }
    Ok(out)
}
