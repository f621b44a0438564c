//! Reading the file's framing: the header, the `MAIN` chunk and its children, and the values
//! inside a chunk ([`Cursor`]), every read checked against the bytes that are there.
//!
//! ```text
//! "VOX " | version u32 | MAIN: id, content bytes N, children bytes M, content, children
//!                          child: id, content bytes n, children bytes (0), content
//! ```

use std::borrow::Cow;
use std::collections::HashSet;

use super::error::{ChunkAt, ChunkId, VoxError};

/// One child chunk of `MAIN`: where it is and its content.
pub(crate) struct Chunk<'a> {
    /// Its id and header offset.
    pub at: ChunkAt,
    /// Its content bytes.
    pub content: &'a [u8],
    /// Offset of the first content byte.
    pub content_offset: usize,
}

impl<'a> Chunk<'a> {
    /// A cursor over the content.
    pub(super) fn cursor(&self) -> Cursor<'a> {
        Cursor {
            bytes: self.content,
            pos: 0,
            base: self.content_offset,
            chunk: self.at,
        }
    }
}

/// The file's version and the children of its `MAIN` chunk, in file order.
pub(crate) fn read_chunks(bytes: &[u8]) -> Result<(u32, Vec<Chunk<'_>>), VoxError> {
    if bytes.len() < 4 || &bytes[..4] != b"VOX " {
        return Err(VoxError::NotVox {
            found: bytes[..bytes.len().min(4)].to_vec(),
        });
    }
    let version = le_u32(bytes, 4, None)?;
    let main = header(bytes, 8, bytes.len())?;
    if &main.id.0 != b"MAIN" {
        return Err(VoxError::NoMain {
            found: ChunkAt {
                id: main.id,
                offset: 8,
            },
        });
    }
    let main_at = ChunkAt {
        id: main.id,
        offset: 8,
    };
    let children_start = main.content.saturating_add(20);
    let children_end = children_start.saturating_add(main.children);
    // Walk the children that are there first, so that a file cut short is reported at the
    // chunk it cuts, not only as a short 'MAIN'.
    let region_end = children_end.min(bytes.len());
    if children_start > bytes.len() {
        return Err(truncated(main_at, 20, main.content, bytes.len() - 20));
    }
    let mut chunks = Vec::new();
    let mut pos = children_start;
    while pos < region_end {
        let h = header(bytes, pos, region_end)?;
        let at = ChunkAt {
            id: h.id,
            offset: pos,
        };
        let content_offset = pos + 12;
        let available = region_end - content_offset;
        if h.content > available {
            return Err(truncated(at, content_offset, h.content, available));
        }
        if h.children != 0 {
            return Err(VoxError::UnexpectedChildren { chunk: at });
        }
        chunks.push(Chunk {
            at,
            content: &bytes[content_offset..content_offset + h.content],
            content_offset,
        });
        pos = content_offset + h.content;
    }
    if children_end > bytes.len() {
        return Err(VoxError::Truncated {
            chunk: Some(main_at),
            offset: bytes.len(),
            needed: (children_end - bytes.len()) as u64,
            available: 0,
        });
    }
    if children_end < bytes.len() {
        return Err(VoxError::TrailingBytes {
            offset: children_end,
            count: bytes.len() - children_end,
        });
    }
    Ok((version, chunks))
}

/// A chunk header's fields, sizes as `usize`.
struct Header {
    id: ChunkId,
    content: usize,
    children: usize,
}

/// Reads the 12-byte chunk header at `pos`, which must end by `end`.
fn header(bytes: &[u8], pos: usize, end: usize) -> Result<Header, VoxError> {
    if end < pos + 12 {
        return Err(VoxError::Truncated {
            chunk: None,
            offset: pos,
            needed: 12,
            available: end.saturating_sub(pos),
        });
    }
    let id = ChunkId(bytes[pos..pos + 4].try_into().expect("4 bytes"));
    let content = le_u32(bytes, pos + 4, None)? as usize;
    let children = le_u32(bytes, pos + 8, None)? as usize;
    Ok(Header {
        id,
        content,
        children,
    })
}

fn truncated(chunk: ChunkAt, offset: usize, needed: usize, available: usize) -> VoxError {
    VoxError::Truncated {
        chunk: Some(chunk),
        offset,
        needed: needed as u64,
        available,
    }
}

/// The little-endian `u32` at `pos`.
fn le_u32(bytes: &[u8], pos: usize, chunk: Option<ChunkAt>) -> Result<u32, VoxError> {
    match bytes.get(pos..pos + 4) {
        Some(b) => Ok(u32::from_le_bytes(b.try_into().expect("4 bytes"))),
        None => Err(VoxError::Truncated {
            chunk,
            offset: pos,
            needed: 4,
            available: bytes.len().saturating_sub(pos),
        }),
    }
}

