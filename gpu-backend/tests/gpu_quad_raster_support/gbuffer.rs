//! Reading the renderer's G-buffer back (a compute pass copies its textures' texels into a
//! buffer: the targets cannot be copied from), and what its texels say: the surface's face,
//! block, depth and AO byte, comparable with a visibility word.

use gpu_backend::GpuContext;
use gpu_backend::readback::read_buffer;
use gpu_backend::render::RenderTargets;

/// One pixel of the G-buffer.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GTexel {
    /// The octahedral normal (`oct32_encode`).
    pub oct: u32,
    /// The block id.
    pub block: u32,
    /// Reversed-Z depth (`near / view depth`; 0 where nothing was drawn).
    pub depth: f32,
    /// Albedo's alpha (AO / 3) as its 8-bit unorm byte.
    pub ao8: u32,
}

const SHADER: &str = r"
@group(0) @binding(0) var albedo: texture_2d<f32>;
@group(0) @binding(1) var normal: texture_2d<u32>;
@group(0) @binding(2) var depth: texture_depth_2d;
@group(0) @binding(3) var<storage, read_write> texels: array<vec4<u32>>;

@compute @workgroup_size(8, 8)
fn copy_texels(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(normal);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = vec2<i32>(id.xy);
    let n = textureLoad(normal, p, 0);
    let d = textureLoad(depth, p, 0);
    let a = textureLoad(albedo, p, 0).a;
    texels[id.y * size.x + id.x] = vec4<u32>(n.x, n.y, bitcast<u32>(d), u32(round(a * 255.0)));
}
";

fn texture_entry(binding: u32, sample_type: wgpu::TextureSampleType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

/// The G-buffer texels of `targets`, row-major (blocks until the GPU is done).
pub(crate) fn read_gbuffer(ctx: &GpuContext, targets: &RenderTargets) -> Vec<GTexel> {
    let device = &ctx.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("gbuffer readback"),
        source: wgpu::ShaderSource::Wgsl(SHADER.into()),
    });
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("gbuffer readback"),
        entries: &[
            texture_entry(0, wgpu::TextureSampleType::Float { filterable: false }),
            texture_entry(1, wgpu::TextureSampleType::Uint),
            texture_entry(2, wgpu::TextureSampleType::Depth),
            wgpu::BindGroupLayoutEntry {
                binding: 3,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: false },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
        ],
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("gbuffer readback"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("gbuffer readback"),
        layout: Some(&pipeline_layout),
        module: &module,
        entry_point: Some("copy_texels"),
        compilation_options: Default::default(),
        cache: None,
    });
    let (width, height) = (targets.width, targets.height);
    let texels = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("gbuffer texels"),
        size: u64::from(width * height) * 16,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("gbuffer readback"),
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&targets.albedo),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&targets.normal),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::TextureView(&targets.depth),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: texels.as_entire_binding(),
            },
        ],
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups(width.div_ceil(8), height.div_ceil(8), 1);
    }
    ctx.queue.submit([encoder.finish()]);
    let bytes = read_buffer(device, &ctx.queue, &texels, 0, texels.size()).expect("readback");
    bytemuck::pod_collect_to_vec(&bytes)
}

/// The face (`FaceDirection` index: +X, -X, +Y, -Y, +Z, -Z) whose normal an `oct32_encode`d
/// normal is closest to.
pub(crate) fn oct_face(oct: u32) -> u32 {
    let x = f32::from((oct & 0xffff) as u16 as i16) / 32767.0;
    let y = f32::from((oct >> 16) as u16 as i16) / 32767.0;
    let z = 1.0 - x.abs() - y.abs();
    let (x, y) = if z < 0.0 {
        ((1.0 - y.abs()) * x.signum(), (1.0 - x.abs()) * y.signum())
    } else {
        (x, y)
    };
    let n = [x, y, z];
    let axis = (0..3)
        .max_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
        .expect("three axes");
    axis as u32 * 2 + u32::from(n[axis] < 0.0)
}
