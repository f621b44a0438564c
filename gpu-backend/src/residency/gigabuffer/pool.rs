//! One kind's pages: a wgpu buffer and an `offset-allocator` per page, created on demand.

use offset_allocator::{Allocation, Allocator};
use wgpu::{Buffer, BufferDescriptor, BufferUsages, Device};

use render_model::pages::PageLayout;

use super::GigabufferError;
use crate::device::alloc;

/// One page: a storage buffer bound whole, and the allocator of its elements.
#[derive(Debug)]
struct Page {
    buffer: Buffer,
    allocator: Allocator,
}

/// An allocation in a pool: `count` elements at `offset` of page `page`.
#[derive(Clone, Copy)]
pub(crate) struct PoolAllocation {
    pub page: u32,
    pub offset: u32,
    pub count: u32,
    inner: Allocation,
}

impl std::fmt::Debug for PoolAllocation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PoolAllocation")
            .field("page", &self.page)
            .field("offset", &self.offset)
            .field("count", &self.count)
            .finish()
    }
}

/// The pages of one kind. Pages are created when the existing ones cannot satisfy an
/// allocation, up to the layout's page count, so memory grows with use up to the configured
/// size.
#[derive(Debug)]
pub(crate) struct Pool {
    pub layout: PageLayout,
    pages: Vec<Page>,
    max_allocs: u32,
    used_elements: u64,
    allocations: u64,
}

/// The buffer usages of every page: bound as storage, written by copies, read back by tests
/// and future compaction.
pub(crate) const PAGE_USAGES: BufferUsages = BufferUsages::STORAGE
    .union(BufferUsages::COPY_DST)
    .union(BufferUsages::COPY_SRC);

#[cfg(feature = "test-support")]
impl Drop for Pool {
    fn drop(&mut self) {
        // What the pool still holds leaves with it.
        crate::test_support::count_node_bytes(
            self.used_elements * u64::from(self.layout.kind.element_size()),
            false,
        );
    }
}

impl Pool {
    /// A pool without pages; `max_allocs` bounds the allocator nodes of each page.
    pub(super) fn new(layout: PageLayout, max_allocs: u32) -> Pool {
        Pool {
            layout,
            pages: Vec::new(),
            max_allocs,
            used_elements: 0,
            allocations: 0,
        }
    }

    /// `count` (>= 1) contiguous elements in one page. Tries the existing pages in order, then
    /// creates the next page. Returns whether a page was created.
    pub(super) fn allocate(
        &mut self,
        device: &Device,
        count: u32,
    ) -> Result<(PoolAllocation, bool), GigabufferError> {
        let kind = self.layout.kind;
        if self.layout.page_count == 0 {
            return Err(GigabufferError::KindDisabled {
                kind,
                requested: count.into(),
            });
        }
        if count > self.layout.page_capacity {
            return Err(GigabufferError::LayerTooLarge {
                kind,
                requested: count.into(),
                page_capacity: self.layout.page_capacity,
            });
        }
        #[cfg(feature = "test-support")]
        {
            let bytes = u64::from(count) * u64::from(kind.element_size());
            if let Some(limit) = crate::test_support::node_bytes_refused(bytes) {
                return Err(GigabufferError::PageCreation {
                    kind,
                    page: self.pages.len() as u32,
                    bytes,
                    message: format!(
                        "injected for a test: the node data of this process would pass \
                         {limit} bytes"
                    ),
                });
            }
        }
        for (page, p) in self.pages.iter_mut().enumerate() {
            if let Some(inner) = p.allocator.allocate(count) {
                return Ok((self.record(page as u32, count, inner), false));
            }
        }
        let next = self.pages.len() as u32;
        if next < self.layout.page_count && count <= self.layout.capacity_of(next) {
            self.create_page(device, next)?;
            if let Some(inner) = self.pages[next as usize].allocator.allocate(count) {
                return Ok((self.record(next, count, inner), true));
            }
        }
        Err(self.out_of_memory(count))
    }

    fn record(&mut self, page: u32, count: u32, inner: Allocation) -> PoolAllocation {
        #[cfg(feature = "test-support")]
        crate::test_support::count_node_bytes(
            u64::from(count) * u64::from(self.layout.kind.element_size()),
            true,
        );
        self.used_elements += u64::from(count);
        self.allocations += 1;
        PoolAllocation {
            page,
            offset: inner.offset,
            count,
            inner,
        }
    }

    fn out_of_memory(&self, requested: u32) -> GigabufferError {
        let (mut free, mut largest) = (0u64, 0u32);
        for p in &self.pages {
            let report = p.allocator.storage_report();
            free += u64::from(report.total_free_space);
            largest = largest.max(report.largest_free_region);
        }
        let uncreated: u64 = (self.pages.len() as u32..self.layout.page_count)
            .map(|p| u64::from(self.layout.capacity_of(p)))
            .sum();
        GigabufferError::OutOfMemory {
            kind: self.layout.kind,
            requested: requested.into(),
            free_elements: free + uncreated,
            largest_free_region: largest,
        }
    }

    fn create_page(&mut self, device: &Device, page: u32) -> Result<(), GigabufferError> {
        let kind = self.layout.kind;
        let capacity = self.layout.capacity_of(page);
        let bytes = self.layout.page_bytes(page);
        let label = format!("gigabuffer {kind} page {page}");
        let refused = |message: String| GigabufferError::PageCreation {
            kind,
            page,
            bytes,
            message,
        };
        let buffer = alloc::create_buffer(
            device,
            &BufferDescriptor {
                label: Some(&label),
                size: bytes,
                usage: PAGE_USAGES,
                mapped_at_creation: false,
            },
        )
        .map_err(|e| refused(e.message))?;
        // Nodes are bounded by free regions + allocations <= 2 * capacity + 1.
        let max_allocs = self
            .max_allocs
            .min(capacity.saturating_mul(2).saturating_add(2))
            .max(2);
        self.pages.push(Page {
            buffer,
            allocator: Allocator::with_max_allocs(capacity, max_allocs),
        });
        Ok(())
    }

    /// Returns an allocation to its page.
    pub(super) fn free(&mut self, allocation: PoolAllocation) {
        #[cfg(feature = "test-support")]
        crate::test_support::count_node_bytes(
            u64::from(allocation.count) * u64::from(self.layout.kind.element_size()),
            false,
        );
        self.used_elements -= u64::from(allocation.count);
        self.allocations -= 1;
        self.pages[allocation.page as usize]
            .allocator
            .free(allocation.inner);
    }

    /// The buffer of page `page`, if created.
    pub(super) fn page(&self, page: u32) -> Option<&Buffer> {
        self.pages.get(page as usize).map(|p| &p.buffer)
    }

    /// Pages created so far.
    pub(super) fn pages_created(&self) -> u32 {
        self.pages.len() as u32
    }

    /// Elements in live allocations.
    pub(super) fn used_elements(&self) -> u64 {
        self.used_elements
    }

    /// Live allocations.
    pub(super) fn allocations(&self) -> u64 {
        self.allocations
    }

    /// Bytes of the pages created so far.
    pub(super) fn reserved_bytes(&self) -> u64 {
        (0..self.pages_created())
            .map(|p| self.layout.page_bytes(p))
            .sum()
    }
}
