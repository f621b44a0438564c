//! One frame, pass by pass: [`Renderer::record_frame`].

use wgpu::CommandEncoder;

use render_model::cull::CullView;
use render_model::cull::{
    CullParams, LodParams, OcclusionView, PHASE_EARLY, PHASE_LATE, PHASE_TEST, lod,
};
use render_model::frame::{FRAME_SHADOWS, FRAME_SPLAT, FrameShape, FrameUniforms};
use render_model::grass::{self, GrassCullUniforms, GrassFrame, GrassUniforms};
use render_model::lighting::{SHADOW_FILL_LOD, ShadowFillUniforms, ShadowTraceUniforms};

use render_model::props::{PROP_CULL_FRUSTUM, PROP_CULL_OCCLUSION, PropCullUniforms};

use super::Renderer;
use crate::render::error::RenderError;
use crate::render::far::FarPath;
use crate::render::passes::cull::FrameCullParams;
use crate::render::passes::far_raster::FarRasterDraw;
use crate::render::passes::frame::{FrameCtx, Phase, Recorder};
use crate::render::passes::grass::GrassParams;
use crate::render::passes::shadow::{ShadowParams, ShadowPass};

impl Renderer {
    /// The level-of-detail selection's inputs of the next frame (anchor, budget, focal
    /// length, hysteresis), or `None` without level-of-detail selection: what a residency
    /// plan ([`memory_plan`](render_model::memory_plan)) selects with.
    pub fn lod_params(&self) -> Option<LodParams> {
        self.cull_params(false, PHASE_TEST).lod
    }

    /// The cull's parameters of the next frame: `smooth` draws the smooth layer, `phase` is
    /// the occlusion phase (ignored without occlusion culling).
    fn cull_params(&self, smooth: bool, phase: u32) -> CullParams {
        let (width, height) = (self.targets.width, self.targets.height);
        let view = &self.view;
        let lod = view.lod.map(|settings| LodParams {
            anchor_chunk: [
                view.anchor.chunk.x,
                view.anchor.chunk.y,
                view.anchor.chunk.z,
            ],
            top_level: self.residency.top_level(),
            anchor_offset: view.anchor.offset,
            budget_px: settings.budget_px,
            focal_px: lod::focal_px(view.camera.fov_y, height),
            hysteresis: settings.hysteresis,
            chunk_edge: self.config.chunk_size.edge() as f32,
            pad: 0,
        });
        let far_cell_px = match view.lod {
            Some(settings) if self.far_choice.path != FarPath::Off => Some(settings.far_cell_px),
            _ => None,
        };
        let occlusion = self.passes.culls.occlusion().then(|| OcclusionView {
            view_proj: view.camera.view_projection(width, height),
            width,
            height,
            near: view.camera.near as f32,
        });
        CullParams {
            lod,
            far_cell_px,
            smooth,
            occlusion,
            phase,
            from_list: false,
        }
    }

    /// The grass pass's parameters of the next frame (`None` when clutter is not drawn).
    /// `cull` is the frame's last opaque cull record, whose selection the grass follows.
    fn grass_params(&self, view: &CullView, cull: &CullParams) -> Option<GrassParams> {
        self.passes.grass.as_ref()?;
        if !self.view.clutter {
            return None;
        }
        let focal_px = lod::focal_px(self.view.camera.fov_y, self.targets.height);
        let budget_px = self
            .view
            .lod
            .map_or(grass::DEFAULT_BUDGET_PX, |l| l.budget_px);
        let mut flags = 0;
        if cull.lod.is_some() {
            flags |= grass::GRASS_CULL_LOD;
        }
        if self.passes.culls.occlusion() {
            flags |= grass::GRASS_CULL_OCCLUSION;
        }
        let frame = GrassFrame {
            wind_phase: grass::wind_phase(self.view.time),
            wind_strength: self.view.wind,
            focal_px,
            budget_px,
        };
        Some(GrassParams {
            cull: GrassCullUniforms {
                planes: view.planes,
                camera_chunk: [view.chunk.x, view.chunk.y, view.chunk.z],
                slot_bound: self.residency.table().slot_bound(),
                camera_offset: view.offset,
                chunk_edge: self.config.chunk_size.edge() as f32,
                lod: cull.lod.unwrap_or_default(),
                flags,
                focal_px,
                budget_px,
                pad: 0,
            },
            draw: GrassUniforms::from(&frame),
        })
    }

