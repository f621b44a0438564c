//! The region file format: the edited chunks of one `8 x 8 x 8`-chunk region, each
//! codec-encoded (`voxel_core::storage::codec`) with its own checksum.
//!
//! ```text
//!  offset  size  field (little-endian)
//!  0       4     magic "VXRG"
//!  4       2     version (REGION_VERSION)
//!  6       1     chunk edge (8, 16, 32 or 62)
//!  7       1     region edge in chunks (REGION_EDGE)
//!  8       12    region coordinate, 3 x i32
//!  20      4     chunk count n
//!  24      4     crc32 of bytes 0..24 and of the table
//!  28      16 n  table: chunk index in the region (u16, x fastest), 0 (u16), offset of its
//!                bytes from the file start (u32), their length (u32), their crc32 (u32)
//!  ...           the chunks' codec bytes
//! ```
//!
//! A file is refused whole ([`RegionFormatError`]) when its header or table cannot be trusted:
//! too short for what it declares (truncated), another magic, a newer version, a header
//! checksum that does not match, or a table naming a chunk twice or out of the region. A chunk
//! whose bytes fail their checksum or the codec is reported ([`ChunkFault`]) and the file's
//! other chunks still load.

use core::fmt;

use voxel_core::storage::{CodecError, PaletteChunk, decode_chunk, encode_chunk};
use voxel_core::{ChunkCoord, ChunkSize};

/// The first four bytes of a region file.
pub const REGION_MAGIC: [u8; 4] = *b"VXRG";
/// The format version this build writes and reads; newer files are refused.
pub const REGION_VERSION: u16 = 1;
/// A region's edge in chunks.
pub const REGION_EDGE: i32 = 8;
/// Bytes before the table.
pub const REGION_HEADER_LEN: usize = 28;
const ENTRY_LEN: usize = 16;

/// Why a region file is refused whole.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RegionFormatError {
    /// The file is shorter than its header, its table or a chunk it lists.
    Truncated {
        /// Bytes the file would need.
        needed: u64,
        /// Bytes it has.
        got: u64,
    },
    /// The file does not start with [`REGION_MAGIC`].
    BadMagic {
        /// Its first bytes.
        found: [u8; 4],
    },
    /// A format version this build cannot read (newer, or 0).
    UnsupportedVersion {
        /// The file's version.
        version: u16,
        /// The version this build reads.
        supported: u16,
    },
    /// The header and table do not match their checksum.
    HeaderChecksum {
        /// The stored checksum.
        stored: u32,
        /// The checksum of the bytes.
        computed: u32,
    },
    /// The chunk edge or region edge is not one this world uses.
    WrongShape {
        /// The file's chunk edge.
        chunk_edge: u8,
        /// The file's region edge.
        region_edge: u8,
    },
    /// The region coordinate differs from the one its name gives.
    WrongRegion {
        /// The coordinate in the file.
        found: [i32; 3],
        /// The coordinate expected.
        expected: [i32; 3],
    },
    /// The table lists a chunk index twice or past the region.
    BadTable {
        /// The entry.
        entry: u32,
        /// The chunk index it gives.
        index: u16,
    },
}

impl fmt::Display for RegionFormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RegionFormatError::Truncated { needed, got } => {
                write!(f, "truncated: needs {needed} bytes, has {got}")
            }
            RegionFormatError::BadMagic { found } => {
                write!(
                    f,
                    "not a region file: magic {found:?}, expected {REGION_MAGIC:?}"
                )
            }
            RegionFormatError::UnsupportedVersion { version, supported } => write!(
                f,
                "region format version {version}, this build reads version {supported}"
            ),
            RegionFormatError::HeaderChecksum { stored, computed } => write!(
                f,
                "header checksum {stored:#010x} does not match its bytes ({computed:#010x})"
            ),
            RegionFormatError::WrongShape {
                chunk_edge,
                region_edge,
            } => write!(
                f,
                "chunks of edge {chunk_edge} in regions of {region_edge}, not this world's"
            ),
            RegionFormatError::WrongRegion { found, expected } => {
                write!(f, "holds region {found:?}, its name says {expected:?}")
            }
            RegionFormatError::BadTable { entry, index } => {
                write!(
                    f,
                    "table entry {entry} names chunk index {index} twice or past the region"
                )
            }
        }
    }
}

