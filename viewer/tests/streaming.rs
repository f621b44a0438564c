//! The streamed terrain on the local Vulkan adapter (lavapipe here), at small sizes:
//! streaming converges to exactly the view's selection, moving the camera frees and loads the
//! right nodes, no frame drawn while streaming leaves sky where the full-detail terrain has
//! ground, the overlay's controls change the renderer, and screenshots are PNGs of the
//! frame's size. Without an adapter each test prints `skipped: ...` (and fails under
//! `CI=true`).

use std::collections::HashSet;
use std::time::Duration;

use gpu_backend::render::far::{FarPath, FarRequest};
use gpu_backend::render::{Renderer, RendererConfig};
use gpu_backend::test_support::headless_or_skip;
use gpu_backend::{DeviceOptions, GpuContext};
use render_model::camera::Camera;
use render_model::cull::{LodParams, lod};
use render_model::lighting::Lighting;
use viewer::controls::Controls;
use viewer::gpu_view::upload_world;
use viewer::headless::{draw_frame, load};
use viewer::scene::{Terrain, TerrainBlocks, terrain_scene, terrain_view};
use viewer::screenshot::save_screenshot;
use viewer::stream::selection::{Extent, Selection};
use viewer::stream::{MesherMode, NodeKey, StreamSettings, Streamer};
use viewer::view::StreamedView;
use voxel_core::{ChunkSize, WorldPos};

const LOAD: Duration = Duration::from_secs(300);

fn context() -> Option<GpuContext> {
    headless_or_skip(&DeviceOptions::default())
}

/// A small streamed terrain: radius `radius`, little memory, few nodes.
fn small(radius: u32) -> StreamSettings {
    StreamSettings {
        radius,
        memory_bytes: 64 << 20,
        max_nodes: 1 << 13,
        ..StreamSettings::default()
    }
}

fn terrain() -> Terrain {
    Terrain::new(1, TerrainBlocks::palette().1)
}

/// A camera at `(x, y, z)` looking along `yaw` degrees, `pitch` degrees.
fn camera_at(x: f64, y: f64, z: f64, yaw: f64, pitch: f64) -> Camera {
    let p = glam::DVec3::new(x, y, z);
    let floor = p.floor();
    Camera {
        voxel: WorldPos::new(floor.x as i32, floor.y as i32, floor.z as i32),
        fraction: p - floor,
        yaw: yaw.to_radians(),
        pitch: pitch.to_radians(),
        fov_y: 70f64.to_radians(),
        near: Camera::DEFAULT_NEAR,
    }
}

/// What the renderer's rule selects from `camera` for `settings` at `height` pixels.
fn expected(settings: &StreamSettings, camera: &Camera, height: u32) -> HashSet<NodeKey> {
    let eye = camera.eye(settings.chunk);
    let params = LodParams {
        anchor_chunk: [eye.chunk.x, eye.chunk.y, eye.chunk.z],
        top_level: settings.top_level(),
        anchor_offset: eye.offset,
        budget_px: settings.budget_px,
        focal_px: lod::focal_px(camera.fov_y, height),
        hysteresis: settings.hysteresis,
        chunk_edge: settings.chunk.edge() as f32,
        pad: 0,
    };
    let extent = Extent {
        radius: f64::from(settings.radius),
        top_block: i64::from(voxel_scene::TERRAIN_TOP),
    };
    Selection::of(&params, &extent).keys
}

fn resident(streamer: &Streamer) -> HashSet<NodeKey> {
    streamer.resident_keys().copied().collect()
}

