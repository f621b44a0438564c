//! The numbers the rasteriser's shaders and its Rust side share: constants, the big-quad record
//! ([`RasterQuad`]), the per-page dispatch record ([`PageArgs`]), the state words and the
//! configuration that sizes the lists. Unit tests check every constant and layout against
//! naga's reflection of the shaders.

use bytemuck::{Pod, Zeroable};

/// Invocations per workgroup of both rasterising entry points (`QR_WORKGROUP`).
pub const WORKGROUP: u32 = 64;
/// Edge of the screen tiles large quads are split into, pixels (`QR_TILE`).
pub const TILE: u32 = 16;
/// Quads whose pixel box holds more pixel centres than this go to the tile list
/// (`QR_LOCAL_MAX_PIXELS`); smaller ones are drawn by the workgroup that set them up.
pub const LOCAL_MAX_PIXELS: u32 = 256;
/// The T-junction hair, pixels at the quad's distance (`QR_EPS_PX`; the G-buffer's
/// `DILATION_PX`).
pub const EPS_PX: f32 = 1.0 / 64.0;
/// The least hair, blocks (`QR_EPS_MIN`; the G-buffer's `MIN_DILATION`).
pub const EPS_MIN: f32 = 1.0 / 4096.0;
/// Hits further than this along the ray are ignored (rays almost parallel to a quad).
pub const MAX_T: f32 = 1e30;
/// The setup clips projections at `near * NEAR_CLIP` (`QR_NEAR_CLIP`).
pub const NEAR_CLIP: f32 = 0.999;
/// Pixels a projection's box is padded by (`QR_BOX_PAD`).
pub const BOX_PAD: f32 = 0.125;
/// Largest workgroup count of one dispatch dimension.
pub const MAX_GROUPS: u32 = 65_535;
/// Largest screen edge (pixel coordinates are packed in 16 bits).
pub const MAX_SCREEN_EDGE: u32 = 1 << 15;
/// A big quad's box holds more than [`LOCAL_MAX_PIXELS`] pixels, so it is wider or taller than
/// a tile and touches at least this many tiles: the big-quad list needs at most
/// `tile_capacity / MIN_TILES_PER_BIG` entries and never fills before the tile list.
pub const MIN_TILES_PER_BIG: u32 = 2;
const _: () = assert!(
    LOCAL_MAX_PIXELS >= TILE * TILE,
    "a big quad spans two tiles or more"
);

/// The words of the rasteriser's state buffer: list counters (cleared by every record) and
/// statistics (cleared by `gpu_backend`'s `QuadRaster::clear_stats`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StateWord {
    /// Tile entries appended by the record (`QR_TILE_COUNT`).
    TileCount = 0,
    /// Big-quad entries appended by the record (`QR_BIG_COUNT`).
    BigCount = 1,
    /// Quads read from the drawn commands (`QR_STAT_QUADS`).
    Quads = 8,
    /// Quads with a non-empty pixel box: front-facing, past the near plane, on screen
    /// (`QR_STAT_VISIBLE`).
    Visible = 9,
    /// Pixel centres tested by the quads pass (`QR_STAT_LOCAL_PIXELS`).
    LocalPixels = 10,
    /// Quads sent to the tile list (`QR_STAT_BIG`).
    Big = 11,
    /// Big quads the tile list had no room for, drawn by their quads-pass workgroup instead
    /// (`QR_STAT_OVERFLOW`).
    Overflow = 12,
    /// Pixel centres tested by the tiles pass (`QR_STAT_TILE_PIXELS`).
    TilePixels = 13,
    /// Pixel centres that hit a quad: visibility words written (`QR_STAT_HITS`).
    Hits = 14,
}

/// Words of the state buffer.
pub const STATE_WORDS: u32 = 16;
/// The first statistics word (words below it are cleared by every record).
pub const FIRST_STAT_WORD: u32 = 8;

