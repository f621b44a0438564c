//! The present pass on a real adapter (lavapipe in CI), without a window: the renderer's
//! `Rgba8UnormSrgb` output copied into a target of a swapchain format reaches it with the same
//! bytes, whether the target's format encodes sRGB (hardware) or the shader does.

use gpu_backend::GpuContext;
use gpu_backend::device::DeviceOptions;
use gpu_backend::present::{PresentBlit, SurfaceEncoding};
use gpu_backend::readback::read_buffer;
use gpu_backend::test_support::headless_or_skip;
use wgpu::{Extent3d, TextureFormat, TextureUsages};

const WIDTH: u32 = 64;
const HEIGHT: u32 = 4;

fn texture(ctx: &GpuContext, format: TextureFormat, usage: TextureUsages) -> wgpu::Texture {
    ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("present test"),
        size: Extent3d {
            width: WIDTH,
            height: HEIGHT,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// Every byte value in each channel (256 texels), alpha 255.
fn source_bytes() -> Vec<u8> {
    (0..WIDTH * HEIGHT)
        .flat_map(|i| {
            let i = i as u8;
            [i, 255 - i, i.wrapping_mul(7), 255]
        })
        .collect()
}

/// Blits the source into a target of `format` with `encoding` and reads the target back.
fn blit_into(ctx: &GpuContext, format: TextureFormat, encoding: SurfaceEncoding) -> Vec<u8> {
    let source = texture(
        ctx,
        TextureFormat::Rgba8UnormSrgb,
        TextureUsages::TEXTURE_BINDING | TextureUsages::COPY_DST,
    );
    let bytes_per_row = WIDTH * 4;
    ctx.queue.write_texture(
        source.as_image_copy(),
        &source_bytes(),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(bytes_per_row),
            rows_per_image: None,
        },
        source.size(),
    );
    let target = texture(
        ctx,
        format,
        TextureUsages::RENDER_ATTACHMENT | TextureUsages::COPY_SRC,
    );
    let readback = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("present test readback"),
        size: u64::from(bytes_per_row * HEIGHT),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let blit = PresentBlit::new(&ctx.device, format, encoding);
    assert_eq!((blit.format(), blit.encoding()), (format, encoding));
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    blit.record(
        &ctx.device,
        &mut encoder,
        &source.create_view(&Default::default()),
        &target.create_view(&Default::default()),
    );
    encoder.copy_texture_to_buffer(
        target.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &readback,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                // 64 texels x 4 bytes = 256, already COPY_BYTES_PER_ROW_ALIGNMENT.
                bytes_per_row: Some(bytes_per_row),
                rows_per_image: None,
            },
        },
        target.size(),
    );
    ctx.queue.submit([encoder.finish()]);
    read_buffer(&ctx.device, &ctx.queue, &readback, 0, readback.size()).expect("readback")
}

/// Each byte within 1 of the source's (an sRGB decode, then an encode, may round once).
fn assert_same_bytes(case: &str, got: &[u8], swap_red_blue: bool) {
    let want = source_bytes();
    assert_eq!(got.len(), want.len());
    let mut worst = 0;
    for (texel, (g, w)) in got.chunks(4).zip(want.chunks(4)).enumerate() {
        let g = if swap_red_blue {
            [g[2], g[1], g[0], g[3]]
        } else {
            [g[0], g[1], g[2], g[3]]
        };
        for c in 0..4 {
            let d = g[c].abs_diff(w[c]);
            worst = worst.max(d);
            assert!(
                d <= 1,
                "{case}: texel {texel} channel {c}: got {}, source {}",
                g[c],
                w[c]
            );
        }
    }
    eprintln!("{case}: largest byte difference {worst}");
}

#[test]
fn srgb_targets_get_the_output_bytes_through_the_hardware_encode() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let got = blit_into(
        &ctx,
        TextureFormat::Bgra8UnormSrgb,
        SurfaceEncoding::Hardware,
    );
    assert_same_bytes("Bgra8UnormSrgb", &got, true);
    let got = blit_into(
        &ctx,
        TextureFormat::Rgba8UnormSrgb,
        SurfaceEncoding::Hardware,
    );
    assert_same_bytes("Rgba8UnormSrgb", &got, false);
}

#[test]
fn plain_targets_get_the_output_bytes_through_the_shader_encode() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let got = blit_into(&ctx, TextureFormat::Bgra8Unorm, SurfaceEncoding::Shader);
    assert_same_bytes("Bgra8Unorm", &got, true);
    // Without the encode the bytes would be linear: visibly darker mid-tones.
    let linear = blit_into(&ctx, TextureFormat::Rgba8Unorm, SurfaceEncoding::Hardware);
    let want = source_bytes();
    assert!(
        linear[4 * 128] + 20 < want[4 * 128],
        "an unencoded plain target would be darker ({} vs {})",
        linear[4 * 128],
        want[4 * 128]
    );
}
