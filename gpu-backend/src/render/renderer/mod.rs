//! [`Renderer`]: resident nodes, camera and lighting in; one frame recorded into one encoder.
//! The frame, pass by pass, is [`Renderer::record_frame`] (`record.rs`); the passes are built
//! from the configuration in `build.rs`.

mod build;
mod config;
mod opaque_choice;
mod record;
mod submit;

pub use config::{OpaquePath, RendererConfig};
pub use opaque_choice::OpaqueChoice;

use wgpu::{Device, Queue};

use render_model::camera::Camera;
use render_model::cull::{LodAnchor, LodSettings};
use render_model::lighting::{Lighting, LightingError};
use render_model::resident::ChunkMeshData;
use voxel_core::MaterialPalette;

use super::error::RenderError;
use super::far::FarChoice;
use super::passes::fullscreen::FullscreenPath;
use super::passes::shared::Shared;
use super::passes::targets::{FrameImage, RenderTargets, read_output};
use crate::device::{DeviceHealth, GpuContext};
use crate::residency::{ChunkHandle, Gigabuffer, Residency, ResidencyConfig};
use crate::timing::GpuTimer;
use build::Passes;

/// What the next frames show and how: the camera, the light, the level-of-detail selection
/// and the view options.
#[derive(Debug)]
struct View {
    camera: Camera,
    lighting: Lighting,
    /// Level-of-detail selection; `None` draws level 0 only (full detail).
    lod: Option<LodSettings>,
    anchor: LodAnchor,
    /// The wireframe view: meshes are drawn as their quads' edges.
    wireframe: bool,
    /// The opaque path drawing now: `Raster` or `Compute` (the latter only with a compute
    /// rasteriser).
    opaque: OpaquePath,
    /// Clutter is drawn (only with a grass pass).
    clutter: bool,
    /// The time the wind sways the grass at, seconds.
    time: f64,
    /// The wind's strength: 0 still, 1 the full sway of `render_model::grass::WIND_SWAY`.
    wind: f32,
}

/// The deferred voxel renderer (see the [module docs](super) for a frame's passes).
#[derive(Debug)]
pub struct Renderer {
    device: Device,
    queue: Queue,
    config: RendererConfig,
    residency: Residency,
    view: View,
    targets: RenderTargets,
    shared: Shared,
    passes: Passes,
    /// The far path in use and why.
    far_choice: FarChoice,
    timer: GpuTimer,
    /// The device's largest storage binding (the visibility buffers' limit).
    max_page_bytes: u64,
    /// The device's faults: a frame of a lost device is refused by name.
    health: DeviceHealth,
    /// The glTF props ([`crate::render::props`]).
    props: GpuProps,
    /// Their passes and the occlusion stand-in texture, made with the first model.
    prop_passes: Option<PropPasses>,
}

/// The prop cull and draw, and the 1 x 1 pyramid bound when the frame culls no occlusion.
#[derive(Debug)]
pub(super) struct PropPasses {
    pub(super) cull: PropCullPass,
    pub(super) draw: PropsPass,
    pub(super) no_pyramid: wgpu::TextureView,
}

use render_model::props::PropPlacement;
use voxel_scene::props::PropModel;

use crate::device::alloc::create_texture;
use crate::render::passes::prop_cull::PropCullPass;
use crate::render::passes::props::PropsPass;
use crate::render::props::{GpuProps, PropError, PropId, PropModelId};

