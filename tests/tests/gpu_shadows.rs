//! Sun shadows and sky visibility: the GPU's shadow pass against the CPU reference, on
//! lavapipe in CI.
//!
//! Each scene is drawn by `gpu_backend::render::Renderer` with [`Lighting::shadows`] on and
//! by the CPU reference (`render_deferred`) from the same description. Two things are
//! compared: the images (under the image tests' tolerance, [`Tolerance::LAVAPIPE`]), and the
//! per-pixel visibility itself, the GPU's words read back against
//! `shadow::surface_visibility` at the CPU ray's hit. The visibility sets may differ on at
//! most [`VISIBILITY_SHARE`] of the compared pixels (lavapipe): a pixel whose hit point lies
//! within rounding of a shadow boundary, where the GPU's point (from its depth buffer) and
//! the CPU's (exact) fall on two sides. Silhouette pixels (where the two renderers' depths
//! differ by more than 2 %) are not compared. Each test also checks that what it looks for is
//! there: enough shadowed pixels, darker than with shadows off.

#[allow(dead_code, reason = "each test file uses part of the shared helpers")]
mod image_support;

use gpu_backend::DeviceOptions;
use gpu_backend::GpuContext;
use gpu_backend::render::far::{FarPath, FarRequest};
use gpu_backend::render::{FullscreenPath, Renderer, RendererConfig};
use gpu_backend::test_support::headless_or_skip;
use image_support::scenes::{
    HEIGHT, MAX_DISTANCE, TestScene, WIDTH, cpu_render_lit, scene_from_fn,
};
use image_support::{Image, Tolerance, assert_images_match};
use mesher::BlockClasses;
use mesher::lod::{NodeSettings, downsample_levels, mesh_nodes};
use render_model::camera::Camera;
use render_model::cull::{CullStats, LodAnchor, LodSettings};
use render_model::lighting::Lighting;
use render_model::lighting::shadow::{GridClipped, ShadowSettings, Visibility, surface_visibility};
use viewer::gpu_view::upload_nodes;
use viewer::reference_raycast::trace_ray;
use voxel_core::{BlockId, ChunkCoord, ChunkSize, Material, MaterialPalette, WorldPos};

/// The share of compared pixels whose visibility may differ (see the module docs; set on
/// lavapipe, where the tests differ on under 1 %).
const VISIBILITY_SHARE: f64 = 0.02;

/// The default daylight with both shadow features on.
fn shadowed() -> Lighting {
    Lighting {
        shadows: ShadowSettings::default(),
        ..Lighting::default()
    }
}

/// A level-of-detail setup: the settings, the anchor and the levels to upload.
struct Lod {
    settings: LodSettings,
    anchor: LodAnchor,
    top: u32,
}

/// How the frame is drawn besides the scene: the full-screen passes' path, and whether
/// every node is far-drawn by the compute splat.
#[derive(Clone, Copy, Debug, Default)]
struct Draw {
    fullscreen: FullscreenPath,
    splat: bool,
}

/// What one GPU frame gave.
struct GpuFrame {
    image: Image,
    visibility: Option<Vec<Visibility>>,
    labels: Vec<String>,
    stats: CullStats,
}

/// Renders `scene` on the GPU under `lighting`: level-0 nodes, and with `lod` the coarser
/// levels too, selected by its settings from its anchor.
fn gpu_frame(
    ctx: &GpuContext,
    scene: &TestScene,
    lighting: &Lighting,
    lod: Option<&Lod>,
) -> GpuFrame {
    gpu_frame_drawn(ctx, scene, lighting, lod, Draw::default())
}