#[test]
fn streaming_converges_and_follows_the_camera() {
    let Some(ctx) = context() else {
        return;
    };
    let settings = small(192);
    let (w, h) = (96, 54);
    let mut view = StreamedView::new(&ctx, &settings, w, h).unwrap();
    let first = terrain_view(&terrain());
    load(&mut view, &first, LOAD, |_| {}).unwrap();
    let want = expected(&settings, &first, h);
    let got = resident(view.streamer());
    assert!(want.len() > 100, "{} nodes selected", want.len());
    assert_eq!(got, want, "resident nodes are exactly the selection");
    assert!(view.streamer().holes().is_empty());
    let drawn = view.streamer().status().drawn_nodes;
    assert_eq!(view.renderer().chunk_count(), drawn);
    assert!(
        drawn > 50 && drawn < want.len(),
        "{drawn} of {} draw",
        want.len()
    );
    assert!(
        view.renderer().chunks_per_level()[1] > 0,
        "levels of detail beyond the near ring"
    );

    // 300 blocks east: the nodes of the old view that the new one lacks leave the entries
    // (freed, or kept in the cache of dropped nodes), the new ones are loaded.
    let before = view.streamer().counters();
    let moved = Camera {
        voxel: WorldPos::new(first.voxel.x + 300 / 16 * 16, first.voxel.y, first.voxel.z),
        ..first
    };
    load(&mut view, &moved, LOAD, |_| {}).unwrap();
    let want_moved = expected(&settings, &moved, h);
    let got_moved = resident(view.streamer());
    assert_eq!(got_moved, want_moved);
    let left: Vec<&NodeKey> = want.difference(&want_moved).collect();
    assert!(!left.is_empty());
    assert!(
        left.iter().all(|k| !got_moved.contains(k)),
        "left nodes freed"
    );
    let after = view.streamer().counters();
    let cached = view.streamer().status().cached_nodes;
    assert!(after.freed > before.freed || cached > 0, "{after:?}");
    assert!(after.uploaded > before.uploaded);
    assert_eq!(
        view.renderer().chunk_count(),
        view.streamer().status().drawn_nodes
    );
    assert_eq!(
        view.streamer().anchor().map(|a| a.chunk),
        Some(moved.eye(settings.chunk).chunk)
    );
}

/// A renderer holding every level-0 chunk of the terrain over `n x n` chunks of 16^3 around
/// the origin, drawn at full detail.
fn full_detail(ctx: &GpuContext, n: i32, w: u32, h: u32) -> Renderer {
    let scene = terrain_scene(1, ChunkSize::S16, n, 3, n);
    let mut config = RendererConfig::new(w, h, ChunkSize::S16);
    config.max_chunks = (n * n * 3) as u32;
    let mut renderer = Renderer::new(ctx, &config, &scene.palette).unwrap();
    upload_world(&mut renderer, &scene.world, &scene.palette).unwrap();
    renderer
        .set_lighting(&Lighting::default())
        .expect("the default lighting renders");
    renderer
}

/// What is compared: every pixel where the full-detail frame (every chunk at level 0, no LOD,
/// no far draws) shows terrain, each frame drawn while the camera moves and the view streams
/// shows terrain too (depth > 0). Coarser levels hold the finer ones' ground (a coarse cell is
/// air only where all its blocks are), so wherever the streamed frame draws a coarser node
/// its ground can only cover more; sky where full detail has ground would be a hole. The
/// camera looks down from above, so everything in view lies well inside the streamed radius
/// and the full-detail square.
#[test]
fn no_frame_shows_a_hole_while_streaming() {
    let Some(ctx) = context() else {
        return;
    };
    let settings = small(320);
    let (w, h) = (80, 48);
    let mut reference = full_detail(&ctx, 28, w, h);
    let mut view = StreamedView::new(&ctx, &settings, w, h).unwrap();
    let camera = |step: u32| {
        // East and a little north, 3 blocks a frame: the anchor moves every few frames,
        // while earlier plans are still loading.
        let x = -120.0 + 3.0 * f64::from(step);
        let z = 20.0 - f64::from(step);
        camera_at(x, 70.0, z, 250.0, -55.0)
    };
    load(&mut view, &camera(0), LOAD, |_| {}).unwrap();
    let (mut drawn_frames, mut loading_frames, mut covered) = (0, 0, 0u64);
    for step in 0..48 {
        let rc = camera(step);
        view.update(&rc).unwrap();
        assert!(view.ready());
        assert!(view.streamer().holes().is_empty(), "step {step}");
        loading_frames += usize::from(view.streamer().status().loading.is_some());
        draw_frame(&ctx, &mut view).unwrap();
        let got = view.renderer().read_image().unwrap();
        reference.set_camera(&rc);
        reference.render().unwrap();
        let want = reference.read_image().unwrap();
        let holes: Vec<usize> = (0..want.depth.len())
            .filter(|&i| want.depth[i] > 0.0 && got.depth[i] <= 0.0)
            .collect();
        assert!(
            holes.is_empty(),
            "step {step}: {} pixels show sky where the terrain is (first at {:?})",
            holes.len(),
            holes.first().map(|&i| (i as u32 % w, i as u32 / w))
        );
        covered += want.depth.iter().filter(|&&d| d > 0.0).count() as u64;
        drawn_frames += 1;
    }
    eprintln!(
        "{drawn_frames} frames drawn, {loading_frames} of them while a view loaded, {covered} \
         terrain pixels checked"
    );
    assert!(drawn_frames >= 24, "{drawn_frames} frames drawn");
    assert!(loading_frames > 0, "some frames were drawn while loading");
    assert!(covered > u64::from(w * h) * 10);
}

