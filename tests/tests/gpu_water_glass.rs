//! Water, glass and MagicaVoxel materials on the GPU against the CPU reference, on lavapipe
//! in CI: the rule of `render_model::lighting::surface` (depth tint of volumes, Fresnel sky
//! reflection, sun highlight, metalness, emission) drawn by both renderers, and checks that
//! each effect shows where it should (each with the image it must differ from).
//!
//! The tolerance is the other image tests' ([`Tolerance::LAVAPIPE`]); a failure writes the
//! images under `target/image-tests/<name>/`.

#[allow(dead_code, reason = "each test file uses part of the shared helpers")]
mod image_support;
#[path = "../../scene/tests/support/writer.rs"]
mod writer;

use gpu_backend::DeviceOptions;
use gpu_backend::render::{OpaquePath, Renderer, RendererConfig};
use gpu_backend::test_support::headless_or_skip;
use image_support::scenes::{HEIGHT, TestScene, WIDTH, cpu_render, gpu_render, scene_from_fn};
use image_support::{Image, Tolerance, assert_images_match};
use mesher::MeshSettings;
use render_model::camera::Camera;
use viewer::gpu_view::upload_world_with;
use viewer::reference_raycast::{Trace, trace_ray};
use voxel_core::{BlockId, ChunkSize, Material, MaterialClass, MaterialPalette, WorldPos};

const TOLERANCE: Tolerance = Tolerance::LAVAPIPE;

/// The reference's ray of every pixel (row-major), for choosing pixels by what they show.
fn traces(scene: &TestScene, camera: &Camera) -> Vec<Trace> {
    let (w, h) = (WIDTH, HEIGHT);
    let block_at = |p| scene.world.get_block(p);
    (0..h)
        .flat_map(|py| (0..w).map(move |px| (px, py)))
        .map(|(px, py)| {
            let dir = camera.ray_direction(px, py, w, h);
            trace_ray(
                &block_at,
                &scene.palette,
                camera.voxel,
                camera.fraction,
                dir,
                image_support::scenes::MAX_DISTANCE,
            )
        })
        .collect()
}

/// The mean RGB of `image` over the pixels `pick` chooses from their traces, and how many.
fn mean_over(image: &Image, traces: &[Trace], pick: impl Fn(&Trace) -> bool) -> ([f64; 3], usize) {
    let mut sum = [0.0f64; 3];
    let mut n = 0;
    for (i, t) in traces.iter().enumerate() {
        if pick(t) {
            for (c, s) in sum.iter_mut().enumerate() {
                *s += f64::from(image.rgba[4 * i + c]);
            }
            n += 1;
        }
    }
    (sum.map(|s| s / n.max(1) as f64), n)
}

/// Renders `scene` on the GPU and checks it against the reference; `None` without a Vulkan
/// adapter (the skip is printed, and fails under `CI=true`).
fn gpu_matches_cpu(name: &str, scene: &TestScene) -> Option<Image> {
    let ctx = headless_or_skip(&DeviceOptions::default())?;
    let (gpu, times) = gpu_render(&ctx, scene, &scene.camera);
    assert!(
        times.iter().any(|t| t.label == "transparent"),
        "{name}: the transparent pass reports its time"
    );
    let cpu = cpu_render(scene, &scene.camera);
    assert_images_match(name, &gpu, &cpu, &TOLERANCE);
    Some(gpu)
}

fn transparent(r: u8, g: u8, b: u8, alpha: u8, roughness: u8, volume: bool) -> Material {
    Material {
        colour: [r, g, b, alpha],
        roughness,
        volume,
        ..Material::opaque(r, g, b).with_class(MaterialClass::Transparent)
    }
}

fn camera(voxel: [i32; 3], yaw: f64, pitch: f64, fov_y: f64) -> Camera {
    Camera {
        voxel: WorldPos::new(voxel[0], voxel[1], voxel[2]),
        fraction: glam::DVec3::new(0.31, 0.47, 0.53),
        yaw,
        pitch,
        fov_y,
        near: Camera::DEFAULT_NEAR,
    }
}

