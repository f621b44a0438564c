//! Edits of the streamed terrain on the local Vulkan adapter (lavapipe here), at small sizes:
//! the frame right after an edit equals the frame of a view loaded from the edited world (so
//! the edit is on screen the next frame at every level that shows it, and nothing else moved);
//! a world saved and loaded draws the identical frame; the window's click breaks the block under
//! the cursor and places one in front of it; a flight carving spheres draws no frame
//! with a hole and reports its edit-to-screen latency. Without an adapter each test prints
//! `skipped: ...` (and fails under `CI=true`).

use std::time::Duration;

use gpu_backend::test_support::headless_or_skip;
use gpu_backend::{DeviceOptions, GpuContext};
use render_model::camera::Camera;
use viewer::edits::SharedWorld;
use viewer::flight::{FlightPath, fly_over};
use viewer::headless::{draw_frame, load};
use viewer::scene::{Terrain, TerrainBlocks};
use viewer::stream::StreamSettings;
use viewer::view::StreamedView;
use voxel_core::{BlockId, WorldPos};
use voxel_world::Edit;

const LOAD: Duration = Duration::from_secs(300);
const SIZE: (u32, u32) = (192, 108);

fn context() -> Option<GpuContext> {
    headless_or_skip(&DeviceOptions::default())
}

/// A small view lavapipe streams in seconds.
fn settings() -> StreamSettings {
    StreamSettings {
        radius: 160,
        memory_bytes: 64 << 20,
        max_nodes: 4096,
        ..StreamSettings::default()
    }
}

fn world() -> SharedWorld {
    let s = settings();
    SharedWorld::new(s.seed, s.chunk, s.top_level()).unwrap()
}

fn terrain() -> Terrain {
    Terrain::new(settings().seed, TerrainBlocks::palette().1)
}

/// Looking down at the ground around `(x, z)` from 24 blocks above it.
fn camera_over(x: i32, z: i32) -> Camera {
    let ground = terrain().height(x, z).max(terrain().sea_level);
    Camera {
        voxel: WorldPos::new(x, ground + 24, z + 20),
        fraction: glam::DVec3::splat(0.5),
        yaw: 0.0,
        pitch: -50f64.to_radians(),
        fov_y: 70f64.to_radians(),
        near: Camera::DEFAULT_NEAR,
    }
}

/// The edits the tests make: a pit carved at the ground, a stone pillar, a block of sand.
fn edits() -> Vec<Edit> {
    let t = terrain();
    let g = t.height(0, 0).max(t.sea_level);
    let stone = TerrainBlocks::palette().1.stone;
    vec![
        Edit::Sphere {
            centre: WorldPos::new(0, g, 0),
            radius: 6,
            id: BlockId::AIR,
        },
        Edit::Box {
            min: WorldPos::new(9, g - 2, -3),
            max: WorldPos::new(11, g + 9, -1),
            id: stone,
        },
        Edit::Block {
            pos: WorldPos::new(-8, t.height(-8, 4) + 1, 4),
            id: TerrainBlocks::palette().1.sand,
        },
    ]
}

/// A view of `world` loaded around `camera`.
fn loaded(ctx: &GpuContext, world: SharedWorld, camera: &Camera) -> StreamedView {
    let mut view = StreamedView::with_world(ctx, &settings(), SIZE.0, SIZE.1, world).unwrap();
    load(&mut view, camera, LOAD, |_| {}).unwrap();
    view
}

fn frame(ctx: &GpuContext, view: &mut StreamedView, camera: &Camera) -> Vec<u8> {
    view.update(camera).unwrap();
    draw_frame(ctx, view).unwrap();
    view.renderer().read_image().unwrap().rgba
}

/// Pixels whose channels differ by more than 2/255.
fn differing(a: &[u8], b: &[u8]) -> usize {
    a.chunks_exact(4)
        .zip(b.chunks_exact(4))
        .filter(|(p, q)| p.iter().zip(*q).any(|(x, y)| x.abs_diff(*y) > 2))
        .count()
}

fn write_png(name: &str, rgba: &[u8]) {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("stream_edits");
    std::fs::create_dir_all(&dir).unwrap();
    let png = gpu_backend::png::encode_png(SIZE.0, SIZE.1, rgba).unwrap();
    std::fs::write(dir.join(name), png).unwrap();
}

#[test]
fn the_frame_after_an_edit_is_the_edited_worlds_frame() {
    let Some(ctx) = context() else { return };
    let camera = camera_over(0, 0);
    let mut view = loaded(&ctx, world(), &camera);
    let before = frame(&ctx, &mut view, &camera);
    let done = view.apply_edits(&edits()).unwrap();
    assert!(done.swapped > 0, "the edits touch drawn nodes: {done:?}");
    let after = frame(&ctx, &mut view, &camera);
    write_png("before.png", &before);
    write_png("after.png", &after);

    let edited = world();
    edited.apply(&edits()).unwrap();
    let mut fresh = loaded(&ctx, edited, &camera);
    let reference = frame(&ctx, &mut fresh, &camera);
    write_png("reference.png", &reference);

    let changed = differing(&before, &after);
    assert!(
        changed > 300,
        "the edits are on screen the next frame: {changed} pixels changed"
    );
    let off = differing(&after, &reference);
    assert_eq!(
        off, 0,
        "the frame after the edits differs from the edited world's own frame in {off} pixels"
    );
    assert!(view.streamer().holes().is_empty());
}

