//! The streamed terrain as heightmap cubes (`--mesher heightmap`) on the local Vulkan adapter
//! (lavapipe here): the frame of a loaded view matches the greedy frame of the same view within
//! 1 % of pixels off by more than 8/255 (the built-in terrain has no overhangs and no trees),
//! the shell pass draws the boxes, and the view's node data is at least ten times smaller
//! than the greedy view's. A far path asked for with heightmap cubes is refused by name.
//! Without an adapter each test prints `skipped: ...` (and fails under `CI=true`).

#[path = "support/geometry_views.rs"]
mod geometry_views;

use geometry_views::{SIZE, frame, pixels_off, terrain_pixels};
use gpu_backend::DeviceOptions;
use gpu_backend::render::far::{FarPath, FarRequest};
use gpu_backend::test_support::headless_or_skip;
use viewer::stream::{MesherMode, StreamSettings};
use viewer::view::StreamedView;
use voxel_core::formats::DataKind;

/// The compared view meshed by `mesher`, without grass (whose units are the same in both
/// geometries).
fn settings(mesher: MesherMode) -> StreamSettings {
    StreamSettings {
        clutter: false,
        ..geometry_views::settings(mesher)
    }
}

/// Bytes of node data: the gigabuffer kinds (the tables are sized by capacity, alike in both).
fn node_bytes(view: &StreamedView) -> u64 {
    view.renderer()
        .resident_bytes()
        .into_iter()
        .filter(|(kind, _)| DataKind::ALL.iter().any(|k| k.name() == *kind))
        .map(|(_, bytes)| bytes)
        .sum()
}

#[test]
fn a_heightmap_view_matches_the_greedy_view_in_a_tenth_of_the_bytes() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let (greedy, greedy_view) = frame(&ctx, &settings(MesherMode::Greedy));
    let (heights, view) = frame(&ctx, &settings(MesherMode::Heightmap));
    let (nodes, boxes) = view
        .renderer()
        .shell_stats()
        .unwrap()
        .expect("the shell pass exists with --mesher heightmap");
    assert!(
        nodes > 10 && boxes > 1000,
        "{nodes} nodes and {boxes} boxes drawn"
    );
    let off = pixels_off(&greedy, &heights);
    let pixels = (SIZE.0 * SIZE.1) as usize;
    if let Ok(dir) = std::env::var("HEIGHTMAP_FRAMES") {
        for (name, rgba) in [("greedy", &greedy), ("heightmap", &heights)] {
            let png = gpu_backend::png::encode_png(SIZE.0, SIZE.1, rgba).unwrap();
            std::fs::write(format!("{dir}/{name}.png"), png).unwrap();
        }
    }
    assert!(
        off * 100 <= pixels,
        "{off} of {pixels} pixels off by more than 8/255"
    );
    let ground = terrain_pixels(&greedy);
    assert!(ground * 2 > pixels, "only {ground} pixels of terrain");
    let (greedy_bytes, height_bytes) = (node_bytes(&greedy_view), node_bytes(&view));
    eprintln!("node data: greedy {greedy_bytes} B, heightmap {height_bytes} B; {off} px off");
    assert!(
        height_bytes * 10 <= greedy_bytes,
        "heightmap nodes hold {height_bytes} B against greedy's {greedy_bytes} B"
    );
}

#[test]
fn a_far_path_with_heightmap_cubes_is_refused_by_name() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let mut asked = settings(MesherMode::Heightmap);
    asked.far = FarRequest::Path(FarPath::Sprite);
    let Err(error) = StreamedView::new(&ctx, &asked, SIZE.0, SIZE.1) else {
        panic!("a far path cannot run with heightmap cubes");
    };
    let error = error.to_string();
    assert!(
        error.contains("heightmap") && error.contains("far"),
        "{error}"
    );
}
