//! The grass pass against the CPU rasterisation of the same crossed quads
//! (`voxel_reference::grass_raster`), on lavapipe in CI: still, at a fixed wind time, moving
//! with the time, and gone when clutter is turned off.
//!
//! The scene is two chunks of clutter units only (blades and flowers of several sizes, seeds
//! and tints), so every pixel is grass or sky. Occlusion culling is off: a chunk without quads
//! has no mesh box to test. Comparison rules and tolerances are `image_support`'s.

#[allow(dead_code, reason = "each test file uses part of the shared helpers")]
mod image_support;

use glam::{DVec3, Vec2, Vec3};
use gpu_backend::DeviceOptions;
use gpu_backend::render::{OpaquePath, RenderError, Renderer, RendererConfig};
use gpu_backend::test_support::{headless_or_skip, skip};
use image_support::{Image, Tolerance, assert_images_match};
use render_model::Camera;
use render_model::cull::lod;
use render_model::grass::{DEFAULT_BUDGET_PX, GrassFrame, unit_corners, wind_phase};
use render_model::lighting::Lighting;
use render_model::resident::ChunkMeshData;
use voxel_core::formats::{ChunkLayersData, ClutterUnit, ClutterUnitFields, UnormExtent};
use voxel_core::{ChunkCoord, ChunkSize, MaterialPalette, WorldPos};
use voxel_reference::grass_raster::{GrassChunk, render_grass};

const WIDTH: u32 = 96;
const HEIGHT: u32 = 72;

/// The renderer image tests' lavapipe tolerance: measured here, every pixel's coverage agrees
/// (edges included), colour within 1 code, depth within 7e-6 blocks.
const GRASS: Tolerance = Tolerance::LAVAPIPE;

fn size() -> ChunkSize {
    ChunkSize::from_edge(16).expect("chunk size")
}

/// A 6 x 8 field of units in a chunk: every fourth kind a flower, seeds and scale steps
/// varying, green blade tints and a red, yellow or violet flower head.
fn units(chunk: u32) -> Vec<ClutterUnit> {
    let extent = UnormExtent::new(size().edge() as f32).expect("extent");
    let mut out = Vec::new();
    // Both chunks' fields meet near x = 16, in front of the camera.
    let x0 = if chunk == 0 { 9.3 } else { 0.5 };
    for i in 0..48u32 {
        let (x, z) = (i % 6, i / 6);
        let kind = ((i + chunk) % 8) as u8;
        let flower = kind % 4 == 3;
        let tint = if flower {
            [[220, 40, 40, 255], [230, 210, 40, 255], [150, 60, 200, 255]][i as usize % 3]
        } else {
            [60 + (i * 5 % 40) as u8, 150 + (i * 7 % 60) as u8, 40, 255]
        };
        let fields = ClutterUnitFields {
            position: Vec3::new(x0 + 1.2 * x as f32, 2.0, 1.0 + 0.9 * z as f32),
            normal: Vec3::Y,
            kind,
            scale_step: ((i * 7) % 16) as u8,
            seed: ((i * 5 + chunk) % 16) as u8,
            uv: Vec2::new(f32::from(kind % 16) / 16.0, f32::from(kind / 16) / 16.0),
            uv_size: Vec2::splat(15.0 / 255.0),
            tint,
        };
        out.push(ClutterUnit::encode(&fields, extent).expect("unit encodes"));
    }
    out
}

fn camera() -> Camera {
    Camera::new(
        WorldPos::new(16, 3, -2),
        DVec3::new(0.0, 0.3, 0.5),
        std::f64::consts::PI,
        -0.4,
        0.9,
    )
}

struct Scene {
    chunks: Vec<(ChunkCoord, Vec<ClutterUnit>)>,
}

fn scene() -> Scene {
    Scene {
        chunks: (0..2)
            .map(|x| (ChunkCoord::new(x, 0, 0), units(x as u32)))
            .collect(),
    }
}

fn renderer(ctx: &gpu_backend::GpuContext, scene: &Scene, clutter: bool) -> Renderer {
    renderer_on(ctx, scene, clutter, OpaquePath::Raster)
}

