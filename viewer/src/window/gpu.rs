//! The window's GPU side: device and swapchain, the scene's renderer, the overlay; one frame
//! at a time.

use std::sync::Arc;
use std::time::Instant;

use gpu_backend::gigabuffer::DataKind;
use gpu_backend::render::{RenderCamera, Renderer, RendererConfig};
use gpu_backend::{DeviceOptions, FrameSkipped, GpuContext, TimingPath, WindowOutput};
use winit::event::WindowEvent;
use winit::event_loop::OwnedDisplayHandle;
use winit::window::Window;

use super::WindowError;
use super::overlay::Overlay;
use super::stats::FrameStats;
use crate::gpu_view::upload_world;
use crate::lighting::{Lighting, lighting_params};
use crate::scene::Scene;

/// What the scene put on the GPU (counted once, after the upload).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SceneCounts {
    /// Resident chunks.
    pub chunks: usize,
    /// Greedy quads (opaque and transparent).
    pub quads: u64,
    /// Smooth quads.
    pub smooth_quads: u64,
    /// Gigabuffer bytes in use.
    pub bytes: u64,
}

/// Device, swapchain, renderer and overlay of one window.
pub struct GpuWindow {
    window: Arc<Window>,
    ctx: GpuContext,
    output: WindowOutput,
    renderer: Renderer,
    overlay: Overlay,
    counts: SceneCounts,
    chunk_size: voxel_core::ChunkSize,
}

impl GpuWindow {
    /// Creates the device for `window`, uploads `scene` and sets up the overlay.
    pub fn new(
        window: Arc<Window>,
        display: OwnedDisplayHandle,
        scene: &Scene,
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
        let chunk_size = scene.world.size();
        let config = RendererConfig::new(width.max(1), height.max(1), chunk_size);
        let mut renderer =
            Renderer::new(&ctx, &config, &scene.palette).map_err(WindowError::Renderer)?;
        upload_world(&mut renderer, &scene.world, &scene.palette).map_err(WindowError::Scene)?;
        renderer.set_lighting(&lighting_params(&Lighting::default()));
        let overlay = Overlay::new(&window, &ctx.device, output.format());
        let counts = scene_counts(&renderer);
        Ok(GpuWindow {
            window,
            ctx,
            output,
            renderer,
            overlay,
            counts,
            chunk_size,
        })
    }

    /// The window.
    pub fn window(&self) -> &Arc<Window> {
        &self.window
    }

    /// The adapter, as text.
    pub fn adapter(&self) -> String {
        self.ctx.capabilities.adapter.to_string()
    }

    /// The swapchain size, pixels.
    pub fn size(&self) -> (u32, u32) {
        self.output.size()
    }

    /// What the scene put on the GPU.
    pub fn counts(&self) -> SceneCounts {
        self.counts
    }

    /// The chunk size of the scene.
    pub fn chunk_size(&self) -> voxel_core::ChunkSize {
        self.chunk_size
    }

    /// True when pass times are GPU timestamps (otherwise CPU wall time per pass).
    pub fn gpu_timestamps(&self) -> bool {
        matches!(
            self.ctx.capabilities.timing,
            TimingPath::GpuTimestamps { .. }
        )
    }

    /// Feeds a window event to the overlay: whether it consumed it.
    pub fn overlay_event(&mut self, event: &WindowEvent) -> bool {
        let response = self.overlay.on_window_event(&self.window, event);
        if response.repaint {
            self.window.request_redraw();
        }
        response.consumed
    }

    /// The pointer is over the overlay.
    pub fn overlay_wants_pointer(&self) -> bool {
        self.overlay.wants_pointer()
    }

    /// Follows the window's new inner size: swapchain and renderer targets.
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), WindowError> {
        self.output.resize(width, height);
        let (w, h) = self.output.size();
        if w > 0 && h > 0 {
            self.renderer.resize(w, h).map_err(WindowError::Renderer)?;
        }
        Ok(())
    }

    /// Draws and presents one frame from `camera` with the overlay's `lines` (no overlay for
    /// `None`); records its
    /// times into `stats`. `Ok(Err(reason))` when the swapchain gave no image this time.
    ///
    /// The pass times are collected right after the present, which waits for the GPU: frames
    /// do not overlap, so the figures are each frame's own (a viewer for measuring, not a
    /// throughput-tuned loop). The CPU frame time runs from the acquired image to the present.
    pub fn draw(
        &mut self,
        camera: &RenderCamera,
        lines: Option<&[String]>,
        stats: &mut FrameStats,
    ) -> Result<Result<(), FrameSkipped>, WindowError> {
        let frame = match self.output.acquire() {
            Ok(frame) => frame,
            Err(skipped) => return Ok(Err(skipped)),
        };
        // CPU time from here: acquiring waits for the display (vsync), which is not work.
        let started = Instant::now();
        let size = frame.size();
        if (
            self.renderer.targets().width,
            self.renderer.targets().height,
        ) != size
        {
            self.renderer
                .resize(size.0, size.1)
                .map_err(WindowError::Renderer)?;
        }
        self.renderer.set_camera(camera);
        let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
        self.renderer
            .record_frame(&mut encoder)
            .map_err(WindowError::Renderer)?;
        self.output
            .blit(&mut encoder, &self.renderer.targets().output, &frame);
        let extra = match lines {
            Some(lines) => self.overlay.paint(
                &self.window,
                &self.ctx,
                &mut encoder,
                frame.view(),
                size,
                lines,
            ),
            None => Vec::new(),
        };
        self.ctx
            .queue
            .submit(extra.into_iter().chain([encoder.finish()]));
        self.window.pre_present_notify();
        self.output.present(frame);
        let cpu = started.elapsed();
        let passes = self
            .renderer
            .collect_timings()
            .map_err(WindowError::Renderer)?;
        stats.record(Instant::now(), cpu, passes);
        Ok(Ok(()))
    }
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
