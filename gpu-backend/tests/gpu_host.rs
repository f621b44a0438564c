//! The backend plugged into a host's wgpu setup: `GpuContext::from_wgpu` adopts the host's
//! device (capabilities from what it enabled, a device below the required limits refused by
//! name), and `HostPass` draws the renderer's frame into the host's own colour and depth
//! targets: exactly the renderer's output where it drew something, the host's pixels
//! elsewhere, the host's depth convention, and the host's depth test.

use gpu_backend::device::{DeviceError, DeviceOptions, optional_features, required_limits};
use gpu_backend::readback::read_buffer;
use gpu_backend::render::{HostDepth, HostError, HostPass, HostTargets};
use gpu_backend::test_support::{NO_ADAPTER, headless_or_skip, skip};
use gpu_backend::{GpuContext, Renderer, RendererConfig};
use render_model::camera::{Camera, Eye};
use render_model::resident::ChunkMeshData;
use voxel_core::formats::ChunkLayersData;
use voxel_core::formats::{FaceDirection, PackedQuad, PackedQuadFields};
use voxel_core::{BlockId, ChunkCoord, ChunkSize, Material, MaterialPalette};
use wgpu::{Limits, TextureFormat, TextureUsages};

const W: u32 = 64;
const H: u32 = 48;
const NEAR: f32 = 0.05;
const FAR: f32 = 500.0;
const FOV: f32 = 1.0;

/// The host's own instance and adapter (Vulkan), or `None` after a skip line.
fn host_adapter() -> Option<(wgpu::Instance, wgpu::Adapter)> {
    let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    descriptor.backends = wgpu::Backends::VULKAN;
    let instance = wgpu::Instance::new(descriptor);
    match pollster::block_on(instance.request_adapter(&Default::default())) {
        Ok(adapter) => Some((instance, adapter)),
        Err(_) => {
            skip(NO_ADAPTER);
            None
        }
    }
}

fn host_device(
    adapter: &wgpu::Adapter,
    features: wgpu::Features,
    limits: Limits,
) -> (wgpu::Device, wgpu::Queue) {
    pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        required_features: features,
        required_limits: limits,
        ..Default::default()
    }))
    .expect("the adapter gives the device")
}

#[test]
fn a_host_device_is_adopted_with_the_features_it_enabled() {
    let Some((instance, adapter)) = host_adapter() else {
        return;
    };
    let (device, queue) = host_device(
        &adapter,
        optional_features(adapter.features()),
        required_limits(),
    );
    let ctx = GpuContext::from_wgpu(instance.clone(), adapter.clone(), device.clone(), queue)
        .expect("a device with the required limits is adopted");
    assert_eq!(ctx.capabilities.enabled_features, device.features());
    assert_eq!(
        ctx.capabilities.indirect_first_instance,
        device
            .features()
            .contains(wgpu::Features::INDIRECT_FIRST_INSTANCE)
    );
    // Without optional features every fallback is taken; nothing is requested behind the host.
    let (device, queue) = host_device(&adapter, wgpu::Features::empty(), required_limits());
    let ctx = GpuContext::from_wgpu(instance, adapter, device, queue).expect("adopted");
    assert!(ctx.capabilities.enabled_features.is_empty());
    assert!(!ctx.capabilities.indirect_first_instance && !ctx.capabilities.int64_atomics);
}

#[test]
fn a_device_below_the_required_limits_is_refused_by_name() {
    let Some((instance, adapter)) = host_adapter() else {
        return;
    };
    let (device, queue) = host_device(
        &adapter,
        wgpu::Features::empty(),
        Limits::downlevel_defaults(),
    );
    match GpuContext::from_wgpu(instance, adapter, device, queue) {
        Err(e @ DeviceError::MissingCapabilities { .. }) => {
            let text = e.to_string();
            assert!(
                text.contains("max_storage_buffers_per_shader_stage: has 4"),
                "{text}"
            );
        }
        other => panic!("expected MissingCapabilities, got {other:?}"),
    }
}

