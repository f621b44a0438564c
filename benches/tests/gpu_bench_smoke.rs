//! The GPU benchmark on a small terrain (lavapipe in CI): every pass is timed, the quad
//! gigabuffer holds exactly 8 bytes per greedy quad, scenes grow as asked, and the image shows
//! terrain.

use benches::gpu_bench::{BenchConfig, run};
use benches::gpu_scene::MeshedTerrain;
use gpu_backend::DeviceOptions;
use gpu_backend::test_support::headless_or_skip;
use voxel_core::ChunkSize;

#[test]
fn small_terrain_scenes() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let terrain = MeshedTerrain::generate(96, ChunkSize::S8, 1).unwrap();
    let total = terrain.meshes.len();
    assert!(total > 100, "{total} chunks");
    let config = BenchConfig {
        scene_chunks: vec![20, 100, total],
        width: 96,
        height: 64,
        frames: 2,
    };
    let (reports, image) = run(&ctx, &terrain, &config).unwrap();
    assert_eq!(
        reports.iter().map(|r| r.chunks).collect::<Vec<_>>(),
        [20, 100, total]
    );
    for r in &reports {
        assert_eq!(r.quads, terrain.quad_count(r.chunks));
        assert_eq!(
            r.bytes_per_quad(),
            8.0,
            "quad gigabuffer holds only packed quads"
        );
        for pass in [
            "cull",
            "cull transparent",
            "gbuffer",
            "lighting",
            "transparent",
            "tonemap",
        ] {
            assert!(r.pass(pass).is_some(), "pass {pass} not timed");
        }
        assert!(r.cpu_frame_us > 0.0);
    }
    assert!(reports[0].covered_side < reports[2].covered_side);
    // Terrain covers the lower part of the image: those pixels are not the sky's colour.
    let sky = &image.rgba[..4];
    let bottom_row = &image.rgba[(image.height as usize - 1) * image.width as usize * 4..];
    let ground = bottom_row.chunks(4).filter(|p| *p != sky).count();
    assert!(ground > image.width as usize / 2, "{ground} ground pixels");

    let bad = BenchConfig {
        scene_chunks: vec![100, 20],
        ..config
    };
    let err = run(&ctx, &terrain, &bad).unwrap_err();
    assert!(err.to_string().contains("ascending"), "{err}");
}