impl std::error::Error for RegionFormatError {}

/// Why one chunk of a region file does not load.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ChunkFaultKind {
    /// Its bytes do not match their checksum.
    Checksum {
        /// The stored checksum.
        stored: u32,
        /// The checksum of the bytes.
        computed: u32,
    },
    /// Its bytes match their checksum but the codec refuses them.
    Codec(CodecError),
    /// It decodes to a chunk of another size.
    WrongSize(ChunkSize),
}

/// One chunk of a region that does not load; the others do.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ChunkFault {
    /// The chunk.
    pub coord: ChunkCoord,
    /// Why.
    pub kind: ChunkFaultKind,
}

impl fmt::Display for ChunkFault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let c = self.coord;
        match &self.kind {
            ChunkFaultKind::Checksum { stored, computed } => write!(
                f,
                "chunk ({}, {}, {}): checksum {stored:#010x} does not match its bytes ({computed:#010x})",
                c.x, c.y, c.z
            ),
            ChunkFaultKind::Codec(e) => write!(f, "chunk ({}, {}, {}): {e}", c.x, c.y, c.z),
            ChunkFaultKind::WrongSize(s) => {
                write!(f, "chunk ({}, {}, {}): decodes to {s:?}", c.x, c.y, c.z)
            }
        }
    }
}

/// A decoded region file.
#[derive(Clone, Debug, Default)]
pub struct Region {
    /// The chunks that loaded, in table order.
    pub chunks: Vec<(ChunkCoord, PaletteChunk)>,
    /// The chunks that did not.
    pub faults: Vec<ChunkFault>,
}

/// The region holding chunk `c`, by Euclidean division.
pub fn region_of(c: ChunkCoord) -> [i32; 3] {
    [c.x, c.y, c.z].map(|v| v.div_euclid(REGION_EDGE))
}

fn chunk_at(region: [i32; 3], index: u16) -> Option<ChunkCoord> {
    let i = i32::from(index);
    let local = [
        i % REGION_EDGE,
        i / REGION_EDGE % REGION_EDGE,
        i / (REGION_EDGE * REGION_EDGE),
    ];
    let c: Vec<i32> = region
        .iter()
        .zip(local)
        .map(|(&r, l)| r.checked_mul(REGION_EDGE).and_then(|b| b.checked_add(l)))
        .collect::<Option<Vec<_>>>()?;
    Some(ChunkCoord::new(c[0], c[1], c[2]))
}

fn index_in_region(c: ChunkCoord) -> u16 {
    let l = [c.x, c.y, c.z].map(|v| v.rem_euclid(REGION_EDGE));
    (l[0] + REGION_EDGE * (l[1] + REGION_EDGE * l[2])) as u16
}

