//! The cache of dropped nodes (`StreamSettings::cache_nodes`) on the local Vulkan adapter
//! (lavapipe here): flying out and back over the same ground meshes and uploads at most 10 %
//! of the first view's nodes a second time; under a small cache the oldest nodes are evicted
//! and only what fits is reused; an edit drops a cached node it dirties; no frame shows a hole.
//! Without an adapter each test prints `skipped: ...` (and fails under `CI=true`).

use std::time::Duration;

use gpu_backend::test_support::headless_or_skip;
use gpu_backend::{DeviceOptions, GpuContext};
use render_model::camera::Camera;
use viewer::headless::load;
use viewer::stream::{StreamCounters, StreamSettings};
use viewer::view::StreamedView;
use voxel_core::WorldPos;
use voxel_world::Edit;

const LOAD: Duration = Duration::from_secs(300);
const SIZE: (u32, u32) = (160, 90);

fn context() -> Option<GpuContext> {
    headless_or_skip(&DeviceOptions::default())
}

fn settings(cache_nodes: u32) -> StreamSettings {
    StreamSettings {
        radius: 128,
        memory_bytes: 64 << 20,
        max_nodes: 4096,
        cache_nodes,
        ..StreamSettings::default()
    }
}

fn camera_at(x: i32) -> Camera {
    Camera {
        voxel: WorldPos::new(x, 60, 0),
        fraction: glam::DVec3::splat(0.5),
        yaw: 0.0,
        pitch: -20f64.to_radians(),
        fov_y: 70f64.to_radians(),
        near: Camera::DEFAULT_NEAR,
    }
}

/// Loads the view at the origin, then 320 blocks east, then at the origin again; returns the
/// counters after each leg and the first view's resident nodes.
fn out_and_back(ctx: &GpuContext, view: &mut StreamedView) -> ([StreamCounters; 3], usize) {
    let mut legs = [StreamCounters::default(); 3];
    load(view, &camera_at(0), LOAD, |_| {}).unwrap();
    legs[0] = view.streamer().counters();
    let first = view.streamer().status().resident_nodes;
    load(view, &camera_at(320), LOAD, |_| {}).unwrap();
    legs[1] = view.streamer().counters();
    assert!(view.streamer().holes().is_empty());
    load(view, &camera_at(0), LOAD, |_| {}).unwrap();
    legs[2] = view.streamer().counters();
    assert!(view.streamer().holes().is_empty());
    let _ = ctx;
    (legs, first)
}

#[test]
fn flying_back_reuses_the_nodes_it_left() {
    let Some(ctx) = context() else { return };
    let mut view = StreamedView::new(&ctx, &settings(8192), SIZE.0, SIZE.1).unwrap();
    let ([_, out, back], first) = out_and_back(&ctx, &mut view);
    let built_again = back.built - out.built;
    let uploaded_again = back.uploaded - out.uploaded;
    eprintln!(
        "stream_cache: the return built {built_again} and uploaded {uploaded_again} of the first \
         view's {first} nodes, {} taken from the cache",
        back.cache_hits - out.cache_hits
    );
    assert!(first > 100, "{first} nodes in the first view");
    assert!(
        built_again * 10 <= first as u64 && uploaded_again * 10 <= first as u64,
        "the return built {built_again} and uploaded {uploaded_again} of {first} nodes"
    );
    assert!(back.cache_hits > out.cache_hits, "{back:?}");
    let status = view.streamer().status();
    assert_eq!(
        view.memory().used(),
        status.node_bytes + status.cached_bytes,
        "the cache counts in the view's memory"
    );

    // Without a cache the same return builds most of the first view again.
    let mut plain = StreamedView::new(&ctx, &settings(0), SIZE.0, SIZE.1).unwrap();
    let ([_, out, back], first) = out_and_back(&ctx, &mut plain);
    assert_eq!(back.cache_hits, 0);
    assert!(
        (back.built - out.built) * 2 > first as u64,
        "without a cache the return builds {} of {first}",
        back.built - out.built
    );
    assert_eq!(plain.streamer().status().cached_nodes, 0);
}

#[test]
fn a_small_cache_evicts_the_oldest_and_an_edit_drops_what_it_dirties() {
    let Some(ctx) = context() else { return };
    let mut view = StreamedView::new(&ctx, &settings(32), SIZE.0, SIZE.1).unwrap();
    let ([_, out, back], first) = out_and_back(&ctx, &mut view);
    assert!(back.evicted > 0, "{back:?}");
    assert!(view.streamer().status().cached_nodes <= 32);
    let hits = back.cache_hits - out.cache_hits;
    assert!(hits <= 32, "{hits} hits from a cache of 32");
    assert!(
        (back.built - out.built) as usize + 32 >= first / 2,
        "a small cache cannot spare the return its meshing"
    );

    // Leave the origin, dirty a node the cache holds there, and come back: it is built
    // afresh from the edited world, not taken from the cache.
    let mut view = StreamedView::new(&ctx, &settings(8192), SIZE.0, SIZE.1).unwrap();
    load(&mut view, &camera_at(0), LOAD, |_| {}).unwrap();
    load(&mut view, &camera_at(320), LOAD, |_| {}).unwrap();
    let cached_before = view.streamer().status().cached_nodes;
    let before = view.streamer().counters();
    // Stone from the ground up into the air: it changes blocks whatever the ground's height.
    let stone = viewer::scene::TerrainBlocks::palette().1.stone;
    view.apply_edits(&[Edit::Box {
        min: WorldPos::new(-4, 0, -24),
        max: WorldPos::new(4, 60, -16),
        id: stone,
    }])
    .unwrap();
    let after = view.streamer().counters();
    assert!(
        after.evicted > before.evicted,
        "the edit drops dirtied cached nodes"
    );
    assert!(view.streamer().status().cached_nodes < cached_before);
}

/// With a single level the renderer draws every resident node, so the plan's dropped nodes
/// are freed, not cached (a cached node there would be drawn outside the streamed radius).
#[test]
fn a_single_level_view_caches_nothing() {
    let Some(ctx) = context() else { return };
    let small = StreamSettings {
        radius: 32,
        ..settings(8192)
    };
    assert_eq!(small.top_level(), 0);
    let mut view = StreamedView::new(&ctx, &small, SIZE.0, SIZE.1).unwrap();
    load(&mut view, &camera_at(0), LOAD, |_| {}).unwrap();
    let first = view.streamer().status().resident_nodes;
    load(&mut view, &camera_at(320), LOAD, |_| {}).unwrap();
    let status = view.streamer().status();
    assert!(first > 0 && status.resident_nodes > 0, "{status:?}");
    assert_eq!(status.cached_nodes, 0, "{status:?}");
}