#[test]
fn overlay_controls_change_the_renderer() {
    let Some(ctx) = context() else {
        return;
    };
    let settings = small(128);
    let (w, h) = (96, 54);
    let mut view = StreamedView::new(&ctx, &settings, w, h).unwrap();
    // The default view: hills with lakes on either side.
    let camera = terrain_view(&terrain());
    load(&mut view, &camera, LOAD, |_| {}).unwrap();
    let frame_stats = |view: &mut StreamedView| {
        draw_frame(&ctx, view).unwrap();
        view.renderer().read_frame_stats().unwrap().0
    };
    let before = frame_stats(&mut view);
    assert!(before.far_nodes > 0, "far draws on: {before:?}");

    // The budget: a new plan, the same renderer.
    let mut controls = view.controls();
    controls.budget_px = 4.0;
    view.apply(&ctx, &controls).unwrap();
    load(&mut view, &camera, LOAD, |_| {}).unwrap();
    assert!(view.replacement().is_none());
    assert_eq!(view.renderer().lod().map(|l| l.budget_px), Some(4.0));

    // Far draws off: a replacement streamer with a renderer without a far path, swapped in
    // once loaded (the old one draws until then).
    controls.far = FarRequest::Off;
    view.apply(&ctx, &controls).unwrap();
    assert!(view.replacement().is_some());
    assert_ne!(
        view.renderer().far_choice().path,
        FarPath::Off,
        "still the old one"
    );
    load(&mut view, &camera, LOAD, |_| {}).unwrap();
    assert!(view.replacement().is_none());
    assert_eq!(view.renderer().far_choice().path, FarPath::Off);
    assert_eq!(view.renderer().lod().map(|l| l.budget_px), Some(4.0));
    let meshed = frame_stats(&mut view);
    assert_eq!(meshed.far_nodes, 0);
    assert!(meshed.transparent_quads > 0, "water in view: {meshed:?}");

    // A change taken back before it loaded: the replacement is dropped.
    let mut smooth = controls;
    smooth.mesher = MesherMode::Smooth;
    view.apply(&ctx, &smooth).unwrap();
    assert!(view.replacement().is_some());
    view.apply(&ctx, &controls).unwrap();
    assert!(view.replacement().is_none());
    assert_eq!(view.controls(), controls);

    // The transparent layer hidden: no water drawn.
    controls.layers.transparent = false;
    view.apply(&ctx, &controls).unwrap();
    load(&mut view, &camera, LOAD, |_| {}).unwrap();
    let hidden = frame_stats(&mut view);
    assert_eq!(hidden.transparent_quads, 0, "{hidden:?}");
    assert!(hidden.mesh_quads > 0);

    // The mesher mode: smooth meshes.
    assert_eq!(view.renderer().smooth_quad_count(), 0);
    controls.mesher = MesherMode::Smooth;
    view.apply(&ctx, &controls).unwrap();
    load(&mut view, &camera, LOAD, |_| {}).unwrap();
    assert!(
        view.renderer().smooth_quad_count() > 0,
        "smooth meshes resident"
    );
    assert!(frame_stats(&mut view).smooth_quads > 0);
    assert_eq!(view.controls(), controls);

    // A bad budget changes nothing and says why.
    let bad = Controls {
        budget_px: f32::NAN,
        ..controls
    };
    let err = view.apply(&ctx, &bad).unwrap_err().to_string();
    assert!(err.contains("error budget"), "{err}");
    assert_eq!(view.controls(), controls);
}

