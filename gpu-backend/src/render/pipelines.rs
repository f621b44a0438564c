//! Bind group layouts and pipelines of the renderer (created once per [`Renderer`]).
//!
//! | group | layout           | bindings                                                    |
//! | ----- | ---------------- | ----------------------------------------------------------- |
//! | 0     | `frame`          | 0 frame uniforms, 1 materials                              |
//! | 1     | `quads`          | 0 one page of the quad gigabuffer, 1 command records, 9 the opaque visibility buffer (transparent pass) |
//! | 1     | `smooth`         | 2 smooth-vertex page, 3 smooth-quad page, 4 smooth draws   |
//! | 1     | `gbuffer_read`   | 0 albedo, 1 normal, 2 depth, 4 and 5 far visibility buffers, 6 hdr out (compute) (lighting pass) |
//! | 1     | `hdr_read`       | 3 hdr, 7 output out (compute) (tonemap pass)                |
//!
//! The full-screen passes run as fragment passes or as compute passes ([`FullscreenPath`]);
//! only the chosen path's pipelines are built.
//!
//! [`Renderer`]: super::Renderer

use wgpu::{
    BindGroupLayout, BindGroupLayoutEntry, BindingType, BlendState, BufferBindingType,
    ColorTargetState, CompareFunction, DepthStencilState, Device, RenderPipeline, ShaderModule,
    ShaderStages, TextureSampleType,
};

use super::targets::{
    ALBEDO_FORMAT, DEPTH_FORMAT, HDR_FORMAT, NORMAL_FORMAT, OUTPUT_FORMAT, OUTPUT_STORAGE_FORMAT,
};
use crate::shaders::{DEFERRED, GBUFFER};

/// How the full-screen passes (lighting, tonemap) run: the same per-pixel function either way.
/// On compute-heavy GPUs (the H100 rasterises through a few units) compute is faster; see
/// BENCHMARKS.md for the measured pair.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FullscreenPath {
    /// A full-screen triangle per pass.
    Fragment,
    /// 8 x 8-pixel workgroups writing storage textures.
    #[default]
    Compute,
}

/// The lighting and tonemap pipelines of one [`FullscreenPath`].
#[derive(Debug)]
pub enum FullscreenPipelines {
    /// Fragment pipelines.
    Fragment {
        /// G-buffer to HDR.
        lighting: RenderPipeline,
        /// HDR to the sRGB output.
        tonemap: RenderPipeline,
    },
    /// Compute pipelines.
    Compute {
        /// G-buffer to HDR.
        lighting: wgpu::ComputePipeline,
        /// HDR to the output.
        tonemap: wgpu::ComputePipeline,
    },
}

/// Every layout and pipeline the renderer draws with.
#[derive(Debug)]
pub struct Pipelines {
    /// Group 0 of every pipeline.
    pub frame_layout: BindGroupLayout,
    /// Group 1 of the quad pipelines.
    pub quad_layout: BindGroupLayout,
    /// Group 1 of the smooth pipeline.
    pub smooth_layout: BindGroupLayout,
    /// Group 1 of the lighting pipeline.
    pub gbuffer_read_layout: BindGroupLayout,
    /// Group 1 of the tonemap pipeline.
    pub hdr_read_layout: BindGroupLayout,
    /// Opaque greedy quads into the G-buffer.
    pub quad_gbuffer: RenderPipeline,
    /// Smooth quads into the G-buffer.
    pub smooth_gbuffer: RenderPipeline,
    /// The wireframe view of `quad_gbuffer`: only the quads' edges.
    pub quad_gbuffer_wire: RenderPipeline,
    /// The wireframe view of `smooth_gbuffer`.
    pub smooth_gbuffer_wire: RenderPipeline,
    /// Transparent greedy quads, lit and blended into the HDR target.
    pub quad_transparent: RenderPipeline,
    /// Lighting and tonemap.
    pub fullscreen: FullscreenPipelines,
}

