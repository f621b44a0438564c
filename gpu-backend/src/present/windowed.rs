//! [`GpuContext::new_windowed`]: a context whose adapter can present to a window, with the
//! window's output. It builds on [`crate::device`] (adapter choice, device creation), which
//! knows nothing of windows.

use std::sync::Arc;

use wgpu::wgt::WgpuHasDisplayHandle;
use wgpu::{Adapter, DisplayAndWindowHandle, Instance, InstanceDescriptor, Surface};

use super::{WindowOutput, choose_surface_format};
use crate::device::{DeviceError, DeviceOptions, GpuContext};

impl GpuContext {
    /// A context that presents to a window, and the window's output (its surface configured
    /// for `width x height`; a zero size is allowed and waits for
    /// [`WindowOutput::resize`]).
    ///
    /// `display` is the windowing system connection the window belongs to (with winit, the
    /// event loop's `OwnedDisplayHandle`); `window` the window itself (e.g. an
    /// `Arc<winit::window::Window>`), kept by the output so the surface can be re-created if it
    /// is lost. Only adapters that can present to the window's surface are considered.
    ///
    /// Errors: [`DeviceError::CreateSurface`] when the surface cannot be created,
    /// [`DeviceError::NoPresentingAdapter`] when adapters exist but none can present to it,
    /// [`DeviceError::NoAdapter`] when there is none at all.
    pub fn new_windowed<W>(
        options: &DeviceOptions,
        display: Box<dyn WgpuHasDisplayHandle>,
        window: W,
        width: u32,
        height: u32,
    ) -> Result<(GpuContext, WindowOutput), DeviceError>
    where
        W: DisplayAndWindowHandle + 'static,
    {
        let mut descriptor = InstanceDescriptor::new_with_display_handle_from_env(display);
        descriptor.backends = options.backends;
        let instance = Instance::new(descriptor);
        let window: Arc<dyn DisplayAndWindowHandle> = Arc::new(window);
        let surface = instance
            .create_surface(Arc::clone(&window))
            .map_err(|e| DeviceError::CreateSurface(Box::new(e)))?;
        let presents = |adapter: &Adapter| can_present(adapter, &surface);
        let ctx = GpuContext::create(instance, options, Some(&presents))?;
        let output = WindowOutput::new(&ctx, surface, window, width, height)?;
        Ok((ctx, output))
    }
}

/// `adapter` can present to `surface`, in a format the window output can use.
fn can_present(adapter: &Adapter, surface: &Surface<'_>) -> bool {
    adapter.is_surface_supported(surface)
        && choose_surface_format(&surface.get_capabilities(adapter).formats).is_some()
}
