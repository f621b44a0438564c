//! Device setup: adapter choice, feature probing with recorded fallbacks, limits.
//!
//! [`GpuContext::new_headless`] creates an instance, picks an adapter, and requests a device
//! with the optional features this backend can use when the adapter has them:
//!
//! | feature                             | used for                                 | fallback when missing or disabled          |
//! | ----------------------------------- | ---------------------------------------- | ------------------------------------------ |
//! | `MULTI_DRAW_INDIRECT_COUNT`         | one draw call per layer, count on GPU    | `multi_draw_indexed_indirect` over the whole command buffer, culled commands zeroed (`instance_count = 0`) |
//! | `TIMESTAMP_QUERY` (+ `_INSIDE_ENCODERS`, `_INSIDE_PASSES`) | per-pass GPU time        | CPU wall-clock timing around submissions   |
//! | `INDIRECT_FIRST_INSTANCE`           | per-draw data through `first_instance`   | per-draw data read by draw index elsewhere |
//! | `SHADER_INT64` + `SHADER_INT64_ATOMIC_MIN_MAX` | far draws splatted in compute (64-bit atomic max of depth and payload) | far draws rasterised as ray-box sprites |
//! | `SHADER_EARLY_DEPTH_TEST`           | sprites' conservative depth (early depth test kept with `frag_depth`) | the depth test after the sprite's fragment shader |
//!
//! What was chosen is recorded in [`GpuCapabilities`], which the passes read; nothing else
//! queries the device's features. [`DeviceOptions`] can force each fallback so tests exercise
//! both paths on one adapter (lavapipe supports them all).
//!
//! Limits: the WebGPU defaults, raised to the adapter's values for the buffer limits the
//! gigabuffer depends on (`max_buffer_size`, `max_storage_buffer_binding_size`,
//! `max_storage_buffers_per_shader_stage`).
//!
//! [`GpuContext::new_windowed`] (in [`crate::present`], which builds on this module) does the
//! same for a window: it creates the window's surface first and considers only adapters that
//! can present to it, then returns the context with a window output.
//!
//! [`GpuContext::from_wgpu`] adopts a host engine's own instance, adapter, device and queue
//! instead: nothing is requested, the capabilities are probed from what the device
//! has enabled, and a device below the backend's required limits is refused with each missing
//! limit named.

mod adopt;
pub mod alloc;
mod error;
mod health;

use std::fmt;

use wgpu::{
    Adapter, Backends, Device, DeviceType, Features, Instance, InstanceDescriptor, Limits,
    PowerPreference, Queue,
};

pub use adopt::{optional_features, required_limits};
pub use error::DeviceError;
pub use health::{DeviceFault, DeviceHealth};

/// How the context is created. `Default` is the configuration for real use: Vulkan, the
/// high-performance adapter, every optional feature the adapter has.
#[derive(Clone, Debug)]
pub struct DeviceOptions {
    /// Backends searched for adapters. The crate is built with Vulkan only.
    pub backends: Backends,
    /// Which kind of adapter is preferred when several exist.
    pub power_preference: PowerPreference,
    /// Only adapters whose name contains this (case-insensitive) are considered.
    pub adapter_name: Option<String>,
    /// Do not enable `MULTI_DRAW_INDIRECT_COUNT` even if supported (test the fallback).
    pub disable_indirect_count: bool,
    /// Do not enable any timestamp query feature even if supported (test CPU timing).
    pub disable_timestamps: bool,
    /// Do not enable `INDIRECT_FIRST_INSTANCE` even if supported.
    pub disable_indirect_first_instance: bool,
    /// Do not enable the 64-bit atomics of the compute splat even if supported.
    pub disable_int64_atomics: bool,
    /// Do not enable `SHADER_EARLY_DEPTH_TEST` (conservative depth) even if supported.
    pub disable_early_depth_test: bool,
}

impl Default for DeviceOptions {
    fn default() -> Self {
        DeviceOptions {
            backends: Backends::VULKAN,
            power_preference: PowerPreference::HighPerformance,
            adapter_name: None,
            disable_indirect_count: false,
            disable_timestamps: false,
            disable_indirect_first_instance: false,
            disable_int64_atomics: false,
            disable_early_depth_test: false,
        }
    }
}

