//! glTF props on the GPU: the retained store of uploaded models, the instance registry
//! ([`render_model::props::PropRegistry`]) mirrored into GPU buffers by dirty ranges, the prop
//! cull ([`crate::render::passes::prop_cull`]) and the prop draw
//! ([`crate::render::passes::props`]).
//!
//! **Instances.** A [`PropId`] is one placed model: one registry instance per (model instance,
//! primitive), each in the batch of its primitive and material, with `local = placement.local
//! * node matrix` composed in `f64` and rounded once (as `voxel_reference::prop_raster` does).
//!
//! **Frame order.** After the opaque phases (with occlusion culling: after the late phase,
//! whose depth pyramid was built this frame from the early phase's depth) the cull zeroes
//! every batch's instance count and tests every slot against the frustum and, when the
//! renderer culls occlusion, against that pyramid; then one `draw_indexed_indirect` per batch
//! draws into the G-buffer over the voxels' depth. Props do not enter the pyramid.
//!
//! **Materials.** The G-buffer's albedo holds sRGB colour bytes, not a palette index, so props
//! write `linear_to_srgb(base colour factor * texel)` there (8-bit rounding: the image tests
//! allow for it), AO full and material id 0. The emissive colour (`emissiveFactor *
//! emissiveTexture * strength`, linear) goes in the bits the voxels leave free
//! ([`render_model::props::encode_emission`]: the albedo's alpha and the material word's upper
//! half), and the lighting pass adds it, exposed, to the shaded colour, as the voxels' palette
//! emission is added; a material brighter than the word holds is refused by name. OPAQUE
//! draws every fragment and MASK discards below the cutoff, into the G-buffer; BLEND is not
//! drawn there but after the lighting and the voxels' transparent layer, lit forward with the
//! same model (no shadows), premultiplied over the lit colour, depth-tested and not writing
//! depth, batches back to front ([`render_model::props::blend_order`] states the order and
//! its limits).
//!
//! Nothing is created while no model is added: the pipelines and buffers come with the first.

mod store;

use std::fmt;

use wgpu::{Buffer, BufferUsages, Device, Queue};

use render_model::props::{
    PlacementError, PrimitiveId, PropHandle, PropPlacement, PropPrimitiveDesc, PropRegistry,
    PropRegistryError,
};
use voxel_scene::props::PropModel;

use crate::device::alloc::{AllocError, create_buffer};
pub use store::{PropMaterialUniform, StoredDraw, StoredModel};

/// A model added with [`GpuProps::add_model`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PropModelId(pub u32);

/// A placed model made by [`GpuProps::create`]; stale once deleted, even when its index is
/// reused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PropId {
    /// Index in the instance table.
    pub index: u32,
    /// Generation of the entry when made.
    pub generation: u32,
}

/// Why a props call was refused.
#[derive(Debug)]
#[non_exhaustive]
pub enum PropError {
    /// The model id names no added model.
    UnknownModel(PropModelId),
    /// The instance was deleted (or never made).
    StaleProp(PropId),
    /// The registry refused (full).
    Registry(PropRegistryError),
    /// A placement composed with a node matrix is not finite.
    Placement(PlacementError),
    /// The device refused a buffer or texture.
    Alloc(AllocError),
    /// A texture's pixels do not match its size.
    Texture(render_model::props::MipError),
    /// A material's emissive colour (factor times strength) is not finite or brighter than
    /// the G-buffer's emission holds (`render_model::props::EMISSION_MAX`).
    Emission {
        /// Index of the material in the model (`None`: glTF's default material).
        material: Option<usize>,
        /// Its emissive colour.
        emissive: [f32; 3],
    },
}

impl fmt::Display for PropError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PropError::UnknownModel(m) => write!(f, "no prop model {}", m.0),
            PropError::StaleProp(p) => write!(
                f,
                "prop {} (generation {}) was deleted or never made",
                p.index, p.generation
            ),
            PropError::Registry(e) => write!(f, "prop registry: {e:?}"),
            PropError::Placement(e) => write!(f, "prop placement: {e:?}"),
            PropError::Alloc(e) => write!(f, "prop store: {e}"),
            PropError::Texture(e) => write!(f, "prop texture: {e}"),
            PropError::Emission { material, emissive } => write!(
                f,
                "prop material {material:?}: emissive colour {emissive:?} (factor times \
                 strength) is not a finite colour of at most {} per channel",
                render_model::props::EMISSION_MAX
            ),
        }
    }
}