/// A renderer on `ctx` with the host's own quads: a 16 x 16 floor and a wall in chunk 0.
fn renderer_with_quads(ctx: &GpuContext) -> Renderer {
    let mut palette = MaterialPalette::new();
    palette.push(Material::opaque(200, 120, 60)).expect("room");
    let mut renderer =
        Renderer::new(ctx, &RendererConfig::new(W, H, ChunkSize::S16), &palette).expect("renderer");
    let quad = |position, width, height, face| {
        PackedQuad::encode(&PackedQuadFields {
            position,
            width,
            height,
            face,
            ao: [3, 2, 3, 1],
            block: BlockId(1),
        })
        .expect("valid quad")
    };
    let floor = [quad([0, 0, 0], 16, 16, FaceDirection::PosY)];
    let wall = [quad([0, 1, 0], 16, 6, FaceDirection::PosZ)];
    let mut layers = ChunkLayersData::default();
    layers.opaque_quads[usize::from(FaceDirection::PosY.index())] = &floor;
    layers.opaque_quads[usize::from(FaceDirection::PosZ.index())] = &wall;
    renderer
        .upload_chunk(&ChunkMeshData {
            coord: ChunkCoord::new(0, 0, 0),
            lod: 0,
            layers,
        })
        .expect("upload");
    renderer.set_camera(&{
        let chunk = ChunkCoord::new(0, 0, 1);
        let offset = [8.0, 6.0, 8.0];
        let yaw = 0.2;
        let pitch = -0.4;
        let fov_y = f64::from(FOV);
        let near = f64::from(NEAR);
        let eye = Eye { chunk, offset };
        let camera = Camera::at_eye(eye, ChunkSize::S16, yaw, pitch, fov_y)
            .expect("the eye is inside the i32 world");
        Camera { near, ..camera }
    });
    renderer
}

/// A standard-depth perspective projection (0 at `NEAR`, 1 at `FAR`) for `W x H`.
fn projection() -> [[f32; 4]; 4] {
    let f = 1.0 / (FOV / 2.0).tan();
    [
        [f * H as f32 / W as f32, 0.0, 0.0, 0.0],
        [0.0, f, 0.0, 0.0],
        [0.0, 0.0, FAR / (NEAR - FAR), -1.0],
        [0.0, 0.0, NEAR * FAR / (NEAR - FAR), 0.0],
    ]
}

fn host_texture(ctx: &GpuContext, format: TextureFormat, width: u32) -> wgpu::Texture {
    ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("host target"),
        size: wgpu::Extent3d {
            width,
            height: H,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: TextureUsages::RENDER_ATTACHMENT | TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// Clears the host's targets to blue and to `depth`.
fn clear(
    encoder: &mut wgpu::CommandEncoder,
    colour: &wgpu::Texture,
    depth: &wgpu::Texture,
    value: f32,
) {
    let (cv, dv) = (
        colour.create_view(&Default::default()),
        depth.create_view(&Default::default()),
    );
    drop(encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: &cv,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLUE),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &dv,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Clear(value),
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        ..Default::default()
    }));
}

/// A 4-byte-per-texel texture's texels, rows tightly packed (`W * 4` is a whole row pitch).
fn read_texels(ctx: &GpuContext, texture: &wgpu::Texture, aspect: wgpu::TextureAspect) -> Vec<u8> {
    let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: u64::from(W * H * 4),
        usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(W * 4),
                rows_per_image: None,
            },
        },
        texture.size(),
    );
    ctx.queue.submit([encoder.finish()]);
    read_buffer(&ctx.device, &ctx.queue, &buffer, 0, buffer.size()).expect("readback")
}

