//! The GPU renderer against the CPU reference raycaster, on lavapipe in CI.
//!
//! Each scene is rendered twice with the same camera, palette and lighting model: by
//! `gpu_backend::render::Renderer` (greedy quads, cull, G-buffer, deferred lighting,
//! transparent pass, tonemap) and by `viewer::deferred_reference::render_deferred` (a DDA ray
//! per pixel centre, shaded with the lighting model's CPU twin). The comparison rules and
//! tolerances are in `image_support` ([`Tolerance::LAVAPIPE`]); a failure writes actual,
//! expected and difference PNGs under `target/image-tests/<name>/` and names the folder.

mod image_support;

use gpu_backend::DeviceOptions;
use gpu_backend::test_support::headless_or_skip;
use image_support::mesh_raster::{mesh_triangles, rasterise, smooth_pixels};
use image_support::scenes::{
    self, TestScene, cpu_render, cpu_render_lit, gpu_render, gpu_render_lit, gpu_render_with,
};
use image_support::{Image, Tolerance, assert_images_match, compare};
use mesher::SurfaceMode;
use render_model::lighting::Lighting;
use voxel_core::ChunkSize;

const TOLERANCE: Tolerance = Tolerance::LAVAPIPE;

fn gpu_matches_cpu(name: &str, scene: &TestScene) -> Option<Image> {
    let ctx = headless_or_skip(&DeviceOptions::default())?;
    let (gpu, times) = gpu_render(&ctx, scene, &scene.camera);
    let labels: Vec<&str> = times.iter().map(|t| t.label.as_str()).collect();
    assert_eq!(
        labels,
        [
            "cull",
            "gbuffer",
            "hiz",
            "cull late",
            "gbuffer late",
            "cull transparent",
            "lighting",
            "transparent",
            "tonemap",
            "antialias"
        ],
        "{name}: one timed scope per pass"
    );
    let cpu = cpu_render(scene, &scene.camera);
    assert_images_match(name, &gpu, &cpu, &TOLERANCE);
    Some(gpu)
}

#[test]
fn one_cube() {
    gpu_matches_cpu("cube", &scenes::cube(0));
}

#[test]
fn sphere_on_a_floor_with_water() {
    gpu_matches_cpu("sphere", &scenes::sphere());
}

#[test]
fn glass_panes_blend_back_to_front() {
    gpu_matches_cpu("glass_panes", &scenes::glass_panes());
}

#[test]
fn terrain_patch() {
    gpu_matches_cpu("terrain", &scenes::terrain());
}

#[test]
fn magicavoxel_model() {
    let Some(dir) = tests::sample_data("vox") else {
        return;
    };
    let path = dir.join("chr_knight.vox");
    let vox = viewer::scene::vox::load_vox_file(&path, ChunkSize::S16, 1 << 20)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let (lo, hi) = vox.bounds.expect("the model has voxels");
    let scene = TestScene {
        camera: viewer::scene::camera_looking_at(lo, hi),
        world: vox.world,
        palette: vox.palette,
    };
    gpu_matches_cpu("vox_chr_knight", &scene);
}

/// NoCubes on the GPU against a CPU rasterisation of the same quads (`mesh_raster`), under the
/// same tolerance as the other scenes: the smooth layer (BlockVertex quads by vertex pulling)
/// and the greedy cube faces, their depth and shading, and the seams between them (hill on
/// floor, pillar through hill, chunk borders). Seen from above, the floor fills the view, so
/// there is no silhouette: a gap at a seam would show the sky, a coverage mismatch.
#[test]
fn nocubes_matches_a_cpu_rasterisation_of_its_quads() {
    let scene = scenes::smooth_hill();
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let (gpu, _) = gpu_render_with(&ctx, &scene, &scene.camera, SurfaceMode::NoCubes);
    let triangles = mesh_triangles(&scene, &scene.camera, SurfaceMode::NoCubes);
    let params = Lighting::default();
    let cpu = rasterise(&triangles, &scene, &scene.camera, &params);
    let sky = gpu.depth.iter().filter(|d| !d.is_finite()).count();
    assert_eq!(sky, 0, "sky seen through {sky} pixels of the NoCubes mesh");
    let smooth = smooth_pixels(&cpu);
    assert!(
        smooth * 10 > cpu.depth.len(),
        "the smooth layer covers only {smooth} of {} pixels",
        cpu.depth.len()
    );
    assert_images_match("nocubes", &gpu, &cpu, &TOLERANCE);

    // The reference tells the smooth layer from the blocks it smooths.
    let (blocky, _) = gpu_render(&ctx, &scene, &scene.camera);
    let c = compare(&blocky, &cpu, &TOLERANCE);
    assert!(
        !c.passed(&TOLERANCE) && c.depth_failures * 10 > smooth,
        "the blocky render passes for the smooth one: {c:?}"
    );
}

