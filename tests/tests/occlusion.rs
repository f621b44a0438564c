//! Two-phase occlusion culling in the renderer: a chunk behind a wall is culled once the
//! depth pyramid has seen the wall, a chunk beside the wall in view is drawn, and the image is
//! the image drawn without occlusion culling.

#[allow(dead_code, reason = "each test file uses part of the shared helpers")]
mod image_support;

use gpu_backend::DeviceOptions;
use gpu_backend::render::{FrameImage, Renderer, RendererConfig};
use gpu_backend::test_support::headless_or_skip;
use image_support::scenes::{HEIGHT, TestScene, WIDTH, scene_from_fn};
use mesher::MeshSettings;
use render_model::camera::Camera;
use render_model::cull::CullStats;
use render_model::lighting::Lighting;
use viewer::gpu_view::upload_world_with;
use voxel_core::{BlockId, ChunkSize, Material, MaterialPalette, WorldPos};

/// A 16 x 16 wall 30 blocks in front of the eye (chunk (0, 0, 0)), a 7^3 cube 70 blocks
/// away straight behind it (chunk (0, 0, -3)) and one off to the side, in view (chunk
/// (2, 0, -3)).
fn wall_scene() -> TestScene {
    let mut palette = MaterialPalette::new();
    let stone = palette.push(Material::opaque(150, 150, 160)).unwrap();
    let cube = |x: i32, y: i32, z: i32, x0: i32| {
        (x0..x0 + 7).contains(&x) && (4..11).contains(&y) && (-40..-33).contains(&z)
    };
    let fill = |x: i32, y: i32, z: i32| {
        let wall = (0..16).contains(&x) && (0..16).contains(&y) && (0..2).contains(&z);
        if wall || cube(x, y, z, 4) || cube(x, y, z, 40) {
            stone
        } else {
            BlockId::AIR
        }
    };
    let mut scene = scene_from_fn(palette, ChunkSize::S16, [0, 0, -40], [46, 15, 1], 0, fill);
    scene.camera = Camera {
        voxel: WorldPos::new(8, 8, 30),
        fraction: glam::DVec3::splat(0.5),
        yaw: 0.0,
        pitch: 0.0,
        fov_y: 60f64.to_radians(),
        near: Camera::DEFAULT_NEAR,
    };
    scene
}

/// Renders `frames` frames of `scene`; returns the last frame's pixels and cull counters.
fn render(
    ctx: &gpu_backend::GpuContext,
    scene: &TestScene,
    occlusion: bool,
    frames: usize,
) -> (FrameImage, CullStats) {
    let size = scene.world.size();
    let config = RendererConfig {
        occlusion,
        ..RendererConfig::new(WIDTH, HEIGHT, size)
    };
    let mut renderer = Renderer::new(ctx, &config, &scene.palette).expect("renderer");
    upload_world_with(
        &mut renderer,
        &scene.world,
        &scene.palette,
        &MeshSettings::default(),
    )
    .expect("upload");
    renderer.set_camera(&scene.camera);
    renderer
        .set_lighting(&Lighting::default())
        .expect("the default lighting renders");
    for _ in 0..frames {
        renderer.render().expect("frame");
    }
    let (stats, _) = renderer.read_frame_stats().expect("stats");
    (renderer.read_image().expect("readback"), stats)
}

#[test]
fn a_chunk_behind_a_wall_is_culled_and_one_in_view_is_not() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let scene = wall_scene();
    let (open, open_stats) = render(&ctx, &scene, false, 1);
    assert_eq!(open_stats.occluded, 0);
    assert_eq!(open_stats.mesh_nodes, 3, "{open_stats:?}");
    // Frame 1 has no pyramid from a previous frame; by frame 3 the hidden chunk has been
    // tested against the wall's depth and stays culled.
    let (culled, stats) = render(&ctx, &scene, true, 3);
    println!("with occlusion culling: {stats:?}");
    assert_eq!(stats.selected, 3, "{stats:?}");
    assert_eq!(stats.occluded, 1, "the cube behind the wall: {stats:?}");
    assert_eq!(
        stats.mesh_nodes, 2,
        "the wall and the cube in view: {stats:?}"
    );
    let differing = open
        .rgba
        .chunks_exact(4)
        .zip(culled.rgba.chunks_exact(4))
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(differing, 0, "culling changes no pixel");
    // The cube in view shows in the right quarter of the image.
    let right_hits = (0..HEIGHT)
        .flat_map(|y| (WIDTH * 3 / 4..WIDTH).map(move |x| (y * WIDTH + x) as usize))
        .filter(|&i| culled.depth[i] > 0.0)
        .count();
    assert!(right_hits > 0, "the cube beside the wall is drawn");
}