impl DeviceOptions {
    /// Options that force every fallback path (no indirect count, no timestamps, no
    /// indirect first instance, no 64-bit atomics, no conservative depth).
    pub fn all_fallbacks() -> Self {
        DeviceOptions {
            disable_indirect_count: true,
            disable_timestamps: true,
            disable_indirect_first_instance: true,
            disable_int64_atomics: true,
            disable_early_depth_test: true,
            ..DeviceOptions::default()
        }
    }
}

/// How layers are drawn from the cull pass's commands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MultiDrawPath {
    /// `multi_draw_indexed_indirect_count`: the GPU reads the number of commands.
    IndirectCount,
    /// `multi_draw_indexed_indirect` over every command slot; the cull pass writes culled
    /// slots as zeroed commands (`instance_count = 0`).
    ZeroedCommands,
}

/// How passes are timed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TimingPath {
    /// GPU timestamp queries.
    GpuTimestamps {
        /// `write_timestamp` on command encoders is available.
        inside_encoders: bool,
        /// `write_timestamp` inside render and compute passes is available.
        inside_passes: bool,
        /// Nanoseconds per timestamp tick (`Queue::get_timestamp_period`).
        period_ns: f32,
    },
    /// CPU wall-clock time around submissions (no per-pass GPU figures).
    Cpu,
}

/// The adapter a context runs on, as text for reports.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AdapterSummary {
    /// Adapter name, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)` or `NVIDIA H200`.
    pub name: String,
    /// Backend, e.g. `Vulkan`.
    pub backend: String,
    /// Device type, e.g. `Cpu` or `DiscreteGpu`.
    pub device_type: String,
    /// Driver name and version information.
    pub driver: String,
}

impl fmt::Display for AdapterSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} ({}, {}, driver {})",
            self.name, self.backend, self.device_type, self.driver
        )
    }
}

/// What the device can do, after feature probing and forced fallbacks. Passes read this,
/// never the raw feature set.
#[derive(Clone, Debug, PartialEq)]
pub struct GpuCapabilities {
    /// The adapter.
    pub adapter: AdapterSummary,
    /// Draw path for the cull pass's commands.
    pub multi_draw: MultiDrawPath,
    /// Timing path.
    pub timing: TimingPath,
    /// `INDIRECT_FIRST_INSTANCE` is enabled: indirect commands may use a non-zero
    /// `first_instance`.
    pub indirect_first_instance: bool,
    /// `SHADER_INT64` and `SHADER_INT64_ATOMIC_MIN_MAX` are enabled: far draws can be splatted
    /// in compute.
    pub int64_atomics: bool,
    /// `SHADER_EARLY_DEPTH_TEST` is enabled: fragment shaders that write depth can keep the
    /// early depth test with a conservative depth.
    pub early_depth_test: bool,
    /// Largest storage buffer binding, bytes (lavapipe 128 MiB, NVIDIA 2 GiB or more).
    pub max_storage_buffer_binding_size: u64,
    /// Largest buffer, bytes.
    pub max_buffer_size: u64,
    /// Storage buffers one shader stage may bind.
    pub max_storage_buffers_per_shader_stage: u32,
    /// Features the adapter offers (before anything was disabled).
    pub adapter_features: Features,
    /// Features enabled on the device.
    pub enabled_features: Features,
}

impl GpuCapabilities {
    /// The largest buffer that can be bound whole as one storage binding: the size of a
    /// gigabuffer page.
    pub fn max_page_bytes(&self) -> u64 {
        self.max_storage_buffer_binding_size
            .min(self.max_buffer_size)
    }
}

/// A wgpu device and queue with the capabilities this backend probed.
#[derive(Debug)]
pub struct GpuContext {
    /// The instance (kept for surfaces and polling).
    pub instance: Instance,
    /// The adapter the device runs on.
    pub adapter: Adapter,
    /// The device.
    pub device: Device,
    /// Its queue.
    pub queue: Queue,
    /// What the device can do, and the fallbacks chosen.
    pub capabilities: GpuCapabilities,
    /// The device's first fault outside any error scope (loss, an uncaught error), recorded
    /// instead of wgpu's default panic.
    pub health: DeviceHealth,
}