/// A glossy, thin glass pane three blocks over a floor with coloured blocks on it, seen from
/// above at an angle: the floor and the blocks tinted through the pane, the sky's reflection
/// and the pane's edges. (Colours change only where surfaces do: a colour edge within one
/// plane, such as a checkerboard's, is rounded differently by a rasteriser and a ray.)
#[test]
fn a_glass_pane_over_a_floor_matches_the_reference() {
    let mut palette = MaterialPalette::new();
    let light = palette.push(Material::opaque(220, 210, 190)).unwrap();
    let red = palette.push(Material::opaque(200, 50, 40)).unwrap();
    let dark = palette.push(Material::opaque(70, 80, 90)).unwrap();
    let glass = palette
        .push(transparent(150, 210, 230, 110, 30, false))
        .unwrap();
    let mut scene = scene_from_fn(
        palette,
        ChunkSize::S16,
        [-12, -1, -12],
        [12, 3, 12],
        0,
        move |x, y, z| match y {
            -1 => light,
            0 if z == -2 && x.abs() <= 8 => red,
            0 if x == 3 && z.abs() <= 8 => dark,
            3 if x.abs() <= 6 && z.abs() <= 6 => glass,
            _ => BlockId::AIR,
        },
    );
    scene.camera = camera([0, 13, 15], 0.1, -0.75, 1.0);
    gpu_matches_cpu("glass_pane_floor", &scene);
}

/// Sandy ground one block under the water's surface, with a pit eight blocks deeper.
fn pool(volume: bool) -> TestScene {
    let mut palette = MaterialPalette::new();
    let sand = palette.push(Material::opaque(215, 200, 140)).unwrap();
    let water = palette
        .push(transparent(40, 90, 170, 140, 255, volume))
        .unwrap();
    let mut scene = scene_from_fn(
        palette,
        ChunkSize::S16,
        [-12, -9, -12],
        [12, 0, 12],
        0,
        move |x, y, z| {
            let pit = (-3..=3).contains(&x) && (-3..=3).contains(&z) && y >= -8;
            if y == 0 || pit {
                water
            } else if y < 0 {
                sand
            } else {
                BlockId::AIR
            }
        },
    );
    scene.camera = camera([0, 16, 9], 0.0, -1.15, 1.0);
    scene
}

/// Water over a floor with a pit: GPU against the reference, and the deep water over the pit
/// is more tinted (less of the sand's red) than the one-block-deep water around it. The same
/// water as a thin layer (no depth tint) shows both alike, so the check fails without the tint.
#[test]
fn deep_water_is_more_tinted_than_shallow_water() {
    let scene = pool(true);
    let Some(gpu) = gpu_matches_cpu("water_pit", &scene) else {
        return;
    };
    let traces = traces(&scene, &scene.camera);
    let inside = |t: &Trace| match (t.layers[0], t.hit) {
        (Some(l), Some(h)) => Some(h.distance - l.distance),
        _ => None,
    };
    let deep = |t: &Trace| inside(t).is_some_and(|d| d > 8.0);
    let shallow = |t: &Trace| inside(t).is_some_and(|d| d < 1.6);
    let (deep_colour, n_deep) = mean_over(&gpu, &traces, deep);
    let (shallow_colour, n_shallow) = mean_over(&gpu, &traces, shallow);
    assert!(
        n_deep > 100 && n_shallow > 100,
        "{n_deep} deep, {n_shallow} shallow pixels"
    );
    assert!(
        deep_colour[0] + 40.0 < shallow_colour[0],
        "deep water {deep_colour:?} is not more tinted than shallow {shallow_colour:?}"
    );
    let ctx = headless_or_skip(&DeviceOptions::default()).expect("the adapter of the first render");
    let thin = pool(false);
    let (flat, _) = gpu_render(&ctx, &thin, &thin.camera);
    let (deep_flat, _) = mean_over(&flat, &traces, deep);
    let (shallow_flat, _) = mean_over(&flat, &traces, shallow);
    assert!(
        (deep_flat[0] - shallow_flat[0]).abs() < 12.0,
        "without the depth tint deep {deep_flat:?} and shallow {shallow_flat:?} look alike"
    );
}

