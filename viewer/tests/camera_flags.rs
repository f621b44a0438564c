//! `--camera` and `--fov` place the headless frame's camera (the CPU raycaster draws it, so
//! that test needs no GPU) and the window's first view (checked against the GPU's headless
//! frame on a virtual X server; skips like `window_image.rs` without Xvfb or a Vulkan
//! adapter, outside CI), and terrain options given with `--vox` are refused.

mod support;

use std::path::Path;
use std::process::Stdio;
use std::time::{Duration, Instant};

use support::{
    KillOnDrop, Xvfb, have_adapter, read_png, read_xwd, run_viewer, text, viewer_command,
    xvfb_or_skip,
};

/// Renders the one-chunk terrain (columns 0..32 on x and z) headless with the CPU raycaster
/// and `extra` arguments; returns the RGBA pixels.
fn frame(dir: &Path, name: &str, extra: &[&str]) -> Vec<u8> {
    let out = dir.join(format!("{name}.png"));
    let out_arg = out.to_string_lossy().into_owned();
    let mut args = vec![
        "--headless",
        "--cpu",
        "--width",
        "64",
        "--height",
        "40",
        "--chunks",
        "1",
        "--out",
        &out_arg,
    ];
    args.extend_from_slice(extra);
    let output = run_viewer(&args, None);
    assert!(
        output.status.success(),
        "viewer {args:?} failed:\n{}\n{}",
        text(&output.stdout),
        text(&output.stderr)
    );
    read_png(&out)
}

/// Share of pixels that differ by more than 8 in some channel.
fn changed(a: &[u8], b: &[u8]) -> f64 {
    let n = a.len() / 4;
    let differ = a
        .chunks(4)
        .zip(b.chunks(4))
        .filter(|(p, q)| p.iter().zip(*q).any(|(x, y)| x.abs_diff(*y) > 8))
        .count();
    differ as f64 / n as f64
}