    /// The shell cull's uniforms of the next frame (`None` without a shell pass): the grass
    /// cull's layout, with the selection, frustum and occlusion of `cull`, the frame's last
    /// opaque cull record.
    fn shell_cull_uniforms(&self, view: &CullView, cull: &CullParams) -> Option<GrassCullUniforms> {
        self.passes.shells.as_ref()?;
        let mut flags = 0;
        if cull.lod.is_some() {
            flags |= grass::GRASS_CULL_LOD;
        }
        if self.passes.culls.occlusion() {
            flags |= grass::GRASS_CULL_OCCLUSION;
        }
        // The voxel cull's far rule (CullUniforms' CULL_FAR): the far path draws those nodes.
        let far = cull.lod.zip(cull.far_cell_px);
        if far.is_some() {
            flags |= grass::SHELL_CULL_FAR;
        }
        Some(GrassCullUniforms {
            planes: view.planes,
            camera_chunk: [view.chunk.x, view.chunk.y, view.chunk.z],
            slot_bound: self.residency.table().slot_bound(),
            camera_offset: view.offset,
            chunk_edge: self.config.chunk_size.edge() as f32,
            lod: cull.lod.unwrap_or_default(),
            flags,
            focal_px: far.map_or(0.0, |(lod, _)| lod.focal_px),
            // The far threshold, in the shell cull.
            budget_px: far.map_or(0.0, |(_, px)| px),
            pad: 0,
        })
    }

    /// The shadow pass's parameters of the next frame, after making the pass (and fitting it
    /// to the targets and the quad pages) when the lighting switches shadows on; `None` with
    /// shadows off.
    fn prepare_shadows(&mut self) -> Result<Option<ShadowParams>, RenderError> {
        let settings = self.view.lighting.shadows;
        if !settings.enabled() {
            return Ok(None);
        }
        let (width, height) = (self.targets.width, self.targets.height);
        let pass = match &mut self.passes.shadow {
            Some(pass) => pass,
            none => none.insert(
                ShadowPass::new(&self.device, &self.shared, width, height)
                    .map_err(RenderError::Alloc)?,
            ),
        };
        pass.fit(width, height).map_err(RenderError::Alloc)?;
        let pages = self
            .residency
            .gigabuffer()
            .layout(voxel_core::formats::DataKind::Quads)
            .page_count;
        pass.fit_pages(pages.max(1)).map_err(RenderError::Alloc)?;
        let camera = &self.view.camera;
        let edge = self.config.chunk_size.edge() as i32;
        let v = camera.voxel;
        let lod = self.cull_params(false, PHASE_TEST).lod;
        let fill = ShadowFillUniforms {
            lod: lod.unwrap_or_default(),
            camera_chunk: [v.x, v.y, v.z].map(|c| c.div_euclid(edge)),
            slot_bound: self.residency.table().slot_bound(),
            camera_block: [v.x, v.y, v.z].map(|c| c.rem_euclid(edge)),
            chunk_edge: edge as u32,
            flags: if lod.is_some() { SHADOW_FILL_LOD } else { 0 },
            page: 0,
            page_capacity: 1,
            bound_capacity: 0,
        };
        let trace = ShadowTraceUniforms::new(&settings, camera.fraction.to_array());
        let changes = self.residency.changes();
        let refill = self
            .passes
            .shadow
            .as_ref()
            .is_none_or(|pass| pass.needs_fill(&fill, changes));
        Ok(Some(ShadowParams {
            fill,
            changes,
            trace,
            refill,
        }))
    }

    /// Uploads the props' changed records and this frame's cull uniforms; `None` when no
    /// prop instance slot exists.
    fn sync_props(&mut self) -> Result<Option<PropCullUniforms>, RenderError> {
        if self.prop_passes.is_none() || self.props.registry().slot_count() == 0 {
            return Ok(None);
        }
        self.props
            .sync(&self.device, &self.queue)
            .map_err(RenderError::Props)?;
        let (width, height) = (self.targets.width, self.targets.height);
        let mut flags = PROP_CULL_FRUSTUM;
        if self.passes.hiz.is_some() && self.passes.culls.occlusion() {
            flags |= PROP_CULL_OCCLUSION;
        }
        let registry = self.props.registry();
        let uniforms = PropCullUniforms::new(
            &self.view.camera,
            width,
            height,
            registry.slot_count(),
            registry.batch_count(),
            flags,
        );
        if let Some(b) = self.props.buffers() {
            self.queue
                .write_buffer(&b.uniforms, 0, bytemuck::bytes_of(&uniforms));
        }
        Ok(Some(uniforms))
    }

