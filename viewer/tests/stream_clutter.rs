//! Clutter placed only where the grass pass can draw it (`StreamSettings::clutter_placement`,
//! `render_model::grass::may_draw_grass`), on the local Vulkan adapter (lavapipe here): the
//! resident clutter is a small part of what every level-0 node would carry, the near frame
//! and the grass drawn are those of clutter on every node, and a flight out and back (over
//! the cache of dropped nodes) gives clutter to the nodes it nears and takes it from those it
//! leaves, with no frame drawing a node that lacks its clutter. Without an adapter each test
//! prints `skipped: ...` (and fails under `CI=true`).

mod support;

use std::collections::HashSet;
use std::time::Duration;

use gpu_backend::test_support::headless_or_skip;
use gpu_backend::{DeviceOptions, GpuContext};
use render_model::camera::Camera;
use render_model::cull::{LodParams, lod};
use render_model::grass::chunk_may_draw_grass;
use viewer::headless::{draw_frame, load};
use viewer::scene::{Terrain, TerrainBlocks};
use viewer::stream::{ClutterPlacement, NodeKey, StreamSettings};
use viewer::view::StreamedView;
use voxel_core::WorldPos;
use voxel_core::formats::DataKind;

const LOAD: Duration = Duration::from_secs(300);
/// Large enough for a grass reach of some 29 blocks (focal length 128 px at 1 px).
const SIZE: (u32, u32) = (320, 180);

fn context() -> Option<GpuContext> {
    headless_or_skip(&DeviceOptions::default())
}

fn settings(placement: ClutterPlacement) -> StreamSettings {
    StreamSettings {
        radius: 160,
        memory_bytes: 96 << 20,
        max_nodes: 4096,
        clutter_placement: placement,
        ..StreamSettings::default()
    }
}

/// A camera three blocks over the ground at column `(x, 40)`, looking east and a little down
/// over the meadow.
fn low_camera(x: i32) -> Camera {
    let terrain = Terrain::new(1, TerrainBlocks::palette().1);
    let ground = terrain.height(x, 40).max(terrain.sea_level);
    Camera {
        voxel: WorldPos::new(x, ground + 3, 40),
        fraction: glam::DVec3::splat(0.5),
        yaw: -std::f64::consts::FRAC_PI_2,
        pitch: -0.2,
        fov_y: 70f64.to_radians(),
        near: Camera::DEFAULT_NEAR,
    }
}

/// The clutter units in the view's gigabuffer (resident and cached nodes).
fn resident_units(view: &StreamedView) -> u64 {
    let used = view.renderer().gigabuffer().resident();
    used.kinds.get(DataKind::Clutter).used_bytes / 20
}

/// A frame of `view`: its pixels and the grass pass's `(chunks, units)` drawn.
fn frame(ctx: &GpuContext, view: &mut StreamedView) -> (Vec<u8>, (u32, u32)) {
    view.renderer_mut().set_time(1.5);
    draw_frame(ctx, view).unwrap();
    let stats = view
        .renderer()
        .grass_stats()
        .unwrap()
        .expect("a grass pass");
    (view.renderer().read_image().unwrap().rgba, stats)
}

/// The low camera moved to where `view`'s committed anchor is: a fresh view loaded there
/// plans from the same anchor (the camera is within the hysteresis of it), so the two select
/// the same nodes.
fn at_anchor(view: &StreamedView, like: &Camera) -> Camera {
    let anchor = view.streamer().anchor().expect("a committed plan");
    let edge = f64::from(view.settings().chunk.edge());
    let c = [anchor.chunk.x, anchor.chunk.y, anchor.chunk.z];
    let p = glam::DVec3::from_array(std::array::from_fn(|a| {
        f64::from(c[a]) * edge + f64::from(anchor.offset[a])
    }));
    let floor = p.floor();
    Camera {
        voxel: WorldPos::new(floor.x as i32, floor.y as i32, floor.z as i32),
        fraction: p - floor,
        ..*like
    }
}

/// Whether the placement rule admits level-0 node `key` from `view`'s committed anchor.
fn admitted(view: &StreamedView, key: &NodeKey) -> bool {
    let anchor = view.streamer().anchor().expect("a committed plan");
    let settings = view.settings();
    let budget = view
        .streamer()
        .status()
        .budget_px
        .expect("a committed plan");
    let params = LodParams {
        anchor_chunk: [anchor.chunk.x, anchor.chunk.y, anchor.chunk.z],
        top_level: settings.top_level(),
        anchor_offset: anchor.offset,
        budget_px: budget,
        focal_px: lod::focal_px(view.renderer().camera().fov_y, SIZE.1),
        hysteresis: settings.hysteresis,
        chunk_edge: settings.chunk.edge() as f32,
        pad: 0,
    };
    key.level == 0 && chunk_may_draw_grass(&params, [key.coord.x, key.coord.y, key.coord.z])
}

