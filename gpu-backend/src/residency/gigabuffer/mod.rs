//! The gigabuffer: one large storage buffer per kind of chunk data, sub-allocated per chunk.
//!
//! ```text
//!  upload(layers) ──► per kind: offset-allocator ──► (page, offset) ──► ChunkRanges (global offsets)
//!        │                                                  │
//!        └──► bytes into the frame's staging arena ─────────┴──► flush(encoder): one staging
//!                                                                buffer, one copy per run
//! ```
//!
//! In Project Ascendant's spirit: a chunk's packed layers go in with [`Gigabuffer::upload`],
//! which returns a [`ChunkHandle`] and the [`ChunkRanges`] the chunk tables point at;
//! [`Gigabuffer::free`] gives the space back; [`Gigabuffer::is_valid`] tells a live handle from
//! a stale one (handles carry a generation, so a freed handle never names a later chunk).
//! There are no in-place updates: to replace a chunk's mesh, upload the new one, point the
//! chunk table at it, and free the old handle, all in the same frame.
//!
//! **Kinds and pages.** Each [`DataKind`] has its own set of pages sized from
//! [`GigabufferConfig`] and the device's binding limit (see [`PageLayout`]); a kind configured
//! with 0 bytes is not created. Pages are created when the existing ones cannot hold an
//! allocation, so memory grows with the resident surface up to the configured size;
//! [`Gigabuffer::page_epoch`] changes whenever a page appears, so bind groups can be rebuilt.
//!
//! **Allocation.** `offset-allocator` (Sebastian Aaltonen's O(1) TLSF-like allocator) in units
//! of elements, 32-bit offsets. One allocation per kind per chunk (a chunk's opaque and
//! transparent quads share one). Its size classes are floating-point bins (3-bit mantissa), so
//! a free region is found for a request only if it is at least the request rounded up to its
//! bin: up to 12.5% of a large free region may be unusable for one request.
//!
//! **Errors, never panics.** Out of space, a layer larger than a page, a disabled kind, too
//! many chunks, a page the device refuses to create, a stale handle, and smooth-quad indices
//! past the chunk's vertices are all [`GigabufferError`]s. A failed upload allocates nothing.
//!
//! **Ordering.** Uploads are copied into a CPU arena at once (the caller's slices need not
//! outlive the call) and reach the GPU at [`Gigabuffer::flush`], which records the copies into
//! the caller's encoder (see `staging` for why). Freed space may be handed out again in the same
//! frame; copies run in upload order and the queue orders them after earlier frames' draws.

mod config;
mod error;
mod handles;
mod pool;
mod report;
mod staging;

use wgpu::{Buffer, CommandEncoder, Device};

use render_model::pages::{PageLayout, PageLayoutError};
use render_model::resident::ChunkRanges;
use voxel_core::formats::{ChunkLayersData, DataKind, FaceLayerRange, LayerRange};

use crate::device::GpuCapabilities;
pub use config::GigabufferConfig;
pub use error::GigabufferError;
use handles::{Handle, HandleTable};
use pool::{Pool, PoolAllocation};
pub use report::{KindUsage, ResidentReport};
pub use staging::FlushStats;
use staging::StagingQueue;

/// Names one uploaded chunk; generation-checked (see [`Gigabuffer::is_valid`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ChunkHandle(Handle);

impl ChunkHandle {
    /// Dense slot index, reused (with a new generation) after a free: usable as an index into
    /// per-chunk side tables.
    pub fn slot(self) -> u32 {
        self.0.index()
    }

    /// The slot's generation when the handle was issued.
    pub fn generation(self) -> u32 {
        self.0.generation()
    }
}

/// The result of an upload.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UploadedChunk {
    /// The chunk's handle.
    pub handle: ChunkHandle,
    /// Where its layers are.
    pub ranges: ChunkRanges,
}

/// What the gigabuffer remembers about a live chunk.
#[derive(Debug)]
struct ChunkEntry {
    allocations: [Option<PoolAllocation>; DataKind::COUNT],
    ranges: ChunkRanges,
}

