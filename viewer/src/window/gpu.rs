//! The window's GPU side: device and swapchain, the scene's renderer (a fixed scene's, or the
//! streamed view's), the overlay; one frame at a time.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use gpu_backend::render::{Renderer, RendererConfig};
use gpu_backend::{DeviceOptions, FrameSkipped, GpuContext, TimingPath, WindowOutput};
use render_model::camera::Camera;
use render_model::cull::CullStats;
use voxel_core::formats::DataKind;
use winit::event::WindowEvent;
use winit::event_loop::OwnedDisplayHandle;
use winit::window::Window;

use super::overlay::Overlay;
use super::panel::Panel;
use super::stats::FrameStats;
use super::{WindowError, WindowSource};
use crate::controls::Controls;
use crate::gpu_view::upload_world;
use crate::screenshot::{ScreenshotError, save_screenshot};
use crate::stream::StreamError;
use crate::view::{OPAQUE_TRIAL_FRAMES, StreamedView};
use render_model::lighting::Lighting;

/// The clear colour of the window while the first view loads (a dusk sky).
const LOADING_SKY: wgpu::Color = wgpu::Color {
    r: 0.18,
    g: 0.24,
    b: 0.32,
    a: 1.0,
};

/// What a fixed scene put on the GPU (counted once, after the upload).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct SceneCounts {
    /// Resident chunks.
    pub chunks: usize,
    /// Greedy quads (opaque and transparent).
    pub quads: u64,
    /// Smooth quads.
    pub smooth_quads: u64,
    /// Gigabuffer bytes in use.
    pub bytes: u64,
}

/// What the window draws.
pub(super) enum Drawn {
    /// A scene uploaded whole.
    Fixed {
        /// Its renderer (boxed, as the streamed view is: both are large).
        renderer: Box<Renderer>,
        /// What it holds.
        counts: SceneCounts,
    },
    /// The streamed terrain.
    Streamed(Box<StreamedView>),
}

impl Drawn {
    /// The renderer that draws.
    pub(super) fn renderer(&self) -> &Renderer {
        match self {
            Drawn::Fixed { renderer, .. } => renderer,
            Drawn::Streamed(view) => view.renderer(),
        }
    }

    fn renderer_mut(&mut self) -> &mut Renderer {
        match self {
            Drawn::Fixed { renderer, .. } => renderer,
            Drawn::Streamed(view) => view.renderer_mut(),
        }
    }

    /// True when a frame shows the scene (a streamed view has committed its first plan).
    pub(super) fn ready(&self) -> bool {
        match self {
            Drawn::Fixed { .. } => true,
            Drawn::Streamed(view) => view.ready(),
        }
    }
}

/// How often the overlay's cull counters are read back.
const CULL_READ_INTERVAL: std::time::Duration = std::time::Duration::from_millis(250);

/// Device, swapchain, renderer and overlay of one window.
pub(super) struct GpuWindow {
    window: Arc<Window>,
    ctx: GpuContext,
    output: WindowOutput,
    drawn: Drawn,
    overlay: Overlay,
    /// A recent frame's cull counters (read while the overlay is shown, a few times a
    /// second: reading them waits for the GPU, which ends the overlap of frames).
    cull: Option<CullStats>,
    /// When `cull` was last read.
    cull_read: Option<Instant>,
    /// When the window opened: the grass sways with the time since.
    opened: Instant,
}

