//! The viewer's modes, run as the built binary: a real window on a virtual X server (Xvfb)
//! presenting frames through the Vulkan driver (lavapipe in CI), and the PNG fallbacks.
//!
//! The window test starts its own `Xvfb` on a display number the server picks itself
//! (`-displayfd`), and stops it when done, also when the test fails. Without Xvfb (or without a
//! Vulkan adapter) the test prints one `skipped:` line, except under `CI=true`, where
//! `scripts/setup-debian.sh` installs both and their absence is a failure.

mod support;

use std::time::Instant;

use render_model::lighting::Lighting;
use support::{Xvfb, have_adapter, read_png, run_viewer, text, xvfb_or_skip};
use viewer::gpu_view::render_scene;
use viewer::scene::terrain_scene;
use voxel_core::ChunkSize;

/// Runs the viewer in a window on a fresh Xvfb with `args` (after `--window --chunks 1`) and
/// returns its `window:` line; `None` when skipped (no Xvfb or no adapter, outside CI).
fn window_line(args: &[&str]) -> Option<String> {
    let xvfb = xvfb_or_skip()?;
    if !have_adapter() {
        return None;
    }
    let server = Xvfb::start(&xvfb, None);
    let started = Instant::now();
    let mut all = vec!["--window", "--chunks", "1", "--frames-timeout", "40"];
    all.extend(args);
    let output = run_viewer(&all, Some(&server.display));
    let elapsed = started.elapsed();
    drop(server);
    let (stdout, stderr) = (text(&output.stdout), text(&output.stderr));
    assert!(
        output.status.success(),
        "viewer {all:?} failed ({}):\nstdout:\n{stdout}\nstderr:\n{stderr}",
        output.status
    );
    assert!(
        !stdout.contains("wrote"),
        "window mode writes no PNG:\n{stdout}"
    );
    let line = stdout
        .lines()
        .find(|l| l.starts_with("window: "))
        .unwrap_or_else(|| panic!("no `window:` line in:\n{stdout}\nstderr:\n{stderr}"))
        .to_owned();
    eprintln!("{line} ({elapsed:.1?})");
    Some(line)
}

#[test]
fn window_mode_presents_frames_on_a_virtual_display() {
    let Some(line) = window_line(&["--frames", "3", "--width", "160", "--height", "96"]) else {
        return;
    };
    let prefix = "window: presented 3 frames 160x96 on ";
    assert!(line.starts_with(prefix), "unexpected line {line:?}");
    assert!(line.len() > prefix.len(), "the adapter is named: {line:?}");
}

#[test]
fn window_mode_follows_a_resize() {
    // The swapchain and the renderer's targets must follow the window: the viewer closes only
    // once frames were presented at the new size.
    let args = [
        "--frames",
        "3",
        "--width",
        "160",
        "--height",
        "96",
        "--resize-to",
        "120x72",
    ];
    let Some(line) = window_line(&args) else {
        return;
    };
    let (_, rest) = line
        .split_once(" frames ")
        .unwrap_or_else(|| panic!("unexpected line {line:?}"));
    assert!(rest.starts_with("120x72 on "), "not resized: {line:?}");
}

/// Without a display, or with `--headless`, the viewer writes the frame of the GPU renderer:
/// the PNG is the reference frame rendered here in the test process (`render_scene` on the
/// same scene, camera and lighting), pixel for pixel.
///
/// The fault it catches: a PNG that is not the rendered frame (rows written bottom-up, the
/// channels swapped, a blank buffer), which a check of the file's magic bytes or size lets
/// through. Planted (`write_png` given the rows bottom-up), this test failed with
/// "no-display: 30.08% of the pixels differ from the reference by more than 16".
#[test]
fn without_a_display_or_with_headless_the_viewer_writes_a_png() {
    if !have_adapter() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("viewer-window-mode-{}", std::process::id()));
    // What `--chunks 1` shows: terrain seed 1, one chunk of 32^3 by 2 high, its suggested view.
    let scene = terrain_scene(1, ChunkSize::S32, 1, 2, 1);
    let reference = render_scene(
        &scene,
        &scene.suggested_view,
        &Lighting::default(),
        (48, 32),
        false,
    )
    .expect("the reference frame")
    .rgba;
    for (case, display, extra) in [
        ("no-display", None, None),
        ("headless", Some(":9999"), Some("--headless")),
    ] {
        let out = dir.join(format!("{case}.png"));
        let out_arg = out.to_string_lossy().into_owned();
        let mut args = vec![
            "--width", "48", "--height", "32", "--chunks", "1", "--out", &out_arg,
        ];
        args.extend(extra);
        let output = run_viewer(&args, display);
        let (stdout, stderr) = (text(&output.stdout), text(&output.stderr));
        assert!(
            output.status.success(),
            "{case}: viewer failed:\nstdout:\n{stdout}\nstderr:\n{stderr}"
        );
        assert!(
            stdout.contains("viewer: wrote ") && !stdout.contains("window: "),
            "{case}: {stdout}"
        );
        let bytes = std::fs::read(&out).unwrap_or_else(|e| panic!("{case}: {e}"));
        assert!(bytes.starts_with(b"\x89PNG"), "{case}: not a PNG");
        support::assert_shows(&read_png(&out), &reference, 0.0, case);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn forced_window_without_a_display_fails_with_a_message() {
    // No display at all: winit cannot connect; `--window` makes that an error, not a PNG.
    let output = run_viewer(
        &[
            "--window", "--frames", "1", "--chunks", "1", "--width", "32", "--height", "32",
        ],
        None,
    );
    let stderr = text(&output.stderr);
    assert!(!output.status.success(), "must fail: {stderr}");
    assert!(stderr.contains("viewer: window: "), "{stderr}");
    assert!(!text(&output.stdout).contains("wrote"));
}