/// [`gpu_frame`] drawn the `draw` way.
fn gpu_frame_drawn(
    ctx: &GpuContext,
    scene: &TestScene,
    lighting: &Lighting,
    lod: Option<&Lod>,
    draw: Draw,
) -> GpuFrame {
    let mut config = RendererConfig {
        fullscreen: draw.fullscreen,
        ..RendererConfig::new(WIDTH, HEIGHT, scene.world.size())
    };
    if draw.splat {
        config = config.with_far(FarRequest::Path(FarPath::Splat), 1 << 22);
    }
    let mut renderer = Renderer::new(ctx, &config, &scene.palette).expect("renderer");
    let classes = BlockClasses::from_palette(&scene.palette);
    let settings = NodeSettings {
        mesh: mesher::MeshSettings::default(),
        far_blocks: draw.splat,
        ..Default::default()
    };
    let coords = |world: &voxel_core::storage::WorldMap<_>| {
        let mut c: Vec<ChunkCoord> = world.iter().map(|(c, _)| c).collect();
        c.sort_unstable();
        c
    };
    let nodes =
        mesh_nodes(&scene.world, 0, &coords(&scene.world), &classes, &settings).expect("level 0");
    upload_nodes(&mut renderer, &nodes).expect("upload");
    if let Some(lod) = lod {
        let levels = downsample_levels(&scene.world, &classes, lod.top).expect("levels");
        for (i, world) in levels.iter().enumerate() {
            let level = i as u32 + 1;
            let nodes =
                mesh_nodes(world, level, &coords(world), &classes, &settings).expect("level");
            upload_nodes(&mut renderer, &nodes).expect("upload");
        }
        renderer.set_lod(Some(lod.settings)).expect("lod settings");
    } else if draw.splat {
        // Level 0 everywhere, every node far-drawn.
        let far = LodSettings {
            budget_px: 0.0,
            far_cell_px: 1e9,
            ..LodSettings::default()
        };
        renderer.set_lod(Some(far)).expect("lod settings");
    }
    renderer.set_camera(&scene.camera);
    // After the camera, which moves the anchor with it.
    if let Some(lod) = lod {
        renderer.set_lod_anchor(lod.anchor);
    }
    renderer
        .set_lighting(lighting)
        .expect("the lighting renders");
    let times = renderer.render().expect("frame");
    let frame = renderer.read_image().expect("readback");
    let camera = scene.camera;
    let depth = frame
        .depth
        .iter()
        .enumerate()
        .map(|(i, &d)| camera.eye_distance(i as u32 % WIDTH, i as u32 / WIDTH, WIDTH, HEIGHT, d))
        .collect();
    let (stats, _) = renderer.read_frame_stats().expect("stats");
    GpuFrame {
        image: Image {
            width: WIDTH,
            height: HEIGHT,
            rgba: frame.rgba,
            depth,
            surfaces: None,
        },
        visibility: renderer
            .read_shadow_visibility()
            .expect("visibility readback"),
        labels: times.into_iter().map(|t| t.label).collect(),
        stats,
    }
}

/// What the CPU reference says of one pixel: its hit's normal and the visibility there.
#[derive(Clone, Copy, Debug)]
struct CpuPixel {
    voxel: WorldPos,
    normal: [i32; 3],
    distance: f32,
    seen: Visibility,
}

/// The CPU visibility of every pixel (`None` for sky), by the shared rule.
fn cpu_visibility(scene: &TestScene, lighting: &Lighting) -> Vec<Option<CpuPixel>> {
    let camera = scene.camera;
    let palette = &scene.palette;
    let block_at = |p| scene.world.get_block(p);
    let solid = |c: [i32; 3]| {
        let at = WorldPos::new(
            camera.voxel.x.wrapping_add(c[0]),
            camera.voxel.y.wrapping_add(c[1]),
            camera.voxel.z.wrapping_add(c[2]),
        );
        palette.class(block_at(at)).is_ok_and(|c| c.is_opaque())
    };
    (0..WIDTH * HEIGHT)
        .map(|i| {
            let dir = camera.ray_direction(i % WIDTH, i / WIDTH, WIDTH, HEIGHT);
            let trace = trace_ray(
                &block_at,
                palette,
                camera.voxel,
                camera.fraction,
                dir,
                MAX_DISTANCE,
            );
            let hit = trace.hit?;
            let origin = (camera.fraction + dir * hit.distance).as_vec3().to_array();
            let n = hit.normal.map(|c| c as f32);
            let seen = surface_visibility(
                &GridClipped(solid),
                &lighting.shadows,
                origin,
                n,
                lighting.sun_direction,
            );
            Some(CpuPixel {
                voxel: hit.voxel,
                normal: hit.normal,
                distance: hit.distance as f32,
                seen,
            })
        })
        .collect()
}

