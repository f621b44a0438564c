//! Helpers of the depth pyramid's GPU tests: a depth image rendered into a `Depth32Float`
//! texture and read back, random depth images and visibility buffers, and the `hiz_probe`
//! harness with its query and answer structs.

use gpu_backend::GpuContext;
use gpu_backend::readback::read_whole;
use gpu_backend::render::passes::hiz::DepthPyramid;
use gpu_backend::shaders::HIZ_PROBE;
use wgpu::util::DeviceExt;

use crate::common::Rng;

/// Writes `frag_depth` from a storage buffer, one value per pixel.
const FILL_WGSL: &str = "
@group(0) @binding(0) var<storage, read> depths: array<f32>;
@group(0) @binding(1) var<uniform> width: vec4<u32>;

@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs(@builtin(position) p: vec4<f32>) -> @builtin(frag_depth) f32 {
    return depths[u32(p.y) * width.x + u32(p.x)];
}
";

/// The depth-fill pipeline.
pub(crate) struct Fill {
    pipeline: wgpu::RenderPipeline,
}

impl Fill {
    pub(crate) fn new(device: &wgpu::Device) -> Fill {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("depth fill"),
            source: wgpu::ShaderSource::Wgsl(FILL_WGSL.into()),
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("depth fill"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: wgpu::TextureFormat::Depth32Float,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[],
            }),
            multiview_mask: None,
            cache: None,
        });
        Fill { pipeline }
    }

    /// Renders `values` (`width x height`, row-major) into `view`.
    pub(crate) fn run(
        &self,
        ctx: &GpuContext,
        view: &wgpu::TextureView,
        width: u32,
        values: &[f32],
    ) {
        let device = &ctx.device;
        let depths = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("depth values"),
            contents: bytemuck::cast_slice(values),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("depth width"),
            contents: bytemuck::cast_slice(&[width, 0, 0, 0]),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("depth fill"),
            layout: &self.pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: depths.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: uniform.as_entire_binding(),
                },
            ],
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("depth fill"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(0.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.draw(0..3, 0..1);
        }
        ctx.queue.submit([encoder.finish()]);
    }
}

/// A `Depth32Float` texture like the renderer's (`RENDER_ATTACHMENT | TEXTURE_BINDING |
/// COPY_SRC`) and its view.
pub(crate) fn depth_target(
    ctx: &GpuContext,
    width: u32,
    height: u32,
) -> (wgpu::Texture, wgpu::TextureView) {
    let texture = ctx.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("depth"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Depth32Float,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    (texture, view)
}

/// The depth texture's values, row-major.
pub(crate) fn read_depth(ctx: &GpuContext, texture: &wgpu::Texture) -> Vec<f32> {
    let (width, height) = (texture.width(), texture.height());
    let row = (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
        * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("depth readback"),
        size: u64::from(row) * u64::from(height),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    encoder.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::DepthOnly,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: None,
            },
        },
        texture.size(),
    );
    ctx.queue.submit([encoder.finish()]);
    let words: Vec<f32> = read_whole(&ctx.device, &ctx.queue, &buffer).expect("depth readback");
    words
        .chunks(row as usize / 4)
        .flat_map(|r| &r[..width as usize])
        .copied()
        .collect()
}

/// A visibility buffer holding `words` (`STORAGE | COPY_DST`).
pub(crate) fn visibility_buffer(ctx: &GpuContext, words: &[u64]) -> wgpu::Buffer {
    ctx.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("visibility"),
            contents: bytemuck::cast_slice(words),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        })
}

/// A reversed-Z depth in `(0, 1]`, in steps of 2^-24 (exact in `f32`).
pub(crate) fn unit_depth(rng: &mut Rng) -> f32 {
    (1 + rng.below(1 << 24)) as f32 / (1 << 24) as f32
}

/// A random depth image: blocks of `tile` pixels (1 = noise) of sky (one in six) or a depth,
/// so that whole rectangles can be behind or in front of everything.
pub(crate) fn random_depth(rng: &mut Rng, width: u32, height: u32, tile: u32) -> Vec<f32> {
    let tiles_x = width.div_ceil(tile);
    let tiles: Vec<f32> = (0..tiles_x * height.div_ceil(tile))
        .map(|_| {
            if rng.below(6) == 0 {
                0.0
            } else {
                unit_depth(rng)
            }
        })
        .collect();
    (0..width * height)
        .map(|p| tiles[((p / width / tile) * tiles_x + p % width / tile) as usize])
        .collect()
}