/// Draws `near` from `camera` (within the hysteresis of its anchor) beside a fresh view with
/// clutter on every level-0 node loaded there: the near view's clutter nodes are exactly
/// those of the other that the rule admits, the grass pass draws the same chunks and units,
/// and the frames match. Returns the grass drawn and the two views' clutter units.
fn matches_everywhere(ctx: &GpuContext, near: &mut StreamedView, camera: &Camera) -> [u64; 3] {
    let mut all =
        StreamedView::new(ctx, &settings(ClutterPlacement::Everywhere), SIZE.0, SIZE.1).unwrap();
    load(&mut all, camera, LOAD, |_| {}).unwrap();
    near.update(camera).unwrap();
    assert_eq!(near.streamer().anchor(), all.streamer().anchor());
    let mine: HashSet<NodeKey> = near.streamer().clutter_keys().copied().collect();
    let theirs: HashSet<NodeKey> = all
        .streamer()
        .clutter_keys()
        .filter(|k| admitted(near, k))
        .copied()
        .collect();
    let odd: Vec<&NodeKey> = mine.symmetric_difference(&theirs).take(4).collect();
    assert!(
        odd.is_empty(),
        "{} nodes hold clutter, the rule admits {} of the {} nodes with clutter everywhere \
         (differing: {odd:?} ...)",
        mine.len(),
        theirs.len(),
        all.streamer().status().clutter_nodes
    );
    let (got, got_stats) = frame(ctx, near);
    let (want, want_stats) = frame(ctx, &mut all);
    eprintln!("stream_clutter: grass drawn {got_stats:?} near, {want_stats:?} everywhere");
    assert_eq!(got_stats, want_stats, "(chunks, units) the grass pass drew");
    let (largest, beyond) = support::image_difference(&got, &want, 0);
    eprintln!(
        "stream_clutter: largest channel difference {largest}, {:.3}% of pixels differ",
        beyond * 100.0
    );
    support::assert_shows(&got, &want, 0.0, "clutter within the grass reach");
    [
        u64::from(got_stats.1),
        near.streamer().status().clutter_units,
        all.streamer().status().clutter_units,
    ]
}

#[test]
fn clutter_stays_within_the_grass_reach_and_the_frame_is_the_same() {
    let Some(ctx) = context() else { return };
    let camera = low_camera(0);
    let mut near =
        StreamedView::new(&ctx, &settings(ClutterPlacement::Near), SIZE.0, SIZE.1).unwrap();
    load(&mut near, &camera, LOAD, |_| {}).unwrap();
    let status = near.streamer().status();
    assert_eq!(
        resident_units(&near),
        status.clutter_units,
        "the gigabuffer's clutter"
    );
    assert!(near.streamer().clutter_missing().is_empty());
    assert!(near.streamer().stray_clutter().is_empty());
    let [drawn, mine, everywhere] = matches_everywhere(&ctx, &mut near, &camera);
    eprintln!(
        "stream_clutter: {mine} units on {} nodes within the grass reach, {everywhere} with \
         clutter on every level-0 node; {drawn} drawn",
        status.clutter_nodes
    );
    assert!(drawn > 1000, "grass in view");
    assert!(
        mine * 4 < everywhere,
        "{mine} units within the reach of {everywhere} on every node"
    );
}

/// Flies the low camera from column `from` to `to` (x), `step` blocks a frame, checking every
/// frame that no node the committed plan places clutter on lacks it and no hole shows.
fn fly(ctx: &GpuContext, view: &mut StreamedView, from: i32, to: i32, step: i32) -> usize {
    let mut frames = 0;
    let mut x = from;
    while x != to {
        x = if to > x {
            (x + step).min(to)
        } else {
            (x - step).max(to)
        };
        view.update(&low_camera(x)).unwrap();
        assert!(view.ready());
        let streamer = view.streamer();
        assert!(streamer.holes().is_empty(), "a hole at x = {x}");
        let missing = streamer.clutter_missing();
        assert!(missing.is_empty(), "x = {x}: no clutter on {missing:?}");
        draw_frame(ctx, view).unwrap();
        frames += 1;
    }
    frames
}

#[test]
fn a_flight_gives_clutter_to_the_nodes_it_nears_and_takes_it_from_those_it_leaves() {
    let Some(ctx) = context() else { return };
    let mut view =
        StreamedView::new(&ctx, &settings(ClutterPlacement::Near), SIZE.0, SIZE.1).unwrap();
    load(&mut view, &low_camera(0), LOAD, |_| {}).unwrap();
    let start: HashSet<_> = view.streamer().clutter_keys().copied().collect();
    let start_units = view.streamer().status().clutter_units;
    let before = view.streamer().counters();

    // Out 240 blocks east, past the streamed radius of the start: the start's nodes leave
    // the grass reach (their clutter dropped, or the node cached) and the nodes ahead gain it.
    fly(&ctx, &mut view, 0, 240, 4);
    load(&mut view, &low_camera(240), LOAD, |_| {}).unwrap();
    let out = view.streamer().counters();
    let status = view.streamer().status();
    let there: HashSet<_> = view.streamer().clutter_keys().copied().collect();
    eprintln!(
        "stream_clutter: out: {} clutter swaps, {} units on {} nodes ({start_units} at the \
         start), {} cached",
        out.clutter_swaps - before.clutter_swaps,
        status.clutter_units,
        status.clutter_nodes,
        status.cached_nodes
    );
    assert!(
        out.clutter_swaps > before.clutter_swaps,
        "resident nodes gained or dropped clutter as the reach moved"
    );
    assert!(
        start.is_disjoint(&there),
        "the start's nodes hold no clutter now"
    );
    assert!(!there.is_empty());
    assert!(view.streamer().stray_clutter().is_empty());
    assert!(status.clutter_units < start_units * 3, "{status:?}");

    // Back to the start: nodes come back from the cache, with the clutter they need.
    fly(&ctx, &mut view, 240, 0, 4);
    load(&mut view, &low_camera(0), LOAD, |_| {}).unwrap();
    let back = view.streamer().counters();
    assert!(back.cache_hits > out.cache_hits, "{back:?}");
    assert!(view.streamer().clutter_missing().is_empty());
    assert!(view.streamer().stray_clutter().is_empty());
    let camera = at_anchor(&view, &low_camera(0));
    let [drawn, mine, everywhere] = matches_everywhere(&ctx, &mut view, &camera);
    assert!(
        drawn > 1000 && mine * 4 < everywhere,
        "{drawn} {mine} {everywhere}"
    );
}