#[test]
fn the_headless_frame_is_taken_from_the_given_camera() {
    let dir = tempfile_dir();
    // Above the chunk, looking down: terrain fills the view.
    let down_here = frame(&dir, "down-here", &["--camera", "16,36,16,0,-89"]);
    // The same place looking up, and far away looking up: only sky, the same sky.
    let up_here = frame(&dir, "up-here", &["--camera", "16,36,16,0,89"]);
    let up_there = frame(&dir, "up-there", &["--camera", "900,36,-900,0,89"]);
    // Far from the chunk looking down: no terrain below.
    let down_there = frame(&dir, "down-there", &["--camera", "900,36,-900,0,-89"]);
    let default_view = frame(&dir, "default", &[]);
    for (name, image) in [
        ("down here", &down_here),
        ("down there", &down_there),
        ("default", &default_view),
    ] {
        eprintln!(
            "{name}: {:.2} of the pixels differ from the sky",
            changed(image, &up_here)
        );
    }

    assert_eq!(
        changed(&up_here, &up_there),
        0.0,
        "the sky depends on direction only"
    );
    // (Measured: 87 % of the pixels show ground looking down over the chunk, none far from
    // it, 15 % in the default view.)
    assert!(
        changed(&down_here, &up_here) > 0.6,
        "looking down shows the ground"
    );
    assert!(
        changed(&down_here, &down_there) > 0.6,
        "the position moves the camera"
    );
    assert!(
        changed(&down_here, &default_view) > 0.3,
        "--camera replaces the default view"
    );

    // A narrower field of view magnifies: the frame changes, and a wider one changes it too.
    let narrow = frame(
        &dir,
        "narrow",
        &["--camera", "16,36,16,0,-89", "--fov", "20"],
    );
    let wide = frame(
        &dir,
        "wide",
        &["--camera", "16,36,16,0,-89", "--fov", "120"],
    );
    assert!(
        changed(&narrow, &down_here) > 0.2,
        "--fov 20 changes the frame"
    );
    assert!(
        changed(&wide, &down_here) > 0.2,
        "--fov 120 changes the frame"
    );
    // --fov alone narrows the scene's own first view.
    let default_narrow = frame(&dir, "default-narrow", &["--fov", "20"]);
    eprintln!(
        "default view at fov 20: {:.3} of the pixels change",
        changed(&default_narrow, &default_view)
    );
    assert!(changed(&default_narrow, &default_view) > 0.05);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn terrain_options_with_vox_and_bad_cameras_are_refused() {
    for (args, named) in [
        (&["--vox", "model.vox", "--seed", "4"][..], "--seed"),
        (&["--vox", "model.vox", "--chunks", "2"][..], "--chunks"),
        (&["--camera", "1,2,3"][..], "X,Y,Z,YAW,PITCH"),
        (&["--fov", "200"][..], "field of view"),
    ] {
        let output = run_viewer(args, None);
        let stderr = text(&output.stderr);
        assert!(!output.status.success(), "{args:?} accepted");
        assert!(stderr.contains(named), "{args:?}: {stderr}");
        assert!(
            !text(&output.stdout).contains("wrote"),
            "{args:?} wrote a frame"
        );
    }
}

/// A fresh folder for this test's frames.
fn tempfile_dir() -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("viewer-camera-flags-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    dir
}

#[test]
fn the_window_starts_at_the_given_camera() {
    let Some(xvfb) = xvfb_or_skip() else {
        return;
    };
    if !have_adapter() {
        return;
    }
    let (w, h) = (96u32, 64u32);
    let (ws, hs) = (w.to_string(), h.to_string());
    let dir = std::env::temp_dir().join(format!("viewer-camera-window-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let png_path = dir.join("headless.png");
    let png_arg = png_path.to_string_lossy().into_owned();
    let common = [
        "--chunks",
        "1",
        "--width",
        &ws,
        "--height",
        &hs,
        "--camera",
        "40,30,44,35,-25",
        "--fov",
        "50",
    ];

    let mut headless = common.to_vec();
    headless.extend(["--headless", "--out", &png_arg]);
    let output = run_viewer(&headless, None);
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert!(
        text(&output.stdout).contains("GPU renderer"),
        "the GPU drew the frame"
    );
    let want: Vec<[u8; 3]> = read_png(&png_path)
        .chunks(4)
        .map(|p| [p[0], p[1], p[2]])
        .collect();

    let server = Xvfb::start(&xvfb, Some(&dir));
    let mut window = common.to_vec();
    window.extend(["--window", "--no-overlay", "--frames", "100000"]);
    let viewer = KillOnDrop(
        viewer_command(&window, Some(&server.display))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("the viewer starts"),
    );
    // Wait until the window's corner of the screen is drawn and two reads agree.
    let screen_file = dir.join("Xvfb_screen0");
    let started = Instant::now();
    let mut last: Option<Vec<[u8; 3]>> = None;
    let got = loop {
        assert!(
            started.elapsed() < Duration::from_secs(40),
            "the window never showed a stable image"
        );
        std::thread::sleep(Duration::from_millis(200));
        let Some((width, _, pixels)) = read_xwd(&screen_file) else {
            continue;
        };
        let now: Vec<[u8; 3]> = (0..h)
            .flat_map(|y| (0..w).map(move |x| (y * width + x) as usize))
            .map(|i| pixels[i])
            .collect();
        let drawn = now.iter().all(|p| *p != [0, 0, 0]);
        if drawn && last.as_ref() == Some(&now) {
            break now;
        }
        last = Some(now);
    };
    drop(viewer);
    drop(server);
    let _ = std::fs::remove_dir_all(&dir);
    let worst = got
        .iter()
        .zip(&want)
        .flat_map(|(g, w)| (0..3).map(move |c| g[c].abs_diff(w[c])))
        .max()
        .unwrap_or(0);
    // Same renderer, camera and present pass as window_image.rs: one rounding step allowed.
    assert!(
        worst <= 1,
        "the window's first frame differs from the headless one: {worst}"
    );
}