/// Pixels compared, and those whose sun or sky visibility differ.
#[derive(Debug, Default)]
struct VisibilityDiff {
    compared: usize,
    sun: usize,
    sky: usize,
}

fn compare_visibility(gpu: &GpuFrame, cpu: &[Option<CpuPixel>]) -> VisibilityDiff {
    let words = gpu
        .visibility
        .as_ref()
        .expect("a frame with shadows has visibility words");
    let mut diff = VisibilityDiff::default();
    for (i, c) in cpu.iter().enumerate() {
        let Some(c) = c else { continue };
        let d = gpu.image.depth[i];
        if !d.is_finite() || (d - c.distance).abs() > 0.02 * c.distance {
            continue;
        }
        diff.compared += 1;
        diff.sun += usize::from(words[i].sun != c.seen.sun);
        diff.sky += usize::from(words[i].sky_open != c.seen.sky_open);
    }
    diff
}

fn assert_visibility_agrees(name: &str, gpu: &GpuFrame, cpu: &[Option<CpuPixel>]) {
    let diff = compare_visibility(gpu, cpu);
    let allowed = (diff.compared as f64 * VISIBILITY_SHARE).ceil() as usize;
    let hits = cpu.iter().flatten().count();
    assert!(
        diff.compared * 10 > hits * 9,
        "{name}: only {} of {hits} surface pixels compared: {diff:?}",
        diff.compared
    );
    assert!(
        diff.sun <= allowed && diff.sky <= allowed,
        "{name}: GPU and CPU visibility differ on more than {allowed} pixels: {diff:?}"
    );
}

/// Mean of the RGB codes of `image` over the pixels `select` picks, and their count.
fn mean_brightness(image: &Image, select: impl Fn(usize) -> bool) -> (f64, usize) {
    let picked: Vec<usize> = (0..image.depth.len()).filter(|&i| select(i)).collect();
    let sum: f64 = picked
        .iter()
        .map(|&i| {
            image.rgba[i * 4..i * 4 + 3]
                .iter()
                .map(|&c| f64::from(c))
                .sum::<f64>()
                / 3.0
        })
        .sum();
    (sum / picked.len().max(1) as f64, picked.len())
}

/// A 2 x 8 x 2 stone pillar on a 25 x 25 grass floor, seen from above the side its shadow
/// falls on (the default sun: up, towards +x and +z).
fn pillar() -> TestScene {
    pillar_at(0)
}

/// [`pillar`] with the scene and the camera moved by `shift` blocks on every axis.
fn pillar_at(shift: i32) -> TestScene {
    let mut palette = MaterialPalette::new();
    let floor = palette.push(Material::opaque(120, 160, 90)).unwrap();
    let stone = palette.push(Material::opaque(170, 170, 180)).unwrap();
    let mut scene = scene_from_fn(
        palette,
        ChunkSize::S16,
        [-12, -1, -12],
        [12, 8, 12],
        shift,
        move |x, y, z| {
            if y == -1 {
                floor
            } else if (0..2).contains(&x) && (0..2).contains(&z) && y < 8 {
                stone
            } else {
                BlockId::AIR
            }
        },
    );
    scene.camera = Camera {
        voxel: WorldPos::new(-2 + shift, 20 + shift, 10 + shift),
        fraction: glam::DVec3::new(0.3, 0.4, 0.6),
        yaw: 0.0,
        pitch: -1.0,
        fov_y: 1.0,
        near: Camera::DEFAULT_NEAR,
    };
    scene
}

