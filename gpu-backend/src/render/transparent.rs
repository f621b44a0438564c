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

#[cfg(test)]
mod tests {
    use voxel_core::formats::FaceLayerRange;
    use voxel_core::{ChunkCoord, ChunkSize};

    use super::*;
    use crate::cull::CullConfig;
    use crate::gigabuffer::{DataKind, PageLayout};

    fn chunk(z: i32, offset: u32) -> MeshedChunkInfo {
        MeshedChunkInfo {
            chunk: [0, 0, z],
            centre: [8.0; 3],
            extent: [8.0; 3],
            transparent_quads: FaceLayerRange {
                offset,
                // +Z and -Z faces; only +Z faces the eye at z = +8 in front of every chunk.
                counts: [0, 0, 0, 0, 3, 2],
            },
            ..Default::default()
        }
    }

    #[test]
    fn chunks_come_back_to_front_with_facing_groups_only() {
        let pages = PageLayout::plan(DataKind::Quads, 1 << 20, 1 << 20).unwrap();
        let layout = CullLayout::new(&pages, &CullConfig::new(ChunkSize::S16, 16)).unwrap();
        let camera = CullCamera::without_frustum(ChunkCoord::new(0, 0, 0), [8.0, 8.0, 8.0]);
        // Chunks at z = -1, -3, -2 (all in front of the eye along -z).
        let infos = [chunk(-1, 0), chunk(-3, 100), chunk(-2, 200)];
        let draws = transparent_draws(&infos, &camera, &layout);
        let order: Vec<i32> = draws.iter().map(|d| d.record.chunk[2]).collect();
        assert_eq!(order, [-3, -2, -1], "farthest first");
        for (i, d) in draws.iter().enumerate() {
            assert_eq!(d.record.first_instance, i as u32);
            assert_eq!(d.record.index_count, 6 * 3, "only the 3 +Z quads");
        }
        // The +Z group starts after the groups of lower directions (all empty here).
        assert_eq!(draws[0].record.base_vertex, 4 * 100);
    }
}
