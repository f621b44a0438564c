//! [`VoxError`]: why a `.vox` file was refused, with what is wrong and where.

use std::fmt;

/// A four-byte chunk id as found in the file (`MAIN`, `XYZI`, ...).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ChunkId(pub [u8; 4]);

impl fmt::Display for ChunkId {
    /// The id in quotes, non-printable bytes escaped (`'XYZI'`, `'\x00AB\xff'`).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("'")?;
        for &b in &self.0 {
            if b.is_ascii_graphic() || b == b' ' {
                write!(f, "{}", char::from(b))?;
            } else {
                write!(f, "\\x{b:02x}")?;
            }
        }
        f.write_str("'")
    }
}

/// Where in the file something is: a chunk and the byte offset of its header.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChunkAt {
    /// The chunk's id.
    pub id: ChunkId,
    /// Byte offset of the chunk's header (its id) from the start of the file.
    pub offset: usize,
}

impl fmt::Display for ChunkAt {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "chunk {} at byte {}", self.id, self.offset)
    }
}

/// Why a `.vox` file could not be loaded. Each variant says what is wrong and where: the chunk
/// (id and byte offset), the model (its index, counting `XYZI` chunks from 0), the voxel or
/// the scene node.
#[derive(Debug)]
#[non_exhaustive]
pub enum VoxError {
    /// The file could not be read.
    Read(std::io::Error),
    /// The file does not start with `VOX `.
    NotVox {
        /// The first (up to) four bytes.
        found: Vec<u8>,
    },
    /// The file ends, or the chunk holding it ends, before a value that was to be read.
    Truncated {
        /// The chunk being read; `None` while reading the file header or a chunk header.
        chunk: Option<ChunkAt>,
        /// Byte offset where the missing bytes should start.
        offset: usize,
        /// Bytes needed there.
        needed: u64,
        /// Bytes available there (to the end of the file or of the enclosing chunk).
        available: usize,
    },
    /// The first chunk is not `MAIN`.
    NoMain {
        /// The chunk found instead.
        found: ChunkAt,
    },
    /// Bytes follow the `MAIN` chunk.
    TrailingBytes {
        /// Offset of the first byte after `MAIN`.
        offset: usize,
        /// How many bytes follow.
        count: usize,
    },
    /// A chunk other than `MAIN` declares children.
    UnexpectedChildren {
        /// The chunk.
        chunk: ChunkAt,
    },
    /// A chunk's content is longer or shorter than its kind allows.
    WrongLength {
        /// The chunk.
        chunk: ChunkAt,
        /// What the chunk should hold, e.g. "12 bytes" or "exactly what its fields use".
        expected: String,
        /// Its content length in bytes.
        found: usize,
    },
    /// A `SIZE` chunk is not followed by an `XYZI` chunk, or an `XYZI` chunk has no `SIZE`
    /// before it.
    UnpairedModelChunk {
        /// The chunk out of place.
        chunk: ChunkAt,
    },
    /// A model's size is 0, negative or larger than 256 on some axis.
    BadModelSize {
        /// Index of the model.
        model: usize,
        /// The size as stored (x, y, z in file axes, z up).
        size: [i32; 3],
        /// The `SIZE` chunk.
        chunk: ChunkAt,
    },
    /// An `XYZI` chunk's voxel count does not match the bytes it holds.
    VoxelCountMismatch {
        /// Index of the model.
        model: usize,
        /// The count stored in the chunk.
        declared: u32,
        /// Bytes of voxels the chunk holds after the count (4 per voxel).
        bytes: usize,
        /// The `XYZI` chunk.
        chunk: ChunkAt,
    },
    /// A voxel lies outside its model's size.
    VoxelOutsideModel {
        /// Index of the model.
        model: usize,
        /// Index of the voxel in the model's list.
        voxel: usize,
        /// The voxel's position (file axes).
        position: [u8; 3],
        /// The model's size.
        size: [u32; 3],
    },
    /// A voxel has colour index 0, which MagicaVoxel reserves for empty space.
    ColourIndexZero {
        /// Index of the model.
        model: usize,
        /// Index of the voxel in the model's list.
        voxel: usize,
        /// The voxel's position (file axes).
        position: [u8; 3],
    },
    /// The file holds no model (no `SIZE`/`XYZI` pair).
    NoModels,
    /// The `PACK` chunk's model count differs from the number of models in the file.
    PackCountMismatch {
        /// The count in `PACK`.
        declared: u32,
        /// Models found.
        found: usize,
        /// The `PACK` chunk.
        chunk: ChunkAt,
    },
    /// A second chunk defines something that must be defined once (a scene node id, a layer
    /// id, a material id, the palette, `PACK`).
    Duplicate {
        /// What is defined twice, e.g. "scene node 3".
        what: String,
        /// The second definition.
        chunk: ChunkAt,
    },
    /// A dictionary holds the same key twice.
    DuplicateKey {
        /// The key.
        key: String,
        /// The chunk holding the dictionary.
        chunk: ChunkAt,
    },
    /// A value is out of its allowed range or does not parse: a rotation, a translation, a
    /// hidden flag, a material property, a material id.
    BadValue {
        /// What holds the value, e.g. "scene node 4 (chunk 'nTRN' at byte 900)".
        owner: String,
        /// The key or field, e.g. `_r`.
        key: String,
        /// The value as stored.
        value: String,
        /// What was expected.
        expected: &'static str,
    },
    /// The scene graph has no node 0, its root.
    MissingRoot,
    /// A scene node refers to a node or model that does not exist.
    BadReference {
        /// The referring node and its chunk.
        node: u32,
        /// Its chunk.
        chunk: ChunkAt,
        /// What it refers to: "child node" or "model".
        what: &'static str,
        /// The missing index.
        index: i64,
    },
    /// A scene node is reached twice (the scene graph must be a tree), which includes cycles.
    NodeReachedTwice {
        /// The node.
        node: u32,
    },
    /// The scene graph nests deeper than [`MAX_SCENE_DEPTH`](super::MAX_SCENE_DEPTH).
    SceneTooDeep,
    /// A voxel's world position leaves the i32 range.
    OutOfWorld {
        /// Index of the model.
        model: usize,
        /// The voxel's position in the model (file axes).
        position: [u8; 3],
    },
    /// The scene holds more voxels than the caller allows.
    TooManyVoxels {
        /// The limit.
        limit: usize,
    },
}