/// The gigabuffer (see the [module docs](self)).
#[derive(Debug)]
pub struct Gigabuffer {
    device: Device,
    pools: Vec<Pool>,
    chunks: HandleTable<ChunkEntry>,
    staging: StagingQueue,
    max_chunks: u32,
    page_epoch: u64,
}

impl Gigabuffer {
    /// An empty gigabuffer on `device`, paged for `capabilities`' binding limit. No GPU memory
    /// is taken until the first upload of each kind.
    pub fn new(
        device: &Device,
        capabilities: &GpuCapabilities,
        config: &GigabufferConfig,
    ) -> Result<Gigabuffer, GigabufferError> {
        let device_max = capabilities.max_page_bytes();
        let max_page = config
            .max_page_bytes
            .map_or(device_max, |m| m.min(device_max));
        // Two allocator nodes per chunk (its allocation and a free neighbour), plus slack;
        // offset-allocator needs fewer than u32::MAX - 1.
        let max_allocs = config
            .max_chunks
            .saturating_mul(2)
            .saturating_add(16)
            .min(u32::MAX - 2);
        let pools = DataKind::ALL
            .iter()
            .map(|&kind| {
                let layout = PageLayout::plan(kind, *config.bytes.get(kind), max_page)?;
                Ok(Pool::new(layout, max_allocs))
            })
            .collect::<Result<Vec<_>, PageLayoutError>>()?;
        Ok(Gigabuffer {
            device: device.clone(),
            pools,
            chunks: HandleTable::default(),
            staging: StagingQueue::default(),
            max_chunks: config.max_chunks,
            page_epoch: 0,
        })
    }

    /// Allocates room for every layer of `layers`, queues their bytes for the next
    /// [`flush`](Self::flush), and returns the chunk's handle and ranges. On error nothing
    /// stays allocated.
    pub fn upload(
        &mut self,
        layers: &ChunkLayersData<'_>,
    ) -> Result<UploadedChunk, GigabufferError> {
        if self.chunks.len() >= self.max_chunks as usize {
            return Err(GigabufferError::TooManyChunks {
                max_chunks: self.max_chunks,
            });
        }
        check_smooth_indices(layers)?;
        let counts = layers.element_counts();
        let mut allocations: [Option<PoolAllocation>; DataKind::COUNT] = [None; DataKind::COUNT];
        for (kind, &count) in counts.iter() {
            if count == 0 {
                continue;
            }
            match self.allocate(kind, count) {
                Ok(a) => allocations[kind.index()] = Some(a),
                Err(e) => {
                    for (i, a) in allocations.iter_mut().enumerate() {
                        if let Some(a) = a.take() {
                            self.pools[i].free(a);
                        }
                    }
                    return Err(e);
                }
            }
        }
        let ranges = self.ranges_of(layers, &allocations);
        self.queue_bytes(layers, &allocations);
        let handle = self
            .chunks
            .insert(ChunkEntry {
                allocations,
                ranges,
            })
            .map(ChunkHandle)
            // Unreachable: max_chunks <= u32::MAX bounds the slots; kept as an error anyway.
            .ok_or(GigabufferError::TooManyChunks {
                max_chunks: self.max_chunks,
            })?;
        Ok(UploadedChunk { handle, ranges })
    }

    fn allocate(&mut self, kind: DataKind, count: u64) -> Result<PoolAllocation, GigabufferError> {
        let pool = &mut self.pools[kind.index()];
        let Ok(count32) = u32::try_from(count) else {
            return Err(GigabufferError::LayerTooLarge {
                kind,
                requested: count,
                page_capacity: pool.layout.page_capacity,
            });
        };
        let (allocation, new_page) = pool.allocate(&self.device, count32)?;
        if new_page {
            self.page_epoch += 1;
        }
        Ok(allocation)
    }

    fn global(&self, kind: DataKind, a: &Option<PoolAllocation>) -> LayerRange {
        a.map_or(LayerRange::default(), |a| LayerRange {
            offset: self.pools[kind.index()]
                .layout
                .global_offset(a.page, a.offset),
            count: a.count,
        })
    }