impl std::error::Error for PropError {}

impl From<AllocError> for PropError {
    fn from(e: AllocError) -> Self {
        PropError::Alloc(e)
    }
}

impl From<PropRegistryError> for PropError {
    fn from(e: PropRegistryError) -> Self {
        PropError::Registry(e)
    }
}

struct Entry {
    generation: u32,
    live: Option<(PropModelId, PropPlacement, bool, Vec<PropHandle>)>,
}

/// The GPU copies of the registry's records.
#[derive(Debug)]
pub struct PropBuffers {
    /// Instance records, one per slot.
    pub instances: Buffer,
    /// Batch records (also the indirect draw arguments).
    pub batches: Buffer,
    /// The cull's visible list, one `u32` per slot.
    pub visible: Buffer,
    /// The cull uniforms (`PropCullUniforms`).
    pub uniforms: Buffer,
    slots: u32,
    batch_count: u32,
}

/// What a draw of one batch needs: the model's buffers and the material's group.
#[derive(Clone, Copy, Debug)]
pub struct BatchDraw {
    /// Model index.
    pub model: u32,
    /// Draw state index in that model.
    pub draw: u32,
}

/// The retained props (see the [module docs](self)).
#[derive(Default)]
pub struct GpuProps {
    models: Vec<StoredModel>,
    /// Per registry primitive: model, mesh, primitive.
    primitives: Vec<(u32, usize, usize)>,
    /// Per model: per mesh, per primitive, its registry id.
    primitive_ids: Vec<Vec<Vec<PrimitiveId>>>,
    /// Per registry material index (one per model draw): model and draw.
    materials: Vec<BatchDraw>,
    /// Per model, per draw, the registry material index.
    material_ids: Vec<Vec<u32>>,
    registry: PropRegistry,
    entries: Vec<Entry>,
    free: Vec<u32>,
    buffers: Option<PropBuffers>,
    material_layout: Option<wgpu::BindGroupLayout>,
}

impl fmt::Debug for GpuProps {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("GpuProps")
            .field("models", &self.models.len())
            .field("instances", &self.registry.len())
            .finish_non_exhaustive()
    }
}

