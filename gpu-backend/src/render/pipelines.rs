//! Bind group layouts and pipelines of the renderer (created once per [`Renderer`]).
//!
//! | group | layout           | bindings                                                    |
//! | ----- | ---------------- | ----------------------------------------------------------- |
//! | 0     | `frame`          | 0 frame uniforms, 1 materials                              |
//! | 1     | `quads`          | 0 one page of the quad gigabuffer, 1 command records       |
//! | 1     | `smooth`         | 2 smooth-vertex page, 3 smooth-quad page, 4 smooth draws   |
//! | 1     | `gbuffer_read`   | 0 albedo, 1 normal, 2 depth (lighting pass)                 |
//! | 1     | `hdr_read`       | 3 hdr (tonemap pass)                                        |
//!
//! [`Renderer`]: super::Renderer

use wgpu::{
    BindGroupLayout, BindGroupLayoutEntry, BindingType, BlendState, BufferBindingType,
    ColorTargetState, CompareFunction, DepthStencilState, Device, RenderPipeline, ShaderModule,
    ShaderStages, TextureSampleType,
};

use super::targets::{ALBEDO_FORMAT, DEPTH_FORMAT, HDR_FORMAT, NORMAL_FORMAT, OUTPUT_FORMAT};
use crate::shaders::{DEFERRED, GBUFFER};

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
    /// Transparent greedy quads, lit and blended into the HDR target.
    pub quad_transparent: RenderPipeline,
    /// G-buffer to HDR.
    pub lighting: RenderPipeline,
    /// HDR to the sRGB output.
    pub tonemap: RenderPipeline,
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

fn texture_entry(binding: u32, sample_type: TextureSampleType) -> BindGroupLayoutEntry {
    BindGroupLayoutEntry {
        binding,
        visibility: ShaderStages::FRAGMENT,
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

/// One render pipeline of the renderer.
struct PipelineDesc<'a> {
    label: &'a str,
    module: &'a ShaderModule,
    vertex: &'a str,
    fragment: &'a str,
    groups: [&'a BindGroupLayout; 2],
    targets: &'a [Option<ColorTargetState>],
    depth: Option<DepthStencilState>,
    cull_back: bool,
}

fn pipeline(device: &Device, desc: PipelineDesc<'_>) -> RenderPipeline {
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

fn depth_state(write: bool) -> Option<DepthStencilState> {
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
    /// Compiles the renderer's shaders and builds its pipelines on `device`.
    pub fn new(device: &Device) -> Pipelines {
        let vertex = ShaderStages::VERTEX;
        let both = ShaderStages::VERTEX | ShaderStages::FRAGMENT;
        let storage = BufferBindingType::Storage { read_only: true };
        let frame_layout = layout(
            device,
            "frame",
            &[
                buffer_entry(0, both, BufferBindingType::Uniform),
                buffer_entry(1, both, storage),
            ],
        );
        let quad_layout = layout(
            device,
            "quads",
            &[
                buffer_entry(0, vertex, storage),
                buffer_entry(1, vertex, storage),
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
        let gbuffer_read_layout = layout(
            device,
            "gbuffer read",
            &[
                texture_entry(0, unfilterable),
                texture_entry(1, TextureSampleType::Uint),
                texture_entry(2, TextureSampleType::Depth),
            ],
        );
        let hdr_read_layout = layout(device, "hdr read", &[texture_entry(3, unfilterable)]);

        let geometry = GBUFFER.create_module(device);
        let fullscreen = DEFERRED.create_module(device);
        let gbuffer_targets = [Some(ALBEDO_FORMAT.into()), Some(NORMAL_FORMAT.into())];
        let quad_gbuffer = pipeline(
            device,
            PipelineDesc {
                label: "quads to gbuffer",
                module: &geometry,
                vertex: "vs_quad",
                fragment: "fs_gbuffer",
                groups: [&frame_layout, &quad_layout],
                targets: &gbuffer_targets,
                depth: depth_state(true),
                cull_back: true,
            },
        );
        let smooth_gbuffer = pipeline(
            device,
            PipelineDesc {
                label: "smooth to gbuffer",
                module: &geometry,
                vertex: "vs_smooth",
                fragment: "fs_gbuffer",
                groups: [&frame_layout, &smooth_layout],
                targets: &gbuffer_targets,
                depth: depth_state(true),
                cull_back: true,
            },
        );
        let quad_transparent = pipeline(
            device,
            PipelineDesc {
                label: "transparent quads",
                module: &geometry,
                vertex: "vs_quad_transparent",
                fragment: "fs_transparent",
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
        let lighting = pipeline(
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
        );
        let tonemap = pipeline(
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
        );
        Pipelines {
            frame_layout,
            quad_layout,
            smooth_layout,
            gbuffer_read_layout,
            hdr_read_layout,
            quad_gbuffer,
            smooth_gbuffer,
            quad_transparent,
            lighting,
            tonemap,
        }
    }
}
