//! The streamed terrain as heightmap cubes (`--mesher heightmap`) on the local Vulkan adapter
//! (lavapipe here): the frame of a loaded view matches the greedy frame of the same view within
//! 1 % of pixels off by more than 8/255 (the built-in terrain has no overhangs and no trees),
//! the shell pass draws the boxes, and the view's node data is at least ten times smaller
//! than the greedy view's. A far path asked for with heightmap cubes is refused by name.
//! Without an adapter each test prints `skipped: ...` (and fails under `CI=true`).

use std::time::Duration;

use gpu_backend::render::far::{FarPath, FarRequest};
use gpu_backend::test_support::headless_or_skip;
use gpu_backend::{DeviceOptions, GpuContext};
use render_model::camera::Camera;
use viewer::headless::{draw_frame, load};
use viewer::stream::{MesherMode, StreamSettings};
use viewer::view::StreamedView;
use voxel_core::WorldPos;
use voxel_core::formats::DataKind;

const LOAD: Duration = Duration::from_secs(300);
const SIZE: (u32, u32) = (240, 135);

/// A small view lavapipe streams in seconds, meshed by `mesher`, without grass (whose units
/// are the same in both geometries).
fn settings(mesher: MesherMode) -> StreamSettings {
    StreamSettings {
        radius: 160,
        memory_bytes: 64 << 20,
        max_nodes: 4096,
        mesher,
        clutter: false,
        ..StreamSettings::default()
    }
}

/// Over the hills near the origin, looking out at 20 degrees down.
fn camera() -> Camera {
    Camera {
        voxel: WorldPos::new(0, 50, 0),
        fraction: glam::DVec3::splat(0.5),
        yaw: 0.6,
        pitch: -20f64.to_radians(),
        fov_y: 70f64.to_radians(),
        near: Camera::DEFAULT_NEAR,
    }
}

/// The loaded view's frame, and the view.
fn frame(ctx: &GpuContext, mesher: MesherMode) -> (Vec<u8>, StreamedView) {
    let mut view = StreamedView::new(ctx, &settings(mesher), SIZE.0, SIZE.1).unwrap();
    load(&mut view, &camera(), LOAD, |_| {}).unwrap();
    view.update(&camera()).unwrap();
    draw_frame(ctx, &mut view).unwrap();
    let rgba = view.renderer().read_image().unwrap().rgba;
    (rgba, view)
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
    let (greedy, greedy_view) = frame(&ctx, MesherMode::Greedy);
    let (heights, view) = frame(&ctx, MesherMode::Heightmap);
    let (nodes, boxes) = view
        .renderer()
        .shell_stats()
        .unwrap()
        .expect("the shell pass exists with --mesher heightmap");
    assert!(
        nodes > 10 && boxes > 1000,
        "{nodes} nodes and {boxes} boxes drawn"
    );
    let off = greedy
        .chunks_exact(4)
        .zip(heights.chunks_exact(4))
        .filter(|(a, b)| a.iter().zip(*b).take(3).any(|(x, y)| x.abs_diff(*y) > 8))
        .count();
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
    let sky = greedy[..4].to_vec();
    let ground = greedy.chunks_exact(4).filter(|p| *p != &sky[..]).count();
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
