//! Showing a [`Scene`] with the GPU renderer: meshing its chunks, uploading them, and the
//! camera conversion. Used by the headless viewer and the image tests.

use std::fmt;

use gpu_backend::render::far::FarRequest;
use gpu_backend::render::{RenderError, Renderer, RendererConfig, SceneFootprint};
use gpu_backend::residency::ChunkHandle;
use gpu_backend::{DeviceError, DeviceOptions, GpuContext, PassTime};
use mesher::lod::NodeMesh;
use mesher::{BlockClasses, ChunkMesh, MeshError, MeshSettings};
use render_model::camera::Camera;
use render_model::resident::ChunkMeshData;
use voxel_core::storage::{VoxelStorage, WorldMap};
use voxel_core::{ChunkCoord, MaterialPalette};

use crate::scene::Scene;
use render_model::lighting::{Lighting, LightingError};

/// Why a scene could not be put on the GPU.
#[derive(Debug)]
#[non_exhaustive]
pub enum GpuViewError {
    /// No device (no Vulkan adapter, or the adapter refused).
    Device(DeviceError),
    /// The renderer could not be created or could not render.
    Renderer(RenderError),
    /// Meshing the scene failed (the first chunk in error).
    Mesh(MeshError),
    /// The renderer refused a chunk.
    Render(ChunkCoord, RenderError),
    /// The lighting cannot be rendered.
    Lighting(LightingError),
}

impl fmt::Display for GpuViewError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GpuViewError::Device(e) => write!(f, "{e}"),
            GpuViewError::Renderer(e) => write!(f, "renderer: {e}"),
            GpuViewError::Mesh(e) => write!(f, "meshing the scene: {e}"),
            GpuViewError::Render(c, e) => write!(f, "uploading chunk {c:?}: {e}"),
            GpuViewError::Lighting(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for GpuViewError {}

/// Uploads `nodes` (from `mesher::lod::mesh_nodes`) to `renderer` at their levels. Returns
/// their handles.
pub fn upload_nodes(
    renderer: &mut Renderer,
    nodes: &[NodeMesh],
) -> Result<Vec<ChunkHandle>, GpuViewError> {
    nodes
        .iter()
        .map(|node| {
            renderer
                .upload_chunk(&ChunkMeshData {
                    coord: node.coord,
                    lod: node.level,
                    layers: node.layers(),
                })
                .map_err(|e| GpuViewError::Render(node.coord, e))
        })
        .collect()
}

/// Meshes every stored chunk of `world` (greedy quads with AO, in parallel) and uploads the
/// non-empty ones to `renderer`. Returns their handles.
pub fn upload_world<C: VoxelStorage + Sync>(
    renderer: &mut Renderer,
    world: &WorldMap<C>,
    palette: &MaterialPalette,
) -> Result<Vec<ChunkHandle>, GpuViewError> {
    upload_world_with(renderer, world, palette, &MeshSettings::default())
}

/// [`upload_world`] with other mesh settings (e.g. `SurfaceMode::NoCubes`, whose smooth layer
/// the renderer draws too; clutter needs a renderer made with `RendererConfig::with_clutter`).
pub fn upload_world_with<C: VoxelStorage + Sync>(
    renderer: &mut Renderer,
    world: &WorldMap<C>,
    palette: &MaterialPalette,
    settings: &MeshSettings,
) -> Result<Vec<ChunkHandle>, GpuViewError> {
    upload_meshes(renderer, &mesh_world(world, palette, settings)?)
}

/// Meshes every stored chunk of `world` in parallel, keeping the non-empty meshes.
pub fn mesh_world<C: VoxelStorage + Sync>(
    world: &WorldMap<C>,
    palette: &MaterialPalette,
    settings: &MeshSettings,
) -> Result<Vec<ChunkMesh>, GpuViewError> {
    let classes = BlockClasses::from_palette(palette);
    let mut coords: Vec<ChunkCoord> = world.iter().map(|(c, _)| c).collect();
    coords.sort_by_key(|c| (c.z, c.y, c.x));
    let mut meshes =
        mesher::mesh_chunks(world, &coords, &classes, settings).map_err(GpuViewError::Mesh)?;
    meshes.retain(|m| !m.blocky.is_empty() || !m.smooth.is_empty());
    Ok(meshes)
}

/// Uploads level-0 chunk meshes; returns their handles.
pub fn upload_meshes(
    renderer: &mut Renderer,
    meshes: &[ChunkMesh],
) -> Result<Vec<ChunkHandle>, GpuViewError> {
    meshes
        .iter()
        .map(|mesh| {
            let data = ChunkMeshData {
                coord: mesh.coord,
                lod: 0,
                layers: mesh.layers(),
            };
            renderer
                .upload_chunk(&data)
                .map_err(|e| GpuViewError::Render(mesh.coord, e))
        })
        .collect()
}

/// What `meshes` need resident.
pub fn footprint_of(meshes: &[ChunkMesh]) -> SceneFootprint {
    let mut footprint = SceneFootprint::default();
    for mesh in meshes {
        footprint.add(&mesh.layers());
    }
    footprint
}

/// One frame rendered on the GPU.
#[derive(Clone, Debug)]
pub struct GpuFrame {
    /// Row-major RGBA8, sRGB.
    pub rgba: Vec<u8>,
    /// The adapter it ran on.
    pub adapter: String,
    /// Per-pass times of the frame.
    pub timings: Vec<PassTime>,
    /// Chunks uploaded.
    pub chunks: usize,
}

/// Renders `scene` from `camera` with the GPU renderer on a headless Vulkan device: meshes
/// every chunk, sizes the renderer to what the meshes hold (so any scene the device's memory
/// holds is drawn, however many chunks), uploads them, draws one frame (in the wireframe view
/// with `wireframe`), reads it back.
pub fn render_scene(
    scene: &Scene,
    camera: &Camera,
    lighting: &Lighting,
    (width, height): (u32, u32),
    wireframe: bool,
) -> Result<GpuFrame, GpuViewError> {
    let ctx = GpuContext::new_headless(&DeviceOptions::default()).map_err(GpuViewError::Device)?;
    let size = scene.world.size();
    let meshes = mesh_world(&scene.world, &scene.palette, &MeshSettings::default())?;
    let config =
        RendererConfig::fitted(width, height, size, FarRequest::Off, &footprint_of(&meshes));
    let mut renderer =
        Renderer::new(&ctx, &config, &scene.palette).map_err(GpuViewError::Renderer)?;
    let handles = upload_meshes(&mut renderer, &meshes)?;
    renderer.set_camera(camera);
    renderer
        .set_lighting(lighting)
        .map_err(GpuViewError::Lighting)?;
    renderer.set_wireframe(wireframe);
    let timings = renderer.render().map_err(GpuViewError::Renderer)?;
    let image = renderer.read_image().map_err(GpuViewError::Renderer)?;
    Ok(GpuFrame {
        rgba: image.rgba,
        adapter: ctx.capabilities.adapter.to_string(),
        timings,
        chunks: handles.len(),
    })
}