impl GpuWindow {
    /// Creates the device for `window`, the renderer of `source` and the overlay.
    pub(super) fn new(
        window: Arc<Window>,
        display: OwnedDisplayHandle,
        source: &WindowSource<'_>,
        vsync: bool,
    ) -> Result<GpuWindow, WindowError> {
        let size = window.inner_size();
        let (ctx, mut output) = GpuContext::new_windowed(
            &DeviceOptions::default(),
            Box::new(display),
            Arc::clone(&window),
            size.width,
            size.height,
        )
        .map_err(WindowError::Device)?;
        output.set_vsync(vsync);
        let (width, height) = output.size();
        let (width, height) = (width.max(1), height.max(1));
        let drawn = match source {
            WindowSource::Fixed(scene) => {
                let config = RendererConfig::new(width, height, scene.world.size());
                let mut renderer =
                    Renderer::new(&ctx, &config, &scene.palette).map_err(WindowError::Renderer)?;
                upload_world(&mut renderer, &scene.world, &scene.palette)
                    .map_err(WindowError::Scene)?;
                renderer
                    .set_lighting(&Lighting::default())
                    .expect("the default lighting passes its check");
                let counts = scene_counts(&renderer);
                Drawn::Fixed {
                    renderer: Box::new(renderer),
                    counts,
                }
            }
            WindowSource::Streamed {
                settings, world, ..
            } => Drawn::Streamed(Box::new(
                StreamedView::with_world(&ctx, settings, width, height, world.clone())
                    .map_err(WindowError::Stream)?,
            )),
        };
        let overlay = Overlay::new(&window, &ctx.device, output.format());
        Ok(GpuWindow {
            window,
            ctx,
            output,
            drawn,
            overlay,
            cull: None,
            cull_read: None,
            opened: Instant::now(),
        })
    }

    /// The window.
    pub(super) fn window(&self) -> &Arc<Window> {
        &self.window
    }

    /// The adapter, as text.
    pub(super) fn adapter(&self) -> String {
        self.ctx.capabilities.adapter.to_string()
    }

    /// The swapchain size, pixels.
    pub(super) fn size(&self) -> (u32, u32) {
        self.output.size()
    }

    /// What the window draws.
    pub(super) fn drawn(&self) -> &Drawn {
        &self.drawn
    }

    /// What it draws, mutably (edits).
    pub(super) fn drawn_mut(&mut self) -> &mut Drawn {
        &mut self.drawn
    }

    /// The last drawn frame's cull counters, when the overlay was shown.
    pub(super) fn cull_stats(&self) -> Option<&CullStats> {
        self.cull.as_ref()
    }

    /// True when pass times are GPU timestamps (otherwise CPU wall time per pass).
    pub(super) fn gpu_timestamps(&self) -> bool {
        matches!(
            self.ctx.capabilities.timing,
            TimingPath::GpuTimestamps { .. }
        )
    }

    /// Feeds a window event to the overlay: whether it consumed it.
    pub(super) fn overlay_event(&mut self, event: &WindowEvent) -> bool {
        let response = self.overlay.on_window_event(&self.window, event);
        if response.repaint {
            self.window.request_redraw();
        }
        response.consumed
    }

    /// The pointer is over the overlay.
    pub(super) fn overlay_wants_pointer(&self) -> bool {
        self.overlay.wants_pointer()
    }

    /// Follows the window's new inner size: swapchain and renderer targets.
    pub(super) fn resize(&mut self, width: u32, height: u32) -> Result<(), WindowError> {
        self.output.resize(width, height);
        let (w, h) = self.output.size();
        if w > 0 && h > 0 {
            self.resize_renderers(w, h)?;
        }
        Ok(())
    }

    fn resize_renderers(&mut self, width: u32, height: u32) -> Result<(), WindowError> {
        match &mut self.drawn {
            Drawn::Fixed { renderer, .. } => renderer
                .resize(width, height)
                .map_err(WindowError::Renderer),
            Drawn::Streamed(view) => view.resize(width, height).map_err(WindowError::Stream),
        }
    }

    /// Applies the overlay's controls to the streamed view (nothing for a fixed scene); a
    /// control the device cannot run is an error naming why, and changes nothing.
    pub(super) fn apply(&mut self, controls: &Controls) -> Result<(), StreamError> {
        match &mut self.drawn {
            Drawn::Streamed(view) => view.apply(&self.ctx, controls),
            Drawn::Fixed { .. } => Ok(()),
        }
    }

    /// Writes the last frame (without the overlay) as a PNG under `dir`.
    pub(super) fn screenshot(&self, dir: &Path) -> Result<PathBuf, ScreenshotError> {
        save_screenshot(self.drawn.renderer(), dir)
    }