    /// Records a whole frame into `encoder`, each pass timed by the renderer's
    /// [`GpuTimer`](crate::timing::GpuTimer), then the timer's resolve. Submit the encoder (on
    /// the CPU timing path the timer submits parts of it itself), then call
    /// [`collect_timings`](Self::collect_timings) if wanted.
    ///
    /// ```text
    ///  uploads ─► cull (opaque) ─► quad raster │ far splat ─► G-buffer  (all nodes, or with
    ///                                                                   occlusion culling the
    ///                                                                   early phase: the nodes
    ///                                                                   visible last frame)
    ///          [─► depth pyramid ─► the same four, late, for the rest]  occlusion only
    ///          [─► grass (cull and draw)]                               with clutter
    ///          ─► cull transparent (back to front) [─► shadow grid ─► shadow trace]
    ///          ─► lighting ─► transparent ─► blended props ─► tonemap   (shadows: with them on)
    ///          [─► antialias]                                           when configured
    /// ```
    ///
    /// Every copy and clear comes first; the passes that only dispatch then share compute
    /// passes (`PassChain`), which only a render pass ends: on the compute opaque path with
    /// compute full-screen passes the frame is one compute pass up to lighting, the transparent
    /// pass, and the tonemap's (and the antialias) pass.
    pub fn record_frame(&mut self, encoder: &mut CommandEncoder) -> Result<(), RenderError> {
        self.health.check()?;
        self.residency.flush(encoder, &self.queue)?;
        let prop_uniforms = self.sync_props()?;
        let shadow_params = self.prepare_shadows()?;
        let (width, height) = (self.targets.width, self.targets.height);
        let shape = FrameShape {
            width,
            height,
            chunk_size: self.config.chunk_size,
            material_count: self.shared.material_count(),
            smooth_extent: self.config.smooth.extent,
            smooth_origin: self.config.smooth.origin,
            flags: if self.passes.far_splat.is_some() {
                FRAME_SPLAT
            } else {
                0
            } | if shadow_params.is_some() {
                FRAME_SHADOWS
            } else {
                0
            },
        };
        let uniforms = FrameUniforms::new(&self.view.camera, &self.view.lighting, &shape);
        let params = FrameCullParams {
            early: self.cull_params(true, PHASE_EARLY),
            late: self.cull_params(true, PHASE_LATE),
            transparent: CullParams {
                from_list: true,
                ..self.cull_params(false, PHASE_TEST)
            },
        };
        let view = self
            .view
            .camera
            .cull_view(self.config.chunk_size, width, height);
        let grass_params = self.grass_params(&view, &params.late);
        let shell_cull = self.shell_cull_uniforms(&view, &params.late);
        let frame_group = self.shared.frame_group();
        let quads_in_compute = self.quads_in_compute();
        // The wireframe view's one-pixel lines are what it shows: anti-aliasing would blur
        // them (`set_wireframe`).
        let antialias = self.config.antialias && !self.view.wireframe;
        let passes = &self.passes;
        let splat = passes.far_splat.as_ref();
        let ctx = FrameCtx {
            device: &self.device,
            queue: &self.queue,
            residency: &self.residency,
            targets: &self.targets,
            shared: &self.shared,
            frame_group: &frame_group,
            visibility: splat.map(|s| s.visibility()),
            wireframe: self.view.wireframe,
            quads_in_compute,
        };
        let culls = &passes.culls;
        let far_raster = passes
            .far_raster
            .as_ref()
            .map(|raster| FarRasterDraw::new(raster, &ctx, culls.frame()));
        // The splat draws far nodes only on the splat far path (on the compute opaque path
        // its buffers exist for the rasteriser alone).
        let far_splat = splat.filter(|_| self.far_choice.path == FarPath::Splat);
        let quad_raster = passes
            .quad_raster
            .as_ref()
            .zip(splat)
            .filter(|_| quads_in_compute);

        // Every clear and copy first.
        culls.clear(encoder);
        if let Some(grass) = &passes.grass {
            grass.clear(encoder);
        }
        if let Some(shells) = &passes.shells {
            shells.clear(encoder);
        }
        if let Some(splat) = splat {
            splat.clear(encoder);
        }
        if let Some(far) = &far_raster {
            far.raster.clear(encoder);
        }
        let shadow = passes.shadow.as_ref().zip(shadow_params.as_ref());
        if let Some((shadow, _)) = shadow.filter(|(_, params)| params.refill) {
            shadow.clear(encoder);
        }
        let pyramid = passes.hiz.as_ref().map(|p| p.texture_view());
        let prepared = culls.prepare(&ctx, encoder, &view, &uniforms, &params, pyramid)?;

        let mut rec = Recorder::new(encoder, &mut self.timer);
        let mut phases = vec![Phase::Early];
        if culls.occlusion() {
            phases.push(Phase::Late);
        }
        for phase in phases {
            if phase == Phase::Late
                && let Some(pyramid) = &passes.hiz
            {
                pyramid.record(&ctx, &mut rec)?;
            }
            let commands = culls.commands(phase);
            culls.record(&mut rec, phase, &prepared);
            if let Some((raster, splat)) = quad_raster {
                raster.record_phase(&ctx, &mut rec, phase, commands, splat.visibility())?;
            }
            if let Some(splat) = far_splat {
                splat.record_phase(&ctx, &mut rec, phase, culls.frame());
            }
            passes
                .gbuffer
                .record(&ctx, &mut rec, phase, commands, far_raster);
        }
        // Grass after both opaque phases: the visibility bits then hold this frame's cull.
        if let Some((grass, params)) = passes.grass.as_ref().zip(grass_params.as_ref()) {
            grass.record(&ctx, &mut rec, params, culls.visible_bits());
            // The grass wrote depth: the next early G-buffer pass must clear it.
            passes.gbuffer.depth_drawn();
        }
        // Shells after both opaque phases, like the grass (shells.rs says why).
        if let Some((shells, cull)) = passes.shells.as_ref().zip(shell_cull.as_ref()) {
            shells.record(&ctx, &mut rec, cull, culls.visible_bits());
            passes.gbuffer.depth_drawn();
        }
        // The props after the opaque phases: with occlusion culling, tested against this
        // frame's pyramid (of the early phase's depth).
        if let (Some(uniforms), Some(prop), Some(buffers)) =
            (prop_uniforms, &self.prop_passes, self.props.buffers())
        {
            let pyramid = passes
                .hiz
                .as_ref()
                .map_or(&prop.no_pyramid, |p| p.texture_view());
            prop.cull
                .record(&self.device, &mut rec, buffers, &uniforms, pyramid);
            prop.draw.record(&ctx, &mut rec, &self.props);
            // The props wrote depth: the next early G-buffer pass must clear it.
            passes.gbuffer.depth_drawn();
        }
        // The transparent layer, back to front (`render_model::transparent`), and the raster
        // far draws' commands of the whole frame for their transparent blocks.
        let far_args = far_raster.is_some_and(|f| f.inputs.is_some());
        let far_group = rec.step("cull transparent", !far_args, |rec| {
            culls.record_transparent(rec, &prepared);
            far_raster
                .as_ref()
                .and_then(|f| f.record_all_args(rec.encoder()))
        });
        // Shadows after every opaque draw (the trace reads the final depth and normals).
        if let Some((shadow, params)) = shadow {
            shadow.record(&ctx, &mut rec, params);
        }
        passes.lighting.record(
            &ctx,
            &mut rec,
            splat.map(|s| s.transparent()),
            shadow.map(|(s, _)| s.visibility()),
        );
        let far = far_raster.as_ref().zip(far_group.as_ref());
        passes
            .transparent
            .record(&ctx, &mut rec, culls.transparent_commands(), far);
        // Blended props over the lit colour and the transparent layer, back to front
        // (`render_model::props::blend_order`).
        if let (Some(_), Some(prop)) = (prop_uniforms, &self.prop_passes) {
            let eye = render_model::props::PropEye::of(&self.view.camera);
            prop.draw.record_blend(&ctx, &mut rec, &self.props, &eye);
        }
        passes.tonemap.record(&ctx, &mut rec, antialias);
        if antialias {
            passes.antialias.record(&ctx, &mut rec);
        }
        rec.finish();
        Ok(())
    }
}