fn renderer_on(
    ctx: &gpu_backend::GpuContext,
    scene: &Scene,
    clutter: bool,
    opaque: OpaquePath,
) -> Renderer {
    let mut config = RendererConfig {
        occlusion: false,
        antialias: false,
        opaque,
        ..RendererConfig::new(WIDTH, HEIGHT, size())
    };
    // Without clutter the units are still stored (the gigabuffer has their space), only not
    // drawn: the grass pass is not built.
    config = config.with_clutter(1 << 20);
    config.clutter = clutter;
    let palette = MaterialPalette::default();
    let mut r = Renderer::new(ctx, &config, &palette).expect("renderer");
    for (coord, units) in &scene.chunks {
        let layers = ChunkLayersData {
            clutter_units: units,
            ..Default::default()
        };
        r.upload_chunk(&ChunkMeshData {
            coord: *coord,
            lod: 0,
            layers,
        })
        .expect("upload");
    }
    r.set_camera(&camera());
    r
}

fn gpu_image(r: &mut Renderer) -> (Image, Vec<String>) {
    let times = r.render().expect("frame");
    let frame = r.read_image().expect("readback");
    let cam = *r.camera();
    let depth = frame
        .depth
        .iter()
        .enumerate()
        .map(|(i, &d)| cam.eye_distance(i as u32 % WIDTH, i as u32 / WIDTH, WIDTH, HEIGHT, d))
        .collect();
    let image = Image {
        width: WIDTH,
        height: HEIGHT,
        rgba: frame.rgba,
        depth,
        surfaces: None,
    };
    (image, times.into_iter().map(|t| t.label).collect())
}

fn cpu_image(scene: &Scene, seconds: f64, wind: f32) -> Image {
    let cam = camera();
    let frame = GrassFrame {
        wind_phase: wind_phase(seconds),
        wind_strength: wind,
        focal_px: lod::focal_px(cam.fov_y, HEIGHT),
        budget_px: DEFAULT_BUDGET_PX,
    };
    let chunks: Vec<GrassChunk<'_>> = scene
        .chunks
        .iter()
        .map(|(coord, units)| GrassChunk {
            coord: *coord,
            units,
        })
        .collect();
    let g = render_grass(
        &chunks,
        size(),
        &cam,
        &Lighting::default(),
        &frame,
        WIDTH,
        HEIGHT,
    );
    let depth = g
        .depth
        .iter()
        .enumerate()
        .map(|(i, &d)| cam.eye_distance(i as u32 % WIDTH, i as u32 / WIDTH, WIDTH, HEIGHT, d))
        .collect();
    Image {
        width: WIDTH,
        height: HEIGHT,
        rgba: g.rgba,
        depth,
        surfaces: None,
    }
}

fn grass_pixels(image: &Image) -> usize {
    image.depth.iter().filter(|d| d.is_finite()).count()
}

#[test]
fn still_grass_matches_the_cpu_rasterisation() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let scene = scene();
    let mut r = renderer(&ctx, &scene, true);
    r.set_wind(0.0).expect("wind");
    r.set_time(5.0);
    let (gpu, labels) = gpu_image(&mut r);
    assert!(labels.iter().any(|l| l == "grass"), "timed: {labels:?}");
    let cpu = cpu_image(&scene, 5.0, 0.0);
    assert!(grass_pixels(&cpu) > 500, "the scene shows grass");
    assert_images_match("grass_still", &gpu, &cpu, &GRASS);
    let units = scene.chunks.iter().map(|(_, u)| u.len() as u32).sum();
    assert_eq!(r.grass_stats().expect("stats"), Some((2, units)));
}

/// Without `MULTI_DRAW_INDIRECT_COUNT` the compacted draw list is drawn with its zeroed tail:
/// the same image and counts.
#[test]
fn still_grass_matches_without_indirect_count() {
    let options = DeviceOptions {
        disable_indirect_count: true,
        ..DeviceOptions::default()
    };
    let Some(ctx) = headless_or_skip(&options) else {
        return;
    };
    let scene = scene();
    let mut r = renderer(&ctx, &scene, true);
    r.set_wind(0.0).expect("wind");
    r.set_time(5.0);
    // Two frames: the second draws over a draw list the first filled.
    gpu_image(&mut r);
    let (gpu, _) = gpu_image(&mut r);
    assert_images_match(
        "grass_still_no_count",
        &gpu,
        &cpu_image(&scene, 5.0, 0.0),
        &GRASS,
    );
    let units = scene.chunks.iter().map(|(_, u)| u.len() as u32).sum();
    assert_eq!(r.grass_stats().expect("stats"), Some((2, units)));
}

