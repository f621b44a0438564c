//! Why no context could be created, or why a caller's device cannot be adopted.

use std::fmt;

use wgpu::{Backends, CreateSurfaceError, PowerPreference};

use super::AdapterSummary;

/// Why no context could be created.
#[derive(Debug)]
#[non_exhaustive]
pub enum DeviceError {
    /// No adapter matched; says what was searched.
    NoAdapter {
        /// Backends searched.
        backends: Backends,
        /// Power preference asked for.
        power_preference: PowerPreference,
        /// Name filter, if any.
        adapter_name: Option<String>,
        /// Adapters found but rejected by the name filter.
        rejected: Vec<String>,
    },
    /// The window's surface could not be created (the window or display handle is not one
    /// the Vulkan driver can present to, e.g. no X11 / Wayland surface extension).
    CreateSurface(Box<CreateSurfaceError>),
    /// Adapters exist, but none can present to the window (a headless driver, or a surface
    /// with no usable format).
    NoPresentingAdapter {
        /// The adapters found that cannot present (after the name filter).
        adapters: Vec<String>,
    },
    /// A caller's device ([`GpuContext::from_wgpu`](super::GpuContext::from_wgpu)) lacks
    /// what the backend cannot do without: each entry names a limit with the value the device
    /// has and the value needed.
    MissingCapabilities {
        /// The device's adapter.
        adapter: AdapterSummary,
        /// `"<limit>: has <value>, needs <value>"`, one per limit below the requirement.
        missing: Vec<String>,
    },
    /// The adapter refused the device request.
    RequestDevice {
        /// The adapter asked.
        adapter: AdapterSummary,
        /// wgpu's error (boxed: it is large).
        source: Box<wgpu::RequestDeviceError>,
    },
}

impl DeviceError {
    /// True for [`DeviceError::NoAdapter`]: the machine has no usable GPU or driver, as
    /// opposed to a failure on an adapter that exists (an adapter that cannot present to a
    /// window is [`DeviceError::NoPresentingAdapter`], not this).
    pub fn is_no_adapter(&self) -> bool {
        matches!(self, DeviceError::NoAdapter { .. })
    }
}

impl fmt::Display for DeviceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DeviceError::NoAdapter {
                backends,
                power_preference,
                adapter_name,
                rejected,
            } => {
                write!(
                    f,
                    "no GPU adapter found (backends {backends:?}, power preference \
                     {power_preference:?}"
                )?;
                if let Some(name) = adapter_name {
                    write!(f, ", name containing {name:?}")?;
                }
                write!(f, ")")?;
                if !rejected.is_empty() {
                    write!(f, "; rejected by the name filter: {}", rejected.join(", "))?;
                }
                write!(
                    f,
                    "; on Debian install a Vulkan driver, e.g. `mesa-vulkan-drivers` \
                     (lavapipe) and `libvulkan1`"
                )
            }
            DeviceError::CreateSurface(source) => {
                write!(f, "the window's surface could not be created: {source}")
            }
            DeviceError::NoPresentingAdapter { adapters } => write!(
                f,
                "no adapter can present to this window (found, but cannot present: {})",
                adapters.join(", ")
            ),
            DeviceError::MissingCapabilities { adapter, missing } => write!(
                f,
                "the device on {adapter} lacks what the backend needs: {}",
                missing.join("; ")
            ),
            DeviceError::RequestDevice { adapter, source } => {
                write!(f, "adapter {adapter} refused the device request: {source}")
            }
        }
    }
}

impl std::error::Error for DeviceError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            DeviceError::NoAdapter { .. }
            | DeviceError::NoPresentingAdapter { .. }
            | DeviceError::MissingCapabilities { .. } => None,
            DeviceError::CreateSurface(source) => Some(source.as_ref()),
            DeviceError::RequestDevice { source, .. } => Some(source.as_ref()),
        }
    }
}
