//! What the passes share: the bind group layouts of the surface pipelines, the frame uniforms
//! and materials (group 0 of every renderer pipeline), the quad index buffer, the bind group
//! cache, and how a render pipeline is built.
//!
//! | group | layout   | bindings                                                             |
//! | ----- | -------- | -------------------------------------------------------------------- |
//! | 0     | `frame`  | 0 frame uniforms, 1 materials                                        |
//! | 1     | `quads`  | 0 one page of the quad gigabuffer, 1 command records, 9 the opaque visibility buffer (transparent pass) |
//! | 1     | `smooth` | 2 smooth-vertex page, 3 smooth-quad page, 4 smooth draws             |
//!
//! The full-screen passes' groups 1 are their own (`lighting`, `tonemap`).

use wgpu::{
    BindGroup, BindGroupLayout, BindGroupLayoutEntry, BindingType, Buffer, BufferBindingType,
    BufferUsages, ColorTargetState, CompareFunction, DepthStencilState, Device, RenderPipeline,
    ShaderModule, ShaderStages, TextureSampleType,
};

use render_model::frame::FrameUniforms;
use render_model::materials::gpu_materials;
use voxel_core::MaterialPalette;
use voxel_core::formats::DataKind;

use super::targets::DEPTH_FORMAT;
use crate::bind::{BindGroupCache, buffer_entry};
use crate::device::alloc::AllocError;
use crate::residency::Residency;

/// The resources every pass of the renderer shares (see the [module docs](self)).
#[derive(Debug)]
pub struct Shared {
    device: Device,
    /// Group 0 of every renderer pipeline.
    pub frame_layout: BindGroupLayout,
    /// Group 1 of the quad pipelines (G-buffer and transparent quads).
    pub quad_layout: BindGroupLayout,
    /// Group 1 of the smooth pipelines.
    pub smooth_layout: BindGroupLayout,
    /// Group 2 of the transparent pipelines (quads and raster far blocks): the opaque depth
    /// behind them, which tints volumes.
    pub opaque_depth_layout: BindGroupLayout,
    /// The frame uniforms (`FrameUniforms`), copied in at the start of each frame.
    pub frame_uniforms: Buffer,
    materials: Buffer,
    material_count: u32,
    /// The shared quad index buffer (`render_model::cull::quad_indices`).
    pub quad_indices: Buffer,
    /// Bound where a pass reads a visibility buffer the frame does not have.
    pub no_visibility: Buffer,
    /// The frame's bind groups, made once per set of resources.
    pub(crate) bind_cache: BindGroupCache,
}

