//! The winit application: window events to the camera, the overlay and the GPU; one frame
//! per redraw, then the overlay's changed controls applied and F12's screenshot written.

use std::sync::Arc;
use std::time::{Duration, Instant};

use winit::application::ApplicationHandler;
use winit::dpi::{PhysicalPosition, PhysicalSize};
use winit::event::{
    ElementState, KeyEvent, MouseButton, MouseScrollDelta, StartCause, WindowEvent,
};
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

use gpu_backend::FrameSkipped;

use super::camera::{FlyCamera, MoveKeys};
use super::editing::{Autosave, Brush, click};
use super::gpu::{Drawn, GpuWindow};
use super::lines::overlay_lines;
use super::panel::Panel;
use super::stats::FrameStats;
use super::{WindowError, WindowOptions, WindowReport, WindowSource};
use render_model::camera::Camera;

/// Pixels of a scroll "line" for touchpads that report pixels.
const PIXELS_PER_SCROLL_LINE: f64 = 40.0;

/// Pixels a press may move and still be a click (an edit) rather than a look.
const CLICK_SLOP: f64 = 4.0;

/// How long to wait before trying again after the swapchain gave no image.
const RETRY_AFTER_SKIP: Duration = Duration::from_millis(50);

/// The application state between events.
pub(super) struct App<'a> {
    source: WindowSource<'a>,
    options: WindowOptions,
    gpu: Option<GpuWindow>,
    camera: FlyCamera,
    keys: MoveKeys,
    /// A mouse button is held for looking (pressed outside the overlay).
    dragging: bool,
    /// Pixels the cursor moved since the button went down: a click moves less than
    /// [`CLICK_SLOP`].
    dragged: f64,
    /// What a click writes.
    brush: Brush,
    /// `--world`: where and when the edits are saved.
    autosave: Option<Autosave>,
    cursor: Option<PhysicalPosition<f64>>,
    stats: FrameStats,
    last_frame: Option<Instant>,
    started: Instant,
    /// Why the last frame that was skipped was skipped.
    skipped: Option<FrameSkipped>,
    /// The overlay's content; `panel.show` is toggled by F1.
    panel: Panel,
    /// F12 was pressed: write a screenshot after the next frame.
    screenshot: bool,
    /// `options.resize_to` was asked of the window.
    resize_requested: bool,
    /// The outcome, once known.
    pub result: Option<Result<WindowReport, WindowError>>,
}

