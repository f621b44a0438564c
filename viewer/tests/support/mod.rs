//! Helpers of the viewer's process tests: a virtual X server (Xvfb) started and stopped by the
//! test, the viewer binary run with a time limit, the X framebuffer read back.
#![allow(
    dead_code,
    reason = "each test crate uses a different part of the helpers"
)]

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use gpu_backend::DeviceOptions;
use gpu_backend::test_support::{headless_or_skip, skip};

/// The `Xvfb` program, or `None` after printing `skipped: <test>: Xvfb not installed`. Under
/// `CI=true` a missing Xvfb fails instead (`scripts/setup-debian.sh` installs it).
pub(crate) fn xvfb_or_skip() -> Option<PathBuf> {
    let found = find_program("Xvfb");
    if found.is_none() {
        skip("Xvfb not installed (scripts/setup-debian.sh installs the `xvfb` package)");
    }
    found
}

/// How long the viewer may run before the test gives up on it: a guard against a hang, not
/// a speed check. lavapipe shares the CPU with the other tests of the binary; a 2-second
/// flight that takes 3 s alone has taken over 40 s beside them on a 2-core machine.
const VIEWER_TIMEOUT: Duration = Duration::from_secs(300);

/// An `Xvfb` server, stopped on drop.
pub(crate) struct Xvfb {
    child: Child,
    /// The display, e.g. `:1`.
    pub display: String,
}

impl Xvfb {
    /// Starts `program` on a free display and waits until it accepts connections (it writes
    /// the display number to `-displayfd` only then). With `fbdir`, the screen is also a file
    /// there (`Xvfb_screen0`, XWD), on a black root window.
    pub(crate) fn start(program: &Path, fbdir: Option<&Path>) -> Xvfb {
        let mut command = Command::new(program);
        command.args([
            "-displayfd",
            "1",
            "-screen",
            "0",
            "320x240x24",
            "-nolisten",
            "tcp",
        ]);
        if let Some(dir) = fbdir {
            command.arg("-br").arg("-fbdir").arg(dir);
        }
        let mut child = command
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
pub(crate) fn find_program(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(name))
        .find(|candidate| candidate.is_file())
}

/// The viewer binary with `args` and the display variables `display` (only `DISPLAY`, or
/// none), output piped.
pub(crate) fn viewer_command(args: &[&str], display: Option<&str>) -> Command {
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
    command
}

/// Runs the viewer binary (see [`viewer_command`]), killing it after [`VIEWER_TIMEOUT`].
pub(crate) fn run_viewer(args: &[&str], display: Option<&str>) -> Output {
    let mut child = viewer_command(args, display)
        .spawn()
        .expect("the viewer binary starts");
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

/// Output bytes as text.
pub(crate) fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The RGBA pixels of a PNG file.
pub(crate) fn read_png(path: &Path) -> Vec<u8> {
    let decoder = png::Decoder::new(std::io::Cursor::new(std::fs::read(path).expect("the PNG")));
    let mut reader = decoder.read_info().expect("PNG header");
    let mut rgba = vec![0; reader.output_buffer_size().expect("PNG size")];
    reader.next_frame(&mut rgba).expect("PNG pixels");
    rgba
}

/// A Vulkan adapter exists (else it printed `skipped: <test>: no Vulkan adapter`; panics
/// under CI).
pub(crate) fn have_adapter() -> bool {
    headless_or_skip(&DeviceOptions::default()).is_some()
}

/// Kills the child on drop (a viewer left running when a test fails).
pub(crate) struct KillOnDrop(pub Child);

impl Drop for KillOnDrop {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// The screen in an Xvfb `-fbdir` file (XWD, 32 bits per pixel, BGRX): width, height, RGB
/// pixels row by row. `None` while the file is missing or incomplete.
pub(crate) fn read_xwd(path: &Path) -> Option<(u32, u32, Vec<[u8; 3]>)> {
    let bytes = std::fs::read(path).ok()?;
    let word = |i: usize| -> Option<u32> {
        Some(u32::from_be_bytes(
            bytes.get(4 * i..4 * i + 4)?.try_into().ok()?,
        ))
    };
    let (header, width, height) = (word(0)?, word(4)?, word(5)?);
    let (bits_per_pixel, bytes_per_line, colours) = (word(11)?, word(12)?, word(19)?);
    if bits_per_pixel != 32 {
        return None;
    }
    let start = header as usize + 12 * colours as usize;
    let mut pixels = Vec::with_capacity((width * height) as usize);
    for y in 0..height as usize {
        let row = bytes.get(start + y * bytes_per_line as usize..)?;
        for x in 0..width as usize {
            let p = row.get(4 * x..4 * x + 4)?;
            pixels.push([p[2], p[1], p[0]]);
        }
    }
    Some((width, height, pixels))
}

/// How two RGBA images of one size differ: the largest channel difference, and the share of
/// pixels with a channel more than `over` apart.
pub(crate) fn image_difference(got: &[u8], want: &[u8], over: u8) -> (u8, f64) {
    assert_eq!(got.len(), want.len(), "images of different sizes");
    let mut largest = 0;
    let mut beyond = 0usize;
    for (a, b) in got.chunks(4).zip(want.chunks(4)) {
        let d = a
            .iter()
            .zip(b)
            .map(|(a, b)| a.abs_diff(*b))
            .max()
            .unwrap_or(0);
        largest = largest.max(d);
        beyond += usize::from(d > over);
    }
    (largest, beyond as f64 / (got.len() / 4).max(1) as f64)
}

/// Fails unless the viewer's PNG shows the reference frame: at most `share` of the pixels
/// with a channel more than 16 apart (none when `share` is 0).
pub(crate) fn assert_shows(got: &[u8], want: &[u8], share: f64, what: &str) {
    let (largest, beyond) = image_difference(got, want, 16);
    assert!(
        beyond <= share,
        "{what}: {:.2}% of the pixels differ from the reference by more than 16 (largest \
         difference {largest}), at most {:.2}% allowed",
        beyond * 100.0,
        share * 100.0
    );
}