impl Shared {
    /// The shared resources on `device`: layouts, the frame uniforms, `palette`'s materials and
    /// a quad index buffer of `max_quads_per_draw` quads.
    pub fn new(
        device: &Device,
        palette: &MaterialPalette,
        max_quads_per_draw: u32,
    ) -> Result<Shared, AllocError> {
        let vertex = ShaderStages::VERTEX;
        let all = ShaderStages::VERTEX | ShaderStages::FRAGMENT | ShaderStages::COMPUTE;
        let storage = BufferBindingType::Storage { read_only: true };
        let frame_layout = bind_layout(
            device,
            "frame",
            &[
                buffer_layout_entry(0, all, BufferBindingType::Uniform),
                buffer_layout_entry(1, all, storage),
            ],
        );
        let quad_layout = bind_layout(
            device,
            "quads",
            &[
                buffer_layout_entry(0, vertex, storage),
                buffer_layout_entry(1, vertex, storage),
                buffer_layout_entry(9, ShaderStages::FRAGMENT, storage),
            ],
        );
        let smooth_layout = bind_layout(
            device,
            "smooth",
            &[
                buffer_layout_entry(2, vertex, storage),
                buffer_layout_entry(3, vertex, storage),
                buffer_layout_entry(4, vertex, storage),
            ],
        );
        let opaque_depth_layout = bind_layout(
            device,
            "transparent depth",
            &[texture_layout_entry(
                0,
                ShaderStages::FRAGMENT,
                TextureSampleType::Depth,
            )],
        );
        let indices = render_model::cull::quad_indices(max_quads_per_draw);
        let quad_indices = crate::device::alloc::create_buffer_init(
            device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("quad indices"),
                contents: bytemuck::cast_slice(&indices),
                usage: BufferUsages::INDEX,
            },
        )?;
        let no_visibility = crate::device::alloc::create_buffer(
            device,
            &wgpu::BufferDescriptor {
                label: Some("no far visibility"),
                size: 16,
                usage: BufferUsages::STORAGE,
                mapped_at_creation: false,
            },
        )?;
        let (materials, material_count) = material_buffer(device, palette)?;
        let frame_uniforms = crate::device::alloc::create_buffer(
            device,
            &wgpu::BufferDescriptor {
                label: Some("frame uniforms"),
                size: size_of::<FrameUniforms>() as u64,
                usage: BufferUsages::UNIFORM | BufferUsages::COPY_DST,
                mapped_at_creation: false,
            },
        )?;
        Ok(Shared {
            device: device.clone(),
            frame_layout,
            quad_layout,
            smooth_layout,
            opaque_depth_layout,
            frame_uniforms,
            materials,
            material_count,
            quad_indices,
            no_visibility,
            bind_cache: BindGroupCache::default(),
        })
    }

    /// Replaces the material palette (kept as it was when the device refuses the new one).
    pub fn set_palette(&mut self, palette: &MaterialPalette) -> Result<(), AllocError> {
        (self.materials, self.material_count) = material_buffer(&self.device, palette)?;
        Ok(())
    }

    /// Materials uploaded (larger block ids read entry 0).
    pub fn material_count(&self) -> u32 {
        self.material_count
    }

    /// Group 0 of every renderer pipeline: the frame uniforms and the materials.
    pub fn frame_group(&self) -> BindGroup {
        self.bind_cache.get(
            &self.device,
            "frame",
            &self.frame_layout,
            &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: self.frame_uniforms.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: self.materials.as_entire_binding(),
                },
            ],
        )
    }

    /// Group 1 of the quad pipelines: quad page `page` of `residency`, `records`, and the
    /// opaque visibility buffer the transparent quads test against (a stand-in without one).
    pub fn quad_group(
        &self,
        residency: &Residency,
        page: u32,
        records: &Buffer,
        visibility: Option<&Buffer>,
    ) -> Option<BindGroup> {
        let quads = residency.gigabuffer().page(DataKind::Quads, page)?;
        let visibility = visibility.unwrap_or(&self.no_visibility);
        Some(self.bind_cache.get(
            &self.device,
            "quads",
            &self.quad_layout,
            &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: quads.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: records.as_entire_binding(),
                },
                buffer_entry(9, visibility),
            ],
        ))
    }

    /// Group 1 of the smooth pipelines: smooth page pair `pair`'s pages (`quad_pages` smooth
    /// quad pages per vertex page) and a cull output's smooth records (`records`).
    pub fn smooth_group(
        &self,
        residency: &Residency,
        pair: u32,
        quad_pages: u32,
        records: &Buffer,
    ) -> Option<BindGroup> {
        let quad_pages = quad_pages.max(1);
        let gigabuffer = residency.gigabuffer();
        let vertices = gigabuffer.page(DataKind::SmoothVertices, pair / quad_pages)?;
        let quads = gigabuffer.page(DataKind::SmoothQuads, pair % quad_pages)?;
        Some(self.bind_cache.get(
            &self.device,
            "smooth",
            &self.smooth_layout,
            &[
                buffer_entry(2, vertices),
                buffer_entry(3, quads),
                buffer_entry(4, records),
            ],
        ))
    }
}

/// The palette as a storage buffer, and its entry count.
fn material_buffer(
    device: &Device,
    palette: &MaterialPalette,
) -> Result<(Buffer, u32), AllocError> {
    let materials = gpu_materials(palette);
    let buffer = crate::device::alloc::create_buffer_init(
        device,
        &wgpu::util::BufferInitDescriptor {
            label: Some("materials"),
            contents: bytemuck::cast_slice(&materials),
            usage: BufferUsages::STORAGE,
        },
    )?;
    Ok((buffer, materials.len() as u32))
}

/// A whole-buffer binding of `ty` at `binding`, seen by `visibility`.
pub(crate) fn buffer_layout_entry(
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

/// A 2D texture binding of `sample_type` at `binding`, seen by `visibility`.
pub(crate) fn texture_layout_entry(
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

/// A write-only 2D storage texture of `format` at `binding`, for compute.
pub(crate) fn storage_texture_entry(
    binding: u32,
    format: wgpu::TextureFormat,
) -> BindGroupLayoutEntry {
    BindGroupLayoutEntry {
        binding,
        visibility: ShaderStages::COMPUTE,
        ty: BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension: wgpu::TextureViewDimension::D2,
        },
        count: None,
    }
}

/// A bind group layout of `entries`.
pub(crate) fn bind_layout(
    device: &Device,
    label: &str,
    entries: &[BindGroupLayoutEntry],
) -> BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries,
    })
}

/// One render pipeline of the renderer.
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
    pipeline_with_groups(device, desc, &[])
}

/// [`pipeline`] with bind groups after `desc.groups` (group 2 onwards).
pub(crate) fn pipeline_with_groups(
    device: &Device,
    desc: PipelineDesc<'_>,
    more: &[&BindGroupLayout],
) -> RenderPipeline {
    let mut groups = vec![Some(desc.groups[0]), Some(desc.groups[1])];
    groups.extend(more.iter().map(|g| Some(*g)));
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(desc.label),
        bind_group_layouts: &groups,
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

/// A compute pipeline of `module`'s `entry`, binding `groups`.
pub(crate) fn compute_pipeline(
    device: &Device,
    label: &str,
    module: &ShaderModule,
    entry: &str,
    groups: &[&BindGroupLayout],
) -> wgpu::ComputePipeline {
    let groups: Vec<Option<&BindGroupLayout>> = groups.iter().map(|g| Some(*g)).collect();
    let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &groups,
        immediate_size: 0,
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(label),
        layout: Some(&layout),
        module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
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
