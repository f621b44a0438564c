//! glTF props in a host's own wgpu setup: the host creates the device and its targets, the
//! backend adopts the device, loads a glTF file (`voxel_scene::props`), uploads the model once
//! and places instances by handle (create, move, hide, delete); each frame the backend culls
//! every instance on the GPU and draws one indexed indirect draw per batch into the host's
//! colour and depth targets.
//!
//! `cargo run -p examples --example host_props -- ../shared/data/gltf/Duck.glb`

use gpu_backend::device::{optional_features, required_limits};
use gpu_backend::render::{HostDepth, HostPass, HostTargets};
use gpu_backend::{GpuContext, Renderer, RendererConfig};
use render_model::camera::Camera;
use render_model::props::PropPlacement;
use voxel_core::{ChunkSize, Material, MaterialPalette, WorldPos};
use voxel_scene::props::{PropLimits, load_prop_file};
use wgpu::{TextureFormat as F, TextureUsages as U};

const W: u32 = 256;
const H: u32 = 192;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args()
        .nth(1)
        .ok_or("usage: host_props FILE.glb")?;
    let model = load_prop_file(path.as_ref(), &PropLimits::default())?;
    for w in &model.warnings {
        eprintln!("host_props: {path}: warning: {w}");
    }

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
        device.create_texture(&wgpu::TextureDescriptor {
            label: None,
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let colour = target(F::Rgba8UnormSrgb, U::RENDER_ATTACHMENT);
    let depth = target(F::Depth32Float, U::RENDER_ATTACHMENT);

    // The backend on the host's device; the model uploaded once, three instances by handle.
    let ctx = GpuContext::from_wgpu(instance, adapter, device.clone(), queue.clone())?;
    let mut palette = MaterialPalette::new();
    palette.push(Material::opaque(200, 120, 60))?;
    let mut renderer = Renderer::new(&ctx, &RendererConfig::new(W, H, ChunkSize::S16), &palette)?;
    let duck = renderer.add_prop_model(&model)?;
    let identity = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    let at = |x| PropPlacement::new(WorldPos::new(x, 0, 0), identity);
    let left = renderer.create_prop(duck, at(-3)?)?;
    let middle = renderer.create_prop(duck, at(0)?)?;
    let right = renderer.create_prop(duck, at(3)?)?;
    renderer.set_prop_placement(left, at(-2)?)?;
    renderer.set_prop_visible(right, false)?;
    renderer.delete_prop(middle)?;
    // A deleted handle is refused by name.
    assert!(renderer.set_prop_visible(middle, true).is_err());

    let camera = Camera::new(
        WorldPos::new(0, 2, 6),
        glam::DVec3::splat(0.5),
        0.0,
        -0.2,
        1.0,
    );
    renderer.set_camera(&camera);
    let (f, near) = (1.0 / (camera.fov_y as f32 / 2.0).tan(), camera.near as f32);
    let aspect = W as f32 / H as f32;
    let projection = [
        [f / aspect, 0., 0., 0.],
        [0., f, 0., 0.],
        [0., 0., 0., -1.],
        [0., 0., near, 0.],
    ];
    let targets = HostTargets {
        colour: &colour,
        depth: Some(HostDepth {
            texture: &depth,
            projection,
            compare: wgpu::CompareFunction::Greater,
        }),
    };
    let mut encoder = device.create_command_encoder(&Default::default());
    HostPass::new(&ctx)?.record(&ctx, &mut renderer, &mut encoder, &targets)?;
    queue.submit([encoder.finish()]);

    let image = renderer.read_image()?;
    let drawn = image.depth.iter().filter(|&&d| d > 0.0).count();
    let instances = renderer.read_props_drawn()?;
    println!(
        "the backend drew {instances} prop instance(s), {drawn} pixels, into the host's targets"
    );
    (drawn > 0 && instances > 0)
        .then_some(())
        .ok_or_else(|| "no prop drawn".into())
}
