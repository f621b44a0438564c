//! The interactive window: the scene drawn by the GPU renderer into a winit window, a fly
//! camera, and an egui overlay with statistics and controls.
//!
//! ```text
//!  run_window(source, view, options)
//!    winit event loop ─► App (app.rs): events ─► FlyCamera (camera.rs), Overlay (overlay.rs)
//!    resumed:          window ─► GpuWindow (gpu.rs): GpuContext::new_windowed, and either a
//!                      fixed scene's renderer (meshed and uploaded whole) or a StreamedView
//!                      (the terrain streamed around the camera, `crate::view`)
//!    RedrawRequested:  streaming update ─► renderer.record_frame ─► blit to the swapchain image
//!                      (a plain sky while the first view loads) ─► egui overlay (panel.rs)
//!                      ─► submit, present ─► per-pass times (stats.rs), cull counters
//!                      ─► changed controls applied to the view
//! ```
//!
//! Controls: W/A/S/D (or the arrows) move, Space rises, Shift sinks, a left or right mouse drag
//! looks around, the wheel changes the speed, F1 shows or hides the overlay, F3 switches the
//! wireframe view (also a checkbox in the overlay), F12 writes a
//! screenshot (the renderer's frame without the overlay; its path is printed and shown),
//! Escape closes. On the streamed terrain the overlay also switches the mesher mode, the far
//! draws, the error budget and the layers ([`Controls`](crate::controls::Controls)), and a
//! left click breaks blocks, a right click places them ([`editing`]: `[` `]` brush radius,
//! 1 to 6 its block; with a world folder, saved every 30 s and on closing).
//!
//! With [`WindowOptions::frames`] the window closes by itself after that many presented frames
//! (tests and smoke runs); [`WindowOptions::resize_to`] resizes it on the way.

mod app;
pub mod camera;
pub mod editing;
mod gpu;
mod lines;
pub mod mode;
mod overlay;
mod panel;
pub mod stats;

use std::fmt;
use std::path::PathBuf;
use std::time::Duration;

use gpu_backend::DeviceError;
use gpu_backend::render::RenderError;
use winit::error::{EventLoopError, OsError};
use winit::event_loop::EventLoop;

use crate::edits::SharedWorld;
use crate::gpu_view::GpuViewError;
use crate::scene::Scene;
use crate::stream::{StreamError, StreamSettings};
use render_model::camera::Camera;

/// What the window shows.
#[derive(Debug)]
pub enum WindowSource<'a> {
    /// A scene held whole (a `.vox` file, a fixed square of terrain).
    Fixed(&'a Scene),
    /// The built-in terrain, streamed around the camera.
    Streamed {
        /// How it streams.
        settings: StreamSettings,
        /// The world it shows (the terrain of the settings' seed, edited or loaded).
        world: SharedWorld,
        /// Where the edits are saved (`--world`): every 30 s and on closing.
        world_dir: Option<PathBuf>,
    },
}

/// How the window is opened.
#[derive(Clone, Debug, PartialEq)]
pub struct WindowOptions {
    /// Inner width asked for, pixels (the window manager may give another).
    pub width: u32,
    /// Inner height asked for, pixels.
    pub height: u32,
    /// Close after this many presented frames.
    pub frames: Option<u64>,
    /// With `frames`: give up (an error) when they are not presented within this time.
    pub frames_deadline: Duration,
    /// Wait for the display's refresh when presenting.
    pub vsync: bool,
    /// After the first presented frame, ask the window for this inner size; with `frames`,
    /// the window closes only once the new size is in use (tests the resize path).
    pub resize_to: Option<(u32, u32)>,
    /// Draw the stats overlay (F1 toggles it while running).
    pub overlay: bool,
    /// Where F12 writes screenshots.
    pub screenshot_dir: PathBuf,
    /// Tests: write a screenshot after this many presented frames, as F12 would.
    pub screenshot_at: Option<u64>,
    /// Start in the wireframe view (F3 toggles it).
    pub wireframe: bool,
}

impl WindowOptions {
    /// A `width x height` window with vsync, running until closed.
    pub fn new(width: u32, height: u32) -> WindowOptions {
        WindowOptions {
            width,
            height,
            frames: None,
            frames_deadline: Duration::from_secs(60),
            vsync: true,
            resize_to: None,
            overlay: true,
            screenshot_dir: PathBuf::from("target/screenshots"),
            screenshot_at: None,
            wireframe: false,
        }
    }
}

/// What a window session did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WindowReport {
    /// Frames presented.
    pub frames: u64,
    /// The swapchain's last width, pixels.
    pub width: u32,
    /// The swapchain's last height, pixels.
    pub height: u32,
    /// The adapter it ran on.
    pub adapter: String,
    /// A streamed terrain's state at the end (its progress line).
    pub terrain: Option<String>,
}

impl fmt::Display for WindowReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "presented {} frames {}x{} on {}",
            self.frames, self.width, self.height, self.adapter
        )?;
        if let Some(terrain) = &self.terrain {
            write!(f, "; {terrain}")?;
        }
        Ok(())
    }
}

/// Why the window could not run.
#[derive(Debug)]
#[non_exhaustive]
pub enum WindowError {
    /// No event loop: no display could be opened (or a second loop was asked for).
    EventLoop(EventLoopError),
    /// The window could not be created.
    Window(OsError),
    /// No device can present to the window.
    Device(DeviceError),
    /// The renderer could not be created or failed.
    Renderer(RenderError),
    /// The scene could not be meshed or uploaded.
    Scene(GpuViewError),
    /// The streamed terrain stopped streaming.
    Stream(StreamError),
    /// `--frames`: the frames were not presented in time.
    TooSlow {
        /// Frames presented.
        presented: u64,
        /// Frames asked for.
        wanted: u64,
        /// The time allowed, seconds.
        seconds: u64,
        /// Why the last skipped frame was skipped, if any was.
        last_skip: Option<String>,
    },
    /// The event loop ended before the window was shown.
    NeverShown,
    /// The world could not be saved on closing (why, with the folder).
    Save(String),
}

impl fmt::Display for WindowError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WindowError::EventLoop(e) => write!(f, "no window event loop (no display?): {e}"),
            WindowError::Window(e) => write!(f, "the window could not be created: {e}"),
            WindowError::Device(e) => write!(f, "{e}"),
            WindowError::Renderer(e) => write!(f, "renderer: {e}"),
            WindowError::Scene(e) => write!(f, "scene upload: {e}"),
            WindowError::Stream(e) => write!(f, "streamed terrain: {e}"),
            WindowError::TooSlow {
                presented,
                wanted,
                seconds,
                last_skip,
            } => {
                write!(f, "presented {presented} of {wanted} frames in {seconds} s")?;
                if let Some(why) = last_skip {
                    write!(f, " (last skipped frame: {why})")?;
                }
                Ok(())
            }
            WindowError::Save(why) => write!(f, "{why}"),
            WindowError::NeverShown => {
                write!(f, "the event loop ended before the window was shown")
            }
        }
    }
}

impl std::error::Error for WindowError {}

/// Opens a window showing `source` from the first `view` and runs until it is closed (or
/// `options.frames` are presented). Blocks; call from the main thread, once per process.
pub fn run_window(
    source: WindowSource<'_>,
    view: Camera,
    options: WindowOptions,
) -> Result<WindowReport, WindowError> {
    let event_loop = EventLoop::new().map_err(WindowError::EventLoop)?;
    let mut app = app::App::new(source, view, options);
    event_loop
        .run_app(&mut app)
        .map_err(WindowError::EventLoop)?;
    app.result.unwrap_or(Err(WindowError::NeverShown))
}
