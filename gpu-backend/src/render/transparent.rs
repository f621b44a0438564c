//! The transparent layer's draw order: culled on the CPU, chunks back to front.
//!
//! Blending is order-dependent, and the GPU cull's command order is not deterministic (pages
//! take their slots with atomics), so the transparent layer does not use it. Transparent
//! chunks are few (water surfaces, glass), so they are culled here with the cull pass's own CPU
//! reference ([`cull_chunk`]: same frustum and per-face-direction decisions) and sorted by the
//! camera-relative distance of their box centres, farthest first. Each visible face group
//! becomes one direct `draw_indexed` in that order.
//!
//! **The rule and its artefacts.** Chunks are ordered back to front; faces *within* a chunk
//! are drawn in mesh order, unsorted. So where two transparent surfaces of one chunk overlap on
//! screen (water seen through glass in the same chunk, or the near and far walls of a glass box
//! seen through each other), the farther one may be blended over the nearer one. One
//! transparent surface per pixel per chunk (a water surface seen from above) is always right.
//! Chunks whose boxes overlap in depth can also be mis-ordered near their shared border, and
//! large chunks sorted by centre can swap order when seen edge-on.

use voxel_core::formats::{ChunkDrawIndirect, MeshedChunkInfo};

use crate::cull::{
    ChunkCull, CullCamera, CullLayer, CullLayout, cull_chunk, relative_box, relative_chunk,
};

/// One transparent draw: a face group of one chunk in one page of the quad gigabuffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TransparentDraw {
    /// Page of the quad gigabuffer to bind.
    pub page: u32,
    /// The record the vertex shader reads (`first_instance` is its index in the list).
    pub record: ChunkDrawIndirect,
}

/// The transparent draws of `chunks` for `camera`, back to front (see the
/// [module docs](self)).
pub fn transparent_draws<'a>(
    chunks: impl IntoIterator<Item = &'a MeshedChunkInfo>,
    camera: &CullCamera,
    layout: &CullLayout,
) -> Vec<TransparentDraw> {
    let mut visible: Vec<(f32, u32, u32, u32, &MeshedChunkInfo)> = Vec::new();
    for info in chunks {
        if let ChunkCull::Visible { page, start, faces } =
            cull_chunk(info, camera, CullLayer::Transparent, layout)
            && faces != 0
        {
            let (c, _) = relative_box(info, camera, layout.chunk_edge);
            let distance = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
            visible.push((distance, page, start, faces, info));
        }
    }
    // Farthest first; NaN cannot occur (boxes are finite), total_cmp keeps the sort total.
    visible.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut draws = Vec::new();
    for (_, page, start, faces, info) in visible {
        let rel = relative_chunk(info, camera);
        let mut first = start;
        for (face, &count) in info.transparent_quads.counts.iter().enumerate() {
            if faces >> face & 1 == 1 {
                let index = draws.len() as u32;
                draws.push(TransparentDraw {
                    page,
                    record: ChunkDrawIndirect {
                        index_count: 6 * count,
                        instance_count: 1,
                        first_index: 0,
                        base_vertex: (4 * first) as i32,
                        first_instance: index,
                        chunk: rel,
                    },
                });
            }
            first += count;
        }
    }
    draws
}
