//! Far draws against the CPU reference: the same scenes as the near-field image tests, every
//! node drawn from its surface blocks (ray-box cubes shaded with the meshers' AO from the
//! node's hiding mask) by each far path (splat, sprite, camera quads, and the sprite on a
//! device without any optional feature), must match the deferred CPU raycaster within the
//! image tests' tolerance, as the meshed render does.

#[allow(dead_code, reason = "each test file uses part of the shared helpers")]
mod image_support;

use gpu_backend::DeviceOptions;
use gpu_backend::render::far::{FarPath, FarRequest};
use gpu_backend::render::{OpaquePath, Renderer, RendererConfig};
use gpu_backend::test_support::headless_or_skip;
use image_support::scenes::{HEIGHT, TestScene, WIDTH, cpu_render};
use image_support::{Image, Tolerance, assert_images_match};
use mesher::lod::{NodeSettings, mesh_nodes};
use mesher::{BlockClasses, MeshSettings};
use render_model::camera::Camera;
use render_model::cull::{CullStats, LodSettings};
use render_model::lighting::Lighting;
use viewer::gpu_view::upload_nodes;
use voxel_core::{BlockId, ChunkSize, Material, MaterialPalette, WorldPos};

/// Renders `scene` with every node far-drawn by `far` (level 0 only: budget 0; a far threshold
/// no node exceeds), or every node meshed with `far_cell_px` 0.
fn far_render(
    ctx: &gpu_backend::GpuContext,
    scene: &TestScene,
    camera: &Camera,
    far: FarRequest,
    far_cell_px: f32,
    opaque: OpaquePath,
) -> (Image, CullStats) {
    let size = scene.world.size();
    let config = RendererConfig {
        opaque,
        ..RendererConfig::new(WIDTH, HEIGHT, size).with_far(far, 1 << 22)
    };
    let mut renderer = Renderer::new(ctx, &config, &scene.palette).expect("renderer");
    let classes = BlockClasses::from_palette(&scene.palette);
    let mut coords: Vec<_> = scene.world.iter().map(|(c, _)| c).collect();
    coords.sort_unstable();
    let settings = NodeSettings {
        mesh: MeshSettings::default(),
        far_blocks: true,
        ..Default::default()
    };
    let nodes = mesh_nodes(&scene.world, 0, &coords, &classes, &settings).expect("nodes");
    upload_nodes(&mut renderer, &nodes).expect("upload");
    let render_cam = *camera;
    renderer.set_camera(&render_cam);
    renderer
        .set_lighting(&Lighting::default())
        .expect("the default lighting renders");
    renderer
        .set_lod(Some(LodSettings {
            budget_px: 0.0,
            far_cell_px,
            ..LodSettings::default()
        }))
        .expect("settings");
    renderer.render().expect("frame");
    if opaque == OpaquePath::Compute {
        // The second frame skips the G-buffer pass (nothing rasterised; the depth is still
        // clear): it must show the same.
        let first = renderer.read_image().expect("readback");
        renderer.render().expect("frame");
        assert_eq!(first.rgba, renderer.read_image().expect("readback").rgba);
    }
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
    let image = Image {
        width: WIDTH,
        height: HEIGHT,
        rgba: frame.rgba,
        depth,
        surfaces: None,
    };
    (image, stats)
}

/// Every far path the device runs, named for the image files: the splat needs 64-bit atomics
/// (lavapipe in CI has them; elsewhere its absence is a visible skip).
fn far_paths(ctx: &gpu_backend::GpuContext) -> Vec<(&'static str, FarPath)> {
    let mut paths = vec![
        ("sprite", FarPath::Sprite),
        ("camera_quads", FarPath::CameraQuads),
    ];
    if ctx.capabilities.int64_atomics {
        paths.insert(0, ("splat", FarPath::Splat));
    } else {
        gpu_backend::test_support::skip("the splat needs 64-bit atomics, which this device lacks");
    }
    paths
}

