//! The view the node-geometry tests compare (`stream_shells.rs`, `stream_heightmap.rs`): a
//! small streamed view over the hills near the origin that lavapipe loads in seconds, drawn
//! with one mesher mode, and the pixel comparisons of two frames of it.
#![allow(
    dead_code,
    reason = "each test crate uses a different part of the helpers"
)]

use std::time::Duration;

use gpu_backend::GpuContext;
use render_model::camera::Camera;
use viewer::headless::{draw_frame, load};
use viewer::stream::{MesherMode, StreamSettings};
use viewer::view::StreamedView;
use voxel_core::WorldPos;

/// How long a view may take to load: a guard against a hang, not a speed check.
pub(crate) const LOAD: Duration = Duration::from_secs(300);
/// The frame size.
pub(crate) const SIZE: (u32, u32) = (240, 135);

/// The small view's settings, meshed by `mesher`.
pub(crate) fn settings(mesher: MesherMode) -> StreamSettings {
    StreamSettings {
        radius: 160,
        memory_bytes: 64 << 20,
        max_nodes: 4096,
        mesher,
        ..StreamSettings::default()
    }
}

/// Over the hills near the origin, looking out at 20 degrees down.
pub(crate) fn camera() -> Camera {
    Camera {
        voxel: WorldPos::new(0, 50, 0),
        fraction: glam::DVec3::splat(0.5),
        yaw: 0.6,
        pitch: -20f64.to_radians(),
        fov_y: 70f64.to_radians(),
        near: Camera::DEFAULT_NEAR,
    }
}

/// The loaded view of `settings`' frame (RGBA8), and the view.
pub(crate) fn frame(ctx: &GpuContext, settings: &StreamSettings) -> (Vec<u8>, StreamedView) {
    let mut view = StreamedView::new(ctx, settings, SIZE.0, SIZE.1).unwrap();
    load(&mut view, &camera(), LOAD, |_| {}).unwrap();
    view.update(&camera()).unwrap();
    draw_frame(ctx, &mut view).unwrap();
    let rgba = view.renderer().read_image().unwrap().rgba;
    (rgba, view)
}

/// Pixels of two RGBA8 frames whose colour differs by more than 8/255 in some channel.
pub(crate) fn pixels_off(a: &[u8], b: &[u8]) -> usize {
    a.chunks_exact(4)
        .zip(b.chunks_exact(4))
        .filter(|(a, b)| a.iter().zip(*b).take(3).any(|(x, y)| x.abs_diff(*y) > 8))
        .count()
}

/// Pixels of `rgba` that are not the colour of its first pixel (the sky, in this view).
pub(crate) fn terrain_pixels(rgba: &[u8]) -> usize {
    let sky = &rgba[..4];
    rgba.chunks_exact(4).filter(|p| *p != sky).count()
}