/// The mesh rasteriser against the voxel raycaster on greedy meshes (no GPU needed): two
/// independent CPU references of the same scenes agree under the GPU's tolerance.
#[test]
fn the_mesh_rasteriser_agrees_with_the_raycaster() {
    let params = Lighting::default();
    for (name, scene) in [
        ("raster_cube", scenes::cube(0)),
        ("raster_hill_blocky", scenes::smooth_hill()),
    ] {
        let triangles = mesh_triangles(&scene, &scene.camera, SurfaceMode::Greedy);
        let raster = rasterise(&triangles, &scene, &scene.camera, &params);
        assert_eq!(
            smooth_pixels(&raster),
            0,
            "{name}: greedy meshes are not smooth"
        );
        assert_images_match(
            name,
            &raster,
            &cpu_render(&scene, &scene.camera),
            &TOLERANCE,
        );
    }
}

/// Distance haze: the terrain patch through haze that ends at 70 blocks, on the GPU against
/// the reference; the haze visibly changes the image.
#[test]
fn haze_matches_the_reference() {
    let scene = scenes::terrain();
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let hazy = Lighting {
        haze_distance: 70.0,
        ..Lighting::default()
    };
    let camera = scene.camera;
    let (gpu, _) = gpu_render_lit(&ctx, &scene, &camera, SurfaceMode::Greedy, &hazy, true);
    let cpu = cpu_render_lit(&scene, &camera, &hazy);
    assert_images_match("haze", &gpu, &cpu, &TOLERANCE);
    let (clear, _) = gpu_render_lit(
        &ctx,
        &scene,
        &camera,
        SurfaceMode::Greedy,
        &Lighting::default(),
        true,
    );
    let changed = gpu
        .rgba
        .chunks(4)
        .zip(clear.rgba.chunks(4))
        .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| x.abs_diff(*y) > 8))
        .count();
    let hits = gpu.depth.iter().filter(|d| d.is_finite()).count();
    assert!(
        changed * 2 > hits,
        "haze changes only {changed} of the {hits} pixels that show terrain"
    );
}

/// The sky: looking up over a cube towards the sun, the gradient and the sun disc on the GPU
/// against the reference; the top of the view is bluer than its bottom, and the disc is
/// white.
#[test]
fn sky_and_sun_match_the_reference() {
    let scene = scenes::cube(0);
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let lighting = Lighting::default();
    let [x, y, z] = lighting.sun_direction.map(f64::from);
    // Low on the cube's far side from the sun, looking up at it over the cube.
    let h = x.hypot(z);
    let camera = render_model::Camera {
        voxel: voxel_core::WorldPos::new((-12.0 * x / h) as i32, -1, (-12.0 * z / h) as i32),
        yaw: (-x).atan2(-z),
        pitch: 0.7,
        fov_y: 1.2,
        ..scene.camera
    };
    assert!(y.asin() < 0.7 + 0.5, "the sun is in view");
    let (gpu, _) = gpu_render_lit(&ctx, &scene, &camera, SurfaceMode::Greedy, &lighting, true);
    let cpu = cpu_render_lit(&scene, &camera, &lighting);
    assert_images_match("sky_and_sun", &gpu, &cpu, &TOLERANCE);
    let pixel = |x: u32, y: u32| {
        let i = 4 * (y * gpu.width + x) as usize;
        [gpu.rgba[i], gpu.rgba[i + 1], gpu.rgba[i + 2]]
    };
    let sky = |x: u32, y: u32| !gpu.depth[(y * gpu.width + x) as usize].is_finite();
    let disc = (0..gpu.height)
        .flat_map(|y| (0..gpu.width).map(move |x| (x, y)))
        .filter(|&(x, y)| sky(x, y) && pixel(x, y).iter().all(|&c| c >= 230))
        .count();
    assert!((1..200).contains(&disc), "{disc} pixels of sun disc");
    let (top, bottom) = (pixel(2, 0), pixel(2, gpu.height - 1));
    assert!(sky(2, 0) && sky(2, gpu.height - 1), "the corners show sky");
    let blueness = |p: [u8; 3]| i32::from(p[2]) - i32::from(p[0]);
    assert!(
        blueness(top) > blueness(bottom) + 10,
        "no gradient: top {top:?}, bottom {bottom:?}"
    );
}