impl GpuContext {
    /// A context without a surface, for tests, benchmarks and offscreen rendering.
    pub fn new_headless(options: &DeviceOptions) -> Result<GpuContext, DeviceError> {
        let mut descriptor = InstanceDescriptor::new_without_display_handle_from_env();
        descriptor.backends = options.backends;
        let instance = Instance::new(descriptor);
        GpuContext::from_instance(instance, options)
    }

    /// Picks an adapter of `instance` and creates the device (no surface constraint; the
    /// windowed constructor adds one).
    pub fn from_instance(
        instance: Instance,
        options: &DeviceOptions,
    ) -> Result<GpuContext, DeviceError> {
        GpuContext::create(instance, options, None)
    }

    /// [`from_instance`](Self::from_instance), keeping only adapters for which `presents`
    /// holds when it is given (the windowed constructor's surface test).
    pub(crate) fn create(
        instance: Instance,
        options: &DeviceOptions,
        presents: Option<&dyn Fn(&Adapter) -> bool>,
    ) -> Result<GpuContext, DeviceError> {
        let adapter = choose_adapter(&instance, options, presents)?;
        let adapter_features = adapter.features();
        let wanted = wanted_features(adapter_features, options);
        let limits = wanted_limits(&adapter.limits());
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("gpu-backend device"),
            required_features: wanted,
            required_limits: limits,
            ..Default::default()
        };
        let (device, queue) =
            pollster::block_on(adapter.request_device(&descriptor)).map_err(|source| {
                DeviceError::RequestDevice {
                    adapter: summarize(&adapter),
                    source: Box::new(source),
                }
            })?;
        let capabilities = probe(&adapter, &device, &queue, adapter_features);
        let health = DeviceHealth::watch(&device);
        Ok(GpuContext {
            instance,
            adapter,
            device,
            queue,
            capabilities,
            health,
        })
    }
}

/// The capabilities of `device` as created: the paths follow the features it has enabled,
/// the limits are the device's own. `adapter_features` is what the adapter offers.
pub(crate) fn probe(
    adapter: &Adapter,
    device: &Device,
    queue: &Queue,
    adapter_features: Features,
) -> GpuCapabilities {
    let limits = device.limits();
    let enabled = device.features();
    GpuCapabilities {
        adapter: summarize(adapter),
        multi_draw: if enabled.contains(Features::MULTI_DRAW_INDIRECT_COUNT) {
            MultiDrawPath::IndirectCount
        } else {
            MultiDrawPath::ZeroedCommands
        },
        timing: if enabled.contains(Features::TIMESTAMP_QUERY) {
            TimingPath::GpuTimestamps {
                inside_encoders: enabled.contains(Features::TIMESTAMP_QUERY_INSIDE_ENCODERS),
                inside_passes: enabled.contains(Features::TIMESTAMP_QUERY_INSIDE_PASSES),
                period_ns: queue.get_timestamp_period(),
            }
        } else {
            TimingPath::Cpu
        },
        indirect_first_instance: enabled.contains(Features::INDIRECT_FIRST_INSTANCE),
        int64_atomics: enabled
            .contains(Features::SHADER_INT64 | Features::SHADER_INT64_ATOMIC_MIN_MAX),
        early_depth_test: enabled.contains(Features::SHADER_EARLY_DEPTH_TEST),
        max_storage_buffer_binding_size: limits.max_storage_buffer_binding_size,
        max_buffer_size: limits.max_buffer_size,
        max_storage_buffers_per_shader_stage: limits.max_storage_buffers_per_shader_stage,
        adapter_features,
        enabled_features: enabled,
    }
}

