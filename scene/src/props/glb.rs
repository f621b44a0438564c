//! The GLB container, read strictly: a 12-byte header (`glTF`, version 2, the file's exact
//! length), a JSON chunk first, at most one BIN chunk, chunks of unknown type skipped (as the
//! specification asks), nothing cut short.

use super::error::PropError;

const MAGIC: &[u8; 4] = b"glTF";
const JSON: u32 = 0x4E4F_534A;
const BIN: u32 = 0x004E_4942;

/// The chunks of a GLB file.
#[derive(Debug)]
pub(crate) struct Glb<'a> {
    /// The JSON chunk's bytes.
    pub(crate) json: &'a [u8],
    /// The BIN chunk's bytes (the data of buffer 0 when it has no `uri`).
    pub(crate) bin: Option<&'a [u8]>,
}

/// True when `bytes` start with the GLB magic, or are a piece of it (a GLB cut short).
pub(crate) fn is_glb(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC) || MAGIC.starts_with(bytes)
}

fn u32_at(bytes: &[u8], offset: usize, what: &'static str) -> Result<u32, PropError> {
    let available = bytes.len().saturating_sub(offset);
    match bytes.get(offset..offset + 4) {
        Some(&[a, b, c, d]) => Ok(u32::from_le_bytes([a, b, c, d])),
        _ => Err(PropError::GlbTruncated {
            what,
            offset,
            needed: 4,
            available,
        }),
    }
}

/// Splits a GLB file into its JSON and BIN chunks.
pub(crate) fn split(bytes: &[u8]) -> Result<Glb<'_>, PropError> {
    if bytes.len() < 12 {
        return Err(PropError::GlbTruncated {
            what: "header",
            offset: 0,
            needed: 12,
            available: bytes.len(),
        });
    }
    let version = u32_at(bytes, 4, "header")?;
    if version != 2 {
        return Err(PropError::BadGlb {
            offset: 4,
            problem: format!("container version {version}; only 2 is glTF 2.0"),
        });
    }
    let length = u32_at(bytes, 8, "header")? as usize;
    if length > bytes.len() {
        return Err(PropError::GlbTruncated {
            what: "file (the header's length)",
            offset: 0,
            needed: length as u64,
            available: bytes.len(),
        });
    }
    if length < bytes.len() {
        return Err(PropError::BadGlb {
            offset: 8,
            problem: format!(
                "the header says the file is {length} bytes, but {} bytes follow",
                bytes.len()
            ),
        });
    }
    let mut offset = 12;
    let mut json = None;
    let mut bin = None;
    while offset < bytes.len() {
        let what = if json.is_none() {
            "JSON chunk"
        } else {
            "chunk header"
        };
        let chunk_length = u32_at(bytes, offset, what)? as usize;
        let kind = u32_at(bytes, offset + 4, what)?;
        let start = offset + 8;
        let available = bytes.len() - start;
        if chunk_length > available {
            return Err(PropError::GlbTruncated {
                what: match kind {
                    JSON => "JSON chunk",
                    BIN => "BIN chunk",
                    _ => "chunk",
                },
                offset: start,
                needed: chunk_length as u64,
                available,
            });
        }
        let data = &bytes[start..start + chunk_length];
        match (kind, json.is_some(), bin.is_some()) {
            (JSON, false, _) => json = Some(data),
            (_, false, _) => {
                return Err(PropError::BadGlb {
                    offset,
                    problem: format!("the first chunk has type {kind:#010x}, not JSON"),
                });
            }
            (JSON, true, _) => {
                return Err(PropError::BadGlb {
                    offset,
                    problem: "a second JSON chunk".to_owned(),
                });
            }
            (BIN, true, false) => bin = Some(data),
            (BIN, true, true) => {
                return Err(PropError::BadGlb {
                    offset,
                    problem: "a second BIN chunk".to_owned(),
                });
            }
            // Unknown chunk types are skipped, as the specification asks.
            _ => {}
        }
        offset = start + chunk_length;
    }
    let Some(json) = json else {
        return Err(PropError::GlbTruncated {
            what: "JSON chunk",
            offset: 12,
            needed: 8,
            available: 0,
        });
    };
    Ok(Glb { json, bin })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glb(chunks: &[(u32, &[u8])]) -> Vec<u8> {
        let mut out = b"glTF".to_vec();
        out.extend(2u32.to_le_bytes());
        out.extend(0u32.to_le_bytes());
        for (kind, data) in chunks {
            out.extend((data.len() as u32).to_le_bytes());
            out.extend(kind.to_le_bytes());
            out.extend(*data);
        }
        let len = out.len() as u32;
        out[8..12].copy_from_slice(&len.to_le_bytes());
        out
    }

    #[test]
    fn chunks_are_split_and_unknown_ones_skipped() {
        let bytes = glb(&[(JSON, b"{}  "), (0x1234, b"xxxx"), (BIN, b"abcd")]);
        let g = split(&bytes).unwrap();
        assert_eq!(g.json, b"{}  ");
        assert_eq!(g.bin, Some(&b"abcd"[..]));
    }

    #[test]
    fn every_cut_is_truncated_and_bad_headers_are_named() {
        let bytes = glb(&[(JSON, b"{}  "), (BIN, b"abcd")]);
        for cut in 0..bytes.len() {
            assert!(split(&bytes[..cut]).is_err(), "cut {cut}");
        }
        let mut v = bytes.clone();
        v[4] = 1;
        assert!(matches!(
            split(&v),
            Err(PropError::BadGlb { offset: 4, .. })
        ));
        let mut long = bytes.clone();
        long.push(0);
        assert!(matches!(
            split(&long),
            Err(PropError::BadGlb { offset: 8, .. })
        ));
        let two = glb(&[(JSON, b"{}  "), (BIN, b"a"), (BIN, b"b")]);
        assert!(split(&two).is_err());
        let first_bin = glb(&[(BIN, b"abcd")]);
        assert!(split(&first_bin).is_err());
    }
}