/// Draws into host targets cleared to `host_depth`; returns the host's colour and depth and
/// the renderer's own image.
fn draw_into_host(
    ctx: &GpuContext,
    host_depth: f32,
) -> (Vec<u8>, Vec<f32>, gpu_backend::render::FrameImage) {
    let mut renderer = renderer_with_quads(ctx);
    let colour = host_texture(ctx, TextureFormat::Rgba8UnormSrgb, W);
    let depth = host_texture(ctx, TextureFormat::Depth32Float, W);
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    clear(&mut encoder, &colour, &depth, host_depth);
    let targets = HostTargets {
        colour: &colour,
        depth: Some(HostDepth {
            texture: &depth,
            projection: projection(),
            compare: wgpu::CompareFunction::Less,
        }),
    };
    HostPass::new(ctx)
        .expect("host pass")
        .record(ctx, &mut renderer, &mut encoder, &targets)
        .expect("recorded");
    ctx.queue.submit([encoder.finish()]);
    let image = renderer.read_image().expect("renderer image");
    let host_colour = read_texels(ctx, &colour, wgpu::TextureAspect::All);
    let host_depth =
        bytemuck::pod_collect_to_vec(&read_texels(ctx, &depth, wgpu::TextureAspect::DepthOnly));
    (host_colour, host_depth, image)
}

#[test]
fn the_frame_lands_in_the_host_targets_in_the_host_depth_convention() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let (colour, depth, image) = draw_into_host(&ctx, 1.0);
    let p = projection();
    let mut drawn = 0;
    for i in 0..(W * H) as usize {
        let (host, ours) = (&colour[4 * i..4 * i + 4], &image.rgba[4 * i..4 * i + 4]);
        if image.depth[i] > 0.0 {
            drawn += 1;
            let close = host.iter().zip(ours).all(|(a, b)| a.abs_diff(*b) <= 1);
            assert!(close, "pixel {i}: host {host:?}, renderer {ours:?}");
            let z = NEAR / image.depth[i];
            let expected = (p[2][2] * -z + p[3][2]) / (p[2][3] * -z + p[3][3]);
            assert!(
                (depth[i] - expected).abs() <= 1e-5,
                "pixel {i}: depth {} vs {expected}",
                depth[i]
            );
        } else {
            assert_eq!(
                host,
                [0, 0, 255, 255],
                "pixel {i}: the host's clear colour stays"
            );
            assert_eq!(depth[i], 1.0, "pixel {i}: the host's depth stays");
        }
    }
    assert!(
        drawn > (W * H) as usize / 4,
        "the quads fill much of the view: {drawn}"
    );
}

#[test]
fn the_host_depth_test_hides_the_frame_behind_host_geometry() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    // Host depth 0: the host drew something at the near plane everywhere.
    let (colour, depth, image) = draw_into_host(&ctx, 0.0);
    assert!(image.depth.iter().any(|&d| d > 0.0), "the renderer drew");
    assert!(
        colour.chunks(4).all(|p| p == [0, 0, 255, 255]),
        "nothing passes the host's test"
    );
    assert!(depth.iter().all(|&d| d == 0.0));
}

#[test]
fn targets_of_another_size_or_kind_are_refused() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let mut renderer = renderer_with_quads(&ctx);
    let mut pass = HostPass::new(&ctx).expect("host pass");
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    let wide = host_texture(&ctx, TextureFormat::Rgba8UnormSrgb, W + 1);
    let targets = HostTargets {
        colour: &wide,
        depth: None,
    };
    match pass.record(&ctx, &mut renderer, &mut encoder, &targets) {
        Err(HostError::SizeMismatch {
            target: "colour",
            size,
            renderer,
        }) => {
            assert_eq!((size, renderer), ((W + 1, H), (W, H)));
        }
        other => panic!("expected SizeMismatch, got {other:?}"),
    }
    let depth = host_texture(&ctx, TextureFormat::Depth32Float, W);
    let targets = HostTargets {
        colour: &depth,
        depth: None,
    };
    assert!(matches!(
        pass.record(&ctx, &mut renderer, &mut encoder, &targets),
        Err(HostError::Unusable {
            target: "colour",
            ..
        })
    ));
}
