//! What a refused allocation, an error outside any error scope and a lost device do: each is
//! an error naming the problem, never wgpu's default handler (a panic), and a renderer on a
//! faulted device refuses its next frame by name.

use gpu_backend::device::DeviceFault;
use gpu_backend::device::alloc;
use gpu_backend::render::{RenderError, Renderer, RendererConfig};
use gpu_backend::test_support::headless_or_skip;
use gpu_backend::{DeviceOptions, GpuContext};
use voxel_core::{ChunkSize, Material, MaterialPalette};

fn palette() -> MaterialPalette {
    let mut p = MaterialPalette::new();
    p.push(Material::opaque(200, 50, 50)).unwrap();
    p
}

fn renderer(ctx: &GpuContext) -> Renderer {
    Renderer::new(
        ctx,
        &RendererConfig::new(16, 16, ChunkSize::S16),
        &palette(),
    )
    .expect("renderer")
}

/// A buffer past the device's largest is refused with its label and size, and the device
/// goes on working (no fault recorded: the error scope caught it).
#[test]
fn a_refused_buffer_is_an_error_naming_it() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let too_large = ctx.device.limits().max_buffer_size + 4;
    let error = alloc::create_buffer(
        &ctx.device,
        &wgpu::BufferDescriptor {
            label: Some("a buffer too large"),
            size: too_large,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        },
    )
    .expect_err("past max_buffer_size");
    assert_eq!(error.what, "a buffer too large");
    assert_eq!(error.bytes, too_large);
    let text = error.to_string();
    assert!(text.contains("a buffer too large"), "{text}");
    assert_eq!(ctx.health.fault(), None, "the scope caught it");
    let mut renderer = renderer(&ctx);
    renderer.render().expect("the device still draws");
}

/// An error no scope catches is recorded, not panicked on, and refuses the next frame.
#[test]
fn an_uncaught_error_refuses_the_next_frame_by_name() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    assert!(ctx.health.is_watched());
    let mut renderer = renderer(&ctx);
    renderer.render().expect("a frame before the fault");
    // Outside any error scope: wgpu's default handler would panic here.
    let _invalid = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("invalid outside a scope"),
        size: ctx.device.limits().max_buffer_size + 4,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let fault = ctx.health.fault().expect("the error is recorded");
    assert!(matches!(fault, DeviceFault::Uncaptured(_)), "{fault:?}");
    match renderer.render() {
        Err(RenderError::Device(DeviceFault::Uncaptured(message))) => {
            assert!(!message.is_empty())
        }
        other => panic!("the frame after the fault: {other:?}"),
    }
}

/// A lost device is reported by name: the renderer refuses its frames instead of panicking.
#[test]
fn a_lost_device_refuses_frames_by_name() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let mut renderer = renderer(&ctx);
    renderer.render().expect("a frame before the loss");
    ctx.device.destroy();
    let _ = ctx.device.poll(wgpu::PollType::wait_indefinitely());
    let fault = ctx.health.fault().expect("the loss is recorded");
    assert!(matches!(fault, DeviceFault::Lost { .. }), "{fault:?}");
    let error = renderer.render().expect_err("a frame on a lost device");
    assert!(
        matches!(error, RenderError::Device(DeviceFault::Lost { .. })),
        "{error:?}"
    );
    assert!(error.to_string().contains("lost"), "{error}");
}