/// The share of `image`'s silhouette pixels (a 4-neighbour shows sky where the pixel shows a
/// surface, or the reverse) whose colour is a blend of the two sides: between its sky
/// neighbour's and its surface neighbour's colour, 15 to 85 % of the way, where the two
/// differ by at least 30 codes.
fn blended_edge_share(image: &Image) -> f64 {
    let (w, h) = (image.width as i32, image.height as i32);
    let at = |x: i32, y: i32| (y * w + x) as usize;
    let colour = |i: usize| [0, 1, 2].map(|c| f64::from(image.rgba[4 * i + c]));
    let (mut edges, mut blended) = (0usize, 0usize);
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let here = at(x, y);
            let near = [at(x - 1, y), at(x + 1, y), at(x, y - 1), at(x, y + 1)];
            let sky = |i: usize| !image.depth[i].is_finite();
            let Some(&s) = near.iter().chain([&here]).find(|&&i| sky(i)) else {
                continue;
            };
            let Some(&f) = near.iter().chain([&here]).find(|&&i| !sky(i)) else {
                continue;
            };
            let (sc, fc, pc) = (colour(s), colour(f), colour(here));
            let d: [f64; 3] = core::array::from_fn(|c| fc[c] - sc[c]);
            let len2 = d.iter().map(|v| v * v).sum::<f64>();
            if len2 < 30.0 * 30.0 {
                continue;
            }
            edges += 1;
            let t = (0..3).map(|c| (pc[c] - sc[c]) * d[c]).sum::<f64>() / len2;
            if (0.15..=0.85).contains(&t) {
                blended += 1;
            }
        }
    }
    assert!(edges > 50, "only {edges} silhouette pixels");
    blended as f64 / edges as f64
}

/// Anti-aliasing: on the cube's silhouette against the sky, the antialias pass (FXAA) blends
/// a good share of the edge pixels; the same frame without it blends almost none, so the
/// measure tells the two apart. With it on, the GPU frame matches the CPU reference with the
/// same FXAA (`render_model::antialias`).
#[test]
fn antialiasing_blends_silhouette_edges() {
    let scene = scenes::cube(0);
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let lighting = Lighting::default();
    let render = |antialias| {
        gpu_render_lit(
            &ctx,
            &scene,
            &scene.camera,
            SurfaceMode::Greedy,
            &lighting,
            antialias,
        )
        .0
    };
    let (smooth, jagged) = (render(true), render(false));
    let (on, off) = (blended_edge_share(&smooth), blended_edge_share(&jagged));
    eprintln!("blended silhouette pixels: {on:.3} with FXAA, {off:.3} without");
    assert!(
        off < 0.1,
        "without anti-aliasing {off:.3} of the edge is blended"
    );
    assert!(
        on > 0.2,
        "with anti-aliasing only {on:.3} of the edge is blended"
    );
    let cpu = cpu_render(&scene, &scene.camera);
    assert!(
        blended_edge_share(&cpu) > 0.2,
        "the CPU reference's FXAA blends the edge"
    );
    assert_images_match("antialias", &smooth, &cpu, &TOLERANCE);
}

/// The cube near (2^30, 2^30, 2^30) renders bit for bit like the cube at the origin (the GPU
/// only sees camera-relative numbers), and matches the CPU reference there too.
#[test]
fn far_from_the_origin_renders_like_the_origin() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let near = scenes::cube(0);
    let far = scenes::cube(1 << 30);
    let (near_gpu, _) = gpu_render(&ctx, &near, &near.camera);
    let (far_gpu, _) = gpu_render(&ctx, &far, &far.camera);
    assert_eq!(near_gpu.rgba, far_gpu.rgba, "colour differs at 2^30");
    assert_eq!(near_gpu.depth, far_gpu.depth, "depth differs at 2^30");
    assert_images_match(
        "far_cube",
        &far_gpu,
        &cpu_render(&far, &far.camera),
        &TOLERANCE,
    );
}

/// Without MULTI_DRAW_INDIRECT_COUNT (zeroed commands) and without timestamps (CPU timing)
/// the image is the same.
#[test]
fn fallback_paths_give_the_same_image() {
    let scene = scenes::sphere();
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let (reference, reference_times) = gpu_render(&ctx, &scene, &scene.camera);
    let options = [
        DeviceOptions {
            disable_indirect_count: true,
            ..DeviceOptions::default()
        },
        DeviceOptions {
            disable_timestamps: true,
            ..DeviceOptions::default()
        },
    ];
    for options in options {
        let ctx = headless_or_skip(&options).expect("the adapter exists");
        let (image, times) = gpu_render(&ctx, &scene, &scene.camera);
        assert_eq!(
            times.len(),
            reference_times.len(),
            "{options:?}: every pass timed"
        );
        assert_eq!(image.rgba, reference.rgba, "{options:?}: colour differs");
        assert_eq!(image.depth, reference.depth, "{options:?}: depth differs");
    }
}