    fn ranges_of(
        &self,
        layers: &ChunkLayersData<'_>,
        allocations: &[Option<PoolAllocation>; DataKind::COUNT],
    ) -> ChunkRanges {
        let quads = self.global(DataKind::Quads, &allocations[DataKind::Quads.index()]);
        let opaque_skirts = layers.opaque_skirts.map(|f| f.len() as u32);
        let mut opaque_counts = layers.opaque_quads.map(|f| f.len() as u32);
        for (count, skirt) in opaque_counts.iter_mut().zip(opaque_skirts) {
            // Both are parts of one allocation, whose size fits u32.
            *count += skirt;
        }
        let opaque_total: u32 = opaque_counts.iter().sum();
        let blocks = self.global(
            DataKind::DrawBlocks,
            &allocations[DataKind::DrawBlocks.index()],
        );
        let block_count = layers.draw_blocks.len() as u32;
        let draw_block_skirts = layers.draw_block_skirts.map(|s| s.len() as u32);
        let skirt_total: u32 = draw_block_skirts.iter().sum();
        ChunkRanges {
            opaque_quads: FaceLayerRange {
                offset: quads.offset,
                counts: opaque_counts,
            },
            opaque_skirts,
            transparent_quads: FaceLayerRange {
                // Within one allocation, so this cannot overflow.
                offset: quads.offset + opaque_total,
                counts: layers.transparent_quads.map(|f| f.len() as u32),
            },
            smooth_vertices: self.global(
                DataKind::SmoothVertices,
                &allocations[DataKind::SmoothVertices.index()],
            ),
            smooth_quads: self.global(
                DataKind::SmoothQuads,
                &allocations[DataKind::SmoothQuads.index()],
            ),
            // At most the word count, which the allocation checked against u32.
            smooth_quad_count: layers.smooth_quads.len() as u32,
            smooth_quad_form: layers.smooth_quads.form(),
            clutter_units: self.global(DataKind::Clutter, &allocations[DataKind::Clutter.index()]),
            draw_blocks: LayerRange {
                offset: blocks.offset,
                count: block_count,
            },
            draw_block_skirts,
            hiding_mask: LayerRange {
                offset: blocks.offset + block_count + skirt_total,
                count: layers.hiding_mask.len() as u32,
            },
            transparent_mask: LayerRange {
                offset: blocks.offset + block_count + skirt_total + layers.hiding_mask.len() as u32,
                count: layers.transparent_mask.len() as u32,
            },
            shell_runs: self.global(DataKind::Shells, &allocations[DataKind::Shells.index()]),
        }
    }

    fn queue_bytes(
        &mut self,
        layers: &ChunkLayersData<'_>,
        allocations: &[Option<PoolAllocation>; DataKind::COUNT],
    ) {
        let mut push = |kind: DataKind, parts: &[&[u8]]| {
            let Some(a) = allocations[kind.index()] else {
                return;
            };
            let mut dst = u64::from(a.offset) * u64::from(kind.element_size());
            for part in parts {
                self.staging.push(kind, a.page, dst, part);
                dst += part.len() as u64;
            }
        };
        // Each opaque face group, then that side's skirt; then the transparent groups.
        let quads: Vec<&[u8]> = layers
            .opaque_quads
            .iter()
            .zip(&layers.opaque_skirts)
            .flat_map(|(face, skirt)| [face, skirt])
            .chain(&layers.transparent_quads)
            .map(|f| bytemuck::cast_slice(f))
            .collect();
        push(DataKind::Quads, &quads);
        push(
            DataKind::SmoothVertices,
            &[bytemuck::cast_slice(layers.smooth_vertices)],
        );
        // The mesher's bytes, zero-padded to whole words (compact records are 6 bytes).
        let smooth_quads = layers.smooth_quads.bytes();
        let pad = [0u8; 4];
        push(
            DataKind::SmoothQuads,
            &[
                smooth_quads,
                &pad[..smooth_quads.len().next_multiple_of(4) - smooth_quads.len()],
            ],
        );
        push(
            DataKind::Clutter,
            &[bytemuck::cast_slice(layers.clutter_units)],
        );
        let blocks: Vec<&[u8]> = std::iter::once(bytemuck::cast_slice(layers.draw_blocks))
            .chain(
                layers
                    .draw_block_skirts
                    .iter()
                    .map(|s| bytemuck::cast_slice(s)),
            )
            .chain(std::iter::once(bytemuck::cast_slice(layers.hiding_mask)))
            .chain(std::iter::once(bytemuck::cast_slice(
                layers.transparent_mask,
            )))
            .collect();
        push(DataKind::DrawBlocks, &blocks);
        push(DataKind::Shells, &[bytemuck::cast_slice(layers.shell_runs)]);
    }