    /// Draws and presents one frame from `camera` with the overlay's `panel` (its controls
    /// edited by the user); records its times into `stats`. `Ok(Err(reason))` when the
    /// swapchain gave no image this time.
    ///
    /// Frames overlap by one: after this frame is submitted and presented, the CPU waits for
    /// the GPU to finish the frame before it (so one frame stays in flight while the next is
    /// prepared) and collects that frame's pass times, so the overlay's GPU figures are each
    /// frame's own, one frame late. Reading the cull counters for the overlay waits for this
    /// frame too, a few times a second. The CPU frame time runs from the acquired image to the
    /// present and includes the streaming work of the frame (uploads, frees, plans).
    pub(super) fn draw(
        &mut self,
        camera: &Camera,
        panel: &mut Panel,
        stats: &mut FrameStats,
    ) -> Result<Result<(), FrameSkipped>, WindowError> {
        let frame = match self.output.acquire() {
            Ok(frame) => frame,
            Err(skipped) => return Ok(Err(skipped)),
        };
        // CPU time from here: acquiring waits for the display (vsync), which is not work.
        let started = Instant::now();
        let size = frame.size();
        let targets = self.drawn.renderer().targets();
        if (targets.width, targets.height) != size {
            self.resize_renderers(size.0, size.1)?;
        }
        match &mut self.drawn {
            Drawn::Fixed { renderer, .. } => renderer.set_camera(camera),
            Drawn::Streamed(view) => {
                view.update(camera).map_err(WindowError::Stream)?;
                // `--opaque auto`: chosen once, at the first view.
                if view.ready()
                    && let Some(choice) = view
                        .choose_opaque_path(OPAQUE_TRIAL_FRAMES)
                        .map_err(WindowError::Stream)?
                {
                    let line = format!("opaque path (auto): {choice}");
                    println!("viewer: {line}");
                    panel.message = Some(line);
                }
            }
        }
        let ready = self.drawn.ready();
        let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
        if ready {
            let renderer = self.drawn.renderer_mut();
            renderer.set_wireframe(panel.wireframe);
            renderer.set_time(self.opened.elapsed().as_secs_f64());
            // Without a grass pass (a fixed scene, --clutter off) the checkbox unticks itself.
            if panel.grass != renderer.clutter() && renderer.set_clutter(panel.grass).is_err() {
                panel.grass = false;
            }
            renderer
                .record_frame(&mut encoder)
                .map_err(WindowError::Renderer)?;
            self.output
                .blit(&mut encoder, &renderer.targets().output, &frame);
        } else {
            clear(&mut encoder, frame.view());
        }
        let extra = self.overlay.paint(
            &self.window,
            &self.ctx,
            &mut encoder,
            frame.view(),
            size,
            panel,
        );
        let submission = self
            .ctx
            .queue
            .submit(extra.into_iter().chain([encoder.finish()]));
        self.window.pre_present_notify();
        self.output.present(frame);
        let cpu = started.elapsed();
        let passes = if ready {
            let renderer = self.drawn.renderer_mut();
            renderer.frame_submitted(submission);
            // One frame stays in flight: the GPU draws this one while the CPU prepares the
            // next; the overlay shows the times of the frame before.
            let mut passes = Vec::new();
            while renderer.frames_in_flight() > 1 {
                if let Some(p) = renderer
                    .collect_oldest_timings()
                    .map_err(WindowError::Renderer)?
                {
                    passes = p;
                }
            }
            let due = self
                .cull_read
                .is_none_or(|t| t.elapsed() >= CULL_READ_INTERVAL);
            if panel.show && due {
                self.cull = Some(
                    renderer
                        .read_frame_stats()
                        .map_err(WindowError::Renderer)?
                        .0,
                );
                self.cull_read = Some(Instant::now());
            }
            passes
        } else {
            Vec::new()
        };
        stats.record(Instant::now(), cpu, passes);
        Ok(Ok(()))
    }
}

/// Clears `target` to the loading sky.
fn clear(encoder: &mut wgpu::CommandEncoder, target: &wgpu::TextureView) {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("loading sky"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: target,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(LOADING_SKY),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
}

/// Chunks, quads and bytes resident in `renderer`.
fn scene_counts(renderer: &Renderer) -> SceneCounts {
    let report = renderer.gigabuffer().resident();
    let elements =
        |kind: DataKind| report.kinds.get(kind).used_bytes / u64::from(kind.element_size().max(1));
    SceneCounts {
        chunks: renderer.chunk_count(),
        quads: elements(DataKind::Quads),
        smooth_quads: renderer.smooth_quad_count(),
        bytes: report.used_bytes(),
    }
}
