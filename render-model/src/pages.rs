//! How one kind's configured size is split into pages (pure arithmetic, no GPU).
//!
//! A page is one wgpu buffer that can be bound whole as a storage buffer, so its size is at
//! most the device's `max_storage_buffer_binding_size` (and `max_buffer_size`): 128 MiB on
//! lavapipe, 2 GiB or more on NVIDIA. Every page but the last holds `page_capacity` elements;
//! the last holds the rest. Allocations never straddle pages, so one binding reaches a whole
//! allocation.
//!
//! **Global element offsets.** A range's offset, as stored in `MeshedChunkInfo` and returned by
//! uploads, is `page * page_capacity + offset_in_page` (a `u32`): the shader finds the page as
//! `offset / page_capacity` and the element in it as `offset % page_capacity`. The total
//! element count of a kind is therefore at most `u32::MAX`.

use std::fmt;

use voxel_core::formats::DataKind;

/// The page split of one kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PageLayout {
    /// The kind.
    pub kind: DataKind,
    /// Elements per full page.
    pub page_capacity: u32,
    /// Number of pages (0 when the kind is disabled).
    pub page_count: u32,
    /// Elements in the last page (equal to `page_capacity` when the split is even).
    pub last_page_capacity: u32,
}

/// A configuration the pages cannot hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum PageLayoutError {
    /// More elements than 32-bit offsets can address.
    TooManyElements {
        /// The kind.
        kind: DataKind,
        /// Elements the configured bytes stand for.
        elements: u64,
    },
    /// The page size cannot hold a single element.
    PageTooSmall {
        /// The kind.
        kind: DataKind,
        /// The largest page, bytes.
        max_page_bytes: u64,
    },
}

impl fmt::Display for PageLayoutError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PageLayoutError::TooManyElements { kind, elements } => write!(
                f,
                "{kind}: {elements} elements configured, but offsets are 32-bit (at most {})",
                u32::MAX
            ),
            PageLayoutError::PageTooSmall {
                kind,
                max_page_bytes,
            } => write!(
                f,
                "{kind}: a page of at most {max_page_bytes} bytes cannot hold one {}-byte element",
                kind.element_size()
            ),
        }
    }
}

impl std::error::Error for PageLayoutError {}

impl PageLayout {
    /// Splits `bytes` of `kind` (rounded down to whole elements) into pages of at most
    /// `max_page_bytes`.
    pub fn plan(kind: DataKind, bytes: u64, max_page_bytes: u64) -> Result<Self, PageLayoutError> {
        let size = u64::from(kind.element_size());
        let elements = bytes / size;
        if elements == 0 {
            return Ok(PageLayout {
                kind,
                page_capacity: 0,
                page_count: 0,
                last_page_capacity: 0,
            });
        }
        if elements > u64::from(u32::MAX) {
            return Err(PageLayoutError::TooManyElements { kind, elements });
        }
        let per_page = (max_page_bytes / size).min(elements);
        if per_page == 0 {
            return Err(PageLayoutError::PageTooSmall {
                kind,
                max_page_bytes,
            });
        }
        let page_count = elements.div_ceil(per_page);
        let last = elements - (page_count - 1) * per_page;
        // All three fit: elements <= u32::MAX bounds each of them.
        Ok(PageLayout {
            kind,
            page_capacity: per_page as u32,
            page_count: page_count as u32,
            last_page_capacity: last as u32,
        })
    }

    /// Elements in page `page`, 0 past the last page.
    pub fn capacity_of(&self, page: u32) -> u32 {
        if page + 1 < self.page_count {
            self.page_capacity
        } else if page + 1 == self.page_count {
            self.last_page_capacity
        } else {
            0
        }
    }

    /// Elements over all pages.
    pub fn total_elements(&self) -> u64 {
        match self.page_count {
            0 => 0,
            n => {
                u64::from(n - 1) * u64::from(self.page_capacity)
                    + u64::from(self.last_page_capacity)
            }
        }
    }

    /// Bytes of page `page`.
    pub fn page_bytes(&self, page: u32) -> u64 {
        u64::from(self.capacity_of(page)) * u64::from(self.kind.element_size())
    }