/// A MagicaVoxel `DICT`: string keys and values, in file order, keys unique.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct Dict {
    entries: Vec<(String, String)>,
}

impl Dict {
    /// The value of `key`, if present.
    pub(crate) fn get(&self, key: &str) -> Option<&str> {
        self.entries
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// Builds a dictionary from pairs (tests).
    #[cfg(test)]
    pub(crate) fn from_pairs(pairs: &[(&str, &str)]) -> Dict {
        Dict {
            entries: pairs
                .iter()
                .map(|(k, v)| ((*k).to_owned(), (*v).to_owned()))
                .collect(),
        }
    }
}

/// Reads values from one chunk's content; every error names the chunk and the byte offset.
pub(crate) struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    /// File offset of `bytes[0]`.
    base: usize,
    chunk: ChunkAt,
}

impl<'a> Cursor<'a> {
    /// The chunk this cursor reads.
    pub(super) fn chunk(&self) -> ChunkAt {
        self.chunk
    }

    /// Bytes left to read.
    pub(super) fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    /// The next `n` bytes.
    pub(super) fn take(&mut self, n: u64) -> Result<&'a [u8], VoxError> {
        let remaining = self.remaining();
        if n > remaining as u64 {
            return Err(VoxError::Truncated {
                chunk: Some(self.chunk),
                offset: self.base + self.pos,
                needed: n,
                available: remaining,
            });
        }
        let n = n as usize;
        let out = &self.bytes[self.pos..self.pos + n];
        self.pos += n;
        Ok(out)
    }

    /// The next little-endian `u32`.
    pub(super) fn u32(&mut self) -> Result<u32, VoxError> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().expect("4")))
    }

    /// The next little-endian `i32`.
    pub(super) fn i32(&mut self) -> Result<i32, VoxError> {
        Ok(i32::from_le_bytes(self.take(4)?.try_into().expect("4")))
    }

    /// The next little-endian `f32`.
    pub(super) fn f32(&mut self) -> Result<f32, VoxError> {
        Ok(f32::from_le_bytes(self.take(4)?.try_into().expect("4")))
    }

    /// A count of items each at least `min_item_bytes` long, checked against what is left so
    /// that a lying count fails here instead of allocating.
    pub(super) fn count(&mut self, min_item_bytes: u64) -> Result<usize, VoxError> {
        let at = self.base + self.pos;
        let n = self.u32()?;
        let needed = u64::from(n) * min_item_bytes;
        if needed > self.remaining() as u64 {
            return Err(VoxError::Truncated {
                chunk: Some(self.chunk),
                offset: at + 4,
                needed,
                available: self.remaining(),
            });
        }
        Ok(n as usize)
    }

    /// A `STRING`: a `u32` length and that many bytes (invalid UTF-8 is replaced, since names
    /// are only shown and values that matter are parsed and checked).
    pub(super) fn string(&mut self) -> Result<String, VoxError> {
        Ok(String::from_utf8_lossy(self.raw_string()?).into_owned())
    }

    /// A `STRING`'s bytes.
    fn raw_string(&mut self) -> Result<&'a [u8], VoxError> {
        let n = self.u32()?;
        self.take(u64::from(n))
    }

    /// A `DICT`: a `u32` count and that many key-value `STRING` pairs; keys must be unique.
    /// Repeats are found through a hash set of the keys, so a dictionary of `n` keys costs
    /// `O(n)`, whatever the keys.
    pub(super) fn dict(&mut self) -> Result<Dict, VoxError> {
        let n = self.count(8)?;
        let mut entries: Vec<(String, String)> = Vec::with_capacity(n);
        // Keys as they are read (invalid UTF-8 replaced), borrowed from the file when valid.
        let mut keys: HashSet<Cow<'a, str>> = HashSet::with_capacity(n);
        for _ in 0..n {
            let key = String::from_utf8_lossy(self.raw_string()?);
            let value = self.string()?;
            if !keys.insert(key.clone()) {
                return Err(VoxError::DuplicateKey {
                    key: key.into_owned(),
                    chunk: self.chunk,
                });
            }
            entries.push((key.into_owned(), value));
        }
        Ok(Dict { entries })
    }

    /// Fails unless every byte was read.
    pub(super) fn finish(&self, expected: &str) -> Result<(), VoxError> {
        if self.remaining() == 0 {
            Ok(())
        } else {
            Err(VoxError::WrongLength {
                chunk: self.chunk,
                expected: expected.to_owned(),
                found: self.bytes.len(),
            })
        }
    }
}