/// A quad set up for rasterisation (twin of the WGSL `RasterQuad`, 32 bytes): what the big-quad
/// list holds and what the CPU twin computes.
///
/// Camera-relative, blocks: `plane` is the quad's coordinate on its normal axis; `lo_*` and
/// `hi_*` its bounds on the face's width and height axes (`face_width_axis`,
/// `face_height_axis`), from corners 0 and 2. `face_ao_block` is the [`PackedQuad`]'s second
/// word. `box_lo`/`box_hi` are the inclusive pixel box to test, `x | y << 16` (empty when a
/// component of `lo` exceeds `hi`'s).
///
/// [`PackedQuad`]: voxel_core::formats::PackedQuad
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct RasterQuad {
    /// Coordinate on the normal axis.
    pub plane: f32,
    /// Width-axis coordinate of corner 0.
    pub lo_w: f32,
    /// Height-axis coordinate of corner 0.
    pub lo_h: f32,
    /// Width-axis coordinate of corner 2.
    pub hi_w: f32,
    /// Height-axis coordinate of corner 2.
    pub hi_h: f32,
    /// Face (bits 0..3), corner AO (3..11), block id (11..27).
    pub face_ao_block: u32,
    /// First pixel of the box, `x | y << 16`.
    pub box_lo: u32,
    /// Last pixel of the box, `x | y << 16`.
    pub box_hi: u32,
}

const _: () = assert!(size_of::<RasterQuad>() == 32, "RasterQuad is 32 bytes");

/// The empty box (`qr_empty`).
pub const EMPTY_BOX: (u32, u32) = (u32::MAX, 0);

impl RasterQuad {
    /// The box's first and last pixel, or `None` when empty.
    pub fn pixel_box(&self) -> Option<([u32; 2], [u32; 2])> {
        let lo = [self.box_lo & 0xffff, self.box_lo >> 16];
        let hi = [self.box_hi & 0xffff, self.box_hi >> 16];
        (lo[0] <= hi[0] && lo[1] <= hi[1]).then_some((lo, hi))
    }

    /// Pixel centres in the box.
    pub fn box_area(&self) -> u32 {
        self.pixel_box()
            .map_or(0, |(lo, hi)| (hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1))
    }

    /// Screen tiles the box touches (0 when empty).
    pub fn box_tiles(&self) -> u32 {
        self.pixel_box().map_or(0, |(lo, hi)| {
            (hi[0] / TILE - lo[0] / TILE + 1) * (hi[1] / TILE - lo[1] / TILE + 1)
        })
    }
}

/// One quad page's dispatch of the quads pass (twin of the WGSL `PageArgs`, 32 bytes), written
/// by `qr_page_args`; its first 12 bytes are the indirect dispatch.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct PageArgs {
    /// Workgroups, x.
    pub groups_x: u32,
    /// Workgroups, y.
    pub groups_y: u32,
    /// Workgroups, z (1).
    pub groups_z: u32,
    /// The page's first command slot (`page * commands_per_page`).
    pub first_command: u32,
    /// Drawn commands: `min(counts[page], commands_per_page)`.
    pub commands: u32,
    /// The page.
    pub page: u32,
    /// Zero.
    pub pad: [u32; 2],
}

const _: () = assert!(size_of::<PageArgs>() == 32, "PageArgs is 32 bytes");

/// The args shader's uniforms (twin of the WGSL `ArgsParams`, 16 bytes), fixed per cull
/// output.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct ArgsParams {
    /// Quad pages of the cull output.
    pub page_count: u32,
    /// Command slots per page.
    pub commands_per_page: u32,
    /// Words between two pages' [`PageArgs`].
    pub page_stride: u32,
    /// Entries of the tile list.
    pub tile_capacity: u32,
}

