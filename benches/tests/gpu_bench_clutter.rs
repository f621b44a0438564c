//! The GPU benchmark's clutter (`gpu_bench --clutter`) placed only where its frames can draw
//! grass (`benches::gpu_bench::may_draw_grass`, the viewer's rule) on lavapipe: far fewer
//! units than on every level-0 node, and every frame (full detail and each budget) draws the
//! same grass and the same image as with clutter everywhere.

use benches::gpu_bench::{
    BenchConfig, SceneSummary, bench_camera, budget_params, grass_params, may_draw_grass, run,
};
use benches::gpu_scene::{Clutter, LodTerrain};
use gpu_backend::DeviceOptions;
use gpu_backend::render::far::{FarPath, FarRequest};
use gpu_backend::render::{FullscreenPath, OpaquePath};
use gpu_backend::test_support::headless_or_skip;
use voxel_core::{ChunkCoord, ChunkSize};

#[test]
fn clutter_within_the_grass_reach_draws_what_clutter_everywhere_draws() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let config = BenchConfig {
        width: 320,
        height: 180,
        frames: 1,
        budgets: vec![1.0, 4.0],
        reference: true,
        far: vec![FarRequest::Path(FarPath::Splat)],
        far_cell_px: vec![2.0],
        fullscreen: vec![FullscreenPath::Compute],
        occlusion: vec![true],
        opaque: vec![OpaquePath::Raster],
        lighting: Default::default(),
    };
    let (size, top) = (ChunkSize::S16, 2);
    let params = budget_params(&bench_camera(), &config.budgets, top, config.height, size);
    let grass = grass_params(&params, config.reference);
    let density = mesher::ClutterParams::new(2.0, 1).unwrap();
    let near = |c: ChunkCoord| may_draw_grass(&grass, c);
    let everywhere = |_: ChunkCoord| true;
    let terrain = |on: &(dyn Fn(ChunkCoord) -> bool + Sync)| {
        let clutter = Clutter {
            params: density,
            on,
        };
        LodTerrain::generate_with_clutter(256, size, 1, top, Some(clutter), |_, _| true).unwrap()
    };
    let (near, everywhere) = (terrain(&near), terrain(&everywhere));
    eprintln!(
        "gpu_bench_clutter: {} units within the grass reach, {} on every level-0 node",
        near.clutter_count(),
        everywhere.clutter_count()
    );
    assert!(near.clutter_count() > 0);
    assert!(near.clutter_count() * 4 < everywhere.clutter_count());
    let mut scene = SceneSummary::default();
    let (got, got_images, _) = run(&ctx, &near, &config, &mut scene).unwrap();
    let (want, want_images, _) = run(&ctx, &everywhere, &config, &mut scene).unwrap();
    assert_eq!(got.len(), 3, "full detail and two budgets");
    for (g, w) in got.iter().zip(&want) {
        eprintln!(
            "gpu_bench_clutter: budget {:?}: {} chunks, {} units drawn",
            g.budget_px, g.drawn.grass_chunks, g.drawn.grass_units
        );
        assert_eq!(
            (g.drawn.grass_chunks, g.drawn.grass_units),
            (w.drawn.grass_chunks, w.drawn.grass_units),
            "budget {:?}",
            g.budget_px
        );
    }
    assert!(
        got[0].drawn.grass_units > 0,
        "grass in the full-detail frame"
    );
    for (g, w) in [
        (&got_images.reference, &want_images.reference),
        (&got_images.last, &want_images.last),
    ] {
        let (g, w) = (g.as_ref().unwrap(), w.as_ref().unwrap());
        assert!(g.rgba == w.rgba, "the same frame");
    }
}