#[test]
fn a_pillar_casts_its_shadow_where_the_reference_puts_it() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let scene = pillar();
    let lighting = shadowed();
    let gpu = gpu_frame(&ctx, &scene, &lighting, None);
    assert!(
        gpu.labels.iter().any(|l| l == "shadow grid")
            && gpu.labels.iter().any(|l| l == "shadow trace"),
        "the shadow pass's steps are timed: {:?}",
        gpu.labels
    );
    let cpu = cpu_visibility(&scene, &lighting);
    assert_visibility_agrees("pillar", &gpu, &cpu);
    // The shadow is really there: floor pixels facing the sun that the pillar hides from it.
    let in_shadow =
        |i: usize| cpu[i].is_some_and(|c| c.normal == [0, 1, 0] && c.voxel.y == -1 && !c.seen.sun);
    let lit_floor =
        |i: usize| cpu[i].is_some_and(|c| c.normal == [0, 1, 0] && c.voxel.y == -1 && c.seen.sun);
    let (dark, count) = mean_brightness(&gpu.image, in_shadow);
    let (light, lit) = mean_brightness(&gpu.image, lit_floor);
    assert!(
        count >= 100,
        "only {count} floor pixels in the pillar's shadow"
    );
    assert!(lit > count, "{lit} lit floor pixels");
    assert!(
        dark < 0.7 * light,
        "the shadow ({dark:.1}) is not darker than the lit floor ({light:.1})"
    );
    // Without shadows the same pixels are as bright as the lit floor: this test sees the
    // shadow, not the scene.
    let off = gpu_frame(&ctx, &scene, &Lighting::default(), None);
    let (unshadowed, _) = mean_brightness(&off.image, in_shadow);
    assert!(
        unshadowed > 0.9 * light,
        "{unshadowed:.1} against {light:.1}"
    );
    assert!(off.visibility.is_none(), "no shadow pass without shadows");
    let reference = cpu_render_lit(&scene, &scene.camera, &lighting);
    assert_images_match(
        "shadow_pillar",
        &gpu.image,
        &reference,
        &Tolerance::LAVAPIPE,
    );
    // For a reader: the frames with and without shadows, under target/image-tests/.
    image_support::write_pngs("shadow_pillar", &gpu.image, &reference);
    image_support::write_pngs("shadow_pillar_off", &off.image, &reference);
}

#[test]
fn the_fragment_lighting_and_far_drawn_blocks_are_shadowed_alike() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let scene = pillar();
    let lighting = shadowed();
    let cpu = cpu_visibility(&scene, &lighting);
    let reference = cpu_render_lit(&scene, &scene.camera, &lighting);
    // The default full-screen path is compute (the other tests); here the fragment one.
    let mut draws = vec![(
        "fragment",
        Draw {
            fullscreen: FullscreenPath::Fragment,
            splat: false,
        },
    )];
    if ctx.capabilities.int64_atomics {
        draws.push((
            "splat",
            Draw {
                fullscreen: FullscreenPath::default(),
                splat: true,
            },
        ));
    } else {
        gpu_backend::test_support::skip("the splat needs 64-bit atomics, which this device lacks");
    }
    for (name, draw) in draws {
        let gpu = gpu_frame_drawn(&ctx, &scene, &lighting, None, draw);
        if draw.splat {
            assert!(gpu.stats.far_nodes > 0, "{name}: {:?}", gpu.stats);
        }
        assert_visibility_agrees(name, &gpu, &cpu);
        let name = format!("shadow_pillar_{name}");
        assert_images_match(&name, &gpu.image, &reference, &Tolerance::LAVAPIPE);
    }
}

