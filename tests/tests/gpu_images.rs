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
use image_support::scenes::{self, TestScene, cpu_render, gpu_render, gpu_render_with};
use image_support::{Image, Tolerance, assert_images_match, compare};
use mesher::SurfaceMode;
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
            "tonemap"
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

/// NoCubes on the GPU: the smooth layer (BlockVertex quads by vertex pulling) and the greedy
/// cube faces meet without cracks. Seen from above, the floor fills the view, so a gap at a
/// seam (hill on floor, pillar through hill, chunk borders) would show the sky through it:
/// every pixel must hit geometry. The hill must look different from the blocky render (the
/// smooth layer was drawn) while most of the view, the floor, is the same.
#[test]
fn nocubes_seams_are_closed() {
    let scene = scenes::smooth_hill();
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let (smooth, _) = gpu_render_with(&ctx, &scene, &scene.camera, SurfaceMode::NoCubes);
    let (blocky, _) = gpu_render(&ctx, &scene, &scene.camera);
    let sky = smooth.depth.iter().filter(|d| !d.is_finite()).count();
    assert_eq!(sky, 0, "sky seen through {sky} pixels of the NoCubes mesh");
    assert!(
        blocky.depth.iter().all(|d| d.is_finite()),
        "the floor fills the view"
    );
    let differ = |a: &Image, b: &Image| {
        a.rgba
            .chunks(4)
            .zip(b.rgba.chunks(4))
            .filter(|(p, q)| p.iter().zip(q.iter()).any(|(x, y)| x.abs_diff(*y) > 8))
            .count()
    };
    let pixels = smooth.depth.len();
    let changed = differ(&smooth, &blocky);
    assert!(
        changed > pixels / 20 && changed < pixels / 2,
        "{changed} of {pixels} pixels differ from the blocky render"
    );
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

/// Unit tests of the comparer itself (no GPU needed).
mod comparer {
    use super::image_support::{Image, Tolerance, compare, is_silhouette_edge};

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
            planes: None,
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

    #[test]
    fn a_one_pixel_shift_is_caught() {
        // Shifted by one pixel, the moved column lies on the reference's edge band and is skipped,
        // but a shift by two is not.
        let c = compare(&square(2), &square(0), &Tolerance::LAVAPIPE);
        assert!(!c.passed(&Tolerance::LAVAPIPE), "{c:?}");
        assert!(c.coverage_mismatches > 0);
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
