//! The compute rasteriser's records and sizes, and its CPU reference: what
//! `gpu_backend::render::passes::quad_raster` computes for every pixel centre (depth, the
//! winning quad, its attributes), computed here with the same `f32` operations. The pass's
//! design (tiles, big quads, the 64-bit visibility buffer) is documented with the pass.

mod layout;
pub mod reference;
mod stats;

pub use layout::{
    ArgsParams, BOX_PAD, EMPTY_BOX, EPS_MIN, EPS_PX, FIRST_STAT_WORD, LOCAL_MAX_PIXELS, MAX_GROUPS,
    MAX_SCREEN_EDGE, MAX_T, MIN_TILES_PER_BIG, NEAR_CLIP, PageArgs, QuadRasterConfig, RasterQuad,
    STATE_WORDS, StateWord, TILE, WORKGROUP,
};
pub use reference::PixelSample;
pub use stats::QuadRasterStats;
