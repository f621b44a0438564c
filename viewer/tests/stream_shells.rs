//! The streamed terrain meshed as vertical shells (`--mesher shells`) on the local Vulkan
//! adapter (lavapipe here): the frame of a loaded view matches the greedy frame of the same
//! view within 1 % of pixels off by more than 8/255, the renderer draws runs, and the nodes
//! hold runs instead of opaque quads. Without an adapter each test prints `skipped: ...` (and
//! fails under `CI=true`).

use std::time::Duration;

use gpu_backend::test_support::headless_or_skip;
use gpu_backend::{DeviceOptions, GpuContext};
use render_model::camera::Camera;
use viewer::headless::{draw_frame, load};
use viewer::stream::{MesherMode, StreamSettings};
use viewer::view::StreamedView;
use voxel_core::WorldPos;

const LOAD: Duration = Duration::from_secs(300);
const SIZE: (u32, u32) = (240, 135);

/// A small view lavapipe streams in seconds, meshed by `mesher`.
fn settings(mesher: MesherMode) -> StreamSettings {
    StreamSettings {
        radius: 160,
        memory_bytes: 64 << 20,
        max_nodes: 4096,
        mesher,
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

#[test]
fn a_shell_view_matches_the_greedy_view() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let (greedy, _) = frame(&ctx, MesherMode::Greedy);
    let (shells, view) = frame(&ctx, MesherMode::Shells);
    let (nodes, runs) = view
        .renderer()
        .shell_stats()
        .unwrap()
        .expect("the shell pass exists with --mesher shells");
    assert!(
        nodes > 10 && runs > 1000,
        "{nodes} nodes and {runs} runs drawn"
    );
    let off = greedy
        .chunks_exact(4)
        .zip(shells.chunks_exact(4))
        .filter(|(a, b)| a.iter().zip(*b).take(3).any(|(x, y)| x.abs_diff(*y) > 8))
        .count();
    let pixels = (SIZE.0 * SIZE.1) as usize;
    assert!(
        off * 100 <= pixels,
        "{off} of {pixels} pixels off by more than 8/255"
    );
    // The frames differ somewhere only if something drew: the view is not empty sky.
    let sky = greedy[..4].to_vec();
    let ground = greedy.chunks_exact(4).filter(|p| *p != &sky[..]).count();
    assert!(ground * 2 > pixels, "only {ground} pixels of terrain");
}
