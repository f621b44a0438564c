//! The streamed terrain meshed as vertical shells (`--mesher shells`) on the local Vulkan
//! adapter (lavapipe here): the frame of a loaded view matches the greedy frame of the same
//! view within 1 % of pixels off by more than 8/255, the renderer draws runs, and the nodes
//! hold runs instead of opaque quads. Without an adapter each test prints `skipped: ...` (and
//! fails under `CI=true`).

#[path = "support/geometry_views.rs"]
mod geometry_views;

use geometry_views::{SIZE, frame, pixels_off, settings, terrain_pixels};
use gpu_backend::DeviceOptions;
use gpu_backend::test_support::headless_or_skip;
use viewer::stream::MesherMode;

#[test]
fn a_shell_view_matches_the_greedy_view() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let (greedy, _) = frame(&ctx, &settings(MesherMode::Greedy));
    let (shells, view) = frame(&ctx, &settings(MesherMode::Shells));
    let (nodes, runs) = view
        .renderer()
        .shell_stats()
        .unwrap()
        .expect("the shell pass exists with --mesher shells");
    assert!(
        nodes > 10 && runs > 1000,
        "{nodes} nodes and {runs} runs drawn"
    );
    let off = pixels_off(&greedy, &shells);
    let pixels = (SIZE.0 * SIZE.1) as usize;
    assert!(
        off * 100 <= pixels,
        "{off} of {pixels} pixels off by more than 8/255"
    );
    // The frames differ somewhere only if something drew: the view is not empty sky.
    let ground = terrain_pixels(&greedy);
    assert!(ground * 2 > pixels, "only {ground} pixels of terrain");
}
