//! The GPU benchmark on a small LOD terrain (lavapipe in CI): every pass is timed, the runs
//! follow the settings asked for, the full-detail run draws only level 0 with meshes, a budget
//! run draws coarser levels and far blocks, image errors are measured against full detail,
//! the resident bytes are reported, and the image shows terrain.

use benches::gpu_bench::{
    BenchConfig, SceneSummary, bench_camera, budget_params, image_error, run, selected_by_any,
};
use benches::gpu_scene::{LodTerrain, node_draw_block_words, node_quads};
use gpu_backend::DeviceOptions;
use gpu_backend::render::far::{FarPath, FarRequest};
use gpu_backend::render::{FullscreenPath, OpaquePath};
use gpu_backend::test_support::headless_or_skip;
use voxel_core::ChunkSize;

/// The faults it catches, beyond a run that fails: a budget run whose frame is far from full
/// detail, which the old check (`share_over_8 <= 1.0`, true of every image) let through;
/// planted (each run's error measured against the reference turned upside down), it failed
/// with "budget 1 px, far cells 0.0: ImageErrorReport { mean_abs: 59.66.., share_over_8:
/// 0.929.. }". And an opaque path that draws a different frame at a few pixels, whose mean
/// error against full detail stays within the old bound of 0.5; planted (every 50th pixel of
/// the compute path's frame moved by 20 levels), it failed on the share of pixels off,
/// 0.022 against 0.043, while the means differed by 0.45.
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
        lighting: Default::default(),
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
        // The same picture: the two paths differ only at a few quad-edge pixels, so against
        // full detail their errors agree, in mean and in the share of pixels off.
        let (a, b) = (raster.image_error.unwrap(), compute.image_error.unwrap());
        assert!(
            (a.mean_abs - b.mean_abs).abs() < 0.5
                && (a.share_over_8 - b.share_over_8).abs() <= 0.01,
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
        // The error bound of the budget rule (`lod_view.rs`): a mean of at most 2.5 and at
        // most 5% of the pixels off per pixel of budget.
        let b = f64::from(run.budget_px.expect("a budget run"));
        assert!(
            error.mean_abs <= 2.5 * b && error.share_over_8 <= 0.05 * b,
            "budget {b} px, far cells {:?}: {error:?}",
            run.far_cell_px
        );
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

    // The two opaque paths draw the same frame, compared pixel by pixel.
    let last_frame = |opaque| {
        let one = BenchConfig {
            budgets: vec![8.0],
            far_cell_px: vec![4.0],
            reference: false,
            opaque: vec![opaque],
            ..config.clone()
        };
        let (_, images, _) = run(&ctx, &terrain, &one, &mut SceneSummary::default()).unwrap();
        images.last.expect("a frame").rgba
    };
    let (raster, compute) = (
        last_frame(OpaquePath::Raster),
        last_frame(OpaquePath::Compute),
    );
    let error = image_error(&compute, &raster).expect("frames of one size");
    assert!(
        error.share_over_8 <= 0.01 && error.mean_abs <= 0.5,
        "the compute path's frame against the raster path's: {error:?}"
    );

    let bad = BenchConfig {
        far: Vec::new(),
        ..config
    };
    assert!(run(&ctx, &terrain, &bad, &mut scene).is_err());
}
