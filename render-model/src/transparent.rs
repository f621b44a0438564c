//! The transparent layer's draw order: culled and sorted back to front on the GPU.
//!
//! Blending is order-dependent, so the transparent layer is culled with the cull pass's
//! ordered mode (`gpu_backend::cull::CullOrder::BackToFront`): the same frustum and per-face-direction
//! decisions as the opaque layer, then a counting sort of each quad page's commands on the
//! depth key of their chunk's box centre, farthest first ([`depth_key`]). The draw is one
//! multi-draw-indirect per quad page, like the opaque layer, so the CPU work per frame does not
//! grow with the number of transparent chunks.
//!
//! **The rule and its artefacts.** Chunks are ordered back to front (to about 0.14 % of their
//! distance; closer than that, either order); faces *within* a chunk are drawn in mesh order,
//! unsorted. So where two transparent surfaces of one chunk overlap on screen (water seen
//! through glass in the same chunk, or the near and far walls of a glass box seen through each
//! other), the farther one may be blended over the nearer one. One transparent surface per
//! pixel per chunk (a water surface seen from above) is always right. Chunks whose boxes
//! overlap in depth can also be mis-ordered near their shared border, large chunks sorted by
//! centre can swap order when seen edge-on, and with several quad pages the order holds
//! within each page.
//!
//! **The colour of a layer** is the lighting model's
//! ([`lighting::surface`](crate::lighting::surface)): a thin pane is tinted once by its
//! alpha, a volume (water) by the distance from its surface to the opaque surface behind it,
//! and a smooth layer reflects the sky by Schlick's Fresnel and the sun by GGX. Each layer is
//! premultiplied (`colour + behind * (1 - coverage)`), so the order rule above is unchanged.
//!
//! [`depth_key`]: crate::cull::depth_key

#[cfg(test)]
mod tests {
    use voxel_core::formats::FaceLayerRange;
    use voxel_core::{ChunkCoord, ChunkSize};

    use voxel_core::formats::MeshedChunkInfo;

    use voxel_core::formats::DataKind;

    use crate::cull::{CullConfig, CullLayer, CullLayout, CullView, cull_reference_ordered};
    use crate::pages::PageLayout;

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
        let camera = CullView::without_frustum(ChunkCoord::new(0, 0, 0), [8.0, 8.0, 8.0]);
        // Chunks at z = -1, -3, -2 (all in front of the eye along -z).
        let infos = [chunk(-1, 0), chunk(-3, 100), chunk(-2, 200)];
        let draws = cull_reference_ordered(&infos, &camera, CullLayer::Transparent, &layout);
        let draws = &draws.commands[0];
        let order: Vec<i32> = draws.iter().map(|d| d.record.chunk[2]).collect();
        assert_eq!(order, [-3, -2, -1], "farthest first");
        for (i, d) in draws.iter().enumerate() {
            assert_eq!(d.args.first_instance, i as u32);
            assert_eq!(d.args.index_count, 6 * 3, "only the 3 +Z quads");
        }
        // The +Z group starts after the groups of lower directions (all empty here).
        assert_eq!(draws[0].args.base_vertex, 4 * 100);
    }
}