impl<'a> App<'a> {
    /// An app showing `source` from the first `view`.
    pub(super) fn new(source: WindowSource<'a>, view: Camera, options: WindowOptions) -> App<'a> {
        let autosave = match &source {
            WindowSource::Streamed {
                world_dir: Some(dir),
                ..
            } => Some(Autosave::new(dir.clone())),
            _ => None,
        };
        App {
            dragged: 0.0,
            brush: Brush::default(),
            autosave,
            source,
            camera: FlyCamera::new(view, 32.0),
            panel: Panel {
                show: options.overlay,
                wireframe: options.wireframe,
                grass: true,
                ..Panel::default()
            },
            screenshot: false,
            options,
            gpu: None,
            keys: MoveKeys::default(),
            dragging: false,
            cursor: None,
            stats: FrameStats::default(),
            last_frame: None,
            started: Instant::now(),
            skipped: None,
            resize_requested: false,
            result: None,
        }
    }

    /// Stops the loop with `result` (the first outcome wins).
    fn finish(&mut self, event_loop: &ActiveEventLoop, result: Result<WindowReport, WindowError>) {
        self.result.get_or_insert(result);
        event_loop.exit();
    }

    fn report(&self) -> Option<WindowReport> {
        let gpu = self.gpu.as_ref()?;
        let (width, height) = gpu.size();
        let terrain = match gpu.drawn() {
            Drawn::Streamed(view) => Some(view.status().0.progress_line()),
            Drawn::Fixed { .. } => None,
        };
        Some(WindowReport {
            frames: self.stats.presented(),
            width,
            height,
            adapter: gpu.adapter(),
            terrain,
        })
    }

    fn set_key(&mut self, code: KeyCode, pressed: bool) {
        let keys = &mut self.keys;
        match code {
            KeyCode::KeyW | KeyCode::ArrowUp => keys.forward = pressed,
            KeyCode::KeyS | KeyCode::ArrowDown => keys.back = pressed,
            KeyCode::KeyA | KeyCode::ArrowLeft => keys.left = pressed,
            KeyCode::KeyD | KeyCode::ArrowRight => keys.right = pressed,
            KeyCode::Space => keys.up = pressed,
            KeyCode::ShiftLeft | KeyCode::ShiftRight => keys.down = pressed,
            _ => {}
        }
    }

    /// `[`, `]` resize the brush, 1 to 6 pick its block: true when `code` was one of them.
    fn brush_key(&mut self, code: KeyCode) -> bool {
        let brush = match code {
            KeyCode::BracketLeft => self.brush.resized(false),
            KeyCode::BracketRight => self.brush.resized(true),
            KeyCode::Digit1 => self.brush.with_block(1),
            KeyCode::Digit2 => self.brush.with_block(2),
            KeyCode::Digit3 => self.brush.with_block(3),
            KeyCode::Digit4 => self.brush.with_block(4),
            KeyCode::Digit5 => self.brush.with_block(5),
            KeyCode::Digit6 => self.brush.with_block(6),
            _ => return false,
        };
        self.brush = brush;
        self.panel.message = Some(format!(
            "brush: radius {}, block {}",
            brush.radius, brush.block.0
        ));
        true
    }

    /// A click on the streamed terrain: breaks (or with `place`, places) the brush at the
    /// block under the cursor; the overlay says what happened.
    fn edit_at_cursor(&mut self, place: bool) {
        let (Some(gpu), Some(cursor)) = (self.gpu.as_mut(), self.cursor) else {
            return;
        };
        let size = gpu.size();
        let camera = self.camera.camera();
        let Drawn::Streamed(view) = gpu.drawn_mut() else {
            return;
        };
        let px = (cursor.x.max(0.0) as u32).min(size.0.saturating_sub(1));
        let py = (cursor.y.max(0.0) as u32).min(size.1.saturating_sub(1));
        let line = match click(view, &camera, (px, py), size, self.brush, place) {
            Ok(line) => line,
            Err(e) => format!("edit refused: {e}"),
        };
        self.panel.message = Some(line);
        gpu.window().request_redraw();
    }

    /// Saves the world of `--world` when it is due (or `now`); the error names the folder.
    fn save(&mut self, now: bool) -> Result<(), String> {
        let (Some(autosave), WindowSource::Streamed { world, .. }) =
            (self.autosave.as_mut(), &self.source)
        else {
            return Ok(());
        };
        if let Some(line) = autosave.tick(world, now)? {
            self.panel.message = Some(line);
        }
        Ok(())
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        if let Err(why) = self.save(false) {
            eprintln!("viewer: {why}");
            self.panel.message = Some(why);
        }
        let now = Instant::now();
        let dt = self
            .last_frame
            .map_or(0.0, |t| now.saturating_duration_since(t).as_secs_f64());
        self.last_frame = Some(now);
        // A long stall (a drag of the window, a breakpoint) must not fling the camera.
        self.camera.step(&self.keys, dt.min(0.1));
        let Some(gpu) = self.gpu.as_mut() else {
            return;
        };
        let camera = self.camera.camera();
        self.panel.lines = if self.panel.show {
            overlay_lines(&self.stats, gpu, &self.camera)
        } else {
            Vec::new()
        };
        let streamed = match gpu.drawn() {
            Drawn::Streamed(view) => Some((view.controls(), view.ready(), view.status().0)),
            Drawn::Fixed { .. } => None,
        };
        self.panel.controls = streamed.as_ref().map(|(controls, ..)| *controls);
        self.panel.banner = streamed
            .as_ref()
            .filter(|(_, ready, _)| !ready)
            .map(|(.., status)| status.progress_line());
        let presented = match gpu.draw(&camera, &mut self.panel, &mut self.stats) {
            Ok(Ok(())) => true,
            Ok(Err(skipped)) => {
                self.skipped = Some(skipped);
                false
            }
            Err(e) => return self.finish(event_loop, Err(e)),
        };
        // The overlay's widgets edited the controls: apply what changed.
        if let (Some((before, ..)), Some(after)) = (streamed, self.panel.controls)
            && after != before
            && let Err(e) = gpu.apply(&after)
        {
            eprintln!("viewer: {e}");
            self.panel.message = Some(e.to_string());
        }
        if presented && self.options.screenshot_at == Some(self.stats.presented()) {
            self.screenshot = true;
        }
        if presented && std::mem::take(&mut self.screenshot) {
            let message = match gpu.screenshot(&self.options.screenshot_dir) {
                Ok(path) => {
                    let shown = std::fs::canonicalize(&path).unwrap_or(path);
                    println!("viewer: screenshot {}", shown.display());
                    format!("screenshot {}", shown.display())
                }
                Err(e) => {
                    eprintln!("viewer: screenshot: {e}");
                    format!("screenshot failed: {e}")
                }
            };
            self.panel.message = Some(message);
        }
        let resize_to = self.options.resize_to;
        if let (true, Some((width, height))) = (presented, resize_to)
            && !self.resize_requested
        {
            self.resize_requested = true;
            // Applied when the Resized event comes (at once on X11 without a window manager).
            let _ = gpu
                .window()
                .request_inner_size(PhysicalSize::new(width, height));
        }
        if let Some(target) = self.options.frames {
            let resized = resize_to.is_none_or(|size| gpu.size() == size);
            if self.stats.presented() >= target && resized {
                if let Some(report) = self.report() {
                    self.finish(event_loop, Ok(report));
                }
                return;
            }
            if self.started.elapsed() > self.options.frames_deadline {
                let e = WindowError::TooSlow {
                    presented: self.stats.presented(),
                    wanted: target,
                    seconds: self.options.frames_deadline.as_secs(),
                    last_skip: self.skipped.map(|s| s.to_string()),
                };
                return self.finish(event_loop, Err(e));
            }
        }
        if presented {
            if let Some(gpu) = &self.gpu {
                gpu.window().request_redraw();
            }
        } else {
            // No image this time (minimized, hidden, swapchain trouble): try again shortly
            // rather than spin; `new_events` asks for the redraw.
            event_loop.set_control_flow(ControlFlow::WaitUntil(Instant::now() + RETRY_AFTER_SKIP));
        }
    }
}

impl ApplicationHandler for App<'_> {
    fn new_events(&mut self, event_loop: &ActiveEventLoop, cause: StartCause) {
        if let StartCause::ResumeTimeReached { .. } = cause {
            event_loop.set_control_flow(ControlFlow::Wait);
            if let Some(gpu) = &self.gpu {
                gpu.window().request_redraw();
            }
        }
    }

    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gpu.is_some() {
            return;
        }
        let attributes = Window::default_attributes()
            .with_title("voxel viewer")
            .with_inner_size(PhysicalSize::new(self.options.width, self.options.height));
        let window = match event_loop.create_window(attributes) {
            Ok(window) => Arc::new(window),
            Err(e) => return self.finish(event_loop, Err(WindowError::Window(e))),
        };
        let display = event_loop.owned_display_handle();
        match GpuWindow::new(window, display, &self.source, self.options.vsync) {
            Ok(gpu) => {
                gpu.window().request_redraw();
                self.started = Instant::now();
                self.gpu = Some(gpu);
            }
            Err(e) => self.finish(event_loop, Err(e)),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(gpu) = self.gpu.as_mut() else {
            return;
        };
        let consumed = gpu.overlay_event(&event);
        match event {
            WindowEvent::CloseRequested => {
                if let Some(report) = self.report() {
                    self.finish(event_loop, Ok(report));
                }
            }
            WindowEvent::Resized(size) => {
                if let Err(e) = gpu.resize(size.width, size.height) {
                    return self.finish(event_loop, Err(e));
                }
                gpu.window().request_redraw();
            }
            WindowEvent::KeyboardInput {
                event:
                    KeyEvent {
                        physical_key: PhysicalKey::Code(code),
                        state,
                        ..
                    },
                ..
            } => {
                let pressed = state == ElementState::Pressed;
                if code == KeyCode::Escape && pressed {
                    if let Some(report) = self.report() {
                        self.finish(event_loop, Ok(report));
                    }
                } else if code == KeyCode::F1 && pressed {
                    self.panel.show = !self.panel.show;
                } else if code == KeyCode::F3 && pressed {
                    self.panel.wireframe = !self.panel.wireframe;
                    gpu.window().request_redraw();
                } else if code == KeyCode::F12 && pressed {
                    self.screenshot = true;
                    gpu.window().request_redraw();
                } else if pressed && !consumed && self.brush_key(code) {
                    // `[`, `]` and 1 to 6 changed the brush.
                } else if !consumed || !pressed {
                    // Releases always count, so a key never sticks.
                    self.set_key(code, pressed);
                }
            }
            WindowEvent::Focused(false) => self.keys = MoveKeys::default(),
            WindowEvent::MouseInput { state, button, .. } => {
                let looking = matches!(button, MouseButton::Left | MouseButton::Right);
                if state == ElementState::Released {
                    let clicked = self.dragging && self.dragged < CLICK_SLOP;
                    self.dragging = false;
                    if clicked && looking {
                        self.edit_at_cursor(button == MouseButton::Right);
                    }
                } else if looking && !consumed && !gpu.overlay_wants_pointer() {
                    self.dragging = true;
                    self.dragged = 0.0;
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                if let (true, Some(last)) = (self.dragging, self.cursor) {
                    self.dragged += (position.x - last.x).abs() + (position.y - last.y).abs();
                    self.camera.look(position.x - last.x, position.y - last.y);
                }
                self.cursor = Some(position);
            }
            WindowEvent::CursorLeft { .. } => self.cursor = None,
            WindowEvent::MouseWheel { delta, .. } if !consumed => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => f64::from(y),
                    MouseScrollDelta::PixelDelta(p) => p.y / PIXELS_PER_SCROLL_LINE,
                };
                self.camera.scroll(lines);
            }
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            _ => {}
        }
    }

    fn exiting(&mut self, _event_loop: &ActiveEventLoop) {
        if self.result.is_none() {
            self.result = self.report().map(Ok);
        }
        if let Err(why) = self.save(true) {
            eprintln!("viewer: {why}");
            if matches!(self.result, Some(Ok(_))) {
                self.result = Some(Err(WindowError::Save(why)));
            }
        }
        // Release the surface and device while the display connection is still open.
        self.gpu = None;
    }
}