impl Renderer {
    /// A renderer on `ctx` drawing `palette`'s materials. Needs `INDIRECT_FIRST_INSTANCE`
    /// (the cull pass's commands name their record through `first_instance`).
    pub fn new(
        ctx: &GpuContext,
        config: &RendererConfig,
        palette: &MaterialPalette,
    ) -> Result<Renderer, RenderError> {
        if !ctx.capabilities.indirect_first_instance {
            return Err(RenderError::MissingFeature("INDIRECT_FIRST_INSTANCE"));
        }
        let device = &ctx.device;
        let targets = RenderTargets::new(device, config.width, config.height)?;
        let residency = Residency::new(
            device,
            &ctx.capabilities,
            &ResidencyConfig {
                chunk_size: config.chunk_size,
                gigabuffer: &config.gigabuffer,
                max_chunks: config.max_chunks,
                smooth: config.smooth,
            },
        )?;
        let (passes, far_choice, shared) = Passes::new(ctx, config, &residency, palette)?;
        let edge = config.chunk_size.edge() as i32;
        Ok(Renderer {
            device: device.clone(),
            queue: ctx.queue.clone(),
            residency,
            view: View {
                camera: Camera::new(
                    voxel_core::WorldPos::new(edge / 2, edge / 2, edge / 2),
                    glam::DVec3::splat(0.5),
                    0.0,
                    0.0,
                    1.0,
                ),
                lighting: Lighting::default(),
                lod: None,
                anchor: LodAnchor {
                    chunk: voxel_core::ChunkCoord::new(0, 0, 0),
                    offset: [0.0; 3],
                },
                wireframe: false,
                opaque: if config.opaque == OpaquePath::Compute {
                    OpaquePath::Compute
                } else {
                    OpaquePath::Raster
                },
                clutter: config.clutter,
                time: 0.0,
                wind: 1.0,
            },
            targets,
            shared,
            passes,
            far_choice,
            timer: GpuTimer::new(ctx, 16)?,
            max_page_bytes: ctx.capabilities.max_page_bytes(),
            health: ctx.health.clone(),
            config: config.clone(),
            props: GpuProps::new(),
            prop_passes: None,
        })
    }

