//! Presenting to a window: the swapchain of one window surface and the pass that copies the
//! renderer's output into it.
//!
//! ```text
//!  GpuContext::new_windowed(options, display, window, w, h) ─► (GpuContext, WindowOutput)
//!
//!  per frame:
//!    output.acquire()            ─► WindowFrame, or FrameSkipped (reason; skip the frame)
//!    renderer.record_frame(enc)
//!    output.blit(enc, &renderer.targets().output, &frame)   full-screen triangle
//!    (overlays draw into frame.view(), loading what the blit wrote)
//!    queue.submit(enc); output.present(frame)
//!  on a window resize:
//!    output.resize(w, h); renderer.resize(output.size())
//! ```
//!
//! **Format.** [`choose_surface_format`] prefers an sRGB swapchain format, so the output's
//! bytes reach the screen unchanged (the output is `Rgba8UnormSrgb`: read as linear, written
//! back through the hardware encode). Where the surface offers only plain unorm formats, the
//! present shader applies the sRGB transfer function itself ([`SurfaceEncoding::Shader`]).
//!
//! **Acquiring never panics.** Every [`CurrentSurfaceTexture`] outcome is handled:
//!
//! | outcome      | what [`WindowOutput::acquire`] does                                       |
//! | ------------ | ------------------------------------------------------------------------- |
//! | `Success`    | returns the frame                                                          |
//! | `Suboptimal` | returns the frame; the surface is reconfigured after it is presented      |
//! | `Outdated`   | reconfigures and tries once more; skips the frame if that fails too       |
//! | `Lost`       | re-creates the surface from the window, reconfigures, skips the frame     |
//! | `Timeout`    | skips the frame                                                            |
//! | `Occluded`   | skips the frame                                                            |
//! | `Validation` | skips the frame (the error went to the device's error handler)            |
//!
//! A zero-sized window (minimized) is never configured (wgpu forbids it): frames are skipped
//! until [`WindowOutput::resize`] gives a real size. Sizes above the device's texture limit are
//! clamped.

mod format;
mod windowed;

use std::fmt;
use std::sync::Arc;

use wgpu::{
    Adapter, CommandEncoder, CurrentSurfaceTexture, Device, DisplayAndWindowHandle, Instance,
    PresentMode, Queue, Surface, SurfaceConfiguration, SurfaceTexture, TextureFormat, TextureView,
};

pub use crate::render::passes::present::{PresentBlit, SurfaceEncoding};
pub use format::choose_surface_format;

use crate::device::{DeviceError, GpuContext};

/// Why [`WindowOutput::acquire`] gave no image this time. None of these is fatal: skip the
/// frame and try again with the next one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameSkipped {
    /// The window has no area (minimized, or not yet sized).
    ZeroSize,
    /// The swapchain did not hand out an image in time.
    Timeout,
    /// The window is hidden.
    Occluded,
    /// The surface changed (e.g. resized) and reconfiguring did not help this time.
    Outdated,
    /// The surface was lost; it has been re-created if the window still allows it.
    Lost,
    /// Acquiring raised a validation error (reported to the device's error handler).
    Validation,
}

impl fmt::Display for FrameSkipped {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            FrameSkipped::ZeroSize => "the window has zero size",
            FrameSkipped::Timeout => "timed out waiting for a swapchain image",
            FrameSkipped::Occluded => "the window is occluded",
            FrameSkipped::Outdated => "the swapchain is out of date",
            FrameSkipped::Lost => "the window surface was lost",
            FrameSkipped::Validation => "acquiring the swapchain image failed validation",
        })
    }
}

/// A swapchain image to draw into, from [`WindowOutput::acquire`]; hand it back with
/// [`WindowOutput::present`] after submitting the work that draws it.
#[derive(Debug)]
pub struct WindowFrame {
    texture: SurfaceTexture,
    view: TextureView,
    suboptimal: bool,
}

impl WindowFrame {
    /// The image's view (a render attachment of [`WindowOutput::format`]).
    pub fn view(&self) -> &TextureView {
        &self.view
    }

    /// The image's size, pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.texture.texture.width(), self.texture.texture.height())
    }
}

/// One window's swapchain and the present pass (see the [module docs](self)).
pub struct WindowOutput {
    instance: Instance,
    adapter: Adapter,
    device: Device,
    queue: Queue,
    /// The window, kept to re-create a lost surface.
    window: Arc<dyn DisplayAndWindowHandle>,
    surface: Surface<'static>,
    config: SurfaceConfiguration,
    /// The surface holds `config` (false while the size is zero).
    configured: bool,
    blit: PresentBlit,
}

impl fmt::Debug for WindowOutput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("WindowOutput")
            .field("config", &self.config)
            .field("configured", &self.configured)
            .field("encoding", &self.blit.encoding())
            .finish_non_exhaustive()
    }
}