#[test]
fn a_saved_and_loaded_world_draws_the_same_frame() {
    let Some(ctx) = context() else { return };
    let camera = camera_over(0, 0);
    let dir = tempfile::tempdir().unwrap();
    let first = world();
    first.apply(&edits()).unwrap();
    let saved = first.save(dir.path()).unwrap();
    assert!(saved > 0, "{saved} region files saved");
    assert!(!first.unsaved());
    let s = settings();
    let (again, report) = SharedWorld::load(dir.path(), s.seed, s.chunk, s.top_level()).unwrap();
    assert!(report.faults.is_empty(), "{:?}", report.faults);
    assert_eq!(report.regions, saved);
    assert!(report.chunks >= 3, "{} edited chunks loaded", report.chunks);
    let mut a = loaded(&ctx, first, &camera);
    let mut b = loaded(&ctx, again, &camera);
    let (fa, fb) = (frame(&ctx, &mut a, &camera), frame(&ctx, &mut b, &camera));
    assert_eq!(
        differing(&fa, &fb),
        0,
        "the loaded world draws another frame"
    );

    // Another chunk size is refused by name, not drawn wrong.
    let e = SharedWorld::load(
        dir.path(),
        s.seed,
        voxel_core::ChunkSize::S32,
        s.top_level(),
    )
    .unwrap_err();
    assert!(e.to_string().contains("chunks of"), "{e}");
}

#[test]
fn a_flight_carving_spheres_draws_no_hole_and_reports_latency() {
    let Some(ctx) = context() else { return };
    let t = terrain();
    let height = f64::from(t.height(0, 0).max(t.sea_level) + 24);
    let report = fly_over(
        &ctx,
        &settings(),
        world(),
        &FlightPath::over_origin(height),
        1.0,
        (160, 90),
        240.0,
        |_| {},
    )
    .unwrap();
    assert_eq!(report.frames_with_holes, 0);
    let edits = report.edits.clone().expect("the report has the edits");
    assert_eq!(edits.spheres, 240);
    assert!(edits.swapped_at_once > 0, "{edits:?}");
    assert!(edits.latency.max_ms > 0.0, "{edits:?}");
    assert!(
        report.lines().iter().any(|l| l.contains("edit to screen")),
        "{:?}",
        report.lines()
    );
}

#[test]
fn a_click_breaks_the_block_under_the_cursor_and_places_one_in_front() {
    use viewer::window::editing::{Brush, click};
    let Some(ctx) = context() else { return };
    let camera = camera_over(0, 0);
    let mut view = loaded(&ctx, world(), &camera);
    let centre = (SIZE.0 / 2, SIZE.1 / 2);
    let hit = |view: &StreamedView| {
        let mut w = view.world().write();
        let v = camera.voxel;
        let origin =
            glam::DVec3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z)) + camera.fraction;
        let dir = camera.ray_direction(centre.0, centre.1, SIZE.0, SIZE.1);
        viewer::edits::pick(&mut w, origin, dir, 256.0)
            .unwrap()
            .unwrap()
    };
    let before = hit(&view);
    let line = click(&mut view, &camera, centre, SIZE, Brush::default(), false).unwrap();
    assert!(line.starts_with("broke"), "{line}");
    assert_eq!(
        view.world().write().block(before.hit).unwrap(),
        BlockId::AIR
    );
    let after = hit(&view);
    assert_ne!(
        after.hit, before.hit,
        "the next pick goes past the broken block"
    );
    let stone = TerrainBlocks::palette().1.stone;
    let brush = Brush::default();
    assert_eq!(brush.block, stone);
    let line = click(&mut view, &camera, centre, SIZE, brush, true).unwrap();
    assert!(line.starts_with("placed"), "{line}");
    let placed = after.before.expect("the ray crossed air before the hit");
    assert_eq!(view.world().write().block(placed).unwrap(), stone);
    // The frame shows it: drawn like a view loaded from the edited world.
    let edited = frame(&ctx, &mut view, &camera);
    let again = world();
    again
        .apply(&[
            Edit::Block {
                pos: before.hit,
                id: BlockId::AIR,
            },
            Edit::Block {
                pos: placed,
                id: stone,
            },
        ])
        .unwrap();
    let mut fresh = loaded(&ctx, again, &camera);
    assert_eq!(differing(&edited, &frame(&ctx, &mut fresh, &camera)), 0);
}
