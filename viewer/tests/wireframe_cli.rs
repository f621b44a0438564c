//! `--wireframe` from the command line: the headless frame draws the meshes' quad edges (the
//! same view otherwise), and the flag is refused with `--cpu`, which has no meshes to outline.

mod support;
#[path = "../../scene/tests/support/writer.rs"]
mod vox_writer;

use support::{have_adapter, read_png, run_viewer, text};

/// Renders the streamed terrain headless (meshes only) with `extra` flags; the PNG's RGBA.
fn frame(dir: &std::path::Path, name: &str, extra: &[&str]) -> Vec<u8> {
    let out = dir.join(format!("{name}.png"));
    let out_arg = out.to_string_lossy().into_owned();
    let mut args = vec![
        "--headless",
        "--width",
        "160",
        "--height",
        "100",
        "--radius",
        "96",
        "--far",
        "off",
        "--camera",
        "20,40,20,30,-50",
        "--fov",
        "50",
        "--out",
        &out_arg,
    ];
    args.extend_from_slice(extra);
    let output = run_viewer(&args, None);
    let (stdout, stderr) = (text(&output.stdout), text(&output.stderr));
    assert!(output.status.success(), "{stdout}\n{stderr}");
    read_png(&out)
}

#[test]
fn the_wireframe_frame_outlines_the_meshes_of_the_same_view() {
    if !have_adapter() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("viewer-wireframe-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let filled = frame(&dir, "filled", &[]);
    let wire = frame(&dir, "wire", &["--wireframe"]);
    assert_eq!(filled.len(), wire.len());
    let pixels = filled.len() / 4;
    let differ = filled
        .chunks(4)
        .zip(wire.chunks(4))
        .filter(|(a, b)| a.iter().zip(*b).any(|(a, b)| a.abs_diff(*b) > 8))
        .count();
    // Inside each quad the wireframe shows what lies behind it (sky, or faces further back,
    // often of the same grass colour); at this close view over a tenth of the pixels change.
    assert!(
        differ * 10 > pixels,
        "{differ} of {pixels} pixels differ between the filled and the wireframe frame"
    );
    assert!(differ < pixels, "the edges are drawn");
    let again = frame(&dir, "filled-again", &[]);
    assert_eq!(
        again, filled,
        "the filled frame does not depend on an earlier run"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The model of [`edges_are_drawn_where_the_quads_edges_are`]: a 12 x 6 x 6 box of two
/// colours (file x below 6 colour 1, from 6 on colour 2), so greedy meshing splits each face
/// that spans both halves at x = 6: one quad per face of each half. In world axes (file
/// `(x, y, z)` is world `(x, z, -1 - y)`) it spans x 0..12, y 0..6, z -6..0.
fn two_colour_box() -> Vec<u8> {
    let mut voxels = Vec::new();
    for x in 0..12u8 {
        for y in 0..6u8 {
            for z in 0..6u8 {
                voxels.push([x, y, z, if x < 6 { 1 } else { 2 }]);
            }
        }
    }
    let mut w = vox_writer::VoxWriter::new();
    w.model([12, 6, 6], &voxels);
    w.bytes()
}

/// The box's greedy quads, each as its 4 world corners (in order around the quad) and its
/// outward normal: two halves, each a box with 6 faces less the face the halves share.
fn box_quads() -> Vec<([[f64; 3]; 4], [f64; 3])> {
    let mut quads = Vec::new();
    for (x0, x1) in [(0.0, 6.0), (6.0, 12.0)] {
        let (y0, y1, z0, z1) = (0.0, 6.0, -6.0, 0.0);
        let faces = [
            (
                [[x0, y0, z0], [x0, y1, z0], [x0, y1, z1], [x0, y0, z1]],
                [-1.0, 0.0, 0.0],
            ),
            (
                [[x1, y0, z0], [x1, y1, z0], [x1, y1, z1], [x1, y0, z1]],
                [1.0, 0.0, 0.0],
            ),
            (
                [[x0, y0, z0], [x1, y0, z0], [x1, y0, z1], [x0, y0, z1]],
                [0.0, -1.0, 0.0],
            ),
            (
                [[x0, y1, z0], [x1, y1, z0], [x1, y1, z1], [x0, y1, z1]],
                [0.0, 1.0, 0.0],
            ),
            (
                [[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0]],
                [0.0, 0.0, -1.0],
            ),
            (
                [[x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]],
                [0.0, 0.0, 1.0],
            ),
        ];
        for (corners, normal) in faces {
            // The face the two halves share is inside the box: no quad.
            let inner = corners.iter().all(|c| c[0] == 6.0);
            if !inner {
                quads.push((corners, normal));
            }
        }
    }
    quads
}

/// The pinhole projection of `render_model::camera::Camera::ray_direction`, inverted: the pixel
/// coordinates (pixel centres at `i + 0.5`) of world point `p`, `None` behind the eye.
fn project(
    camera: &render_model::camera::Camera,
    p: [f64; 3],
    (w, h): (u32, u32),
) -> Option<[f64; 2]> {
    let eye = glam::DVec3::new(
        f64::from(camera.voxel.x),
        f64::from(camera.voxel.y),
        f64::from(camera.voxel.z),
    ) + camera.fraction;
    let forward = camera.forward();
    let right = forward.cross(glam::DVec3::Y).normalize();
    let up = right.cross(forward);
    let d = glam::DVec3::from_array(p) - eye;
    let z = d.dot(forward);
    if z <= 1e-6 {
        return None;
    }
    let half_h = (camera.fov_y * 0.5).tan();
    let half_w = half_h * f64::from(w) / f64::from(h);
    let (u, v) = (d.dot(right) / z / half_w, d.dot(up) / z / half_h);
    Some([
        (u + 1.0) * 0.5 * f64::from(w),
        (1.0 - v) * 0.5 * f64::from(h),
    ])
}

/// Distance from pixel centre `q` to the segment `a`-`b`.
fn distance_to_segment(q: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 == 0.0 {
        0.0
    } else {
        (((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    };
    let (px, py) = (a[0] + t * dx - q[0], a[1] + t * dy - q[1]);
    (px * px + py * py).sqrt()
}

/// `--wireframe` draws each greedy quad's edges, and only them: on a two-colour box whose
/// quads are known (12 x 6 x 6, split at x = 6), the pixels the wireframe frame changes from
/// the empty scene's sky lie within 2.5 pixels of a projected quad edge (at least 90% of
/// them), and along every edge of the quads that face the camera at least 80% of the points
/// have a changed pixel within 1.5 pixels. The split at x = 6 runs across flat faces, where
/// the filled frame shows no edge: only a wireframe of the quads draws it, and the test
/// checks that stretch on its own.
///
/// The fault it catches: a wireframe that draws nothing, or the filled quads, or lines
/// elsewhere, which the other test (a tenth of the pixels change, not all) lets through.
/// Planted in `viewer::gpu_view::render_scene`: no mesh uploaded in the wireframe view (it
/// draws nothing), this test failed with "0 pixels changed: no wireframe drawn"; the filled
/// view drawn instead, with "only 58% of the changed pixels lie on a quad edge (1713 of
/// 2976)".
#[test]
fn edges_are_drawn_where_the_quads_edges_are() {
    if !have_adapter() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("viewer-wire-edges-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let model = dir.join("box.vox");
    std::fs::write(&model, two_colour_box()).unwrap();
    // The same model far behind the camera: the frame shows only the sky.
    let mut away = vox_writer::VoxWriter::new();
    away.model([1, 1, 1], &[[0, 0, 0, 1]])
        .transform(0, &[], 1, -1, &[("_t", "500 -500 0")])
        .shape(1, &[], &[0]);
    let empty = dir.join("away.vox");
    std::fs::write(&empty, away.bytes()).unwrap();
    let size = (160u32, 120u32);
    // From above the corner at x 20, z 12, looking at the box's centre (6, 3, -3).
    let (eye, target) = ([20.5, 14.5, 12.5], [6.0, 3.0, -3.0]);
    let d: Vec<f64> = (0..3).map(|i| target[i] - eye[i]).collect();
    let yaw = (-d[0]).atan2(-d[2]).to_degrees();
    let pitch = (d[1] / (d[0] * d[0] + d[2] * d[2]).sqrt())
        .atan()
        .to_degrees();
    let camera_arg = format!("{},{},{},{yaw},{pitch}", eye[0], eye[1], eye[2]);
    let render = |input: &std::path::Path, name: &str, wire: bool| {
        let out = dir.join(format!("{name}.png"));
        let (w, h) = (size.0.to_string(), size.1.to_string());
        let mut args = vec![
            "--headless",
            "--vox",
            input.to_str().unwrap(),
            "--width",
            &w,
            "--height",
            &h,
            "--camera",
            &camera_arg,
            "--fov",
            "50",
            "--out",
            out.to_str().unwrap(),
        ];
        if wire {
            args.push("--wireframe");
        }
        let output = run_viewer(&args, None);
        assert!(output.status.success(), "{}", text(&output.stderr));
        read_png(&out)
    };
    let sky = render(&empty, "sky", false);
    let wire = render(&model, "wire", true);
    let camera = render_model::camera::Camera {
        voxel: voxel_core::WorldPos::new(20, 14, 12),
        fraction: glam::DVec3::splat(0.5),
        yaw: yaw.to_radians(),
        pitch: pitch.to_radians(),
        fov_y: 50f64.to_radians(),
        near: render_model::camera::Camera::DEFAULT_NEAR,
    };
    let eye_v = glam::DVec3::from_array(eye);
    let quads = box_quads();
    let mut all_edges = Vec::new();
    let mut front_edges = Vec::new();
    for (corners, normal) in &quads {
        let facing = (eye_v - glam::DVec3::from_array(corners[0]))
            .dot(glam::DVec3::from_array(*normal))
            > 0.0;
        for i in 0..4 {
            let (a, b) = (corners[i], corners[(i + 1) % 4]);
            if let (Some(pa), Some(pb)) = (project(&camera, a, size), project(&camera, b, size)) {
                all_edges.push((pa, pb, a, b));
                if facing {
                    front_edges.push((pa, pb, a, b));
                }
            }
        }
    }
    let changed: Vec<[f64; 2]> = (0..(size.0 * size.1) as usize)
        .filter(|&i| {
            let (a, b) = (&wire[4 * i..4 * i + 4], &sky[4 * i..4 * i + 4]);
            a.iter().zip(b).any(|(a, b)| a.abs_diff(*b) > 8)
        })
        .map(|i| {
            let (x, y) = (i as u32 % size.0, i as u32 / size.0);
            [f64::from(x) + 0.5, f64::from(y) + 0.5]
        })
        .collect();
    assert!(
        changed.len() > 200,
        "{} pixels changed: no wireframe drawn",
        changed.len()
    );
    let on_edge = changed
        .iter()
        .filter(|q| {
            all_edges
                .iter()
                .any(|(a, b, ..)| distance_to_segment(**q, *a, *b) <= 2.5)
        })
        .count();
    let share = on_edge as f64 / changed.len() as f64;
    assert!(
        share >= 0.9,
        "only {:.0}% of the changed pixels lie on a quad edge ({on_edge} of {})",
        share * 100.0,
        changed.len()
    );
    // Along each front edge, points a pixel apart (ends left out: corners blur).
    let (mut points, mut drawn, mut split_points, mut split_drawn) = (0, 0, 0, 0);
    for (a, b, wa, wb) in &front_edges {
        let length = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        let steps = length.floor() as usize;
        let split = wa[0] == 6.0 && wb[0] == 6.0;
        for s in 2..steps.saturating_sub(1) {
            let t = s as f64 / length;
            let q = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
            if !(0.0..f64::from(size.0)).contains(&q[0])
                || !(0.0..f64::from(size.1)).contains(&q[1])
            {
                continue;
            }
            let hit = changed
                .iter()
                .any(|c| (c[0] - q[0]).abs() <= 1.5 && (c[1] - q[1]).abs() <= 1.5);
            points += 1;
            drawn += usize::from(hit);
            if split {
                split_points += 1;
                split_drawn += usize::from(hit);
            }
        }
    }
    assert!(
        points > 100 && split_points > 10,
        "{points} points, {split_points} on the split"
    );
    for (what, hit, of) in [
        ("the quads' edges", drawn, points),
        ("the split at x = 6", split_drawn, split_points),
    ] {
        assert!(
            hit * 10 >= of * 8,
            "{hit} of {of} points along {what} have a line drawn within 1.5 px"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn wireframe_with_the_cpu_raycaster_is_refused() {
    let output = run_viewer(&["--headless", "--cpu", "--wireframe"], None);
    let stderr = text(&output.stderr);
    assert!(!output.status.success());
    assert!(
        stderr.contains("--wireframe") && stderr.contains("--cpu"),
        "{stderr}"
    );
}
