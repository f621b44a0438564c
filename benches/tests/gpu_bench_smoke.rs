//! The GPU benchmark on a small LOD terrain (lavapipe in CI): every pass is timed, the runs
//! follow the settings asked for, the full-detail run draws only level 0 with meshes, a budget
//! run draws coarser levels and far blocks, image errors are measured against full detail,
//! the resident bytes are reported, and the image shows terrain.

use benches::gpu_bench::{
    BenchConfig, SceneSummary, bench_camera, budget_params, run, selected_by_any,
};
use benches::gpu_scene::{LodTerrain, node_draw_block_words, node_quads};
use gpu_backend::DeviceOptions;
use gpu_backend::render::far::{FarPath, FarRequest};
use gpu_backend::render::{FullscreenPath, OpaquePath};
use gpu_backend::test_support::headless_or_skip;
use voxel_core::ChunkSize;

#[test]
fn small_lod_terrain_runs() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let terrain = LodTerrain::generate(256, ChunkSize::S8, 1, 3, |_, _| true).unwrap();
    assert!(
        terrain.levels[0].len() > 500,
        "{} nodes",
        terrain.levels[0].len()
    );
    let config = BenchConfig {
        width: 160,
        height: 90,
        frames: 2,
        budgets: vec![1.0, 8.0],
        reference: true,
        far: vec![FarRequest::Path(FarPath::Splat)],
        far_cell_px: vec![0.0, 4.0],
        fullscreen: vec![FullscreenPath::Compute],
        occlusion: vec![true],
        opaque: vec![OpaquePath::Raster, OpaquePath::Compute],
    };
    let mut scene = SceneSummary::default();
    let (runs, images, choices) = run(&ctx, &terrain, &config, &mut scene).unwrap();
    assert_eq!(choices[0].path, FarPath::Splat);
    // Full detail, then 2 budgets x 2 far thresholds, per opaque path.
    assert_eq!(runs.len(), 9);
    for (raster, compute) in runs[1..5].iter().zip(&runs[5..]) {
        assert_eq!(
            (raster.opaque.as_str(), compute.opaque.as_str()),
            ("Raster", "Compute")
        );
        assert!(compute.passes.iter().any(|p| p.label == "quad raster"));
        assert_eq!(raster.drawn.mesh_quads, compute.drawn.mesh_quads);
        // The same picture: the two paths differ only at a few quad-edge pixels.
        let (a, b) = (raster.image_error.unwrap(), compute.image_error.unwrap());
        assert!(
            (a.mean_abs - b.mean_abs).abs() < 0.5,
            "raster {a:?} against compute {b:?}"
        );
    }
    assert_eq!(runs[0].budget_px, None);
    assert_eq!(
        runs[0].drawn.selected_per_level.len(),
        1,
        "full detail: level 0 only"
    );
    assert_eq!(runs[0].drawn.far_nodes, 0);
    assert!(runs[0].image_error.is_none());
    for run in &runs[1..5] {
        let error = run.image_error.expect("measured against full detail");
        assert!(error.mean_abs.is_finite() && error.share_over_8 <= 1.0);
        for pass in ["cull", "gbuffer", "hiz", "cull late", "lighting", "tonemap"] {
            assert!(
                run.passes.iter().any(|p| p.label == pass),
                "pass {pass} not timed"
            );
        }
        assert!(run.cpu_frame_us > 0.0);
    }
    let coarse = &runs[3];
    assert_eq!(coarse.budget_px, Some(8.0));
    assert!(
        coarse.drawn.selected_per_level.len() > 1,
        "an 8-pixel budget selects coarser levels: {:?}",
        coarse.drawn.selected_per_level
    );
    let far = &runs[4];
    assert!(
        far.drawn.far_nodes > 0 && far.drawn.far_blocks > 0,
        "{:?}",
        far.drawn
    );
    assert!(
        runs[1].image_error.unwrap().mean_abs <= coarse.image_error.unwrap().mean_abs,
        "a tighter budget is closer to full detail"
    );
    let bytes = |name: &str| {
        scene
            .resident_bytes
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| *v)
    };
    // Resident for the budgets' runs: what some budget selects (the reference's level 0 had a
    // renderer of its own).
    let params = budget_params(
        &bench_camera(),
        &config.budgets,
        terrain.levels.len() as u32 - 1,
        config.height,
        terrain.size,
    );
    let selected = || {
        terrain
            .nodes()
            .filter(|n| selected_by_any(&params, n.level, n.coord))
    };
    assert!(selected().count() < terrain.nodes().count());
    assert_eq!(
        bytes("quads"),
        Some(selected().map(node_quads).sum::<u64>() * 8)
    );
    assert_eq!(
        bytes("draw blocks"),
        Some(selected().map(node_draw_block_words).sum::<u64>() * 4)
    );
    // Terrain covers the lower part of the image: those pixels are not the sky's colour.
    let image = images.last.expect("last image");
    let sky = &image.rgba[..4];
    let bottom_row = &image.rgba[(image.height as usize - 1) * image.width as usize * 4..];
    let ground = bottom_row.chunks(4).filter(|p| *p != sky).count();
    assert!(ground > image.width as usize / 2, "{ground} ground pixels");

    let bad = BenchConfig {
        far: Vec::new(),
        ..config
    };
    assert!(run(&ctx, &terrain, &bad, &mut scene).is_err());
}
