//! The backend inside a host's own wgpu setup: the host creates the instance, adapter, device,
//! queue and its colour and depth targets (reversed-Z, as many engines use); the backend adopts
//! the device and draws the host's own `PackedQuad`s into those targets, depth-tested against
//! what the host drew (here: nothing, the targets are as created, zeroed = far).

use gpu_backend::device::{optional_features, required_limits};
use gpu_backend::render::{HostDepth, HostPass, HostTargets};
use gpu_backend::{GpuContext, Renderer, RendererConfig};
use render_model::camera::Camera;
use render_model::resident::ChunkMeshData;
use voxel_core::formats::ChunkLayersData;
use voxel_core::formats::{FaceDirection, PackedQuad, PackedQuadFields};
use voxel_core::{BlockId, ChunkCoord, ChunkSize, Material, MaterialPalette, WorldPos};
use wgpu::{TextureFormat as F, TextureUsages as U};

const W: u32 = 256;
const H: u32 = 192;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // The host's own wgpu objects, with the limits and optional features the backend names.
    let desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    let instance = wgpu::Instance::new(desc);
    let adapter = pollster::block_on(instance.request_adapter(&Default::default()))?;
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        required_features: optional_features(adapter.features()),
        required_limits: required_limits(),
        ..Default::default()
    }))?;
    let size = wgpu::Extent3d {
        width: W,
        height: H,
        depth_or_array_layers: 1,
    };
    let target = |format, usage| {
        let (dimension, view_formats) = (wgpu::TextureDimension::D2, &[][..]);
        let (label, mip_level_count, sample_count) = (None, 1, 1);
        device.create_texture(&wgpu::TextureDescriptor {
            label,
            size,
            mip_level_count,
            sample_count,
            dimension,
            format,
            usage,
            view_formats,
        })
    };
    let colour = target(F::Rgba8UnormSrgb, U::RENDER_ATTACHMENT);
    let depth = target(F::Depth32Float, U::RENDER_ATTACHMENT);

    // The backend on the host's device: a renderer and the host's own quad, a 16 x 16 floor.
    let ctx = GpuContext::from_wgpu(instance, adapter, device.clone(), queue.clone())?;
    let mut palette = MaterialPalette::new();
    palette.push(Material::opaque(200, 120, 60))?;
    let mut renderer = Renderer::new(&ctx, &RendererConfig::new(W, H, ChunkSize::S16), &palette)?;
    let (position, width, height, face) = ([0, 0, 0], 16, 16, FaceDirection::PosY);
    let (ao, block) = ([3, 3, 3, 3], BlockId(1));
    let floor = [PackedQuad::encode(&PackedQuadFields {
        position,
        width,
        height,
        face,
        ao,
        block,
    })?];
    let mut layers = ChunkLayersData::default();
    layers.opaque_quads[usize::from(face.index())] = &floor;
    let coord = ChunkCoord::new(0, 0, 0);
    renderer.upload_chunk(&ChunkMeshData {
        coord,
        lod: 0,
        layers,
    })?;
    let eye = WorldPos::new(8, 6, 24);
    let camera = Camera::new(eye, glam::DVec3::splat(0.5), 0.0, -0.4, 1.0);
    renderer.set_camera(&camera);

    // Draw into the host's targets, depth converted to its projection (reversed-Z, infinite).
    let (f, near) = (1.0 / (camera.fov_y as f32 / 2.0).tan(), camera.near as f32);
    let aspect = W as f32 / H as f32;
    let projection = [
        [f / aspect, 0., 0., 0.],
        [0., f, 0., 0.],
        [0., 0., 0., -1.],
        [0., 0., near, 0.],
    ];
    let compare = wgpu::CompareFunction::Greater;
    let depth = Some(HostDepth {
        texture: &depth,
        projection,
        compare,
    });
    let targets = HostTargets {
        colour: &colour,
        depth,
    };
    let mut encoder = device.create_command_encoder(&Default::default());
    HostPass::new(&ctx)?.record(&ctx, &mut renderer, &mut encoder, &targets)?;
    queue.submit([encoder.finish()]);

    // What the renderer drew (its own readback of the frame it composited).
    let image = renderer.read_image()?;
    let drawn = image.depth.iter().filter(|&&d| d > 0.0).count();
    println!(
        "the backend drew {drawn} of {} pixels into the host's targets",
        W * H
    );
    (drawn > 0)
        .then_some(())
        .ok_or_else(|| "nothing drawn".into())
}
