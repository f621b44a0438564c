//! What the window shows, read from the virtual X server's framebuffer (Xvfb `-fbdir`), against
//! the PNG the headless mode renders of the same scene from the same camera: the swapchain
//! format, the present pass and the channel order are all on the way. Skips like
//! `window_mode.rs` (no Xvfb or no Vulkan adapter, outside CI).

mod support;

use std::process::Stdio;
use std::time::{Duration, Instant};

use support::{
    KillOnDrop, Xvfb, have_adapter, read_xwd, run_viewer, text, viewer_command, xvfb_or_skip,
};

/// The `w x h` region at the screen's top-left corner (where a window lands without a window
/// manager).
fn region(screen: &(u32, u32, Vec<[u8; 3]>), w: u32, h: u32) -> Vec<[u8; 3]> {
    let (width, _, pixels) = screen;
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (y * width + x) as usize))
        .map(|i| pixels[i])
        .collect()
}

/// The RGB pixels of a PNG file.
fn read_png_rgb(path: &std::path::Path) -> Vec<[u8; 3]> {
    let bytes = std::fs::read(path).expect("the PNG");
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = decoder.read_info().expect("PNG header");
    let mut rgba = vec![0; reader.output_buffer_size().expect("PNG size")];
    reader.next_frame(&mut rgba).expect("PNG pixels");
    rgba.chunks(4).map(|p| [p[0], p[1], p[2]]).collect()
}

#[test]
fn the_window_shows_what_the_headless_renderer_draws() {
    let Some(xvfb) = xvfb_or_skip() else {
        return;
    };
    if !have_adapter() {
        return;
    }
    let (w, h) = (96u32, 64u32);
    let (ws, hs) = (w.to_string(), h.to_string());
    let dir = std::env::temp_dir().join(format!("viewer-window-image-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let png_path = dir.join("headless.png");
    let png_arg = png_path.to_string_lossy().into_owned();
    let common = ["--chunks", "1", "--width", &ws, "--height", &hs];

    let mut headless = common.to_vec();
    headless.extend(["--headless", "--out", &png_arg]);
    let output = run_viewer(&headless, None);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let want = read_png_rgb(&png_path);

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
    // Wait until the region is drawn (no longer the black root) and two reads agree.
    let screen_file = dir.join("Xvfb_screen0");
    let started = Instant::now();
    let mut last: Option<Vec<[u8; 3]>> = None;
    let got = loop {
        assert!(
            started.elapsed() < Duration::from_secs(40),
            "the window never showed a stable image"
        );
        std::thread::sleep(Duration::from_millis(200));
        let Some(screen) = read_xwd(&screen_file) else {
            continue;
        };
        let now = region(&screen, w, h);
        let drawn = now.iter().all(|p| *p != [0, 0, 0]);
        if drawn && last.as_ref() == Some(&now) {
            break now;
        }
        last = Some(now);
    };
    let elapsed = started.elapsed();
    drop(viewer);
    drop(server);
    let _ = std::fs::remove_dir_all(&dir);

    let mut worst = 0;
    let mut total = 0u64;
    for (g, w) in got.iter().zip(&want) {
        for c in 0..3 {
            let d = g[c].abs_diff(w[c]);
            worst = worst.max(d);
            total += u64::from(d);
        }
    }
    let mean = total as f64 / (3 * want.len()) as f64;
    eprintln!(
        "window vs headless ({elapsed:.1?}): largest channel difference {worst}, mean {mean:.3}"
    );
    // The same renderer, device type and camera, and a byte-exact present pass (see
    // gpu-backend's gpu_present test): the bytes agree; one rounding step is allowed.
    assert!(
        worst <= 1,
        "the window differs from the headless image: largest channel difference {worst}"
    );
}