/// How large the rasteriser's lists are.
///
/// Quads whose pixel box holds more than [`LOCAL_MAX_PIXELS`] pixel centres are split into
/// [`TILE`] x [`TILE`] screen tiles, one 8-byte entry each, plus one 32-byte [`RasterQuad`] per
/// quad. When a record's big quads need more tile entries than `tile_capacity`, the quads that
/// do not fit are drawn by the workgroup that set them up (correct, but one workgroup then
/// walks the whole quad: slow for quads covering much of the screen), and counted in
/// [`QuadRasterStats::overflow`](super::QuadRasterStats::overflow). Nothing is dropped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct QuadRasterConfig {
    /// Tile entries per record.
    pub tile_capacity: u32,
}

impl QuadRasterConfig {
    /// Room for big quads covering the screen `screens` times over (their boxes' tiles), for a
    /// `width x height` screen: `screens * ceil(width / 16) * ceil(height / 16)` tile entries.
    /// At 1920 x 1080, 16 screens take 130,560 entries: 1.0 MiB of tiles and 2.0 MiB of big
    /// quads.
    pub fn for_screen(width: u32, height: u32, screens: u32) -> QuadRasterConfig {
        let tiles = u64::from(width.div_ceil(TILE)) * u64::from(height.div_ceil(TILE));
        QuadRasterConfig {
            tile_capacity: (tiles * u64::from(screens)).clamp(1, u64::from(u32::MAX)) as u32,
        }
    }

    /// Entries of the big-quad list: never full before the tile list is.
    pub fn big_capacity(&self) -> u32 {
        self.tile_capacity.div_ceil(MIN_TILES_PER_BIG)
    }

    /// Bytes of the tile list.
    pub fn tile_bytes(&self) -> u64 {
        u64::from(self.tile_capacity) * 8
    }

    /// Bytes of the big-quad list.
    pub fn big_bytes(&self) -> u64 {
        u64::from(self.big_capacity()) * size_of::<RasterQuad>() as u64
    }
}

impl Default for QuadRasterConfig {
    /// 16 screens of 1920 x 1080.
    fn default() -> Self {
        QuadRasterConfig::for_screen(1920, 1080, 16)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boxes_and_capacities() {
        let q = RasterQuad {
            box_lo: 3 | 5 << 16,
            box_hi: 20 | 5 << 16,
            ..RasterQuad::default()
        };
        assert_eq!(q.pixel_box(), Some(([3, 5], [20, 5])));
        assert_eq!(q.box_area(), 18);
        assert_eq!(q.box_tiles(), 2);
        let empty = RasterQuad {
            box_lo: EMPTY_BOX.0,
            box_hi: EMPTY_BOX.1,
            ..RasterQuad::default()
        };
        assert_eq!((empty.box_area(), empty.box_tiles()), (0, 0));
        let c = QuadRasterConfig::for_screen(1920, 1080, 16);
        assert_eq!(c.tile_capacity, 120 * 68 * 16);
        assert_eq!(c.big_capacity(), 120 * 68 * 8);
        assert_eq!(c.tile_bytes(), 1_044_480);
        assert_eq!(QuadRasterConfig::for_screen(0, 0, 0).tile_capacity, 1);
    }

    /// Every box with more than LOCAL_MAX_PIXELS pixel centres touches MIN_TILES_PER_BIG
    /// tiles or more, wherever it lies: the big-quad list never fills first.
    #[test]
    fn big_boxes_touch_at_least_two_tiles() {
        for w in 1..=300u32 {
            for h in [1, 2, 15, 16, 17, 31, 64, 257] {
                if w * h <= LOCAL_MAX_PIXELS {
                    continue;
                }
                for x in [0u32, 1, 7, 15, 16, 100] {
                    let q = RasterQuad {
                        box_lo: x | 9 << 16,
                        box_hi: (x + w - 1) | (9 + h - 1) << 16,
                        ..RasterQuad::default()
                    };
                    assert!(q.box_tiles() >= MIN_TILES_PER_BIG, "{w}x{h} at {x}");
                }
            }
        }
    }
}