    /// Uploads a glTF model for [`create_prop`](Self::create_prop); the prop pipelines are
    /// made with the first model.
    pub fn add_prop_model(&mut self, model: &PropModel) -> Result<PropModelId, PropError> {
        let id = self.props.add_model(&self.device, &self.queue, model)?;
        if self.prop_passes.is_none()
            && let Some(material_layout) = self.props.material_layout()
        {
            let no_pyramid = create_texture(
                &self.device,
                &wgpu::TextureDescriptor {
                    label: Some("no prop pyramid"),
                    size: wgpu::Extent3d {
                        width: 1,
                        height: 1,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: wgpu::TextureFormat::R32Float,
                    usage: wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                },
            )?
            .create_view(&Default::default());
            self.prop_passes = Some(PropPasses {
                cull: PropCullPass::new(&self.device),
                draw: PropsPass::new(&self.device, &self.shared.frame_layout, material_layout),
                no_pyramid,
            });
        }
        Ok(id)
    }

    /// Places an instance of `model` (shown); see [`GpuProps::create`].
    pub fn create_prop(
        &mut self,
        model: PropModelId,
        placement: PropPlacement,
    ) -> Result<PropId, PropError> {
        self.props.create(model, placement, true)
    }

    /// Deletes a prop; its id becomes stale.
    pub fn delete_prop(&mut self, id: PropId) -> Result<(), PropError> {
        self.props.delete(id)
    }

    /// Moves a prop.
    pub fn set_prop_placement(
        &mut self,
        id: PropId,
        placement: PropPlacement,
    ) -> Result<(), PropError> {
        self.props.set_placement(id, placement)
    }

    /// Shows or hides a prop.
    pub fn set_prop_visible(&mut self, id: PropId, visible: bool) -> Result<(), PropError> {
        self.props.set_visible(id, visible)
    }

    /// Prop instances the last frame's cull kept (the sum of every batch's drawn count, read
    /// back: waits for the GPU). 0 when no prop instance exists.
    pub fn read_props_drawn(&self) -> Result<u64, RenderError> {
        let Some(b) = self.props.buffers() else {
            return Ok(0);
        };
        let bytes = crate::readback::read_buffer(
            &self.device,
            &self.queue,
            &b.batches,
            0,
            u64::from(self.props.registry().batch_count()) * 48,
        )?;
        let records: Vec<render_model::props::PropBatchRecord> =
            bytemuck::pod_collect_to_vec(&bytes);
        Ok(records
            .iter()
            .map(|r| u64::from(r.args.instance_count))
            .sum())
    }

    /// The props (registry and GPU buffers: tests read the batch records back from them).
    pub fn props(&self) -> &GpuProps {
        &self.props
    }

    /// Replaces the material palette (kept as it was when the device refuses the new one).
    pub fn set_palette(&mut self, palette: &MaterialPalette) -> Result<(), RenderError> {
        Ok(self.shared.set_palette(palette)?)
    }

    /// Sets the camera of the next frames. The level-of-detail anchor follows it with the
    /// selection's hysteresis (see [`cull::lod`](render_model::cull::lod)); a caller that
    /// streams chunks in sets the anchor itself with [`set_lod_anchor`](Self::set_lod_anchor)
    /// after this.
    pub fn set_camera(&mut self, camera: &Camera) {
        self.view.camera = *camera;
        let eye = camera.eye(self.config.chunk_size);
        let hysteresis = self.view.lod.map_or(0.0, |l| l.hysteresis);
        self.view.anchor = self.view.anchor.follow(
            eye.chunk,
            eye.offset,
            self.config.chunk_size.edge(),
            hysteresis,
        );
    }

    /// The current camera.
    pub fn camera(&self) -> &Camera {
        &self.view.camera
    }

    /// Turns level-of-detail selection on with `settings` (see
    /// [`cull::lod`](render_model::cull::lod)), or off with `None`: then only level-0 chunks
    /// are drawn (full detail). Refuses a non-finite or negative setting.
    pub fn set_lod(&mut self, settings: Option<LodSettings>) -> Result<(), RenderError> {
        self.view.lod = settings.map(LodSettings::validate).transpose()?;
        Ok(())
    }

    /// The level-of-detail settings in use.
    pub fn lod(&self) -> Option<LodSettings> {
        self.view.lod
    }

    /// Moves the level-of-detail anchor (where distances are measured from): a streaming
    /// caller moves it only once the chunks the new selection needs are resident.
    pub fn set_lod_anchor(&mut self, anchor: LodAnchor) {
        self.view.anchor = anchor;
    }

    /// The level-of-detail anchor.
    pub fn lod_anchor(&self) -> LodAnchor {
        self.view.anchor
    }

    /// Sets the light, sky and haze of the next frames, after [`Lighting::check`]; a
    /// lighting that cannot be rendered is refused by name and the previous one kept.
    pub fn set_lighting(&mut self, lighting: &Lighting) -> Result<(), LightingError> {
        lighting.check()?;
        self.view.lighting = *lighting;
        Ok(())
    }

    /// Turns the antialias pass (FXAA of the final image) on or off for the next frames (the
    /// wireframe view never runs it).
    pub fn set_antialias(&mut self, on: bool) {
        self.config.antialias = on;
    }

    /// Whether the antialias pass runs.
    pub fn antialias(&self) -> bool {
        self.config.antialias
    }

    /// Turns the wireframe view on or off: meshed quads (greedy and smooth) are drawn as
    /// their edges, about a pixel wide, lit as usual, with the sky or the far field behind.
    /// It shows how the mesher merged faces. Far-drawn blocks are drawn as usual (a block
    /// there covers about a pixel). On the compute opaque path the meshes go through the
    /// G-buffer pass while the view is on, and the antialias pass does not run (it would
    /// blur the lines).
    pub fn set_wireframe(&mut self, on: bool) {
        self.view.wireframe = on;
    }

    /// Whether the wireframe view is on.
    pub fn wireframe(&self) -> bool {
        self.view.wireframe
    }

    /// Whether the opaque quads of this frame go through the compute rasteriser (the compute
    /// opaque path, outside the wireframe view).
    fn quads_in_compute(&self) -> bool {
        self.view.opaque == OpaquePath::Compute
            && self.passes.quad_raster.is_some()
            && !self.view.wireframe
    }

    /// The opaque path drawing now: `Raster` or `Compute` (`Auto` only picks between them).
    pub fn opaque_path(&self) -> OpaquePath {
        self.view.opaque
    }

    /// Draws the opaque quads of the next frames with `path`. `Compute` needs a renderer made
    /// with [`RendererConfig::opaque`] `Compute`, or `Auto` on a device with 64-bit atomic
    /// min/max; `Auto` is not a path to draw with (see
    /// [`measure_opaque_paths`](Self::measure_opaque_paths)).
    pub fn set_opaque_path(&mut self, path: OpaquePath) -> Result<(), RenderError> {
        match path {
            OpaquePath::Auto => Err(RenderError::OpaquePathUnavailable(
                "Auto picks a path; name Raster or Compute",
            )),
            OpaquePath::Compute if self.passes.quad_raster.is_none() => {
                Err(RenderError::OpaquePathUnavailable(
                    "the compute rasteriser was not built (make the renderer with opaque \
                     Compute, or Auto on a device with 64-bit atomic min/max)",
                ))
            }
            _ => {
                self.view.opaque = path;
                Ok(())
            }
        }
    }

    /// Turns drawing clutter (the grass pass) on or off for the next frames. Turning it on
    /// needs a renderer made with [`RendererConfig::with_clutter`]; otherwise it is refused by
    /// name and stays off.
    pub fn set_clutter(&mut self, on: bool) -> Result<(), RenderError> {
        if on && self.passes.grass.is_none() {
            return Err(RenderError::ClutterUnavailable(
                "the grass pass was not built (make the renderer with RendererConfig::with_clutter)"
                    .into(),
            ));
        }
        self.view.clutter = on;
        Ok(())
    }

    /// Whether clutter is drawn.
    pub fn clutter(&self) -> bool {
        self.view.clutter
    }

    /// Sets the time the grass sways at, seconds (the same time draws the same frame; see
    /// [`render_model::grass::wind_phase`]).
    pub fn set_time(&mut self, seconds: f64) {
        self.view.time = seconds;
    }

    /// Sets the wind's strength: 0 is still, 1 the full sway; a negative or non-finite
    /// strength is refused by name and the previous one kept.
    pub fn set_wind(&mut self, strength: f32) -> Result<(), RenderError> {
        if !(strength.is_finite() && strength >= 0.0) {
            return Err(RenderError::ClutterUnavailable(format!(
                "wind strength {strength} is not a finite number >= 0"
            )));
        }
        self.view.wind = strength;
        Ok(())
    }

    /// Frames recorded so far that filled the shadow grid (the others kept the grid of the
    /// frame before: the same camera block, level-of-detail anchor and resident set); 0 while
    /// no frame had shadows on.
    pub fn shadow_grid_fills(&self) -> u64 {
        self.passes.shadow.as_ref().map_or(0, |s| s.fills())
    }

    /// The grass pass's counts of the last frame, `(chunks drawn, units drawn)` (units before
    /// the per-blade fade; blocks while it reads them back), or `None` without a grass pass.
    pub fn grass_stats(&self) -> Result<Option<(u32, u32)>, RenderError> {
        let Some(grass) = &self.passes.grass else {
            return Ok(None);
        };
        let words: Vec<u32> = bytemuck::pod_collect_to_vec(&crate::readback::read_buffer(
            &self.device,
            &self.queue,
            grass.stats(),
            0,
            8,
        )?);
        Ok(Some((words[0], words[1])))
    }

    /// The shell pass's counts of the last frame, `(nodes drawn, runs drawn)` (blocks while it
    /// reads them back), or `None` without a shell pass.
    pub fn shell_stats(&self) -> Result<Option<(u32, u32)>, RenderError> {
        let Some(shells) = &self.passes.shells else {
            return Ok(None);
        };
        let words: Vec<u32> = bytemuck::pod_collect_to_vec(&crate::readback::read_buffer(
            &self.device,
            &self.queue,
            shells.stats(),
            0,
            8,
        )?);
        Ok(Some((words[0], words[1])))
    }

    /// The far path in use and why it was chosen.
    pub fn far_choice(&self) -> &FarChoice {
        &self.far_choice
    }

    /// Changes how the full-screen passes run (rebuilds their pipelines when it changes).
    pub fn set_fullscreen_path(&mut self, path: FullscreenPath) {
        if path != self.config.fullscreen {
            self.config.fullscreen = path;
            self.passes
                .set_fullscreen_path(&self.device, &self.shared, path);
        }
    }

    /// How the full-screen passes run.
    pub fn fullscreen_path(&self) -> FullscreenPath {
        self.config.fullscreen
    }

    /// Changes the output size (recreates the targets).
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), RenderError> {
        if let Some(splat) = &mut self.passes.far_splat {
            splat.resize(width, height, self.max_page_bytes)?;
        }
        self.targets = RenderTargets::new(&self.device, width, height)?;
        self.passes.gbuffer.targets_changed();
        if let Some(pyramid) = &mut self.passes.hiz {
            *pyramid = crate::render::passes::hiz::DepthPyramid::new(&self.device, width, height)?;
        }
        self.config.width = width;
        self.config.height = height;
        Ok(())
    }