#[test]
fn screenshots_are_pngs_of_the_frame() {
    let Some(ctx) = context() else {
        return;
    };
    let settings = small(64);
    let (w, h) = (72, 40);
    let mut view = StreamedView::new(&ctx, &settings, w, h).unwrap();
    let camera = terrain_view(&terrain());
    load(&mut view, &camera, LOAD, |_| {}).unwrap();
    draw_frame(&ctx, &mut view).unwrap();
    let dir = std::env::temp_dir().join(format!("viewer-screenshots-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let first = save_screenshot(view.renderer(), &dir).unwrap();
    let second = save_screenshot(view.renderer(), &dir).unwrap();
    assert_eq!(first, dir.join("screenshot-1.png"));
    assert_eq!(second, dir.join("screenshot-2.png"), "no overwrite");
    let decoder = png::Decoder::new(std::io::Cursor::new(std::fs::read(&first).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut rgba = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut rgba).unwrap();
    assert_eq!((info.width, info.height), (w, h));
    assert_eq!(info.color_type, png::ColorType::Rgba);
    assert_eq!(rgba, view.renderer().read_image().unwrap().rgba);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The memory plan's rule: a view that does not fit its memory is drawn at a raised budget,
/// whole; one that cannot fit even at the coarsest budget is an error naming the problem.
#[test]
fn too_little_memory_raises_the_budget_and_never_holes() {
    let Some(ctx) = context() else {
        return;
    };
    let (w, h) = (96, 54);
    let camera = terrain_view(&terrain());
    let roomy = StreamSettings {
        max_nodes: 4096,
        ..small(192)
    };
    let mut view = StreamedView::new(&ctx, &roomy, w, h).unwrap();
    load(&mut view, &camera, LOAD, |_| {}).unwrap();
    let needed = view.streamer().status().drawn_nodes as u32;
    assert_eq!(view.streamer().status().memory_floor_px, None);

    // Room for a third of the nodes the view selects at 1 px.
    let tight = StreamSettings {
        max_nodes: needed / 3,
        ..roomy.clone()
    };
    let mut view = StreamedView::new(&ctx, &tight, w, h).unwrap();
    load(&mut view, &camera, LOAD, |_| {}).unwrap();
    let status = view.streamer().status();
    let floor = status.memory_floor_px.expect("the budget was raised");
    assert!(floor > 1.0);
    assert_eq!(status.budget_px, Some(floor));
    assert_eq!(view.renderer().lod().map(|l| l.budget_px), Some(floor));
    assert!(status.drawn_nodes as u32 <= needed / 3);
    assert!(view.streamer().holes().is_empty());
    let want = expected(
        &StreamSettings {
            budget_px: floor,
            ..tight.clone()
        },
        &camera,
        h,
    );
    assert_eq!(
        resident(view.streamer()),
        want,
        "the raised budget's selection, whole"
    );

    // Room for one node: not even the coarsest view fits.
    let hopeless = StreamSettings {
        max_nodes: 1,
        ..roomy
    };
    let mut view = StreamedView::new(&ctx, &hopeless, w, h).unwrap();
    let err = load(&mut view, &camera, LOAD, |_| {})
        .unwrap_err()
        .to_string();
    assert!(err.contains("do not fit even at an error budget"), "{err}");
}
