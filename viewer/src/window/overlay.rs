//! The egui overlay: window events in, the [`Panel`] drawn over the swapchain image.

use std::sync::Arc;

use egui_wgpu::{Renderer as EguiRenderer, RendererOptions, ScreenDescriptor};
use egui_winit::EventResponse;
use gpu_backend::GpuContext;
use wgpu::{CommandBuffer, CommandEncoder, Device, TextureFormat, TextureView};
use winit::event::WindowEvent;
use winit::window::Window;

use super::panel::{Panel, ui};

/// egui's input state and its wgpu renderer for one window.
pub(super) struct Overlay {
    state: egui_winit::State,
    renderer: EguiRenderer,
}

impl Overlay {
    /// An overlay for `window`, drawing into targets of `format`.
    pub(super) fn new(window: &Arc<Window>, device: &Device, format: TextureFormat) -> Overlay {
        let context = egui::Context::default();
        let max_side = device.limits().max_texture_dimension_2d as usize;
        let state = egui_winit::State::new(
            context,
            egui::ViewportId::ROOT,
            window.as_ref(),
            Some(window.scale_factor() as f32),
            window.theme(),
            Some(max_side),
        );
        let renderer = EguiRenderer::new(device, format, RendererOptions::default());
        Overlay { state, renderer }
    }

    /// Feeds a window event to egui; `consumed` says egui used it (e.g. a click on the panel).
    pub(super) fn on_window_event(
        &mut self,
        window: &Window,
        event: &WindowEvent,
    ) -> EventResponse {
        self.state.on_window_event(window, event)
    }

    /// The pointer is over the overlay (drags there are not camera drags).
    pub(super) fn wants_pointer(&self) -> bool {
        self.state.egui_ctx().egui_wants_pointer_input()
    }

    /// Runs the overlay's UI for `panel` (its controls edited in place) and records its
    /// drawing into `target` (of `size` pixels), on top of what is there. Returns command
    /// buffers to submit before `encoder` (none unless a paint callback made some).
    pub(super) fn paint(
        &mut self,
        window: &Window,
        ctx: &GpuContext,
        encoder: &mut CommandEncoder,
        target: &TextureView,
        size: (u32, u32),
        panel: &mut Panel,
    ) -> Vec<CommandBuffer> {
        let (device, queue) = (&ctx.device, &ctx.queue);
        let input = self.state.take_egui_input(window);
        let mut output = self.state.egui_ctx().run_pass(input, |ctx| ui(ctx, panel));
        self.state
            .handle_platform_output(window, output.platform_output);
        let primitives = self
            .state
            .egui_ctx()
            .tessellate(output.shapes, output.pixels_per_point);
        // Drained, not just read: a TexturesDelta dropped with entries is a bug to egui.
        let mut textures = std::mem::take(&mut output.textures_delta);
        for (id, deltas) in textures.set.drain() {
            for delta in &deltas {
                self.renderer.update_texture(device, queue, id, delta);
            }
        }
        let screen = ScreenDescriptor {
            size_in_pixels: [size.0, size.1],
            pixels_per_point: output.pixels_per_point,
        };
        let extra = self
            .renderer
            .update_buffers(device, queue, encoder, &primitives, &screen);
        {
            let mut pass = encoder
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("egui overlay"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: target,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Load,
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: None,
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                })
                .forget_lifetime();
            self.renderer.render(&mut pass, &primitives, &screen);
        }
        for id in textures.free.drain() {
            self.renderer.free_texture(&id);
        }
        extra
    }
}
