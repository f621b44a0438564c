//! Device setup on a real adapter (lavapipe in CI): features are probed, forced fallbacks are
//! honoured, and limits come from the adapter.

use gpu_backend::device::{DeviceOptions, MultiDrawPath, TimingPath};
use gpu_backend::test_support::headless_or_skip;
use wgpu::Features;

#[test]
fn default_options_enable_what_the_adapter_has() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let caps = &ctx.capabilities;
    eprintln!("adapter: {}", caps.adapter);
    eprintln!("capabilities: {caps:#?}");
    let adapter = caps.adapter_features;
    assert_eq!(
        caps.multi_draw == MultiDrawPath::IndirectCount,
        adapter.contains(Features::MULTI_DRAW_INDIRECT_COUNT)
    );
    assert_eq!(
        matches!(caps.timing, TimingPath::GpuTimestamps { .. }),
        adapter.contains(Features::TIMESTAMP_QUERY)
    );
    assert_eq!(
        caps.indirect_first_instance,
        adapter.contains(Features::INDIRECT_FIRST_INSTANCE)
    );
    assert_eq!(caps.enabled_features, ctx.device.features());
    // The buffer limits are the adapter's, not the WebGPU defaults.
    let limits = ctx.adapter.limits();
    assert_eq!(
        caps.max_storage_buffer_binding_size,
        limits.max_storage_buffer_binding_size
    );
    assert_eq!(caps.max_buffer_size, limits.max_buffer_size);
    assert_eq!(ctx.device.limits().max_buffer_size, limits.max_buffer_size);
    assert!(caps.max_page_bytes() <= caps.max_buffer_size);
    if let TimingPath::GpuTimestamps { period_ns, .. } = caps.timing {
        assert!(period_ns > 0.0);
    }
}

#[test]
fn forced_fallbacks_are_recorded_and_enforced() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::all_fallbacks()) else {
        return;
    };
    let caps = &ctx.capabilities;
    assert_eq!(caps.multi_draw, MultiDrawPath::ZeroedCommands);
    assert_eq!(caps.timing, TimingPath::Cpu);
    assert!(!caps.indirect_first_instance);
    let enabled = ctx.device.features();
    assert!(!enabled.intersects(
        Features::MULTI_DRAW_INDIRECT_COUNT
            | Features::TIMESTAMP_QUERY
            | Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
            | Features::TIMESTAMP_QUERY_INSIDE_PASSES
            | Features::INDIRECT_FIRST_INSTANCE
    ));
}

#[test]
fn each_fallback_can_be_forced_alone() {
    let options = DeviceOptions {
        disable_indirect_count: true,
        ..DeviceOptions::default()
    };
    let Some(ctx) = headless_or_skip(&options) else {
        return;
    };
    assert_eq!(ctx.capabilities.multi_draw, MultiDrawPath::ZeroedCommands);
    if ctx
        .capabilities
        .adapter_features
        .contains(Features::TIMESTAMP_QUERY)
    {
        assert_ne!(
            ctx.capabilities.timing,
            TimingPath::Cpu,
            "timestamps stay on"
        );
    }
    let options = DeviceOptions {
        disable_timestamps: true,
        ..DeviceOptions::default()
    };
    let ctx = headless_or_skip(&options).expect("the adapter was there a moment ago");
    assert_eq!(ctx.capabilities.timing, TimingPath::Cpu);
}

#[test]
fn a_name_filter_that_matches_nothing_is_a_clear_error() {
    let options = DeviceOptions {
        adapter_name: Some("no adapter is called this".into()),
        ..DeviceOptions::default()
    };
    let err = gpu_backend::GpuContext::new_headless(&options).unwrap_err();
    assert!(err.is_no_adapter());
    let text = err.to_string();
    assert!(text.contains("no adapter is called this"), "{text}");
    assert!(text.contains("VULKAN"), "{text}");
}
