//! Resident memory, per kind, for benchmarks and on-screen stats.

use voxel_core::formats::PerKind;

/// Memory use of one kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KindUsage {
    /// Bytes in live allocations.
    pub used_bytes: u64,
    /// Bytes of the pages created so far (GPU memory held).
    pub reserved_bytes: u64,
    /// Bytes the kind may grow to (configured, whole elements).
    pub capacity_bytes: u64,
    /// Live allocations.
    pub allocations: u64,
    /// Pages created.
    pub pages: u32,
}

/// Memory use of the whole gigabuffer, for benchmarks and on-screen stats.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ResidentReport {
    /// Per kind.
    pub kinds: PerKind<KindUsage>,
    /// Live chunks.
    pub chunks: u64,
}

impl ResidentReport {
    /// Bytes in live allocations, all kinds.
    pub fn used_bytes(&self) -> u64 {
        self.kinds.iter().map(|(_, u)| u.used_bytes).sum()
    }

    /// Bytes of created pages, all kinds.
    pub fn reserved_bytes(&self) -> u64 {
        self.kinds.iter().map(|(_, u)| u.reserved_bytes).sum()
    }
}
