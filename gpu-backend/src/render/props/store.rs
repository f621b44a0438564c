//! A prop model's GPU resources: its vertex and index buffers (every primitive of the model in
//! one of each) and its base colour and emissive textures (`Rgba8UnormSrgb`, sampled in
//! linear space as the CPU reference samples them, with every mip level, made on the CPU by
//! [`render_model::props::mip_chain`], whose docs say why), each draw's material uniform and
//! bind group.

use wgpu::{Buffer, BufferUsages, Device, Queue};

use render_model::props::{EMISSION_MAX, mip_chain, mip_level_count};
use voxel_scene::props::{AlphaMode, Filter, PropModel, PropSampler, TextureRef, Wrap};

use super::PropError;
use crate::device::alloc::{create_buffer_init, create_texture};

/// The material uniform of one draw (`PropMaterial` in `props.wgsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PropMaterialUniform {
    /// Base colour factor, linear RGBA.
    pub base_colour: [f32; 4],
    /// Emissive colour (factor times strength), linear RGB; `w` 0.
    pub emissive: [f32; 4],
    /// Fragments with alpha below this are discarded (the MASK cutoff; 0 for OPAQUE).
    pub cutoff: f32,
    /// 1 when the base colour texture is bound.
    pub textured: u32,
    /// 1 when back faces are drawn too.
    pub double_sided: u32,
    /// 1 when the emissive texture is bound.
    pub emissive_textured: u32,
}

const _: () = assert!(
    size_of::<PropMaterialUniform>() == 48,
    "PropMaterial is 48 bytes"
);

/// One primitive of a placed mesh: where its indices are in the model's buffers, its
/// material's draw state.
#[derive(Debug)]
pub struct StoredPrimitive {
    /// First index in the model's index buffer.
    pub first_index: u32,
    /// Indices.
    pub index_count: u32,
    /// Added to every index.
    pub base_vertex: i32,
    /// Bounding sphere, mesh space.
    pub sphere: ([f32; 3], f32),
    /// Index of its draw state in [`StoredModel::draws`].
    pub draw: usize,
}

/// One material's draw state: uniform, texture and the bind group of both.
#[derive(Debug)]
pub struct StoredDraw {
    /// Group 2 of the prop pipelines.
    pub group: wgpu::BindGroup,
    /// Back faces drawn.
    pub double_sided: bool,
    /// glTF `BLEND`: drawn blended after the lighting, not into the G-buffer.
    pub blend: bool,
}

/// A model on the GPU.
#[derive(Debug)]
pub struct StoredModel {
    /// Interleaved `PropVertex`es of every primitive.
    pub vertices: Buffer,
    /// `u32` indices of every primitive.
    pub indices: Buffer,
    /// Per mesh, its primitives.
    pub meshes: Vec<Vec<StoredPrimitive>>,
    /// Per primitive material in use, its draw state.
    pub draws: Vec<StoredDraw>,
    /// The model's instances: mesh index and model matrix.
    pub instances: Vec<(usize, [[f32; 4]; 4])>,
}

fn address(w: Wrap) -> wgpu::AddressMode {
    match w {
        Wrap::Repeat => wgpu::AddressMode::Repeat,
        Wrap::ClampToEdge => wgpu::AddressMode::ClampToEdge,
        Wrap::MirroredRepeat => wgpu::AddressMode::MirrorRepeat,
    }
}

fn filter(f: Filter) -> wgpu::FilterMode {
    match f {
        Filter::Nearest => wgpu::FilterMode::Nearest,
        Filter::Linear => wgpu::FilterMode::Linear,
    }
}

/// The sampler of `s`: between mip levels by its mipmap filter, or level 0 only.
fn sampler(device: &Device, s: &PropSampler) -> wgpu::Sampler {
    let (mipmap_filter, lod_max_clamp) = match s.mip {
        Some(Filter::Nearest) => (wgpu::MipmapFilterMode::Nearest, 32.0),
        Some(Filter::Linear) => (wgpu::MipmapFilterMode::Linear, 32.0),
        None => (wgpu::MipmapFilterMode::Nearest, 0.0),
    };
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("prop sampler"),
        address_mode_u: address(s.wrap_u),
        address_mode_v: address(s.wrap_v),
        mag_filter: filter(s.mag),
        min_filter: filter(s.min),
        mipmap_filter,
        lod_max_clamp,
        ..Default::default()
    })
}