    /// The global element offset of `offset` in `page` (see the module docs).
    pub fn global_offset(&self, page: u32, offset: u32) -> u32 {
        // Never overflows for a valid (page, offset): the total fits in u32.
        page * self.page_capacity + offset
    }

    /// The page and in-page offset of a global element offset, or `None` past the end.
    pub fn locate(&self, global: u32) -> Option<(u32, u32)> {
        if self.page_count == 0 || u64::from(global) >= self.total_elements() {
            return None;
        }
        Some((global / self.page_capacity, global % self.page_capacity))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MIB: u64 = 1 << 20;

    #[test]
    fn fits_one_page_when_small() {
        let l = PageLayout::plan(DataKind::Quads, 64 * MIB, 128 * MIB).unwrap();
        assert_eq!(l.page_count, 1);
        assert_eq!(l.page_capacity, (64 * MIB / 8) as u32);
        assert_eq!(l.last_page_capacity, l.page_capacity);
        assert_eq!(l.total_elements(), 64 * MIB / 8);
    }

    #[test]
    fn splits_at_the_binding_limit() {
        // Ascendant's 400 MB of quads on lavapipe's 128 MiB binding limit.
        let l = PageLayout::plan(DataKind::Quads, 400_000_000, 128 * MIB).unwrap();
        assert_eq!(l.page_capacity, (128 * MIB / 8) as u32);
        assert_eq!(l.page_count, 3);
        assert_eq!(l.total_elements(), 400_000_000 / 8);
        assert_eq!(l.capacity_of(0), l.page_capacity);
        assert_eq!(l.capacity_of(2), l.last_page_capacity);
        assert_eq!(l.capacity_of(3), 0);
        assert!(l.page_bytes(0) <= 128 * MIB);
    }

    #[test]
    fn pages_hold_whole_elements() {
        // 20-byte clutter units do not divide 128 MiB.
        let l = PageLayout::plan(DataKind::Clutter, 300 * MIB, 128 * MIB).unwrap();
        assert_eq!(u64::from(l.page_capacity), 128 * MIB / 20);
        assert!(l.page_bytes(0) <= 128 * MIB);
        assert_eq!(l.page_bytes(0) % 20, 0);
        assert_eq!(l.total_elements(), 300 * MIB / 20);
    }

    #[test]
    fn zero_bytes_disables_the_kind() {
        let l = PageLayout::plan(DataKind::Clutter, 19, 128 * MIB).unwrap();
        assert_eq!(l.page_count, 0);
        assert_eq!(l.total_elements(), 0);
        assert_eq!(l.locate(0), None);
    }

    #[test]
    fn offsets_must_fit_u32() {
        let err = PageLayout::plan(DataKind::DrawBlocks, 17 << 30, 2 << 30).unwrap_err();
        assert!(matches!(err, PageLayoutError::TooManyElements { .. }));
        assert!(err.to_string().contains("32-bit"));
        // Exactly u32::MAX elements is fine.
        let l = PageLayout::plan(DataKind::DrawBlocks, 4 * u64::from(u32::MAX), 2 << 30).unwrap();
        assert_eq!(l.total_elements(), u64::from(u32::MAX));
        let last = l.page_count - 1;
        assert_eq!(
            l.global_offset(last, l.last_page_capacity - 1),
            u32::MAX - 1,
            "the last element's global offset"
        );
    }

    #[test]
    fn page_smaller_than_an_element_is_an_error() {
        let err = PageLayout::plan(DataKind::Clutter, 1000, 16).unwrap_err();
        assert!(matches!(err, PageLayoutError::PageTooSmall { .. }));
    }

    #[test]
    fn global_offsets_round_trip() {
        let l = PageLayout::plan(DataKind::SmoothVertices, 1000 * 16, 300 * 16).unwrap();
        assert_eq!(
            (l.page_capacity, l.page_count, l.last_page_capacity),
            (300, 4, 100)
        );
        for global in 0..1000 {
            let (page, offset) = l.locate(global).unwrap();
            assert!(offset < l.capacity_of(page));
            assert_eq!(l.global_offset(page, offset), global);
        }
        assert_eq!(l.locate(1000), None);
    }
}