/// The optional features to enable: those the adapter has, minus the disabled ones.
fn wanted_features(adapter: Features, options: &DeviceOptions) -> Features {
    let mut wanted = Features::empty();
    if !options.disable_indirect_count {
        wanted |= Features::MULTI_DRAW_INDIRECT_COUNT;
    }
    if !options.disable_timestamps {
        wanted |= Features::TIMESTAMP_QUERY;
        // The finer timestamp features are only usable together with TIMESTAMP_QUERY.
        if adapter.contains(Features::TIMESTAMP_QUERY) {
            wanted |=
                Features::TIMESTAMP_QUERY_INSIDE_ENCODERS | Features::TIMESTAMP_QUERY_INSIDE_PASSES;
        }
    }
    if !options.disable_indirect_first_instance {
        wanted |= Features::INDIRECT_FIRST_INSTANCE;
    }
    let int64 = Features::SHADER_INT64 | Features::SHADER_INT64_ATOMIC_MIN_MAX;
    if !options.disable_int64_atomics && adapter.contains(int64) {
        wanted |= int64;
    }
    if !options.disable_early_depth_test {
        wanted |= Features::SHADER_EARLY_DEPTH_TEST;
    }
    wanted & adapter
}

/// WebGPU defaults, with the buffer limits raised to what the adapter offers.
pub(crate) fn wanted_limits(adapter: &Limits) -> Limits {
    let defaults = Limits::default();
    Limits {
        max_buffer_size: adapter.max_buffer_size.max(defaults.max_buffer_size),
        max_storage_buffer_binding_size: adapter
            .max_storage_buffer_binding_size
            .max(defaults.max_storage_buffer_binding_size),
        max_storage_buffers_per_shader_stage: adapter
            .max_storage_buffers_per_shader_stage
            .max(defaults.max_storage_buffers_per_shader_stage),
        ..defaults
    }
    // Never ask for more than the adapter has (a downlevel adapter may be below a default).
    .or_worse_values_from(adapter)
}

/// The best adapter of the requested backends that passes the name filter and, when
/// `presents` is given, passes it (can present to the window).
fn choose_adapter(
    instance: &Instance,
    options: &DeviceOptions,
    presents: Option<&dyn Fn(&Adapter) -> bool>,
) -> Result<Adapter, DeviceError> {
    let all = pollster::block_on(instance.enumerate_adapters(options.backends));
    let mut rejected = Vec::new();
    let mut cannot_present = Vec::new();
    let mut candidates: Vec<Adapter> = Vec::new();
    for adapter in all {
        let name = adapter.get_info().name;
        match &options.adapter_name {
            Some(filter) if !name.to_lowercase().contains(&filter.to_lowercase()) => {
                rejected.push(name);
            }
            _ => match presents {
                Some(presents) if !presents(&adapter) => cannot_present.push(name),
                _ => candidates.push(adapter),
            },
        }
    }
    if candidates.is_empty() && !cannot_present.is_empty() {
        return Err(DeviceError::NoPresentingAdapter {
            adapters: cannot_present,
        });
    }
    // Stable sort: equal ranks keep the enumeration order.
    candidates.sort_by_key(|a| rank(a.get_info().device_type, options.power_preference));
    candidates
        .into_iter()
        .next()
        .ok_or_else(|| DeviceError::NoAdapter {
            backends: options.backends,
            power_preference: options.power_preference,
            adapter_name: options.adapter_name.clone(),
            rejected,
        })
}

/// Lower is better: the device types in the order the power preference wants them. A CPU
/// adapter (lavapipe) is always last, so a real GPU wins whenever there is one.
fn rank(device_type: DeviceType, preference: PowerPreference) -> u8 {
    let order: [DeviceType; 4] = match preference {
        PowerPreference::LowPower => [
            DeviceType::IntegratedGpu,
            DeviceType::DiscreteGpu,
            DeviceType::VirtualGpu,
            DeviceType::Other,
        ],
        _ => [
            DeviceType::DiscreteGpu,
            DeviceType::IntegratedGpu,
            DeviceType::VirtualGpu,
            DeviceType::Other,
        ],
    };
    order
        .iter()
        .position(|&t| t == device_type)
        .map_or(order.len() as u8, |i| i as u8)
}

