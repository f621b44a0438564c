//! The streamed terrain in a window on a virtual X server: frames are presented while it
//! loads, it is streamed by the end, and the screenshot path (the one F12 takes, triggered
//! here by `--screenshot-at`) writes a PNG of the window's size. Skips like `window_mode.rs`
//! (no Xvfb or no Vulkan adapter, outside CI).

mod support;

use support::{Xvfb, have_adapter, run_viewer, text, xvfb_or_skip};

#[test]
fn the_streamed_terrain_loads_in_a_window_and_f12_writes_a_screenshot() {
    let Some(xvfb) = xvfb_or_skip() else {
        return;
    };
    if !have_adapter() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("viewer-window-stream-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let dir_arg = dir.to_string_lossy().into_owned();
    let server = Xvfb::start(&xvfb, None);
    let output = run_viewer(
        &[
            "--window",
            "--radius",
            "64",
            "--width",
            "96",
            "--height",
            "64",
            "--frames",
            "90",
            "--frames-timeout",
            "40",
            "--screenshot-at",
            "80",
            "--screenshot-dir",
            &dir_arg,
        ],
        Some(&server.display),
    );
    drop(server);
    let (stdout, stderr) = (text(&output.stdout), text(&output.stderr));
    assert!(output.status.success(), "{stdout}\n{stderr}");
    let line = stdout
        .lines()
        .find(|l| l.starts_with("window: "))
        .unwrap_or_else(|| panic!("no window line: {stdout}\n{stderr}"));
    assert!(
        line.starts_with("window: presented 90 frames 96x64 on ") && line.contains("; streamed: "),
        "streamed by the end: {line}"
    );
    let shot = stdout
        .lines()
        .find_map(|l| l.strip_prefix("viewer: screenshot "))
        .unwrap_or_else(|| panic!("no screenshot line: {stdout}\n{stderr}"));
    let decoder = png::Decoder::new(std::io::Cursor::new(std::fs::read(shot).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut rgba = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut rgba).unwrap();
    assert_eq!((info.width, info.height), (96, 64));
    let colours: std::collections::HashSet<&[u8]> = rgba.chunks(4).collect();
    assert!(
        colours.len() > 20,
        "terrain drawn: {} colours",
        colours.len()
    );
    let _ = std::fs::remove_dir_all(&dir);
}