impl WindowOutput {
    /// The output of `window`'s `surface` on `ctx`, configured for `width x height`.
    /// [`DeviceError::NoPresentingAdapter`] if the surface offers `ctx`'s adapter no usable
    /// format.
    pub(crate) fn new(
        ctx: &GpuContext,
        surface: Surface<'static>,
        window: Arc<dyn DisplayAndWindowHandle>,
        width: u32,
        height: u32,
    ) -> Result<WindowOutput, DeviceError> {
        let caps = surface.get_capabilities(&ctx.adapter);
        let (format, encoding) = choose_surface_format(&caps.formats).ok_or_else(|| {
            DeviceError::NoPresentingAdapter {
                adapters: vec![format!(
                    "{} (no usable surface format among {:?})",
                    ctx.capabilities.adapter.name, caps.formats
                )],
            }
        })?;
        let config = SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            color_space: wgpu::SurfaceColorSpace::Auto,
            width,
            height,
            present_mode: PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: wgpu::CompositeAlphaMode::Auto,
            view_formats: Vec::new(),
        };
        let mut output = WindowOutput {
            instance: ctx.instance.clone(),
            adapter: ctx.adapter.clone(),
            device: ctx.device.clone(),
            queue: ctx.queue.clone(),
            window,
            surface,
            config,
            configured: false,
            blit: PresentBlit::new(&ctx.device, format, encoding),
        };
        output.resize(width, height);
        Ok(output)
    }

    /// The swapchain format.
    pub fn format(&self) -> TextureFormat {
        self.config.format
    }

    /// Who applies the sRGB encoding.
    pub fn encoding(&self) -> SurfaceEncoding {
        self.blit.encoding()
    }

    /// The swapchain size, pixels (after clamping to the device's texture limit; `(0, 0)`
    /// style sizes while the window has no area). Size the renderer to this.
    pub fn size(&self) -> (u32, u32) {
        (self.config.width, self.config.height)
    }

    /// Resizes the swapchain to the window's new inner size (pixels). A zero width or height
    /// leaves the surface unconfigured until a real size comes.
    pub fn resize(&mut self, width: u32, height: u32) {
        let max = self.device.limits().max_texture_dimension_2d;
        self.config.width = width.min(max);
        self.config.height = height.min(max);
        self.configure();
    }

    /// Waits for the display's refresh (`true`, the default: `AutoVsync`) or presents as fast
    /// as possible (`false`: `AutoNoVsync`, for measuring frame rates).
    pub fn set_vsync(&mut self, vsync: bool) {
        self.config.present_mode = if vsync {
            PresentMode::AutoVsync
        } else {
            PresentMode::AutoNoVsync
        };
        self.configure();
    }

    /// The next swapchain image, or why there is none this time (see the
    /// [module docs](self) for what each outcome does).
    pub fn acquire(&mut self) -> Result<WindowFrame, FrameSkipped> {
        if !self.configured {
            return Err(FrameSkipped::ZeroSize);
        }
        match self.surface.get_current_texture() {
            CurrentSurfaceTexture::Success(texture) => Ok(frame(texture, false)),
            CurrentSurfaceTexture::Suboptimal(texture) => Ok(frame(texture, true)),
            CurrentSurfaceTexture::Outdated => {
                self.configure();
                match self.surface.get_current_texture() {
                    CurrentSurfaceTexture::Success(texture) => Ok(frame(texture, false)),
                    CurrentSurfaceTexture::Suboptimal(texture) => Ok(frame(texture, true)),
                    _ => Err(FrameSkipped::Outdated),
                }
            }
            CurrentSurfaceTexture::Lost => {
                self.recreate_surface();
                Err(FrameSkipped::Lost)
            }
            CurrentSurfaceTexture::Timeout => Err(FrameSkipped::Timeout),
            CurrentSurfaceTexture::Occluded => Err(FrameSkipped::Occluded),
            CurrentSurfaceTexture::Validation => Err(FrameSkipped::Validation),
        }
    }

    /// Records the copy of `source` (the renderer's output view, of this output's size) into
    /// `frame`'s image as one render pass of `encoder`. Draw overlays after it with
    /// `LoadOp::Load`.
    pub fn blit(&self, encoder: &mut CommandEncoder, source: &TextureView, frame: &WindowFrame) {
        self.blit.record(&self.device, encoder, source, &frame.view);
    }

    /// Shows `frame` (submit the work that draws it first). Reconfigures the surface if the
    /// image was suboptimal.
    pub fn present(&mut self, frame: WindowFrame) {
        let suboptimal = frame.suboptimal;
        self.queue.present(frame.texture);
        if suboptimal {
            self.configure();
        }
    }

    /// Applies `config` when the size allows it.
    fn configure(&mut self) {
        self.configured = self.config.width > 0 && self.config.height > 0;
        if self.configured {
            self.surface.configure(&self.device, &self.config);
        }
    }

    /// Replaces a lost surface with a new one of the same window, if the window and the adapter
    /// still allow it (otherwise the old one stays, and the next acquire tries again).
    fn recreate_surface(&mut self) {
        let Ok(surface) = self.instance.create_surface(Arc::clone(&self.window)) else {
            return;
        };
        if !self.adapter.is_surface_supported(&surface) {
            return;
        }
        let formats = surface.get_capabilities(&self.adapter).formats;
        let Some((format, encoding)) = choose_surface_format(&formats) else {
            return;
        };
        self.surface = surface;
        if format != self.config.format || encoding != self.blit.encoding() {
            self.config.format = format;
            self.blit = PresentBlit::new(&self.device, format, encoding);
        }
        self.configure();
    }
}

/// A frame of `texture`, with its view.
fn frame(texture: SurfaceTexture, suboptimal: bool) -> WindowFrame {
    let view = texture.texture.create_view(&Default::default());
    WindowFrame {
        texture,
        view,
        suboptimal,
    }
}