#[test]
fn swaying_grass_matches_the_cpu_rasterisation_at_a_fixed_time() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let scene = scene();
    let mut r = renderer(&ctx, &scene, true);
    r.set_time(1.3);
    let (gpu, _) = gpu_image(&mut r);
    assert_images_match("grass_wind", &gpu, &cpu_image(&scene, 1.3, 1.0), &GRASS);
}

/// The wind moves the image with the time; each time's frame is the CPU rasterisation of
/// quads whose bases stay and whose tops move.
#[test]
fn the_wind_time_moves_the_tops_and_not_the_bases() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let scene = scene();
    let mut r = renderer(&ctx, &scene, true);
    r.set_time(0.2);
    let (a, _) = gpu_image(&mut r);
    r.set_time(1.7);
    let (b, _) = gpu_image(&mut r);
    let differ = (0..a.depth.len())
        .filter(|&i| a.rgba[4 * i..4 * i + 4] != b.rgba[4 * i..4 * i + 4])
        .count();
    assert!(differ > 50, "only {differ} pixels changed with the time");
    // Repeating a time repeats the frame.
    r.set_time(0.2);
    let (again, _) = gpu_image(&mut r);
    assert_eq!(again.rgba, a.rgba, "the same time draws the same frame");
    // The second frame is the CPU rasterisation's at its time, whose quads keep every base
    // where it was and move every top.
    assert_images_match("grass_wind_later", &b, &cpu_image(&scene, 1.7, 1.0), &GRASS);
    let extent = UnormExtent::new(size().edge() as f32).expect("extent");
    let at = |t: f64| GrassFrame {
        wind_phase: wind_phase(t),
        wind_strength: 1.0,
        focal_px: 1.0e4,
        budget_px: DEFAULT_BUDGET_PX,
    };
    for u in scene.chunks.iter().flat_map(|(_, u)| u) {
        let f = u.decode(extent);
        let (qa, qb) = (
            unit_corners(&f, Vec3::ZERO, &at(0.2)),
            unit_corners(&f, Vec3::ZERO, &at(1.7)),
        );
        for q in 0..2 {
            assert_eq!(qa[q][..2], qb[q][..2], "bases stay");
            assert_ne!(qa[q][2..], qb[q][2..], "tops sway");
        }
    }
}

#[test]
fn turning_clutter_off_removes_the_grass() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let scene = scene();
    let mut r = renderer(&ctx, &scene, true);
    let (on, _) = gpu_image(&mut r);
    assert!(grass_pixels(&on) > 500);
    r.set_clutter(false).expect("off");
    let (off, labels) = gpu_image(&mut r);
    assert_eq!(grass_pixels(&off), 0, "no grass with clutter off");
    assert!(
        !labels.iter().any(|l| l == "grass"),
        "no grass pass: {labels:?}"
    );
    r.set_clutter(true).expect("on again");
    let (again, _) = gpu_image(&mut r);
    assert_eq!(again.rgba, on.rgba);
    // A renderer made without clutter has no grass pass and refuses to turn it on.
    let mut plain = renderer(&ctx, &scene, false);
    assert!(matches!(
        plain.set_clutter(true),
        Err(RenderError::ClutterUnavailable(_))
    ));
    assert_eq!(plain.grass_stats().expect("stats"), None);
    let (none, _) = gpu_image(&mut plain);
    assert_eq!(grass_pixels(&none), 0);
}

/// On the compute opaque path the G-buffer pass skips its depth clear while nothing raster
/// drew: the grass draws depth, so turning it off must still clear it.
#[test]
fn turning_clutter_off_on_the_compute_opaque_path_leaves_no_grass_depth() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    if !ctx.capabilities.int64_atomics {
        skip("the compute opaque path needs 64-bit atomics");
        return;
    }
    let scene = scene();
    let mut r = renderer_on(&ctx, &scene, true, OpaquePath::Compute);
    let (on, _) = gpu_image(&mut r);
    assert!(grass_pixels(&on) > 500);
    r.set_clutter(false).expect("off");
    let (off, _) = gpu_image(&mut r);
    assert_eq!(
        grass_pixels(&off),
        0,
        "no grass depth left with clutter off"
    );
}