/// The full-screen passes (lighting, tonemap, antialias) give the same image as fragment
/// passes and as compute passes, with and without anti-aliasing (up to a few edge pixels
/// with it; the fragment tonemap
/// encodes through the sRGB view of its target, the compute one in the shader; the antialias
/// pass writes encoded bytes through the plain view either way).
#[test]
fn fragment_and_compute_screen_passes_agree() {
    let scene = scenes::sphere();
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let lighting = Lighting {
        haze_distance: 60.0,
        ..Lighting::default()
    };
    for antialias in [false, true] {
        let render = |fullscreen| {
            let config = gpu_backend::render::RendererConfig {
                fullscreen,
                antialias,
                ..gpu_backend::render::RendererConfig::new(
                    scenes::WIDTH,
                    scenes::HEIGHT,
                    scene.world.size(),
                )
            };
            let mut renderer = gpu_backend::render::Renderer::new(&ctx, &config, &scene.palette)
                .expect("renderer");
            viewer::gpu_view::upload_world(&mut renderer, &scene.world, &scene.palette)
                .expect("upload");
            renderer.set_camera(&scene.camera);
            renderer.set_lighting(&lighting).expect("lighting");
            renderer.render().expect("frame");
            renderer.read_image().expect("readback").rgba
        };
        let fragment = render(gpu_backend::render::FullscreenPath::Fragment);
        let compute = render(gpu_backend::render::FullscreenPath::Compute);
        let off_by_more = fragment
            .chunks(4)
            .zip(compute.chunks(4))
            .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| x.abs_diff(*y) > 1))
            .count();
        // FXAA's decisions are thresholds: a rounding difference between the stages can flip
        // one on a few edge pixels; everywhere else the two agree to a code.
        let allowed = if antialias {
            fragment.len() / 4 / 1000
        } else {
            0
        };
        assert!(
            off_by_more <= allowed,
            "antialias {antialias}: {off_by_more} pixels differ by more than a code"
        );
    }
}

/// The comparison can fail: a camera moved by half a block is caught.
#[test]
fn a_shifted_camera_is_caught() {
    let scene = scenes::sphere();
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let mut moved = scene.camera;
    moved.fraction.x = (moved.fraction.x + 0.5).fract();
    if moved.fraction.x < scene.camera.fraction.x {
        moved.voxel.x += 1;
    }
    let (gpu, _) = gpu_render(&ctx, &scene, &moved);
    let cpu = cpu_render(&scene, &scene.camera);
    let c = compare(&gpu, &cpu, &TOLERANCE);
    assert!(
        !c.passed(&TOLERANCE),
        "half a block of camera offset went unnoticed: {c:?}"
    );
}

/// The comparison catches a GPU image moved by one pixel, in each direction.
#[test]
fn a_gpu_image_moved_by_one_pixel_is_caught() {
    let scene = scenes::cube(0);
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let (gpu, _) = gpu_render(&ctx, &scene, &scene.camera);
    let cpu = cpu_render(&scene, &scene.camera);
    assert!(compare(&gpu, &cpu, &TOLERANCE).passed(&TOLERANCE));
    for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
        let c = compare(&comparer::moved(&gpu, dx, dy), &cpu, &TOLERANCE);
        assert!(!c.passed(&TOLERANCE), "moved by ({dx}, {dy}): {c:?}");
    }
}

/// Unit tests of the comparer itself (no GPU needed).
mod comparer {
    use super::image_support::{
        Image, PixelSurfaces, Surface, Tolerance, compare, is_silhouette_edge,
    };

