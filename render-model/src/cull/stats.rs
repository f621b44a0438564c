//! The counters the cull pass keeps per frame (twin of the `STAT_*` constants of `cull.wgsl`).

/// Words of the statistics buffer.
pub const STAT_COUNT: u32 = 32;
/// First word of the per-level selected counts.
const STAT_LEVELS: usize = 16;
/// Levels counted.
pub(super) const STAT_LEVEL_COUNT: usize = 16;

/// One frame's cull counters (opaque layer records; the transparent quads from every record).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CullStats {
    /// Nodes selected at their level of detail (all levels).
    pub selected: u32,
    /// Selected nodes outside the frustum.
    pub frustum_culled: u32,
    /// Selected nodes in the frustum but hidden behind the depth pyramid.
    pub occluded: u32,
    /// Nodes drawn from their quads (or smooth quads).
    pub mesh_nodes: u32,
    /// Nodes drawn from their surface blocks.
    pub far_nodes: u32,
    /// Opaque quads drawn (skirts included).
    pub mesh_quads: u32,
    /// Surface blocks far-drawn (skirt blocks included).
    pub far_blocks: u32,
    /// Smooth quads drawn.
    pub smooth_quads: u32,
    /// Skirt sides drawn.
    pub skirt_sides: u32,
    /// Far-list entries appended (may exceed its capacity: the rest were dropped).
    pub far_list: u32,
    /// Transparent quads drawn.
    pub transparent_quads: u32,
    /// Meshed nodes with transparent quads listed for the transparent records (may exceed
    /// the list's capacity: the rest were dropped).
    pub transparent_list: u32,
    /// Selected nodes per level.
    pub per_level: [u32; STAT_LEVEL_COUNT],
}

impl CullStats {
    /// The statistics word counting the far list (`STAT_FAR_LIST`).
    pub const FAR_LIST_WORD: u32 = 9;
    /// The statistics word counting the transparent list (`STAT_TRANSPARENT_LIST`).
    pub const TRANSPARENT_LIST_WORD: u32 = 13;

    /// The counters from the buffer's words (missing words read 0).
    pub fn from_words(words: &[u32]) -> CullStats {
        let w = |i: usize| words.get(i).copied().unwrap_or(0);
        CullStats {
            selected: w(0),
            frustum_culled: w(1),
            occluded: w(2),
            mesh_nodes: w(3),
            far_nodes: w(4),
            mesh_quads: w(5),
            far_blocks: w(6),
            smooth_quads: w(7),
            skirt_sides: w(8),
            far_list: w(Self::FAR_LIST_WORD as usize),
            transparent_quads: w(10),
            transparent_list: w(Self::TRANSPARENT_LIST_WORD as usize),
            per_level: std::array::from_fn(|l| w(STAT_LEVELS + l)),
        }
    }
}