/// A 2-block roof 6 blocks over a floor, held by four pillars, and a closed stone box with
/// its floor inside: under the roof the sky is mostly hidden, inside the box wholly.
fn overhang() -> TestScene {
    let mut palette = MaterialPalette::new();
    let floor = palette.push(Material::opaque(150, 140, 120)).unwrap();
    let stone = palette.push(Material::opaque(110, 110, 120)).unwrap();
    let mut scene = scene_from_fn(
        palette,
        ChunkSize::S16,
        [-20, -1, -20],
        [20, 8, 20],
        0,
        move |x, y, z| {
            let roof = (-8..8).contains(&x) && (-12..0).contains(&z);
            let post = (x == -8 || x == 7) && (z == -12 || z == -1);
            if y == -1 {
                floor
            } else if (roof && (6..8).contains(&y)) || (post && y < 6) {
                stone
            } else {
                BlockId::AIR
            }
        },
    );
    // Low, in front of the roof's open side (+z), looking in under it.
    scene.camera = Camera {
        voxel: WorldPos::new(0, 3, 12),
        fraction: glam::DVec3::new(0.5, 0.5, 0.5),
        yaw: 0.0,
        pitch: -0.2,
        fov_y: 1.1,
        near: Camera::DEFAULT_NEAR,
    };
    scene
}

#[test]
fn under_an_overhang_is_darker_than_open_ground() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let scene = overhang();
    let lighting = shadowed();
    let gpu = gpu_frame(&ctx, &scene, &lighting, None);
    let cpu = cpu_visibility(&scene, &lighting);
    assert_visibility_agrees("overhang", &gpu, &cpu);
    let cpu = &cpu;
    let floor_where = |want: fn(Visibility) -> bool| {
        move |i: usize| {
            cpu[i].is_some_and(|c| c.voxel.y == -1 && c.normal == [0, 1, 0] && want(c.seen))
        }
    };
    let covered = |v: Visibility| v.sky_open <= 2 && !v.sun;
    let (under, n_under) = mean_brightness(&gpu.image, floor_where(covered));
    let (open, n_open) = mean_brightness(&gpu.image, floor_where(|v| v == Visibility::OPEN));
    assert!(
        n_under >= 100 && n_open >= 100,
        "{n_under} covered and {n_open} open floor pixels"
    );
    assert!(
        under < 0.5 * open,
        "under the roof ({under:.1}) against open ground ({open:.1})"
    );
    // The sky's part alone (sun shadows off) darkens the covered floor too.
    let sky_only = Lighting {
        shadows: ShadowSettings {
            sun_shadows: false,
            ..ShadowSettings::default()
        },
        ..Lighting::default()
    };
    let sky = gpu_frame(&ctx, &scene, &sky_only, None);
    let (sky_under, _) = mean_brightness(&sky.image, floor_where(covered));
    let plain = gpu_frame(&ctx, &scene, &Lighting::default(), None);
    let (plain_under, _) = mean_brightness(&plain.image, floor_where(covered));
    assert!(
        sky_under < 0.95 * plain_under,
        "sky visibility alone: {sky_under:.1} against {plain_under:.1} without it"
    );
    let reference = cpu_render_lit(&scene, &scene.camera, &lighting);
    assert_images_match(
        "shadow_overhang",
        &gpu.image,
        &reference,
        &Tolerance::LAVAPIPE,
    );
    image_support::write_pngs("shadow_overhang", &gpu.image, &reference);
    image_support::write_pngs("shadow_overhang_off", &plain.image, &reference);
}

/// A wall 8 blocks high and 2 thick along x across a floor, every feature 2-aligned so that
/// level 1 draws exactly the same surfaces as level 0; seen from above the side its shadow
/// falls on, under a low sun.
fn wall_across_a_border() -> TestScene {
    let mut palette = MaterialPalette::new();
    let floor = palette.push(Material::opaque(130, 150, 100)).unwrap();
    let stone = palette.push(Material::opaque(160, 150, 150)).unwrap();
    let mut scene = scene_from_fn(
        palette,
        ChunkSize::S16,
        [-32, -2, -32],
        [63, 8, 31],
        0,
        move |x, y, z| {
            if y < 0 {
                floor
            } else if (-16..48).contains(&x) && (0..2).contains(&z) && y < 8 {
                stone
            } else {
                BlockId::AIR
            }
        },
    );
    scene.camera = Camera {
        voxel: WorldPos::new(0, 26, 4),
        fraction: glam::DVec3::new(0.5, 0.5, 0.5),
        yaw: 0.0,
        pitch: -1.25,
        fov_y: 1.0,
        near: Camera::DEFAULT_NEAR,
    };
    scene
}