    /// The output and G-buffer textures.
    pub fn targets(&self) -> &RenderTargets {
        &self.targets
    }

    /// The resident nodes (gigabuffer, tables, counts).
    pub fn residency(&self) -> &Residency {
        &self.residency
    }

    /// The gigabuffer (memory use, layouts).
    pub fn gigabuffer(&self) -> &Gigabuffer {
        self.residency.gigabuffer()
    }

    /// Resident chunks.
    pub fn chunk_count(&self) -> usize {
        self.residency.chunk_count()
    }

    /// The highest level of detail any resident chunk has.
    pub fn top_level(&self) -> u32 {
        self.residency.top_level()
    }

    /// Resident chunks per level of detail.
    pub fn chunks_per_level(&self) -> [u32; 16] {
        self.residency.chunks_per_level()
    }

    /// Smooth quads of the resident chunks.
    pub fn smooth_quad_count(&self) -> u64 {
        self.residency.smooth_quad_count()
    }

    /// GPU bytes the renderer holds, by kind: the gigabuffer's used bytes per data kind, the
    /// chunk and node tables, the cull's outputs and far list, the far visibility buffers.
    /// (Render targets are not counted: they depend on the output size only.)
    pub fn resident_bytes(&self) -> Vec<(&'static str, u64)> {
        let mut out = self.residency.resident_bytes();
        out.extend(self.passes.culls.resident_bytes());
        if let Some(grass) = &self.passes.grass {
            out.push(("grass draws", grass.resident_bytes()));
        }
        if let Some(shells) = &self.passes.shells {
            out.push(("shell draws", shells.resident_bytes()));
        }
        if let Some(shadow) = &self.passes.shadow {
            out.push(("shadow grid and visibility", shadow.resident_bytes()));
        }
        if let Some(splat) = &self.passes.far_splat {
            out.push((
                "far visibility buffers",
                splat.visibility().size() + splat.transparent().size(),
            ));
        }
        out
    }

