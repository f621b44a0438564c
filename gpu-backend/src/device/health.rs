//! What went wrong with a device outside any error scope: its loss, or an error no scope
//! caught. wgpu's default handlers panic on both; a context made here records the first fault
//! instead, and the renderer refuses its next frame with it by name.

use std::fmt;
use std::sync::{Arc, Mutex};

use wgpu::Device;

/// A fault of the device: its loss, or an error no error scope caught.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum DeviceFault {
    /// The device is lost (driver reset, GPU removed, out of memory in the driver): nothing
    /// drawn with it shows any more; a new context is needed.
    Lost {
        /// wgpu's reason.
        reason: String,
        /// The driver's message.
        message: String,
    },
    /// An error no error scope caught (a bug of the backend or of its caller), with wgpu's
    /// message.
    Uncaptured(String),
}

impl fmt::Display for DeviceFault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DeviceFault::Lost { reason, message } => {
                write!(f, "the GPU device was lost ({reason}): {message}")
            }
            DeviceFault::Uncaptured(message) => {
                write!(f, "the GPU device reported an error: {message}")
            }
        }
    }
}

impl std::error::Error for DeviceFault {}

/// The first fault of a device, shared by everything drawing with it.
#[derive(Clone, Debug, Default)]
pub struct DeviceHealth {
    fault: Option<Arc<Mutex<Option<DeviceFault>>>>,
}

impl DeviceHealth {
    /// Installs `device`'s lost and uncaptured-error handlers, recording the first fault.
    pub(crate) fn watch(device: &Device) -> DeviceHealth {
        let fault = Arc::new(Mutex::new(None));
        let lost = Arc::clone(&fault);
        device.set_device_lost_callback(move |reason, message| {
            record(
                &lost,
                DeviceFault::Lost {
                    reason: format!("{reason:?}"),
                    message,
                },
            );
        });
        let uncaptured = Arc::clone(&fault);
        device.on_uncaptured_error(Arc::new(move |error: wgpu::Error| {
            record(&uncaptured, DeviceFault::Uncaptured(error.to_string()));
        }));
        DeviceHealth { fault: Some(fault) }
    }

    /// A device whose handlers are its owner's (an adopted host device): no fault is recorded
    /// here.
    pub fn unwatched() -> DeviceHealth {
        DeviceHealth { fault: None }
    }

    /// Whether the device's handlers are this crate's.
    pub fn is_watched(&self) -> bool {
        self.fault.is_some()
    }

    /// The first fault recorded, if any.
    pub fn fault(&self) -> Option<DeviceFault> {
        let fault = self.fault.as_ref()?;
        fault.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// `Err` with the first fault recorded.
    pub fn check(&self) -> Result<(), DeviceFault> {
        self.fault().map_or(Ok(()), Err)
    }
}

fn record(slot: &Mutex<Option<DeviceFault>>, fault: DeviceFault) {
    let mut slot = slot.lock().unwrap_or_else(|e| e.into_inner());
    if slot.is_none() {
        *slot = Some(fault);
    }
}