#[test]
fn a_shadow_across_a_lod_border_does_not_leak() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let scene = wall_across_a_border();
    let d = [0.2f32, 0.6, 0.77];
    let len = d.iter().map(|c| c * c).sum::<f32>().sqrt();
    let lighting = Lighting {
        sun_direction: d.map(|c| c / len),
        ..shadowed()
    };
    // From an anchor at (-40, 4, -8): level-1 nodes nearer than 24 blocks refine, so x < 0
    // is drawn at level 0 and x >= 0 at level 1 (16^3 chunks, level-1 nodes 32 blocks wide).
    let focal = render_model::cull::lod::focal_px(scene.camera.fov_y, HEIGHT);
    let lod = Lod {
        settings: LodSettings {
            budget_px: 1.732_050_8 * focal / 24.0,
            hysteresis: 0.0,
            far_cell_px: 0.0,
        },
        anchor: LodAnchor {
            chunk: ChunkCoord::new(-3, 0, -1),
            offset: [8.0, 4.0, 8.0],
        },
        top: 1,
    };
    let gpu = gpu_frame(&ctx, &scene, &lighting, Some(&lod));
    assert!(
        gpu.stats.per_level[0] > 0 && gpu.stats.per_level[1] > 0,
        "both levels are drawn: {:?}",
        gpu.stats.per_level
    );
    // The x >= 0 half casts from level-1 nodes only: a grid without them differs from the
    // reference on about an eighth of the pixels here (the visibility check fails).
    let cpu = cpu_visibility(&scene, &lighting);
    assert_visibility_agrees("lod_border", &gpu, &cpu);
    // No light in the wall's shadow on either side of the border at x = 0.
    let words = gpu.visibility.as_ref().expect("visibility");
    let shadowed_floor: Vec<usize> = (0..cpu.len())
        .filter(|&i| {
            cpu[i].is_some_and(|c| c.voxel.y == -1 && c.normal == [0, 1, 0] && !c.seen.sun)
        })
        .collect();
    for side in [-1, 1] {
        let here: Vec<usize> = shadowed_floor
            .iter()
            .copied()
            .filter(|&i| {
                cpu[i].is_some_and(|c| (c.voxel.x >= 0) == (side > 0) && (c.voxel.x.abs() > 2))
            })
            .collect();
        let lit = here.iter().filter(|&&i| words[i].sun).count();
        assert!(
            here.len() >= 50,
            "{} shadowed floor pixels on side {side}",
            here.len()
        );
        assert!(
            lit <= here.len() / 50,
            "{lit} of {} shadowed pixels lit on side {side}",
            here.len()
        );
    }
    let near_border = shadowed_floor
        .iter()
        .filter(|&&i| cpu[i].is_some_and(|c| c.voxel.x.abs() <= 2))
        .filter(|&&i| words[i].sun)
        .count();
    assert_eq!(near_border, 0, "light leaks through the LOD border");
    let reference = cpu_render_lit(&scene, &scene.camera, &lighting);
    // Level 1 interpolates its AO over 2-block cells where the wall meets the floor: a few
    // more colour outliers than a level-0 scene has, within 4 codes (lavapipe: 132 pixels
    // past 2 codes, none past 3).
    let tolerance = Tolerance {
        colour: 4,
        colour_outliers: 0.02,
        ..Tolerance::LAVAPIPE
    };
    assert_images_match("shadow_lod_border", &gpu.image, &reference, &tolerance);
    image_support::write_pngs("shadow_lod_border", &gpu.image, &reference);
}