/// The water pit with the opaque quads rasterised in compute: they are not in the depth
/// attachment, so the transparent pass measures the depth tint from the visibility buffer,
/// and the image must still match the reference.
#[test]
fn the_depth_tint_reads_the_compute_rasterised_depth() {
    let scene = pool(true);
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    if !ctx.capabilities.int64_atomics {
        gpu_backend::test_support::skip("the compute rasteriser needs 64-bit atomics");
        return;
    }
    let config = RendererConfig {
        opaque: OpaquePath::Compute,
        ..RendererConfig::new(WIDTH, HEIGHT, scene.world.size())
    };
    let mut renderer = Renderer::new(&ctx, &config, &scene.palette).expect("renderer");
    upload_world_with(
        &mut renderer,
        &scene.world,
        &scene.palette,
        &MeshSettings::default(),
    )
    .expect("upload");
    renderer.set_camera(&scene.camera);
    renderer.render().expect("frame");
    let frame = renderer.read_image().expect("readback");
    let cpu = cpu_render(&scene, &scene.camera);
    // The depth attachment holds no opaque surface on this path: compare the colour, with
    // the reference's depth standing in for the GPU's.
    assert!(frame.depth.iter().all(|&d| d == 0.0 || d.is_finite()));
    let gpu = Image {
        width: WIDTH,
        height: HEIGHT,
        rgba: frame.rgba,
        depth: cpu.depth.clone(),
        surfaces: None,
    };
    assert_images_match("water_pit_compute_opaque", &gpu, &cpu, &TOLERANCE);
}

/// Thin, faint water over a dark floor, smooth or fully rough.
fn dark_pond(roughness: u8) -> TestScene {
    let mut palette = MaterialPalette::new();
    let floor = palette.push(Material::opaque(35, 35, 35)).unwrap();
    let water = palette
        .push(transparent(40, 90, 170, 40, roughness, false))
        .unwrap();
    scene_from_fn(
        palette,
        ChunkSize::S16,
        [-32, -1, -64],
        [31, 0, 15],
        0,
        move |_, y, _| if y == -1 { floor } else { water },
    )
}

/// Fresnel: smooth water seen at a grazing angle reflects much more sky (it is brighter and
/// bluer) than seen straight down; fully rough water, which has no lobe, looks the same both
/// ways. Both views GPU against the reference.
#[test]
fn grazing_views_of_water_reflect_more_sky() {
    let down = camera([0, 12, -8], 0.0, -1.5, 0.7);
    let grazing = camera([0, 2, 14], 0.0, -0.12, 0.7);
    let mut brightening = Vec::new();
    for roughness in [0u8, 255] {
        let mut scene = dark_pond(roughness);
        let mut water = Vec::new();
        for (view, camera) in [("down", down), ("grazing", grazing)] {
            scene.camera = camera;
            let name = format!("fresnel_{view}_rough{roughness}");
            let Some(gpu) = gpu_matches_cpu(&name, &scene) else {
                return;
            };
            let traces = traces(&scene, &camera);
            // Water with the floor behind it, away from the image's far edge.
            let (colour, n) = mean_over(&gpu, &traces, |t| {
                t.layers[0].is_some() && t.hit.is_some_and(|h| h.distance < 60.0)
            });
            assert!(n > 1000, "{name}: {n} water pixels");
            water.push(colour);
        }
        brightening.push(water[1][2] - water[0][2]);
    }
    assert!(
        brightening[0] > 40.0,
        "smooth water: grazing is only {} codes bluer than straight down",
        brightening[0]
    );
    assert!(
        brightening[1].abs() < 6.0,
        "rough water changes by {} codes with the view",
        brightening[1]
    );
}