/// An sRGB texture of `rgba` (`width x height`) with its mip levels.
fn texture(
    device: &Device,
    queue: &Queue,
    width: u32,
    height: u32,
    rgba: &[u8],
) -> Result<wgpu::TextureView, PropError> {
    let chain = mip_chain(width, height, rgba).map_err(PropError::Texture)?;
    let size = wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: 1,
    };
    let texture = create_texture(
        device,
        &wgpu::TextureDescriptor {
            label: Some("prop texture"),
            size,
            mip_level_count: mip_level_count(width, height),
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
    )?;
    let levels = std::iter::once((width, height, rgba))
        .chain(chain.iter().map(|l| (l.width, l.height, l.rgba.as_slice())));
    for (level, (w, h, bytes)) in levels.enumerate() {
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: level as u32,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            bytes,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * w),
                rows_per_image: Some(h),
            },
            wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
        );
    }
    Ok(texture.create_view(&Default::default()))
}

impl StoredModel {
    /// Uploads `model`; `layout` is group 2 of the prop pipelines.
    pub fn upload(
        device: &Device,
        queue: &Queue,
        layout: &wgpu::BindGroupLayout,
        model: &PropModel,
    ) -> Result<StoredModel, PropError> {
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        let mut draws = Vec::new();
        let mut meshes = Vec::new();
        let white = texture(device, queue, 1, 1, &[255; 4])?;
        for mesh in &model.meshes {
            let mut prims = Vec::new();
            for prim in &mesh.primitives {
                let material = model.material_of(prim);
                let emissive = material.emissive.map(|c| c * material.emissive_strength);
                if !emissive.iter().all(|c| (0.0..=EMISSION_MAX).contains(c)) {
                    return Err(PropError::Emission {
                        material: prim.material,
                        emissive,
                    });
                }
                let uniform = PropMaterialUniform {
                    base_colour: material.base_colour,
                    emissive: [emissive[0], emissive[1], emissive[2], 0.0],
                    cutoff: match material.alpha_mode {
                        AlphaMode::Mask { cutoff } => cutoff,
                        // BLEND keeps every fragment: its alpha blends it.
                        AlphaMode::Blend | AlphaMode::Opaque => f32::NEG_INFINITY,
                    },
                    textured: u32::from(material.base_colour_texture.is_some()),
                    double_sided: u32::from(material.double_sided),
                    emissive_textured: u32::from(material.emissive_texture.is_some()),
                };
                let bound = |t: &Option<TextureRef>| -> Result<_, PropError> {
                    Ok(
                        match t.and_then(|t| model.textures.get(t.texture).map(|x| (t, x))) {
                            Some((t, tex)) => (
                                texture(device, queue, tex.width, tex.height, &tex.rgba)?,
                                sampler(device, &t.sampler),
                            ),
                            None => (white.clone(), sampler(device, &PropSampler::default())),
                        },
                    )
                };
                let (view, samp) = bound(&material.base_colour_texture)?;
                let (emissive_view, emissive_samp) = bound(&material.emissive_texture)?;
                let buffer = create_buffer_init(
                    device,
                    &wgpu::util::BufferInitDescriptor {
                        label: Some("prop material"),
                        contents: bytemuck::bytes_of(&uniform),
                        usage: BufferUsages::UNIFORM,
                    },
                )?;
                let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("prop material"),
                    layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: buffer.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: wgpu::BindingResource::TextureView(&view),
                        },
                        wgpu::BindGroupEntry {
                            binding: 2,
                            resource: wgpu::BindingResource::Sampler(&samp),
                        },
                        wgpu::BindGroupEntry {
                            binding: 3,
                            resource: wgpu::BindingResource::TextureView(&emissive_view),
                        },
                        wgpu::BindGroupEntry {
                            binding: 4,
                            resource: wgpu::BindingResource::Sampler(&emissive_samp),
                        },
                    ],
                });
                draws.push(StoredDraw {
                    group,
                    double_sided: material.double_sided,
                    blend: material.alpha_mode == AlphaMode::Blend,
                });
                prims.push(StoredPrimitive {
                    first_index: indices.len() as u32,
                    index_count: prim.indices.len() as u32,
                    base_vertex: vertices.len() as i32,
                    sphere: prim.bounds.bounding_sphere(),
                    draw: draws.len() - 1,
                });
                vertices.extend_from_slice(&prim.vertices);
                indices.extend_from_slice(&prim.indices);
            }
            meshes.push(prims);
        }
        // wgpu refuses empty buffers' bindings; a model without triangles keeps 4 bytes.
        if indices.is_empty() {
            indices.push(0);
        }
        if vertices.is_empty() {
            vertices.push(Default::default());
        }
        let vertices = create_buffer_init(
            device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("prop vertices"),
                contents: bytemuck::cast_slice(&vertices),
                usage: BufferUsages::VERTEX,
            },
        )?;
        let indices = create_buffer_init(
            device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("prop indices"),
                contents: bytemuck::cast_slice(&indices),
                usage: BufferUsages::INDEX,
            },
        )?;
        Ok(StoredModel {
            vertices,
            indices,
            meshes,
            draws,
            instances: model.instances.iter().map(|i| (i.mesh, i.matrix)).collect(),
        })
    }
}