/// The adapter's description for reports.
pub(crate) fn summarize(adapter: &Adapter) -> AdapterSummary {
    let info = adapter.get_info();
    let driver = if info.driver_info.is_empty() {
        info.driver.clone()
    } else {
        format!("{} {}", info.driver, info.driver_info)
    };
    AdapterSummary {
        name: info.name,
        backend: format!("{:?}", info.backend),
        device_type: format!("{:?}", info.device_type),
        driver,
    }
}
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn disabled_features_are_never_requested() {
        let all = Features::all();
        let wanted = wanted_features(all, &DeviceOptions::all_fallbacks());
        assert!(!wanted.contains(Features::MULTI_DRAW_INDIRECT_COUNT));
        assert!(!wanted.intersects(
            Features::TIMESTAMP_QUERY
                | Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
                | Features::TIMESTAMP_QUERY_INSIDE_PASSES
        ));
        assert!(!wanted.contains(Features::INDIRECT_FIRST_INSTANCE));
        let default = wanted_features(all, &DeviceOptions::default());
        assert!(default.contains(
            Features::MULTI_DRAW_INDIRECT_COUNT
                | Features::TIMESTAMP_QUERY_INSIDE_PASSES
                | Features::INDIRECT_FIRST_INSTANCE
        ));
    }

    #[test]
    fn features_the_adapter_lacks_are_never_requested() {
        let wanted = wanted_features(Features::TIMESTAMP_QUERY, &DeviceOptions::default());
        assert_eq!(
            wanted,
            Features::TIMESTAMP_QUERY,
            "only what the adapter offers"
        );
        let wanted = wanted_features(Features::empty(), &DeviceOptions::default());
        assert!(wanted.is_empty());
    }

    #[test]
    fn limits_follow_the_adapter_buffers() {
        let adapter = Limits {
            max_storage_buffer_binding_size: 2 << 30,
            max_buffer_size: 4 << 30,
            ..Limits::default()
        };
        let limits = wanted_limits(&adapter);
        assert_eq!(limits.max_storage_buffer_binding_size, 2 << 30);
        assert_eq!(limits.max_buffer_size, 4 << 30);
        let low = Limits::downlevel_webgl2_defaults();
        let limits = wanted_limits(&low);
        assert!(limits.max_storage_buffer_binding_size <= low.max_storage_buffer_binding_size);
    }

    #[test]
    fn cpu_adapters_rank_last() {
        for preference in [PowerPreference::HighPerformance, PowerPreference::LowPower] {
            let cpu = rank(DeviceType::Cpu, preference);
            for gpu in [DeviceType::DiscreteGpu, DeviceType::IntegratedGpu] {
                assert!(rank(gpu, preference) < cpu);
            }
        }
        assert!(
            rank(DeviceType::DiscreteGpu, PowerPreference::HighPerformance)
                < rank(DeviceType::IntegratedGpu, PowerPreference::HighPerformance)
        );
        assert!(
            rank(DeviceType::IntegratedGpu, PowerPreference::LowPower)
                < rank(DeviceType::DiscreteGpu, PowerPreference::LowPower)
        );
    }

    #[test]
    fn no_adapter_error_names_the_search() {
        let e = DeviceError::NoAdapter {
            backends: Backends::VULKAN,
            power_preference: PowerPreference::HighPerformance,
            adapter_name: Some("H200".into()),
            rejected: vec!["llvmpipe".into()],
        };
        let text = e.to_string();
        for part in ["VULKAN", "HighPerformance", "H200", "llvmpipe"] {
            assert!(text.contains(part), "{text:?} lacks {part}");
        }
        assert!(e.is_no_adapter());
    }

    #[test]
    fn surface_errors_name_the_problem() {
        let e = DeviceError::NoPresentingAdapter {
            adapters: vec!["llvmpipe".into()],
        };
        let text = e.to_string();
        assert!(
            text.contains("no adapter can present to this window"),
            "{text}"
        );
        assert!(text.contains("llvmpipe"), "{text}");
        assert!(!e.is_no_adapter());
    }
}