    /// Frees a chunk's space. A stale handle is an error and frees nothing.
    pub fn free(&mut self, handle: ChunkHandle) -> Result<(), GigabufferError> {
        let entry = self
            .chunks
            .remove(handle.0)
            .ok_or(GigabufferError::StaleHandle(handle))?;
        for (i, a) in entry.allocations.into_iter().enumerate() {
            if let Some(a) = a {
                self.pools[i].free(a);
            }
        }
        Ok(())
    }

    /// True while `handle`'s chunk is resident (uploaded and not freed).
    pub fn is_valid(&self, handle: ChunkHandle) -> bool {
        self.chunks.contains(handle.0)
    }

    /// The ranges of a live chunk.
    pub fn ranges(&self, handle: ChunkHandle) -> Option<&ChunkRanges> {
        self.chunks.get(handle.0).map(|e| &e.ranges)
    }

    /// Records the frame's pending uploads into `encoder` (one staging buffer, one copy per
    /// contiguous run). Call once per frame before the passes that read the gigabuffer, in
    /// the same encoder.
    pub fn flush(&mut self, encoder: &mut CommandEncoder) -> Result<FlushStats, GigabufferError> {
        let pools = &self.pools;
        self.staging
            .record(&self.device, encoder, |kind, page| {
                pools[kind.index()]
                    .page(page)
                    .expect("copies are only queued into created pages")
            })
            .map_err(GigabufferError::Staging)
    }

    /// Bytes waiting for the next flush.
    pub fn pending_bytes(&self) -> u64 {
        self.staging.pending_bytes()
    }

    /// Live chunks.
    pub fn chunk_count(&self) -> usize {
        self.chunks.len()
    }

    /// The page split of `kind`.
    pub fn layout(&self, kind: DataKind) -> &PageLayout {
        &self.pools[kind.index()].layout
    }

    /// Page `page` of `kind`, once created.
    pub fn page(&self, kind: DataKind, page: u32) -> Option<&Buffer> {
        self.pools[kind.index()].page(page)
    }

    /// The created pages of `kind`, in page order.
    pub fn pages(&self, kind: DataKind) -> impl Iterator<Item = &Buffer> {
        let pool = &self.pools[kind.index()];
        (0..pool.pages_created()).filter_map(|p| pool.page(p))
    }

    /// Changes whenever a page is created (rebuild bind groups that list pages).
    pub fn page_epoch(&self) -> u64 {
        self.page_epoch
    }

    /// Memory use per kind.
    pub fn resident(&self) -> ResidentReport {
        let mut report = ResidentReport {
            chunks: self.chunks.len() as u64,
            ..Default::default()
        };
        for (pool, kind) in self.pools.iter().zip(DataKind::ALL) {
            let size = u64::from(kind.element_size());
            *report.kinds.get_mut(kind) = KindUsage {
                used_bytes: pool.used_elements() * size,
                reserved_bytes: pool.reserved_bytes(),
                capacity_bytes: pool.layout.total_elements() * size,
                allocations: pool.allocations(),
                pages: pool.pages_created(),
            };
        }
        report
    }
}

fn check_smooth_indices(layers: &ChunkLayersData<'_>) -> Result<(), GigabufferError> {
    let vertices = layers.smooth_vertices.len();
    let quads = layers.smooth_quads;
    for quad in 0..quads.len() {
        let Some(indices) = quads.get(quad) else {
            return Err(GigabufferError::BadCompactQuad { quad });
        };
        if let Some(&index) = indices.iter().find(|&&i| i as usize >= vertices) {
            return Err(GigabufferError::SmoothIndexOutOfRange {
                quad,
                index,
                vertices,
            });
        }
    }
    Ok(())
}