/// Encodes the chunks of region `region` (all of them inside it, each once) as a region file.
pub fn encode_region(
    region: [i32; 3],
    size: ChunkSize,
    chunks: &[(ChunkCoord, &PaletteChunk)],
) -> Vec<u8> {
    let mut payload = Vec::new();
    let mut table = Vec::with_capacity(chunks.len() * ENTRY_LEN);
    let start = REGION_HEADER_LEN + chunks.len() * ENTRY_LEN;
    for (coord, chunk) in chunks {
        let offset = start + payload.len();
        let before = payload.len();
        encode_chunk(chunk, &mut payload);
        let bytes = &payload[before..];
        table.extend_from_slice(&index_in_region(*coord).to_le_bytes());
        table.extend_from_slice(&0u16.to_le_bytes());
        table.extend_from_slice(&(offset as u32).to_le_bytes());
        table.extend_from_slice(&(bytes.len() as u32).to_le_bytes());
        table.extend_from_slice(&crc32fast::hash(bytes).to_le_bytes());
    }
    let mut out = Vec::with_capacity(start + payload.len());
    out.extend_from_slice(&REGION_MAGIC);
    out.extend_from_slice(&REGION_VERSION.to_le_bytes());
    out.push(size.edge() as u8);
    out.push(REGION_EDGE as u8);
    for v in region {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out.extend_from_slice(&(chunks.len() as u32).to_le_bytes());
    let mut crc = crc32fast::Hasher::new();
    crc.update(&out);
    crc.update(&table);
    out.extend_from_slice(&crc.finalize().to_le_bytes());
    out.extend_from_slice(&table);
    out.extend_from_slice(&payload);
    out
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

/// Decodes a region file that should hold region `expected` of chunks of `size`. Never
/// panics, whatever the bytes.
pub fn decode_region(
    bytes: &[u8],
    expected: [i32; 3],
    size: ChunkSize,
) -> Result<Region, RegionFormatError> {
    let got = bytes.len() as u64;
    if bytes.len() < REGION_HEADER_LEN {
        return Err(RegionFormatError::Truncated {
            needed: REGION_HEADER_LEN as u64,
            got,
        });
    }
    let magic = [bytes[0], bytes[1], bytes[2], bytes[3]];
    if magic != REGION_MAGIC {
        return Err(RegionFormatError::BadMagic { found: magic });
    }
    let version = u16::from_le_bytes([bytes[4], bytes[5]]);
    if version != REGION_VERSION {
        return Err(RegionFormatError::UnsupportedVersion {
            version,
            supported: REGION_VERSION,
        });
    }
    let count = u32_at(bytes, 20) as u64;
    let table_end = REGION_HEADER_LEN as u64 + count * ENTRY_LEN as u64;
    if table_end > got {
        return Err(RegionFormatError::Truncated {
            needed: table_end,
            got,
        });
    }
    let table = &bytes[REGION_HEADER_LEN..table_end as usize];
    let stored = u32_at(bytes, 24);
    let mut crc = crc32fast::Hasher::new();
    crc.update(&bytes[..24]);
    crc.update(table);
    let computed = crc.finalize();
    if stored != computed {
        return Err(RegionFormatError::HeaderChecksum { stored, computed });
    }
    let (chunk_edge, region_edge) = (bytes[6], bytes[7]);
    if u32::from(chunk_edge) != size.edge() || i32::from(region_edge) != REGION_EDGE {
        return Err(RegionFormatError::WrongShape {
            chunk_edge,
            region_edge,
        });
    }
    let found = [8, 12, 16].map(|at| u32_at(bytes, at) as i32);
    if found != expected {
        return Err(RegionFormatError::WrongRegion { found, expected });
    }
    let mut seen = [false; (REGION_EDGE * REGION_EDGE * REGION_EDGE) as usize];
    let mut region = Region::default();
    for (entry, e) in table.chunks_exact(ENTRY_LEN).enumerate() {
        let index = u16::from_le_bytes([e[0], e[1]]);
        let bad = || RegionFormatError::BadTable {
            entry: entry as u32,
            index,
        };
        let slot = seen.get_mut(usize::from(index)).ok_or_else(bad)?;
        if *slot || e[2] != 0 || e[3] != 0 {
            return Err(bad());
        }
        *slot = true;
        let coord = chunk_at(expected, index).ok_or_else(bad)?;
        let (offset, len, stored) = (u32_at(e, 4) as u64, u32_at(e, 8) as u64, u32_at(e, 12));
        let end = offset + len;
        if end > got {
            return Err(RegionFormatError::Truncated { needed: end, got });
        }
        let chunk_bytes = &bytes[offset as usize..end as usize];
        let computed = crc32fast::hash(chunk_bytes);
        let kind = if computed != stored {
            ChunkFaultKind::Checksum { stored, computed }
        } else {
            match decode_chunk(chunk_bytes) {
                Ok(chunk) if voxel_core::storage::VoxelStorage::size(&chunk) == size => {
                    region.chunks.push((coord, chunk));
                    continue;
                }
                Ok(chunk) => {
                    ChunkFaultKind::WrongSize(voxel_core::storage::VoxelStorage::size(&chunk))
                }
                Err(e) => ChunkFaultKind::Codec(e),
            }
        };
        region.faults.push(ChunkFault { coord, kind });
    }
    Ok(region)
}
