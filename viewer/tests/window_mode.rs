//! The viewer's modes, run as the built binary: a real window on a virtual X server (Xvfb)
//! presenting frames through the Vulkan driver (lavapipe in CI), and the PNG fallbacks.
//!
//! The window test starts its own `Xvfb` on a display number the server picks itself
//! (`-displayfd`), and stops it when done, also when the test fails. Without Xvfb (or without a
//! Vulkan adapter) the test prints one `skipped:` line, except under `CI=true`, where
//! `scripts/setup-debian.sh` installs both and their absence is a failure.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use gpu_backend::DeviceOptions;
use gpu_backend::test_support::{headless_or_skip, in_ci};

/// How long the viewer may run before the test gives up on it.
const VIEWER_TIMEOUT: Duration = Duration::from_secs(60);

/// An `Xvfb` server, stopped on drop.
struct Xvfb {
    child: Child,
    display: String,
}

impl Xvfb {
    /// Starts `program` on a free display and waits until it accepts connections (it writes
    /// the display number to `-displayfd` only then).
    fn start(program: &Path) -> Xvfb {
        let mut child = Command::new(program)
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "320x240x24",
                "-nolisten",
                "tcp",
            ])
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start {}: {e}", program.display()));
        let stdout = child.stdout.take().expect("stdout is piped");
        let (sender, receiver) = mpsc::channel();
        std::thread::spawn(move || {
            let mut line = String::new();
            let read = BufReader::new(stdout).read_line(&mut line);
            // The receiver may have timed out and gone; nothing to do then.
            let _ = sender.send(read.map(|_| line));
        });
        // The guard exists from here on, so a failure below still stops the server.
        let mut server = Xvfb {
            child,
            display: String::new(),
        };
        let number = match receiver.recv_timeout(Duration::from_secs(20)) {
            Ok(Ok(line)) if !line.trim().is_empty() => line.trim().to_owned(),
            other => panic!("Xvfb did not report a display number: {other:?}"),
        };
        server.display = format!(":{number}");
        server
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        // Already gone is fine; the wait reaps it either way.
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// `name` on `PATH`, if there.
fn find_program(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(name))
        .find(|candidate| candidate.is_file())
}

/// Runs the viewer binary with `args` and the display variables `display` (only
/// `DISPLAY`, or none), killing it after [`VIEWER_TIMEOUT`].
fn run_viewer(args: &[&str], display: Option<&str>) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_viewer"));
    command
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    if let Some(display) = display {
        command.env("DISPLAY", display);
    }
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        command.env("XDG_RUNTIME_DIR", std::env::temp_dir());
    }
    let mut child = command.spawn().expect("the viewer binary starts");
    let started = Instant::now();
    while child.try_wait().expect("waiting for the viewer").is_none() {
        if started.elapsed() > VIEWER_TIMEOUT {
            let _ = child.kill();
            let output = child.wait_with_output().expect("viewer output");
            panic!(
                "the viewer ran longer than {VIEWER_TIMEOUT:?}; stderr:\n{}",
                String::from_utf8_lossy(&output.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().expect("viewer output")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A Vulkan adapter exists (else the first call printed `skipped: no Vulkan adapter`; panics
/// under CI).
fn have_adapter() -> bool {
    headless_or_skip(&DeviceOptions::default()).is_some()
}

/// Runs the viewer in a window on a fresh Xvfb with `args` (after `--window --chunks 1`) and
/// returns its `window:` line; `None` when skipped (no Xvfb or no adapter, outside CI).
fn window_line(args: &[&str]) -> Option<String> {
    let Some(xvfb) = find_program("Xvfb") else {
        assert!(
            !in_ci(),
            "Xvfb is not installed (scripts/setup-debian.sh installs the `xvfb` package)"
        );
        eprintln!("skipped: Xvfb not installed");
        return None;
    };
    if !have_adapter() {
        return None;
    }
    let server = Xvfb::start(&xvfb);
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

#[test]
fn without_a_display_or_with_headless_the_viewer_writes_a_png() {
    if !have_adapter() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("viewer-window-mode-{}", std::process::id()));
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