/// A floor with a gold metal block, an orange emissive block and a plain orange block, as a
/// MagicaVoxel file with `MATL` chunks (colour indices 1 floor, 2 metal, 3 emissive, 4 plain).
fn matl_file(metal: bool) -> Vec<u8> {
    let mut palette = [[128, 128, 128, 255]; 256];
    palette[0] = [150, 150, 150, 255];
    palette[1] = [252, 204, 48, 255];
    palette[2] = [255, 160, 40, 255];
    palette[3] = [255, 160, 40, 255];
    let mut voxels = Vec::new();
    for x in 0..16u8 {
        for y in 0..12u8 {
            voxels.push([x, y, 0, 1]);
        }
    }
    for (x0, index) in [(1u8, 2u8), (6, 3), (11, 4)] {
        for x in x0..x0 + 3 {
            for y in 4..7 {
                for z in 1..4 {
                    voxels.push([x, y, z, index]);
                }
            }
        }
    }
    let mut w = writer::VoxWriter::new();
    w.model([16, 12, 4], &voxels).palette(&palette);
    if metal {
        w.matl(
            2,
            &[("_type", "_metal"), ("_metal", "1"), ("_rough", "0.2")],
        );
    }
    w.matl(3, &[("_type", "_emit"), ("_emit", "0.8"), ("_flux", "0")]);
    w.bytes()
}

fn vox_scene(bytes: &[u8]) -> TestScene {
    let vox = viewer::scene::vox::load_vox_bytes(bytes, ChunkSize::S16, 1 << 20)
        .expect("the test file loads");
    let (lo, hi) = vox.bounds.expect("the model has voxels");
    TestScene {
        camera: viewer::scene::camera_looking_at(lo, hi),
        world: vox.world,
        palette: vox.palette,
    }
}

/// `MATL` metal and emission on the GPU against the reference: the loader gives the metal
/// block metalness and roughness and the lamp its emission; the lamp's faces are brighter than
/// the same colour without emission, and the metal block looks unlike its diffuse twin.
#[test]
fn matl_metal_and_emission_match_the_reference() {
    let bytes = matl_file(true);
    let scene = vox_scene(&bytes);
    let m = |id: u16| *scene.palette.get(BlockId(id)).unwrap();
    assert_eq!((m(2).metalness, m(2).roughness), (255, 51), "{:?}", m(2));
    assert_eq!((m(3).emission, m(3).metalness), (204, 0), "{:?}", m(3));
    assert_eq!((m(4).roughness, m(4).metalness, m(4).emission), (255, 0, 0));
    let Some(gpu) = gpu_matches_cpu("matl_metal_emit", &scene) else {
        return;
    };
    let traces = traces(&scene, &scene.camera);
    let on = |id: u16| move |t: &Trace| t.hit.is_some_and(|h| h.block == BlockId(id));
    let (lamp, n_lamp) = mean_over(&gpu, &traces, on(3));
    let (plain, n_plain) = mean_over(&gpu, &traces, on(4));
    assert!(
        n_lamp > 50 && n_plain > 50,
        "{n_lamp} lamp, {n_plain} plain pixels"
    );
    let sum = |c: [f64; 3]| c[0] + c[1] + c[2];
    assert!(
        sum(lamp) > sum(plain) + 60.0,
        "the emissive block {lamp:?} is not brighter than its plain twin {plain:?}"
    );
    let ctx = headless_or_skip(&DeviceOptions::default()).expect("the adapter of the first render");
    let diffuse = vox_scene(&matl_file(false));
    let (twin, _) = gpu_render(&ctx, &diffuse, &diffuse.camera);
    let (metal, n_metal) = mean_over(&gpu, &traces, on(2));
    let (matte, _) = mean_over(&twin, &traces, on(2));
    assert!(n_metal > 50, "{n_metal} metal pixels");
    let apart = (0..3)
        .map(|c| (metal[c] - matte[c]).abs())
        .fold(0.0, f64::max);
    assert!(
        apart > 15.0,
        "the metal block {metal:?} looks like its diffuse twin {matte:?}"
    );
}

/// The terrain's water is a smooth volume (so `terrain_patch` in `gpu_images` draws it with
/// the depth tint and the Fresnel reflection on both renderers).
#[test]
fn the_terrain_water_is_a_smooth_volume() {
    let palette_water = viewer::scene::terrain_scene(7, ChunkSize::S16, 1, 1, 1).palette;
    let water = palette_water
        .as_slice()
        .iter()
        .find(|m| m.class == MaterialClass::Transparent)
        .copied()
        .expect("the terrain has water");
    assert!(water.volume && water.roughness < 255, "{water:?}");
}
