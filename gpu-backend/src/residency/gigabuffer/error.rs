//! Gigabuffer errors.

use std::fmt;

use render_model::pages::PageLayoutError;
use voxel_core::formats::DataKind;

use super::ChunkHandle;
use crate::device::alloc::AllocError;

/// Why a gigabuffer operation failed.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum GigabufferError {
    /// The configuration does not fit 32-bit offsets or the device's pages.
    Config(PageLayoutError),
    /// No free region of a kind can hold the layer (every page is full or fragmented).
    OutOfMemory {
        /// The kind.
        kind: DataKind,
        /// Elements asked for.
        requested: u64,
        /// Free elements over all pages, created or not.
        free_elements: u64,
        /// Largest free region in the created pages, elements.
        largest_free_region: u32,
    },
    /// A layer larger than one page (allocations never straddle pages).
    LayerTooLarge {
        /// The kind.
        kind: DataKind,
        /// Elements asked for.
        requested: u64,
        /// Elements per page.
        page_capacity: u32,
    },
    /// Data for a kind configured with 0 bytes.
    KindDisabled {
        /// The kind.
        kind: DataKind,
        /// Elements asked for.
        requested: u64,
    },
    /// The resident chunk limit is reached.
    TooManyChunks {
        /// The limit ([`GigabufferConfig::max_chunks`](super::GigabufferConfig::max_chunks)).
        max_chunks: u32,
    },
    /// The device refused to create a page.
    PageCreation {
        /// The kind.
        kind: DataKind,
        /// Page index.
        page: u32,
        /// Page size, bytes.
        bytes: u64,
        /// wgpu's error.
        message: String,
    },
    /// The handle's chunk was freed already (or it belongs to another gigabuffer).
    StaleHandle(ChunkHandle),
    /// The device refused the staging buffer of a flush (the frame's uploads stay queued).
    Staging(AllocError),
    /// A smooth quad names a vertex past the chunk's smooth vertices.
    SmoothIndexOutOfRange {
        /// Quad index.
        quad: usize,
        /// The offending vertex index.
        index: u32,
        /// Vertices in the chunk.
        vertices: usize,
    },
    /// A compact smooth quad record does not decode (a delta of 0 or past its base index).
    BadCompactQuad {
        /// Quad index.
        quad: usize,
    },
}

impl fmt::Display for GigabufferError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GigabufferError::Config(e) => write!(f, "gigabuffer configuration: {e}"),
            GigabufferError::OutOfMemory {
                kind,
                requested,
                free_elements,
                largest_free_region,
            } => write!(
                f,
                "gigabuffer out of memory: {requested} {kind} elements requested, {free_elements} \
                 free in all, largest free region {largest_free_region}"
            ),
            GigabufferError::LayerTooLarge {
                kind,
                requested,
                page_capacity,
            } => write!(
                f,
                "{requested} {kind} elements do not fit one page of {page_capacity}"
            ),
            GigabufferError::KindDisabled { kind, requested } => write!(
                f,
                "{requested} {kind} elements uploaded, but the {kind} gigabuffer is configured \
                 with 0 bytes"
            ),
            GigabufferError::TooManyChunks { max_chunks } => {
                write!(
                    f,
                    "the gigabuffer already holds its limit of {max_chunks} chunks"
                )
            }
            GigabufferError::PageCreation {
                kind,
                page,
                bytes,
                message,
            } => write!(
                f,
                "the device refused {kind} page {page} ({bytes} bytes): {message}"
            ),
            GigabufferError::StaleHandle(h) => {
                write!(f, "chunk handle {h:?} is stale (freed already)")
            }
            GigabufferError::Staging(e) => write!(f, "gigabuffer uploads: {e}"),
            GigabufferError::SmoothIndexOutOfRange {
                quad,
                index,
                vertices,
            } => write!(
                f,
                "smooth quad {quad} names vertex {index}, but the chunk has {vertices} vertices"
            ),
            GigabufferError::BadCompactQuad { quad } => {
                write!(f, "compact smooth quad {quad} does not decode")
            }
        }
    }
}

impl std::error::Error for GigabufferError {}

impl From<PageLayoutError> for GigabufferError {
    fn from(e: PageLayoutError) -> Self {
        GigabufferError::Config(e)
    }
}
