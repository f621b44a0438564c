//! URIs of buffers and images: `data:` URIs decoded here (base64, the only encoding glTF
//! uses for them), and relative file references resolved beside the `.gltf` file, never
//! outside its folder.

use std::path::{Component, Path, PathBuf};

use super::error::PropError;

/// Where a URI's bytes are.
#[derive(Debug, PartialEq, Eq)]
pub(crate) enum UriKind<'a> {
    /// A `data:` URI's payload, still base64-encoded, and its MIME type.
    Data {
        /// The MIME type before `;base64` (may be empty).
        mime: &'a str,
        /// The base64 text.
        payload: &'a str,
    },
    /// A relative file reference, percent-decoded.
    File(String),
}

/// Classifies `uri`; `owner` names what holds it for errors.
pub(crate) fn classify<'a>(uri: &'a str, owner: &str) -> Result<UriKind<'a>, PropError> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let Some((header, payload)) = rest.split_once(',') else {
            return Err(PropError::BadDataUri {
                owner: owner.to_owned(),
                problem: "no ',' before the payload".to_owned(),
            });
        };
        let Some(mime) = header.strip_suffix(";base64") else {
            return Err(PropError::BadDataUri {
                owner: owner.to_owned(),
                problem: format!("header {header:?} is not base64 (';base64' missing)"),
            });
        };
        return Ok(UriKind::Data { mime, payload });
    }
    let escapes = || PropError::UriEscapes {
        owner: owner.to_owned(),
        uri: uri.to_owned(),
    };
    // A scheme (`http:`, `file:`, a drive letter `C:`) is outside the folder.
    if uri.contains(':') {
        return Err(escapes());
    }
    let decoded = percent_decode(uri).ok_or_else(escapes)?;
    let path = Path::new(&decoded);
    let plain = path
        .components()
        .all(|c| matches!(c, Component::Normal(_) | Component::CurDir));
    if decoded.is_empty() || !plain || decoded.contains('\\') || decoded.contains('\0') {
        return Err(escapes());
    }
    Ok(UriKind::File(decoded))
}

/// `%XX` escapes decoded; `None` for a bad escape or bytes that are not UTF-8.
fn percent_decode(s: &str) -> Option<String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes.get(i + 1..i + 3)?;
            let text = std::str::from_utf8(hex).ok()?;
            out.push(u8::from_str_radix(text, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// The value of one base64 character, `None` for any other byte.
fn sextet(c: u8) -> Option<u32> {
    Some(u32::from(match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' | b'-' => 62,
        b'/' | b'_' => 63,
        _ => return None,
    }))
}

/// Decodes standard (or URL-safe) base64, padding optional; `owner` names the holder.
pub(crate) fn base64_decode(text: &str, owner: &str) -> Result<Vec<u8>, PropError> {
    let bad = |problem: String| PropError::BadDataUri {
        owner: owner.to_owned(),
        problem,
    };
    let trimmed = text.trim_end_matches('=');
    if text.len() - trimmed.len() > 2 {
        return Err(bad("more than two '=' of padding".to_owned()));
    }
    let bytes = trimmed.as_bytes();
    if bytes.len() % 4 == 1 {
        return Err(bad(format!(
            "{} base64 characters cannot end a byte",
            bytes.len()
        )));
    }
    let mut out = Vec::with_capacity(bytes.len() / 4 * 3 + 2);
    for (group_index, group) in bytes.chunks(4).enumerate() {
        let mut word = 0u32;
        for (i, &c) in group.iter().enumerate() {
            let v = sextet(c).ok_or_else(|| {
                bad(format!(
                    "byte {:#04x} at {} is not base64",
                    c,
                    group_index * 4 + i
                ))
            })?;
            word |= v << (18 - 6 * i);
        }
        let [_, a, b, c] = word.to_be_bytes();
        out.extend_from_slice(&[a, b, c][..group.len() - 1]);
    }
    Ok(out)
}

/// Reads a relative file `name` beside the `.gltf` in `folder`, refusing one that resolves
/// (through links) outside it, or larger than `max_bytes`.
pub(crate) fn read_beside(
    folder: &Path,
    name: &str,
    owner: &str,
    uri: &str,
    max_bytes: u64,
) -> Result<Vec<u8>, PropError> {
    let path: PathBuf = folder.join(name);
    let read_error = |source| PropError::Read {
        path: path.clone(),
        source,
    };
    let root = folder.canonicalize().map_err(read_error)?;
    let target = path.canonicalize().map_err(read_error)?;
    if !target.starts_with(&root) {
        return Err(PropError::UriEscapes {
            owner: owner.to_owned(),
            uri: uri.to_owned(),
        });
    }
    let size = std::fs::metadata(&target).map_err(read_error)?.len();
    if size > max_bytes {
        return Err(PropError::Limit {
            limit: super::error::Limit::ExternalBytes,
            allowed: max_bytes,
            requested: size,
        });
    }
    std::fs::read(&target).map_err(read_error)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_decodes_with_and_without_padding() {
        assert_eq!(base64_decode("aGVsbG8=", "t").unwrap(), b"hello");
        assert_eq!(base64_decode("aGVsbG8", "t").unwrap(), b"hello");
        assert_eq!(base64_decode("", "t").unwrap(), b"");
        assert_eq!(base64_decode("AAEC", "t").unwrap(), [0, 1, 2]);
        assert!(base64_decode("a", "t").is_err());
        assert!(base64_decode("a*==", "t").is_err());
        assert!(base64_decode("aa===", "t").is_err());
    }

    #[test]
    fn uris_are_classified_and_escapes_refused() {
        assert_eq!(
            classify("data:application/octet-stream;base64,AAAA", "b").unwrap(),
            UriKind::Data {
                mime: "application/octet-stream",
                payload: "AAAA"
            }
        );
        assert_eq!(
            classify("sub/box%20a.bin", "b").unwrap(),
            UriKind::File("sub/box a.bin".to_owned())
        );
        for bad in [
            "../x.bin",
            "/etc/passwd",
            "http://host/x",
            "C:\\x",
            "a/../../x",
            "%2e%2e/x",
            "",
        ] {
            assert!(
                matches!(classify(bad, "b"), Err(PropError::UriEscapes { .. })),
                "{bad}"
            );
        }
        assert!(matches!(
            classify("data:text/plain,hello", "b"),
            Err(PropError::BadDataUri { .. })
        ));
    }
}