/// Splats on about a third of the pixels, nearer or farther than the depth there, with
/// random payloads; zero (nothing) elsewhere.
pub(crate) fn random_visibility(rng: &mut Rng, depth: &[f32]) -> Vec<u64> {
    depth
        .iter()
        .map(|&d| {
            if rng.below(3) != 0 {
                return 0;
            }
            let splat = match rng.below(3) {
                0 => d,
                1 => unit_depth(rng),
                _ => d * 0.5,
            };
            (u64::from(splat.to_bits()) << 32) | u64::from(rng.next_u32())
        })
        .collect()
}

/// Asserts that `got` equals `want` level by level, texel by texel.
pub(crate) fn assert_levels_equal(got: &[Vec<f32>], want: &[Vec<f32>], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: level count");
    for (m, (g, w)) in got.iter().zip(want).enumerate() {
        assert_eq!(g.len(), w.len(), "{what}: level {m} length");
        if let Some(i) = (0..g.len()).find(|&i| g[i] != w[i]) {
            let differ = (0..g.len()).filter(|&i| g[i] != w[i]).count();
            panic!(
                "{what}: level {m} differs at {differ} texels, first at index {i}: GPU {} \
                 (bits {:#x}), reference {} (bits {:#x})",
                g[i],
                g[i].to_bits(),
                w[i],
                w[i].to_bits()
            );
        }
    }
}

/// `hiz_probe.wgsl`'s query, 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct Query {
    pub rect_min: [f32; 2],
    pub rect_max: [f32; 2],
    pub nearest_depth: f32,
    pub pad: [u32; 3],
}

/// `hiz_probe.wgsl`'s answer, 32 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct Answer {
    pub visible: u32,
    pub level: u32,
    pub farthest_bits: u32,
    pub pixels_lo: u32,
    pub pixels_hi: u32,
    pub pad: [u32; 3],
}

/// Runs `queries` through `hiz_probe` against `pyramid`.
pub(crate) fn probe(ctx: &GpuContext, pyramid: &DepthPyramid, queries: &[Query]) -> Vec<Answer> {
    let device = &ctx.device;
    let storage = |binding: u32, read_only: bool| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("hiz probe"),
        entries: &[
            DepthPyramid::layout_entry(0, wgpu::ShaderStages::COMPUTE),
            storage(1, true),
            storage(2, false),
        ],
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("hiz probe"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let module = HIZ_PROBE.create_module(device);
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("hiz probe"),
        layout: Some(&pipeline_layout),
        module: &module,
        entry_point: Some("hiz_probe"),
        compilation_options: Default::default(),
        cache: None,
    });
    let query_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("hiz queries"),
        contents: bytemuck::cast_slice(queries),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let answers = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("hiz answers"),
        size: (queries.len() * size_of::<Answer>()) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("hiz probe"),
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: pyramid.binding_resource(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: query_buffer.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: answers.as_entire_binding(),
            },
        ],
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.dispatch_workgroups((queries.len() as u32).div_ceil(64), 1, 1);
    }
    ctx.queue.submit([encoder.finish()]);
    read_whole(device, &ctx.queue, &answers).expect("answers readback")
}

/// A random rectangle on (or around, or far off) a `width x height` screen.
pub(crate) fn random_rect(rng: &mut Rng, width: u32, height: u32) -> ([f32; 2], [f32; 2]) {
    let (w, h) = (width as f32, height as f32);
    let coordinate = |rng: &mut Rng, size: f32| {
        let unit = rng.below(1 << 20) as f32 / (1 << 20) as f32;
        -0.25 * size - 4.0 + unit * (1.5 * size + 8.0)
    };
    let a = [coordinate(rng, w), coordinate(rng, h)];
    let extent = |rng: &mut Rng| match rng.below(4) {
        0 => rng.below(3) as f32 + 0.5 * (rng.below(2) as f32),
        1 => rng.below(17) as f32 + rng.below(1024) as f32 / 1024.0,
        2 => rng.below(129) as f32,
        _ => rng.below(4 * (width.max(height) + 1)) as f32,
    };
    let b = [a[0] + extent(rng), a[1] + extent(rng)];
    match rng.below(16) {
        // Inverted corners.
        0 => (b, a),
        // Far off screen, or unbounded.
        1 => ([a[0] - 1e9, a[1]], [b[0] + 1e9, f32::INFINITY]),
        2 => ([w + 1e6, a[1]], [w + 2e6, b[1]]),
        3 => ([a[0], -1e7], [b[0], -5e6]),
        _ => (a, b),
    }
}
