//! Far draws against the CPU reference: the same scenes as the near-field image tests, every
//! node drawn from its surface blocks (ray-box cubes shaded with the meshers' AO from the
//! node's hiding mask), must match the deferred CPU raycaster within the image tests'
//! tolerance, as the meshed render does.

#[allow(dead_code, reason = "each test file uses part of the shared helpers")]
mod image_support;

use gpu_backend::DeviceOptions;
use gpu_backend::cull::LodSettings;
use gpu_backend::render::far::{FarPath, FarRequest};
use gpu_backend::render::{Renderer, RendererConfig};
use gpu_backend::test_support::headless_or_skip;
use image_support::scenes::{HEIGHT, TestScene, WIDTH, cpu_render};
use image_support::{Image, Tolerance, assert_images_match};
use mesher::lod::{NodeSettings, mesh_nodes};
use mesher::{BlockClasses, MeshSettings};
use viewer::camera::Camera;
use viewer::gpu_view::{render_camera, upload_nodes};
use viewer::lighting::{Lighting, lighting_params};

/// Renders `scene` with every node far-drawn by `far` (level 0 only: budget 0; a far threshold
/// no node exceeds), or every node meshed with `far_cell_px` 0.
fn far_render(
    ctx: &gpu_backend::GpuContext,
    scene: &TestScene,
    camera: &Camera,
    far: FarRequest,
    far_cell_px: f32,
) -> Image {
    let size = scene.world.size();
    let config = RendererConfig::new(WIDTH, HEIGHT, size).with_far(far, 1 << 22);
    let mut renderer = Renderer::new(ctx, &config, &scene.palette).expect("renderer");
    let classes = BlockClasses::from_palette(&scene.palette);
    let mut coords: Vec<_> = scene.world.iter().map(|(c, _)| c).collect();
    coords.sort_unstable();
    let settings = NodeSettings {
        mesh: MeshSettings::default(),
        far_blocks: true,
    };
    let nodes = mesh_nodes(&scene.world, 0, &coords, &classes, &settings).expect("nodes");
    upload_nodes(&mut renderer, &nodes).expect("upload");
    let render_cam = render_camera(camera, size);
    renderer.set_camera(&render_cam);
    renderer.set_lighting(&lighting_params(&Lighting::default()));
    renderer
        .set_lod(Some(LodSettings {
            budget_px: 0.0,
            far_cell_px,
            ..LodSettings::default()
        }))
        .expect("settings");
    renderer.render().expect("frame");
    let (stats, splat) = renderer.read_frame_stats().expect("stats");
    if far_cell_px > 0.0 {
        assert!(stats.far_nodes > 0 && stats.far_blocks > 0, "{stats:?}");
        assert_eq!(splat.skipped, 0, "no block is too large or too near");
    } else {
        assert_eq!(stats.far_nodes, 0);
    }
    let frame = renderer.read_image().expect("readback");
    let depth = frame
        .depth
        .iter()
        .enumerate()
        .map(|(i, &d)| {
            let (x, y) = (i as u32 % WIDTH, i as u32 / WIDTH);
            render_cam.eye_distance(x, y, WIDTH, HEIGHT, d)
        })
        .collect();
    Image {
        width: WIDTH,
        height: HEIGHT,
        rgba: frame.rgba,
        depth,
        surfaces: None,
    }
}

fn check_scene(name: &str, scene: &TestScene) {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let reference = cpu_render(scene, &scene.camera);
    let meshed = far_render(
        &ctx,
        scene,
        &scene.camera,
        FarRequest::Path(FarPath::Splat),
        0.0,
    );
    assert_images_match(
        &format!("{name}_meshed"),
        &meshed,
        &reference,
        &Tolerance::LAVAPIPE,
    );
    let far = far_render(
        &ctx,
        scene,
        &scene.camera,
        FarRequest::Path(FarPath::Splat),
        1e9,
    );
    assert_images_match(
        &format!("{name}_far_splat"),
        &far,
        &reference,
        &Tolerance::LAVAPIPE,
    );
}

#[test]
fn far_splat_of_the_terrain_matches_the_reference() {
    check_scene("far_terrain", &image_support::scenes::terrain());
}

#[test]
fn far_splat_of_a_cube_across_chunk_borders_matches_the_reference() {
    check_scene("far_cube", &image_support::scenes::cube(0));
}

#[test]
fn far_splat_of_a_sphere_in_water_matches_the_reference() {
    check_scene("far_sphere_water", &image_support::scenes::sphere());
}
