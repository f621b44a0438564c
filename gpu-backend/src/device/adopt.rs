//! Adopting a host engine's wgpu objects: [`GpuContext::from_wgpu`].
//!
//! A host that already has an instance, an adapter, a device and a queue hands them over; the
//! backend requests nothing. It probes what the device has enabled into [`GpuCapabilities`]
//! (the same probe as a device it created itself, so every optional feature the host did not
//! enable takes its fallback path: see the table in the [module docs](super)), and checks the
//! device's limits against [`required_limits`]. A device below them is refused with
//! [`DeviceError::MissingCapabilities`], which names each limit, the value the device has and
//! the value needed; nothing fails later at pipeline creation for want of a limit.
//!
//! To give the backend every optional path, create the device with the features of
//! [`optional_features`] and at least [`required_limits`] (the host may enable more).

use wgpu::{Adapter, Device, Features, Instance, Limits, Queue};

use super::{
    DeviceError, DeviceHealth, DeviceOptions, GpuCapabilities, GpuContext, probe, summarize,
};
use crate::shaders::{ALL_SHADERS, FORMAT_PARITY};

impl GpuContext {
    /// A context on a host's own wgpu objects. The host keeps
    /// using them as before (wgpu handles are shared clones); the backend only adds its own
    /// buffers, textures and pipelines to `device`.
    ///
    /// Errors: [`DeviceError::MissingCapabilities`] when a limit of `device` is below
    /// [`required_limits`].
    pub fn from_wgpu(
        instance: Instance,
        adapter: Adapter,
        device: Device,
        queue: Queue,
    ) -> Result<GpuContext, DeviceError> {
        let missing = missing_limits(&device.limits());
        if !missing.is_empty() {
            return Err(DeviceError::MissingCapabilities {
                adapter: summarize(&adapter),
                missing,
            });
        }
        let capabilities: GpuCapabilities = probe(&adapter, &device, &queue, adapter.features());
        // The host's device keeps the host's lost and uncaptured-error handlers.
        Ok(GpuContext {
            instance,
            adapter,
            device,
            queue,
            capabilities,
            health: DeviceHealth::unwatched(),
        })
    }
}

/// The limits the backend's pipelines and buffers need: the WebGPU defaults, with as many
/// storage buffers per shader stage as the shader that declares the most (the cull pass).
pub fn required_limits() -> Limits {
    Limits {
        max_storage_buffers_per_shader_stage: max_storage_buffers(),
        ..Limits::default()
    }
}

/// The optional features the backend uses when the device has them (every fallback off):
/// the features to enable on a host device for the fastest paths, where the adapter has them.
pub fn optional_features(adapter: Features) -> Features {
    super::wanted_features(adapter, &DeviceOptions::default())
}

/// `"<limit>: has <value>, needs <value>"` for every limit of `limits` below
/// [`required_limits`].
fn missing_limits(limits: &Limits) -> Vec<String> {
    let mut missing = Vec::new();
    required_limits().check_limits_with_fail_fn(limits, false, |name, needed, has| {
        missing.push(format!("{name}: has {has}, needs {needed}"));
    });
    missing
}

/// The most storage buffers one shader module of the crate declares (an upper bound of what
/// one of its stages binds). The test-only parity shader is left out.
fn max_storage_buffers() -> u32 {
    ALL_SHADERS
        .iter()
        .filter(|spec| spec.name != FORMAT_PARITY.name)
        .map(|spec| {
            let module = naga::front::wgsl::parse_str(&spec.source())
                .unwrap_or_else(|e| panic!("shader {} does not parse: {e}", spec.name));
            module
                .global_variables
                .iter()
                .filter(|(_, var)| matches!(var.space, naga::AddressSpace::Storage { .. }))
                .count() as u32
        })
        .max()
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cull_shader_sets_the_storage_buffer_requirement() {
        let needed = required_limits().max_storage_buffers_per_shader_stage;
        assert!(
            needed >= 14,
            "the cull pass binds 14 storage buffers; got {needed}"
        );
        assert!(needed > Limits::default().max_storage_buffers_per_shader_stage);
    }

    #[test]
    fn limits_below_the_requirement_are_named() {
        let low = Limits::downlevel_defaults();
        let missing = missing_limits(&low);
        assert!(
            missing
                .iter()
                .any(|m| m.starts_with("max_storage_buffers_per_shader_stage: has 4, needs")),
            "{missing:?}"
        );
        assert!(missing_limits(&required_limits()).is_empty());
    }

    #[test]
    fn the_missing_capabilities_error_names_every_limit() {
        let e = DeviceError::MissingCapabilities {
            adapter: crate::device::AdapterSummary {
                name: "host GPU".into(),
                backend: "Vulkan".into(),
                device_type: "Cpu".into(),
                driver: "test".into(),
            },
            missing: vec!["max_bind_groups: has 2, needs 4".into()],
        };
        let text = e.to_string();
        assert!(text.contains("host GPU") && text.contains("max_bind_groups: has 2"));
        assert!(!e.is_no_adapter());
    }
}