/// The meshed render and every far path against the CPU reference. The fallbacks are checked
/// too: on a device with every optional feature disabled but the renderer's one requirement
/// (no 64-bit atomics, no conservative depth, no count buffer) `FarRequest::Auto` draws sprites, and they must match as well.
fn check_scene(name: &str, scene: &TestScene) {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let reference = cpu_render(scene, &scene.camera);
    let (meshed, _) = far_render(
        &ctx,
        scene,
        &scene.camera,
        FarRequest::Path(FarPath::Splat),
        0.0,
        OpaquePath::Raster,
    );
    assert_images_match(
        &format!("{name}_meshed"),
        &meshed,
        &reference,
        &Tolerance::LAVAPIPE,
    );
    // The opaque quads rasterised in compute, alone and beside far-drawn nodes.
    if ctx.capabilities.int64_atomics {
        for (label, far_cell_px) in [("meshed", 0.0), ("far", 1e9)] {
            let (image, _) = far_render(
                &ctx,
                scene,
                &scene.camera,
                FarRequest::Path(FarPath::Splat),
                far_cell_px,
                OpaquePath::Compute,
            );
            assert_images_match(
                &format!("{name}_{label}_compute_opaque"),
                &image,
                &reference,
                &Tolerance::LAVAPIPE,
            );
        }
    }
    for (label, path) in far_paths(&ctx) {
        let (far, _) = far_render(
            &ctx,
            scene,
            &scene.camera,
            FarRequest::Path(path),
            1e9,
            OpaquePath::Raster,
        );
        assert_images_match(
            &format!("{name}_far_{label}"),
            &far,
            &reference,
            &Tolerance::LAVAPIPE,
        );
    }
    // Every fallback the renderer runs with (it needs indirect first instance).
    let fallbacks = DeviceOptions {
        disable_indirect_first_instance: false,
        ..DeviceOptions::all_fallbacks()
    };
    let Some(bare) = headless_or_skip(&fallbacks) else {
        return;
    };
    assert!(!bare.capabilities.int64_atomics && !bare.capabilities.early_depth_test);
    let (far, _) = far_render(
        &bare,
        scene,
        &scene.camera,
        FarRequest::Auto,
        1e9,
        OpaquePath::Raster,
    );
    assert_images_match(
        &format!("{name}_far_fallback"),
        &far,
        &reference,
        &Tolerance::LAVAPIPE,
    );
}

#[test]
fn far_draws_of_the_terrain_match_the_reference() {
    check_scene("far_terrain", &image_support::scenes::terrain());
}

#[test]
fn far_draws_of_a_cube_across_chunk_borders_match_the_reference() {
    check_scene("far_cube", &image_support::scenes::cube(0));
}

#[test]
fn far_draws_of_a_sphere_in_water_match_the_reference() {
    check_scene("far_sphere_water", &image_support::scenes::sphere());
}

/// Far ground 100 to 340 blocks away, half of it behind a near wall (10 blocks away, meshed):
/// far blocks must lose the depth test to the wall where it is in front and win it elsewhere,
/// whatever depth their proxies were rasterised at.
fn wall_before_far_ground() -> TestScene {
    let mut palette = MaterialPalette::new();
    let stone = palette.push(Material::opaque(120, 120, 130)).unwrap();
    let grass = palette.push(Material::opaque(70, 150, 60)).unwrap();
    let wall = palette.push(Material::opaque(180, 90, 60)).unwrap();
    let fill = |x: i32, y: i32, z: i32| {
        let near_wall = (-40..=8).contains(&x) && (20..=45).contains(&y) && (30..=31).contains(&z);
        if near_wall {
            return wall;
        }
        let far = (-160..=176).contains(&x) && (-300..=-60).contains(&z);
        // Ground 2 to 4 blocks high with grass on top.
        let height = 2 + (x.rem_euclid(7) == 0) as i32 + (z.rem_euclid(5) == 0) as i32;
        match () {
            _ if !far || y > height => BlockId::AIR,
            _ if y == height => grass,
            _ => stone,
        }
    };
    let mut scene = image_support::scenes::scene_from_fn(
        palette,
        ChunkSize::S16,
        [-160, 0, -300],
        [176, 45, 31],
        0,
        fill,
    );
    scene.camera = Camera {
        voxel: WorldPos::new(8, 40, 40),
        fraction: glam::DVec3::splat(0.5),
        yaw: 0.0,
        pitch: -0.4,
        fov_y: 70f64.to_radians(),
        near: Camera::DEFAULT_NEAR,
    };
    scene
}

#[test]
fn far_blocks_half_hidden_behind_a_near_wall_match_the_reference() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let scene = wall_before_far_ground();
    let reference = cpu_render(&scene, &scene.camera);
    // Cells of the wall span about 7 pixels, those of the ground under 1: a 2-pixel far
    // threshold meshes the wall and far-draws the ground.
    for (label, path) in far_paths(&ctx) {
        let (image, stats) = far_render(
            &ctx,
            &scene,
            &scene.camera,
            FarRequest::Path(path),
            2.0,
            OpaquePath::Raster,
        );
        assert!(stats.mesh_nodes > 0, "the wall is meshed: {stats:?}");
        assert!(stats.far_nodes > 0, "the ground is far-drawn: {stats:?}");
        assert_images_match(
            &format!("wall_far_ground_{label}"),
            &image,
            &reference,
            &Tolerance::LAVAPIPE,
        );
    }
}