    /// A 16 x 16 image: a square of distance 10 (colour 100) in the middle, sky around it.
    fn square(shift: u32) -> Image {
        let (w, h) = (16u32, 16u32);
        let mut rgba = Vec::new();
        let mut depth = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let inside = (4 + shift..12 + shift).contains(&x) && (4..12).contains(&y);
                rgba.extend_from_slice(&if inside {
                    [100, 100, 100, 255]
                } else {
                    [20, 40, 200, 255]
                });
                depth.push(if inside { 10.0 } else { f32::INFINITY });
            }
        }
        Image {
            width: w,
            height: h,
            rgba,
            depth,
            surfaces: None,
        }
    }

    #[test]
    fn identical_images_pass() {
        let a = square(0);
        let c = compare(&a, &a, &Tolerance::LAVAPIPE);
        assert!(c.passed(&Tolerance::LAVAPIPE), "{c:?}");
        assert_eq!(c.coverage_mismatches, 0);
        assert!(c.edge_pixels > 0 && c.compared + c.edge_pixels == 256);
    }

    #[test]
    fn silhouette_edges_are_skipped_but_interiors_are_not() {
        let a = square(0);
        assert!(is_silhouette_edge(&a, 4, 4));
        assert!(is_silhouette_edge(&a, 3, 8));
        assert!(!is_silhouette_edge(&a, 8, 8));
        assert!(!is_silhouette_edge(&a, 0, 0));
    }

    /// `image` moved by `(dx, dy)` pixels, sky where nothing moved in.
    pub(crate) fn moved(image: &Image, dx: i64, dy: i64) -> Image {
        let (w, h) = (i64::from(image.width), i64::from(image.height));
        let mut out = image.clone();
        for y in 0..h {
            for x in 0..w {
                let (sx, sy) = (x - dx, y - dy);
                let to = (y * w + x) as usize;
                if (0..w).contains(&sx) && (0..h).contains(&sy) {
                    let from = (sy * w + sx) as usize;
                    out.depth[to] = image.depth[from];
                    out.rgba[4 * to..4 * to + 4]
                        .copy_from_slice(&image.rgba[4 * from..4 * from + 4]);
                } else {
                    out.depth[to] = f32::INFINITY;
                    out.rgba[4 * to..4 * to + 4].copy_from_slice(&[20, 40, 200, 255]);
                }
            }
        }
        out
    }

    #[test]
    fn a_one_pixel_shift_is_caught() {
        // Moved by one pixel, every pixel that changes coverage lies in the reference's edge
        // band, where coverage may differ only on a few pixels: here a quarter of the band.
        let reference = square(0);
        for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
            let c = compare(&moved(&reference, dx, dy), &reference, &Tolerance::LAVAPIPE);
            assert_eq!(c.coverage_mismatches, 0, "({dx}, {dy}): {c:?}");
            assert!(c.edge_coverage_share() >= 0.2, "({dx}, {dy}): {c:?}");
            assert!(!c.passed(&Tolerance::LAVAPIPE), "({dx}, {dy}): {c:?}");
        }
        assert_eq!(moved(&reference, 0, 0), reference);
        assert_eq!(moved(&reference, 1, 0), square(1));
    }

    #[test]
    fn a_few_flipped_edge_pixels_pass() {
        // One edge pixel rounded the other way, as a rasterizer may: within the 3% allowed.
        let reference = square(0);
        let mut flipped = reference.clone();
        let i = 4 * 16 + 4;
        flipped.depth[i] = f32::INFINITY;
        flipped.rgba[4 * i..4 * i + 4].copy_from_slice(&[20, 40, 200, 255]);
        let c = compare(&flipped, &reference, &Tolerance::LAVAPIPE);
        assert_eq!(c.edge_coverage_mismatches, 1, "{c:?}");
        assert!(c.passed(&Tolerance::LAVAPIPE), "{c:?}");
    }

    #[test]
    fn an_image_of_creases_fails() {
        // A reference whose every pixel borders another surface compares nothing in depth
        // and colour: past the crease cap, it fails even against itself.
        let mut reference = square(0);
        let surfaces = (0..256)
            .map(|i| PixelSurfaces {
                opaque: Some(Surface::Plane(0, i % 2)),
                layers: [None; 2],
            })
            .collect();
        reference.surfaces = Some(surfaces);
        let c = compare(&reference, &reference, &Tolerance::LAVAPIPE);
        assert_eq!(c.crease_pixels, c.compared, "{c:?}");
        assert!(!c.passed(&Tolerance::LAVAPIPE), "{c:?}");
    }

    #[test]
    fn depth_and_colour_errors_are_caught() {
        let reference = square(0);
        let mut deeper = reference.clone();
        deeper
            .depth
            .iter_mut()
            .filter(|d| d.is_finite())
            .for_each(|d| *d += 0.1);
        assert!(compare(&deeper, &reference, &Tolerance::LAVAPIPE).depth_failures > 0);
        let mut tinted = reference.clone();
        tinted
            .rgba
            .chunks_mut(4)
            .for_each(|p| p[0] = p[0].wrapping_add(5));
        let c = compare(&tinted, &reference, &Tolerance::LAVAPIPE);
        assert!(
            !c.passed(&Tolerance::LAVAPIPE) && c.max_colour_difference == 5,
            "{c:?}"
        );
    }
}