fn buffer_entry(
    binding: u32,
    visibility: ShaderStages,
    ty: BufferBindingType,
) -> BindGroupLayoutEntry {
    BindGroupLayoutEntry {
        binding,
        visibility,
        ty: BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn texture_entry(
    binding: u32,
    visibility: ShaderStages,
    sample_type: TextureSampleType,
) -> BindGroupLayoutEntry {
    BindGroupLayoutEntry {
        binding,
        visibility,
        ty: BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

fn layout(device: &Device, label: &str, entries: &[BindGroupLayoutEntry]) -> BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries,
    })
}

/// One render pipeline of the renderer (also built by the raster far draws).
pub(crate) struct PipelineDesc<'a> {
    pub(crate) label: &'a str,
    pub(crate) module: &'a ShaderModule,
    pub(crate) vertex: &'a str,
    pub(crate) fragment: &'a str,
    pub(crate) groups: [&'a BindGroupLayout; 2],
    pub(crate) targets: &'a [Option<ColorTargetState>],
    pub(crate) depth: Option<DepthStencilState>,
    pub(crate) cull_back: bool,
}

/// The render pipeline `desc` describes (no vertex buffers: every pass pulls its vertices).
pub(crate) fn pipeline(device: &Device, desc: PipelineDesc<'_>) -> RenderPipeline {
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(desc.label),
        bind_group_layouts: &[Some(desc.groups[0]), Some(desc.groups[1])],
        immediate_size: 0,
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(desc.label),
        layout: Some(&layout),
        vertex: wgpu::VertexState {
            module: desc.module,
            entry_point: Some(desc.vertex),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState {
            front_face: wgpu::FrontFace::Ccw,
            cull_mode: desc.cull_back.then_some(wgpu::Face::Back),
            ..Default::default()
        },
        depth_stencil: desc.depth,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module: desc.module,
            entry_point: Some(desc.fragment),
            compilation_options: Default::default(),
            targets: desc.targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The renderer's depth test (reversed-Z), writing depth or not.
pub(crate) fn depth_state(write: bool) -> Option<DepthStencilState> {
    Some(DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(write),
        // Reversed-Z: nearer is greater.
        depth_compare: Some(CompareFunction::Greater),
        stencil: Default::default(),
        bias: Default::default(),
    })
}

impl Pipelines {
    /// Compiles the renderer's shaders and builds its pipelines on `device`, the full-screen
    /// passes for `path`.
    pub fn new(device: &Device, path: FullscreenPath) -> Pipelines {
        let vertex = ShaderStages::VERTEX;
        let all = ShaderStages::VERTEX | ShaderStages::FRAGMENT | ShaderStages::COMPUTE;
        let screen = match path {
            FullscreenPath::Fragment => ShaderStages::FRAGMENT,
            FullscreenPath::Compute => ShaderStages::COMPUTE,
        };
        let storage = BufferBindingType::Storage { read_only: true };
        let frame_layout = layout(
            device,
            "frame",
            &[
                buffer_entry(0, all, BufferBindingType::Uniform),
                buffer_entry(1, all, storage),
            ],
        );
        let quad_layout = layout(
            device,
            "quads",
            &[
                buffer_entry(0, vertex, storage),
                buffer_entry(1, vertex, storage),
                buffer_entry(9, ShaderStages::FRAGMENT, storage),
            ],
        );
        let smooth_layout = layout(
            device,
            "smooth",
            &[
                buffer_entry(2, vertex, storage),
                buffer_entry(3, vertex, storage),
                buffer_entry(4, vertex, storage),
            ],
        );
        let unfilterable = TextureSampleType::Float { filterable: false };
        let storage_texture = |binding, format| BindGroupLayoutEntry {
            binding,
            visibility: ShaderStages::COMPUTE,
            ty: BindingType::StorageTexture {
                access: wgpu::StorageTextureAccess::WriteOnly,
                format,
                view_dimension: wgpu::TextureViewDimension::D2,
            },
            count: None,
        };
        let mut gbuffer_read = vec![
            texture_entry(0, screen, unfilterable),
            texture_entry(1, screen, TextureSampleType::Uint),
            texture_entry(2, screen, TextureSampleType::Depth),
            buffer_entry(4, screen, storage),
            buffer_entry(5, screen, storage),
        ];
        let mut hdr_read = vec![texture_entry(3, screen, unfilterable)];
        if path == FullscreenPath::Compute {
            gbuffer_read.push(storage_texture(6, HDR_FORMAT));
            hdr_read.push(storage_texture(7, OUTPUT_STORAGE_FORMAT));
        }
        let gbuffer_read_layout = layout(device, "gbuffer read", &gbuffer_read);
        let hdr_read_layout = layout(device, "hdr read", &hdr_read);

        let geometry = GBUFFER.create_module(device);
        let fullscreen = DEFERRED.create_module(device);
        let gbuffer_targets = [Some(ALBEDO_FORMAT.into()), Some(NORMAL_FORMAT.into())];
        // The opaque surfaces into the G-buffer: depth written, back faces culled (the
        // wireframe views too: they show what the filled views show).
        let gbuffer = |label, vertex, fragment, surface_layout| {
            pipeline(
                device,
                PipelineDesc {
                    label,
                    module: &geometry,
                    vertex,
                    fragment,
                    groups: [&frame_layout, surface_layout],
                    targets: &gbuffer_targets,
                    depth: depth_state(true),
                    cull_back: true,
                },
            )
        };
        let quad_gbuffer = gbuffer("quads to gbuffer", "vs_quad", "fs_gbuffer", &quad_layout);
        let smooth_gbuffer = gbuffer(
            "smooth to gbuffer",
            "vs_smooth",
            "fs_gbuffer",
            &smooth_layout,
        );
        let quad_gbuffer_wire = gbuffer(
            "quads to gbuffer, wireframe",
            "vs_quad_wire",
            "fs_gbuffer_wire",
            &quad_layout,
        );
        let smooth_gbuffer_wire = gbuffer(
            "smooth to gbuffer, wireframe",
            "vs_smooth_wire",
            "fs_gbuffer_wire",
            &smooth_layout,
        );
        let quad_transparent = pipeline(
            device,
            PipelineDesc {
                label: "transparent quads",
                module: &geometry,
                vertex: "vs_quad_transparent",
                fragment: "fs_transparent_over_visibility",
                groups: [&frame_layout, &quad_layout],
                targets: &[Some(ColorTargetState {
                    format: HDR_FORMAT,
                    blend: Some(BlendState::ALPHA_BLENDING),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
                depth: depth_state(false),
                cull_back: true,
            },
        );
        let fullscreen = match path {
            FullscreenPath::Fragment => FullscreenPipelines::Fragment {
                lighting: pipeline(
                    device,
                    PipelineDesc {
                        label: "lighting",
                        module: &fullscreen,
                        vertex: "vs_fullscreen",
                        fragment: "fs_lighting",
                        groups: [&frame_layout, &gbuffer_read_layout],
                        targets: &[Some(HDR_FORMAT.into())],
                        depth: None,
                        cull_back: false,
                    },
                ),
                tonemap: pipeline(
                    device,
                    PipelineDesc {
                        label: "tonemap",
                        module: &fullscreen,
                        vertex: "vs_fullscreen",
                        fragment: "fs_tonemap",
                        groups: [&frame_layout, &hdr_read_layout],
                        targets: &[Some(OUTPUT_FORMAT.into())],
                        depth: None,
                        cull_back: false,
                    },
                ),
            },
            FullscreenPath::Compute => {
                let compute = |label, read: &BindGroupLayout, entry| {
                    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                        label: Some(label),
                        bind_group_layouts: &[Some(&frame_layout), Some(read)],
                        immediate_size: 0,
                    });
                    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                        label: Some(label),
                        layout: Some(&layout),
                        module: &fullscreen,
                        entry_point: Some(entry),
                        compilation_options: Default::default(),
                        cache: None,
                    })
                };
                FullscreenPipelines::Compute {
                    lighting: compute("lighting", &gbuffer_read_layout, "cs_lighting"),
                    tonemap: compute("tonemap", &hdr_read_layout, "cs_tonemap"),
                }
            }
        };
        Pipelines {
            frame_layout,
            quad_layout,
            smooth_layout,
            gbuffer_read_layout,
            hdr_read_layout,
            quad_gbuffer,
            smooth_gbuffer,
            quad_gbuffer_wire,
            smooth_gbuffer_wire,
            quad_transparent,
            fullscreen,
        }
    }
}