#[test]
fn shadows_off_is_the_image_without_shadows() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let scene = pillar();
    let plain = gpu_frame(&ctx, &scene, &Lighting::default(), None);
    // Off, whatever its bounds: no shadow pass runs, and the frame's bytes are the same.
    let off = Lighting {
        shadows: ShadowSettings {
            max_steps: 7,
            max_distance: 3.0,
            ..ShadowSettings::OFF
        },
        ..Lighting::default()
    };
    let again = gpu_frame(&ctx, &scene, &off, None);
    assert_eq!(plain.image.rgba, again.image.rgba);
    assert!(
        !plain.labels.iter().any(|l| l.starts_with("shadow")),
        "{:?}",
        plain.labels
    );
    assert!(plain.visibility.is_none());
    // On, where nothing blocks sun or sky (the floor alone, far from everything): every
    // factor is 1 and the image is the same bytes.
    let mut open = pillar();
    let mut palette = MaterialPalette::new();
    let floor = palette.push(Material::opaque(120, 160, 90)).unwrap();
    open.world = scene_from_fn(
        palette.clone(),
        ChunkSize::S16,
        [-12, -1, -12],
        [12, -1, 12],
        0,
        move |_, _, _| floor,
    )
    .world;
    open.palette = palette;
    let unshadowed = gpu_frame(&ctx, &open, &Lighting::default(), None);
    let traced = gpu_frame(&ctx, &open, &shadowed(), None);
    let words = traced.visibility.as_ref().expect("visibility");
    assert!(
        words.iter().all(|&w| w == Visibility::OPEN),
        "something blocks the open floor"
    );
    assert_eq!(unshadowed.image.rgba, traced.image.rgba);
    // And the CPU reference: off is its image without shadow rays.
    let cpu_plain = cpu_render_lit(&scene, &scene.camera, &Lighting::default());
    let cpu_off = cpu_render_lit(&scene, &scene.camera, &off);
    assert_eq!(cpu_plain.rgba, cpu_off.rgba);
}

#[test]
fn shadows_near_2_pow_30_match_the_origin() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let lighting = shadowed();
    let here = gpu_frame(&ctx, &pillar_at(0), &lighting, None);
    let far = gpu_frame(&ctx, &pillar_at(1 << 30), &lighting, None);
    let (a, b) = (
        here.visibility.expect("words"),
        far.visibility.expect("words"),
    );
    assert!(a.iter().any(|v| !v.sun), "the origin's frame has a shadow");
    assert_eq!(a, b, "the visibility near 2^30 differs from the origin's");
    assert_eq!(here.image.rgba, far.image.rgba);
}

#[test]
fn bad_shadow_settings_are_refused_by_name() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let scene = pillar();
    let config = RendererConfig::new(WIDTH, HEIGHT, scene.world.size());
    let mut renderer = Renderer::new(&ctx, &config, &scene.palette).expect("renderer");
    let bad = Lighting {
        shadows: ShadowSettings {
            max_distance: f32::NAN,
            ..ShadowSettings::default()
        },
        ..Lighting::default()
    };
    let err = renderer
        .set_lighting(&bad)
        .expect_err("a NaN distance is refused");
    assert!(err.to_string().contains("max_distance"), "{err}");
}

/// Shadows on, the terrain patch of the image tests and a MagicaVoxel model: the GPU image
/// and visibility against the CPU reference.
#[test]
fn the_terrain_and_a_model_are_shadowed_like_the_reference() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let lighting = shadowed();
    let mut scenes = vec![("terrain", image_support::scenes::terrain())];
    if let Some(dir) = tests::sample_data("vox") {
        let path = dir.join("chr_knight.vox");
        let vox = viewer::scene::vox::load_vox_file(&path, ChunkSize::S16, 1 << 20)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let (lo, hi) = vox.bounds.expect("the model has voxels");
        scenes.push((
            "vox_chr_knight",
            TestScene {
                camera: viewer::scene::camera_looking_at(lo, hi),
                world: vox.world,
                palette: vox.palette,
            },
        ));
    }
    for (name, scene) in scenes {
        let gpu = gpu_frame(&ctx, &scene, &lighting, None);
        let cpu = cpu_visibility(&scene, &lighting);
        assert_visibility_agrees(name, &gpu, &cpu);
        let shadowed = gpu
            .visibility
            .as_ref()
            .expect("visibility")
            .iter()
            .filter(|v| !v.sun || v.sky_open < 5)
            .count();
        assert!(
            shadowed > 100,
            "{name}: only {shadowed} pixels see any shadow"
        );
        let reference = cpu_render_lit(&scene, &scene.camera, &lighting);
        let name = format!("shadow_{name}");
        assert_images_match(&name, &gpu.image, &reference, &Tolerance::LAVAPIPE);
        image_support::write_pngs(&name, &gpu.image, &reference);
    }
}