/// Group 2 of the prop draw: the material uniform, the base colour texture and sampler, the
/// emissive texture and sampler.
pub fn material_layout(device: &Device) -> wgpu::BindGroupLayout {
    use wgpu::{BindGroupLayoutEntry, BindingType, ShaderStages};
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("prop material"),
        entries: &[
            BindGroupLayoutEntry {
                binding: 0,
                visibility: ShaderStages::FRAGMENT,
                ty: BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            },
            BindGroupLayoutEntry {
                binding: 1,
                visibility: ShaderStages::FRAGMENT,
                ty: BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            BindGroupLayoutEntry {
                binding: 2,
                visibility: ShaderStages::FRAGMENT,
                ty: BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
            BindGroupLayoutEntry {
                binding: 3,
                visibility: ShaderStages::FRAGMENT,
                ty: BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            BindGroupLayoutEntry {
                binding: 4,
                visibility: ShaderStages::FRAGMENT,
                ty: BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
        ],
    })
}

/// `a * b`, column-major 4 x 4, in `f64`, rounded once.
fn compose(a: &[[f32; 4]; 4], b: &[[f32; 4]; 4]) -> [[f32; 4]; 4] {
    std::array::from_fn(|c| {
        std::array::from_fn(|r| {
            (0..4)
                .map(|k| f64::from(a[k][r]) * f64::from(b[c][k]))
                .sum::<f64>() as f32
        })
    })
}

impl GpuProps {
    /// No models, no instances, nothing on the GPU.
    pub fn new() -> GpuProps {
        GpuProps::default()
    }

    /// Uploads `model` (buffers and textures) and registers its primitives.
    pub fn add_model(
        &mut self,
        device: &Device,
        queue: &Queue,
        model: &PropModel,
    ) -> Result<PropModelId, PropError> {
        let layout = self
            .material_layout
            .get_or_insert_with(|| material_layout(device));
        let stored = StoredModel::upload(device, queue, layout, model)?;
        let id = self.models.len() as u32;
        let mut ids = Vec::new();
        for (m, mesh) in stored.meshes.iter().enumerate() {
            let mut row = Vec::new();
            for (p, prim) in mesh.iter().enumerate() {
                let pid = self.registry.add_primitive(PropPrimitiveDesc {
                    index_count: prim.index_count,
                    first_index: prim.first_index,
                    base_vertex: prim.base_vertex,
                    sphere_centre: prim.sphere.0,
                    sphere_radius: prim.sphere.1,
                });
                self.primitives.push((id, m, p));
                row.push(pid);
            }
            ids.push(row);
        }
        let mut mats = Vec::new();
        for d in 0..stored.draws.len() {
            mats.push(self.materials.len() as u32);
            self.materials.push(BatchDraw {
                model: id,
                draw: d as u32,
            });
        }
        self.material_ids.push(mats);
        self.primitive_ids.push(ids);
        self.models.push(stored);
        Ok(PropModelId(id))
    }

    /// Places an instance of `model`, shown or hidden.
    pub fn create(
        &mut self,
        model: PropModelId,
        placement: PropPlacement,
        visible: bool,
    ) -> Result<PropId, PropError> {
        let handles = self.place(model, &placement, visible)?;
        let index = match self.free.pop() {
            Some(i) => i,
            None => {
                self.entries.push(Entry {
                    generation: 0,
                    live: None,
                });
                self.entries.len() as u32 - 1
            }
        };
        let entry = &mut self.entries[index as usize];
        entry.live = Some((model, placement, visible, handles));
        Ok(PropId {
            index,
            generation: entry.generation,
        })
    }

    fn place(
        &mut self,
        model: PropModelId,
        placement: &PropPlacement,
        visible: bool,
    ) -> Result<Vec<PropHandle>, PropError> {
        let stored = self
            .models
            .get(model.0 as usize)
            .ok_or(PropError::UnknownModel(model))?;
        let mut handles = Vec::new();
        for (mesh, matrix) in &stored.instances {
            let Some(prims) = stored.meshes.get(*mesh) else {
                continue;
            };
            let local = compose(&placement.local, matrix);
            let placed =
                PropPlacement::new(placement.anchor, local).map_err(PropError::Placement)?;
            for (p, prim) in prims.iter().enumerate() {
                let pid = self.primitive_ids[model.0 as usize][*mesh][p];
                let material = self.material_ids[model.0 as usize][prim.draw];
                match self.registry.create(pid, material, placed, visible) {
                    Ok(h) => handles.push(h),
                    Err(e) => {
                        for h in handles {
                            let _ = self.registry.delete(h);
                        }
                        return Err(e.into());
                    }
                }
            }
        }
        Ok(handles)
    }

    fn live(
        &mut self,
        id: PropId,
    ) -> Result<&mut (PropModelId, PropPlacement, bool, Vec<PropHandle>), PropError> {
        self.entries
            .get_mut(id.index as usize)
            .filter(|e| e.generation == id.generation)
            .and_then(|e| e.live.as_mut())
            .ok_or(PropError::StaleProp(id))
    }

    /// Deletes an instance; its id becomes stale.
    pub fn delete(&mut self, id: PropId) -> Result<(), PropError> {
        let handles = std::mem::take(&mut self.live(id)?.3);
        for h in handles {
            self.registry.delete(h)?;
        }
        let entry = &mut self.entries[id.index as usize];
        entry.live = None;
        entry.generation = entry.generation.wrapping_add(1);
        self.free.push(id.index);
        Ok(())
    }

    /// Moves an instance.
    pub fn set_placement(&mut self, id: PropId, placement: PropPlacement) -> Result<(), PropError> {
        let (model, _, visible, handles) = {
            let live = self.live(id)?;
            (live.0, live.1, live.2, std::mem::take(&mut live.3))
        };
        for h in handles {
            self.registry.delete(h)?;
        }
        let handles = self.place(model, &placement, visible)?;
        let live = self.live(id)?;
        live.1 = placement;
        live.3 = handles;
        Ok(())
    }

    /// Shows or hides an instance.
    pub fn set_visible(&mut self, id: PropId, visible: bool) -> Result<(), PropError> {
        let handles = {
            let live = self.live(id)?;
            live.2 = visible;
            live.3.clone()
        };
        for h in handles {
            self.registry.set_visible(h, visible)?;
        }
        Ok(())
    }

    /// Live instances (placed models).
    pub fn len(&self) -> usize {
        self.entries.iter().filter(|e| e.live.is_some()).count()
    }

    /// True when no instance lives.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The registry (its records are what the GPU holds after [`sync`](Self::sync)).
    pub fn registry(&self) -> &PropRegistry {
        &self.registry
    }

    /// The GPU buffers, once an instance slot exists.
    pub fn buffers(&self) -> Option<&PropBuffers> {
        self.buffers.as_ref()
    }

    /// The draw of material index `material` (a batch record's `material`).
    pub fn batch_draw(&self, material: u32) -> Option<(&StoredModel, &StoredDraw)> {
        let d = self.materials.get(material as usize)?;
        let model = self.models.get(d.model as usize)?;
        let draw = model.draws.get(d.draw as usize)?;
        Some((model, draw))
    }

    /// True when material index `material` is glTF `BLEND` (drawn by the blended pass).
    pub fn is_blended(&self, material: u32) -> bool {
        self.batch_draw(material).is_some_and(|(_, d)| d.blend)
    }

    /// The material layout (group 2 of the prop draw), once a model exists.
    pub fn material_layout(&self) -> Option<&wgpu::BindGroupLayout> {
        self.material_layout.as_ref()
    }

    /// Copies what changed since the last call into the GPU buffers (all of it when the
    /// registry's layout moved or the buffers are new).
    pub fn sync(&mut self, device: &Device, queue: &Queue) -> Result<(), PropError> {
        let upload = self.registry.take_upload();
        let slots = self.registry.slot_count().max(1);
        let batch_count = self.registry.batch_count().max(1);
        let stale = self
            .buffers
            .as_ref()
            .is_none_or(|b| b.slots < slots || b.batch_count < batch_count);
        let instances = self.registry.instance_records();
        let batches = self.registry.batch_records();
        if stale {
            let make = |label, size: u64, usage| {
                create_buffer(
                    device,
                    &wgpu::BufferDescriptor {
                        label: Some(label),
                        size,
                        usage: usage | BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    },
                )
            };
            self.buffers = Some(PropBuffers {
                instances: make(
                    "prop instances",
                    u64::from(slots) * 64,
                    BufferUsages::STORAGE,
                )?,
                batches: make(
                    "prop batches",
                    u64::from(batch_count) * 48,
                    BufferUsages::STORAGE | BufferUsages::INDIRECT | BufferUsages::COPY_SRC,
                )?,
                visible: make(
                    "prop visible list",
                    u64::from(slots) * 4,
                    BufferUsages::STORAGE,
                )?,
                uniforms: make("prop cull uniforms", 208, BufferUsages::UNIFORM)?,
                slots,
                batch_count,
            });
        }
        let Some(b) = &self.buffers else {
            return Ok(());
        };
        if stale || upload.full {
            queue.write_buffer(&b.instances, 0, bytemuck::cast_slice(instances));
            queue.write_buffer(&b.batches, 0, bytemuck::cast_slice(batches));
        } else {
            for r in upload.instances {
                let part = &instances[r.start as usize..r.end as usize];
                queue.write_buffer(
                    &b.instances,
                    u64::from(r.start) * 64,
                    bytemuck::cast_slice(part),
                );
            }
            for r in upload.batches {
                let part = &batches[r.start as usize..r.end as usize];
                queue.write_buffer(
                    &b.batches,
                    u64::from(r.start) * 48,
                    bytemuck::cast_slice(part),
                );
            }
        }
        Ok(())
    }
}