    /// Uploads a chunk's mesh (its bytes reach the GPU with the next recorded frame) and
    /// returns its handle. On error nothing stays allocated.
    pub fn upload_chunk(&mut self, mesh: &ChunkMeshData<'_>) -> Result<ChunkHandle, RenderError> {
        Ok(self.residency.upload(mesh)?)
    }

    /// Sends the pending uploads (gigabuffer copies, chunk and node records) to the GPU now,
    /// in a submission of their own, without drawing: for a renderer that streams chunks in
    /// while nothing of it is shown (a recorded frame starts with the same flush).
    pub fn flush_uploads(&mut self) -> Result<(), RenderError> {
        let mut encoder = self.device.create_command_encoder(&Default::default());
        self.residency.flush(&mut encoder, &self.queue)?;
        self.queue.submit([encoder.finish()]);
        Ok(())
    }

    /// Frees a resident chunk: its space and table slot. A stale or foreign handle is an
    /// error and frees nothing.
    pub fn free_chunk(&mut self, handle: ChunkHandle) -> Result<(), RenderError> {
        Ok(self.residency.free(handle)?)
    }

    /// Reads the last frame's output and depth back (blocks).
    ///
    /// The depth is the frame's: where a far draw was splatted nearer than the rasterised
    /// depth, the splat's.
    pub fn read_image(&self) -> Result<FrameImage, RenderError> {
        let mut image = read_output(&self.device, &self.queue, &self.targets)?;
        if let Some(splat) = &self.passes.far_splat {
            let words: Vec<[u32; 2]> = bytemuck::pod_collect_to_vec(&crate::readback::read_buffer(
                &self.device,
                &self.queue,
                splat.visibility(),
                0,
                splat.visibility().size(),
            )?);
            for (depth, word) in image.depth.iter_mut().zip(words) {
                *depth = depth.max(f32::from_bits(word[1]));
            }
        }
        Ok(image)
    }
}