/// The level-0 nodes of `scene`, meshed as the image tests mesh them.
fn level0_nodes(scene: &TestScene) -> Vec<mesher::lod::NodeMesh> {
    let classes = BlockClasses::from_palette(&scene.palette);
    let mut coords: Vec<ChunkCoord> = scene.world.iter().map(|(c, _)| c).collect();
    coords.sort_unstable();
    mesh_nodes(&scene.world, 0, &coords, &classes, &NodeSettings::default()).expect("level 0")
}

/// The grid is kept only while neither the camera nor the resident set changes: under a still
/// camera, swapping the floor's nodes for the pillar's shows the pillar's shadow in the next
/// frame, a frame with nothing changed gives the same pixels, and swapping back removes it.
#[test]
fn the_grid_follows_the_resident_set_under_a_still_camera() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let with_pillar = pillar();
    let mut palette = MaterialPalette::new();
    let floor_id = palette.push(Material::opaque(120, 160, 90)).unwrap();
    palette.push(Material::opaque(170, 170, 180)).unwrap();
    let floor_only = scene_from_fn(
        palette,
        ChunkSize::S16,
        [-12, -1, -12],
        [12, 8, 12],
        0,
        move |_, y, _| if y == -1 { floor_id } else { BlockId::AIR },
    );
    let config = RendererConfig::new(WIDTH, HEIGHT, with_pillar.world.size());
    let mut renderer = Renderer::new(&ctx, &config, &with_pillar.palette).expect("renderer");
    renderer.set_camera(&with_pillar.camera);
    renderer
        .set_lighting(&shadowed())
        .expect("the lighting renders");
    let frame = |renderer: &mut Renderer| {
        renderer.render().expect("frame");
        let visibility = renderer
            .read_shadow_visibility()
            .expect("visibility readback")
            .expect("shadows are on");
        let sunlit = visibility.iter().filter(|v| v.sun).count();
        (renderer.read_image().expect("readback").rgba, sunlit)
    };
    let floor_handles = upload_nodes(&mut renderer, &level0_nodes(&floor_only)).expect("upload");
    let (_, open) = frame(&mut renderer);
    for handle in floor_handles {
        renderer.free_chunk(handle).expect("free");
    }
    let pillar_handles = upload_nodes(&mut renderer, &level0_nodes(&with_pillar)).expect("upload");
    let (shadowed_rgba, lit) = frame(&mut renderer);
    let fills = renderer.shadow_grid_fills();
    let (again, lit_again) = frame(&mut renderer);
    assert_eq!(
        renderer.shadow_grid_fills(),
        fills,
        "a frame with nothing changed filled the grid again"
    );
    // The pillar hides part of the floor from the sun (and hides some floor from the camera).
    let cpu = cpu_visibility(&with_pillar, &shadowed());
    let dark = cpu.iter().flatten().filter(|c| !c.seen.sun).count();
    assert!(dark >= 100, "the reference shadows only {dark} pixels");
    assert!(
        lit + dark / 2 < open,
        "the pillar's shadow is not in the frame after the upload: {lit} sunlit pixels, \
         {open} before it"
    );
    assert_eq!(lit_again, lit, "a frame with nothing changed");
    assert!(
        again == shadowed_rgba,
        "a frame with nothing changed drew other pixels"
    );
    for handle in pillar_handles {
        renderer.free_chunk(handle).expect("free");
    }
    upload_nodes(&mut renderer, &level0_nodes(&floor_only)).expect("upload");
    let (_, open_again) = frame(&mut renderer);
    assert_eq!(
        open_again, open,
        "the shadow stays after the pillar is gone"
    );
    assert_eq!(
        renderer.shadow_grid_fills(),
        fills + 1,
        "the change refilled it"
    );
}
