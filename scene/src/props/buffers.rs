//! The data of every buffer (the GLB BIN chunk, a `data:` URI, or a file beside the `.gltf`)
//! and of buffer views, bounds checked once here.

use std::borrow::Cow;
use std::path::Path;

use gltf::Document;

use super::PropLimits;
use super::error::PropError;
use super::uri::{UriKind, base64_decode, classify, read_beside};

/// Where relative URIs are resolved: nowhere (bytes were given) or beside the `.gltf`.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Base<'p> {
    /// Bytes alone: an external URI is [`PropError::ExternalUri`].
    None,
    /// The folder of the `.gltf` file.
    Folder(&'p Path),
}

/// The bytes a URI names; `owner` names what holds it.
pub(crate) fn uri_bytes<'a>(
    uri: &'a str,
    owner: &str,
    base: Base<'_>,
    limits: &PropLimits,
    external_total: &mut u64,
) -> Result<Cow<'a, [u8]>, PropError> {
    match classify(uri, owner)? {
        UriKind::Data { payload, .. } => Ok(Cow::Owned(base64_decode(payload, owner)?)),
        UriKind::File(name) => match base {
            Base::None => Err(PropError::ExternalUri {
                owner: owner.to_owned(),
                uri: uri.to_owned(),
            }),
            Base::Folder(folder) => {
                let left = limits.max_external_bytes.saturating_sub(*external_total);
                let bytes = read_beside(folder, &name, owner, uri, left).map_err(|e| match e {
                    PropError::Limit { requested, .. } => PropError::Limit {
                        limit: super::error::Limit::ExternalBytes,
                        allowed: limits.max_external_bytes,
                        requested: requested.saturating_add(*external_total),
                    },
                    other => other,
                })?;
                *external_total += bytes.len() as u64;
                Ok(Cow::Owned(bytes))
            }
        },
    }
}

/// Every buffer's data, in file order, each at least its `byteLength` long.
pub(crate) fn load_buffers<'a>(
    document: &'a Document,
    bin: Option<&'a [u8]>,
    base: Base<'_>,
    limits: &PropLimits,
    external_total: &mut u64,
) -> Result<Vec<Cow<'a, [u8]>>, PropError> {
    let mut out = Vec::new();
    for (index, buffer) in document.as_json().buffers.iter().enumerate() {
        let owner = format!("buffer {index}");
        let data: Cow<'a, [u8]> = match (&buffer.uri, bin) {
            (Some(uri), _) => uri_bytes(uri, &owner, base, limits, external_total)?,
            // Only buffer 0 may be the GLB's BIN chunk.
            (None, Some(bin)) if index == 0 => Cow::Borrowed(bin),
            (None, _) => return Err(PropError::MissingBuffer { buffer: index }),
        };
        let declared = buffer.byte_length.0;
        if (data.len() as u64) < declared {
            return Err(PropError::BufferTooShort {
                buffer: index,
                declared,
                actual: data.len(),
            });
        }
        out.push(data);
    }
    Ok(out)
}

/// The bytes of buffer view `view`: its range of its buffer, checked.
pub(crate) fn view_bytes<'b>(
    document: &Document,
    buffers: &'b [Cow<'_, [u8]>],
    view: usize,
) -> Result<&'b [u8], PropError> {
    let json = &document.as_json().buffer_views;
    // Validation guarantees both indices; `get` keeps a miss an error, not a panic.
    let invalid = || PropError::Invalid {
        problems: vec![format!("buffer view {view} or its buffer does not exist")],
    };
    let v = json.get(view).ok_or_else(invalid)?;
    let buffer = v.buffer.value();
    let data = buffers.get(buffer).ok_or_else(invalid)?;
    let offset = v.byte_offset.map_or(0, |o| o.0);
    let end = offset.saturating_add(v.byte_length.0);
    if end > data.len() as u64 {
        return Err(PropError::ViewOutOfBuffer {
            view,
            buffer,
            end,
            buffer_length: data.len(),
        });
    }
    Ok(&data[offset as usize..end as usize])
}