impl VoxError {
    /// The chunk the error is in, when it is about one chunk.
    pub fn chunk(&self) -> Option<ChunkAt> {
        use VoxError as E;
        match self {
            E::Truncated { chunk, .. } => *chunk,
            E::NoMain { found } => Some(*found),
            E::UnexpectedChildren { chunk }
            | E::WrongLength { chunk, .. }
            | E::UnpairedModelChunk { chunk }
            | E::BadModelSize { chunk, .. }
            | E::VoxelCountMismatch { chunk, .. }
            | E::PackCountMismatch { chunk, .. }
            | E::Duplicate { chunk, .. }
            | E::DuplicateKey { chunk, .. }
            | E::BadReference { chunk, .. } => Some(*chunk),
            _ => None,
        }
    }
}

impl fmt::Display for VoxError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use VoxError as E;
        match self {
            E::Read(e) => write!(f, "cannot read the file: {e}"),
            E::NotVox { found } => write!(
                f,
                "not a MagicaVoxel file: it starts with {:?}, not \"VOX \"",
                String::from_utf8_lossy(found)
            ),
            E::Truncated {
                chunk,
                offset,
                needed,
                available,
            } => {
                match chunk {
                    Some(at) => write!(f, "{at} is truncated")?,
                    None => write!(f, "the file is cut short in a header")?,
                }
                write!(
                    f,
                    ": {needed} bytes needed at byte {offset}, only {available} there"
                )
            }
            E::NoMain { found } => write!(f, "the first chunk must be 'MAIN', found {found}"),
            E::TrailingBytes { offset, count } => write!(
                f,
                "{count} bytes follow the 'MAIN' chunk (from byte {offset}); the file should end there"
            ),
            E::UnexpectedChildren { chunk } => {
                write!(f, "{chunk} has children; only 'MAIN' may have them")
            }
            E::WrongLength {
                chunk,
                expected,
                found,
            } => write!(f, "{chunk} holds {found} bytes; it should hold {expected}"),
            E::UnpairedModelChunk { chunk } => write!(
                f,
                "{chunk} is unpaired: every model is a 'SIZE' chunk followed by an 'XYZI' chunk"
            ),
            E::BadModelSize { model, size, chunk } => write!(
                f,
                "model {model} ({chunk}) has size {} x {} x {}; each side must be 1 to 256",
                size[0], size[1], size[2]
            ),
            E::VoxelCountMismatch {
                model,
                declared,
                bytes,
                chunk,
            } => write!(
                f,
                "model {model} ({chunk}) says it holds {declared} voxels ({} bytes), but has {bytes} bytes of voxels",
                4 * u64::from(*declared)
            ),
            E::VoxelOutsideModel {
                model,
                voxel,
                position: [x, y, z],
                size: [sx, sy, sz],
            } => write!(
                f,
                "model {model}: voxel {voxel} at ({x}, {y}, {z}) lies outside the model's size {sx} x {sy} x {sz}"
            ),
            E::ColourIndexZero {
                model,
                voxel,
                position: [x, y, z],
            } => write!(
                f,
                "model {model}: voxel {voxel} at ({x}, {y}, {z}) has colour index 0 (reserved for empty space)"
            ),
            E::NoModels => write!(f, "the file holds no model (no 'SIZE' and 'XYZI' chunks)"),
            E::PackCountMismatch {
                declared,
                found,
                chunk,
            } => write!(
                f,
                "{chunk} says the file holds {declared} models, but it holds {found}"
            ),
            E::Duplicate { what, chunk } => write!(f, "{chunk} defines {what} a second time"),
            E::DuplicateKey { key, chunk } => {
                write!(f, "{chunk} holds a dictionary with the key {key:?} twice")
            }
            E::BadValue {
                owner,
                key,
                value,
                expected,
            } => write!(f, "{owner}: {key} = {value:?} is not {expected}"),
            E::MissingRoot => write!(f, "the scene graph has no node 0 (its root transform node)"),
            E::BadReference {
                node,
                chunk,
                what,
                index,
            } => write!(
                f,
                "scene node {node} ({chunk}) refers to {what} {index}, which does not exist"
            ),
            E::NodeReachedTwice { node } => write!(
                f,
                "scene node {node} is reached twice from the root (a cycle or a shared node; the scene graph must be a tree)"
            ),
            E::SceneTooDeep => write!(
                f,
                "the scene graph nests deeper than {} nodes",
                super::MAX_SCENE_DEPTH
            ),
            E::OutOfWorld {
                model,
                position: [x, y, z],
            } => write!(
                f,
                "model {model}: voxel ({x}, {y}, {z}) lands outside the i32 world after its transforms"
            ),
            E::TooManyVoxels { limit } => {
                write!(f, "the scene holds more than the allowed {limit} voxels")
            }
        }
    }
}

impl std::error::Error for VoxError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            VoxError::Read(e) => Some(e),
            _ => None,
        }
    }
}
