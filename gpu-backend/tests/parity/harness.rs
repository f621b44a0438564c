//! Runs one `decode_*` entry point of the parity shader over an input array and reads the
//! output words back.

use gpu_backend::GpuContext;
use gpu_backend::readback::read_buffer;
use gpu_backend::shaders::ShaderSpec;
use wgpu::util::{BufferInitDescriptor, DeviceExt};

/// Written into every output word before the dispatch, so a word the shader never writes
/// shows up (zero would hide behind fields whose value is 0).
pub(crate) const UNWRITTEN: u32 = 0xdead_beef;

/// A context with the parity shader module.
pub(crate) struct Harness {
    pub ctx: GpuContext,
    module: wgpu::ShaderModule,
}

/// One entry point: its name, the binding of its input array, its output stride in words, and
/// whether it reads the `params` uniform (the unorm extent).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Entry {
    pub name: &'static str,
    pub binding: u32,
    pub stride: usize,
    pub uses_extent: bool,
}

impl Harness {
    pub(crate) fn new(ctx: GpuContext, shader: &ShaderSpec) -> Harness {
        let module = shader.create_module(&ctx.device);
        Harness { ctx, module }
    }

    /// A module from any source on the same device (for deliberately broken copies).
    pub(crate) fn module(&self, label: &str, source: &str) -> wgpu::ShaderModule {
        self.ctx
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(label),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            })
    }

    /// Decodes `count` elements of `input` (their bytes) with `entry` of the parity shader;
    /// returns `count * entry.stride` words.
    pub(crate) fn run(&self, entry: Entry, input: &[u8], count: usize, extent: f32) -> Vec<u32> {
        self.run_module(&self.module, entry, input, count, extent)
    }

    /// [`run`](Self::run) with another module that has the same entry points.
    pub(crate) fn run_module(
        &self,
        module: &wgpu::ShaderModule,
        entry: Entry,
        input: &[u8],
        count: usize,
        extent: f32,
    ) -> Vec<u32> {
        let device = &self.ctx.device;
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry.name),
            layout: None,
            module,
            entry_point: Some(entry.name),
            compilation_options: Default::default(),
            cache: None,
        });
        let words = count * entry.stride;
        let out = device.create_buffer_init(&BufferInitDescriptor {
            label: Some("parity out"),
            contents: bytemuck::cast_slice(&vec![UNWRITTEN; words]),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let input = device.create_buffer_init(&BufferInitDescriptor {
            label: Some("parity in"),
            contents: input,
            usage: wgpu::BufferUsages::STORAGE,
        });
        let mut params = [0u8; 16];
        params[..4].copy_from_slice(&extent.to_le_bytes());
        let params = device.create_buffer_init(&BufferInitDescriptor {
            label: Some("parity params"),
            contents: &params,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let mut entries = vec![
            wgpu::BindGroupEntry {
                binding: 0,
                resource: out.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: entry.binding,
                resource: input.as_entire_binding(),
            },
        ];
        if entry.uses_extent {
            entries.push(wgpu::BindGroupEntry {
                binding: 1,
                resource: params.as_entire_binding(),
            });
        }
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(entry.name),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &entries,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups((count as u32).div_ceil(64), 1, 1);
        }
        self.ctx.queue.submit([encoder.finish()]);
        let bytes = read_buffer(device, &self.ctx.queue, &out, 0, out.size()).expect("readback");
        bytemuck::cast_slice(&bytes).to_vec()
    }
}
