//! One frame, in order: uploads, the cull of both layers, the G-buffer pass, lighting, the
//! transparent pass and the tonemap, each timed.

use wgpu::CommandEncoder;
use wgpu::util::DeviceExt;

use super::Renderer;
use crate::cull::{CullInputs, OcclusionInputs, PreparedCull, UniformSource};
use crate::pass_chain::PassChain;
use crate::render::error::RenderError;
use crate::render::far::FarPath;
use crate::render::far::raster::{FarRaster, FarRasterInputs};
use crate::render::far::splat::{SplatInputs, SplatStats};
use render_model::cull::{
    CullLayer, CullParams, CullStats, LodParams, OcclusionView, PHASE_EARLY, PHASE_LATE,
    PHASE_TEST, lod,
};
use render_model::frame::{FRAME_SPLAT, FrameShape, FrameUniforms};
use render_model::quad_raster::QuadRasterStats;
use voxel_core::formats::DataKind;

use crate::render::quad_raster::QuadRasterInputs;
use crate::timing::{PassTime, TimerScope};

impl Renderer {
    /// The highest level of detail any resident chunk has.
    pub fn top_level(&self) -> u32 {
        self.per_level.iter().rposition(|&n| n > 0).unwrap_or(0) as u32
    }

    /// Resident chunks per level of detail.
    pub fn chunks_per_level(&self) -> [u32; 16] {
        self.per_level
    }

    /// The level-of-detail selection's inputs of the next frame (anchor, budget, focal
    /// length, hysteresis), or `None` without level-of-detail selection: what a residency
    /// plan ([`memory_plan`](crate::render::memory_plan)) selects with.
    pub fn lod_params(&self) -> Option<LodParams> {
        self.cull_params(false, PHASE_TEST).lod
    }

    /// The cull's parameters of the next frame: `smooth` draws the smooth layer, `phase` is
    /// the occlusion phase (ignored without occlusion culling).
    pub(super) fn cull_params(&self, smooth: bool, phase: u32) -> CullParams {
        let (width, height) = (self.targets.width, self.targets.height);
        let lod = self.lod.map(|settings| LodParams {
            anchor_chunk: [
                self.anchor.chunk.x,
                self.anchor.chunk.y,
                self.anchor.chunk.z,
            ],
            top_level: self.top_level(),
            anchor_offset: self.anchor.offset,
            budget_px: settings.budget_px,
            focal_px: lod::focal_px(self.camera.fov_y, height),
            hysteresis: settings.hysteresis,
            chunk_edge: self.config.chunk_size.edge() as f32,
            pad: 0,
        });
        let far_cell_px = match self.lod {
            Some(settings) if self.far_choice.path != FarPath::Off => Some(settings.far_cell_px),
            _ => None,
        };
        let occlusion = self.occlusion.as_ref().map(|_| OcclusionView {
            view_proj: self.camera.view_projection(width, height),
            width,
            height,
            near: self.camera.near as f32,
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

    /// Records a whole frame into `encoder`, each pass timed by the renderer's
    /// [`GpuTimer`](crate::timing::GpuTimer), then the timer's resolve. Submit the encoder (on
    /// the CPU timing path the timer submits parts of it itself), then call
    /// [`collect_timings`](Self::collect_timings) if wanted.
    ///
    /// ```text
    ///  uploads ─► cull (opaque) ─► far splat ─► G-buffer            (all nodes, or with occlusion
    ///                                                                culling the early phase:
    ///                                                                the nodes visible last frame)
    ///          [─► depth pyramid ─► cull late ─► far splat ─► G-buffer (load)]   occlusion only
    ///          ─► cull transparent (back to front) ─► lighting ─► transparent ─► tonemap
    /// ```
    ///
    /// Every copy and clear comes first; the steps that only dispatch then share compute
    /// passes ([`PassChain`]), which only a render pass ends: on the compute opaque path with
    /// compute full-screen passes the frame is one compute pass up to lighting, the transparent
    /// pass, and the tonemap's pass.
    pub fn record_frame(&mut self, encoder: &mut CommandEncoder) -> Result<(), RenderError> {
        let (width, height) = (self.targets.width, self.targets.height);
        self.gigabuffer.flush(encoder);
        self.table.flush(&self.queue);
        self.nodes.flush(&self.queue);
        let shape = FrameShape {
            width,
            height,
            chunk_size: self.config.chunk_size,
            material_count: self.material_count,
            smooth_extent: self.config.smooth.extent,
            smooth_origin: self.config.smooth.origin,
            flags: if self.splat.is_some() { FRAME_SPLAT } else { 0 },
        };
        let uniforms = FrameUniforms::new(&self.camera, &self.lighting, &shape);
        let frame_group = self.frame_group();
        let culls = self.prepare_frame(encoder, &uniforms)?;
        let mut chain = PassChain::new(encoder, "frame compute");
        self.record_opaque_phase(&mut chain, &frame_group, culls.early.as_ref(), PHASE_EARLY)?;
        if let Some(occlusion) = &self.occlusion {
            let scope = self.timer.begin_chained(&mut chain, "hiz");
            occlusion
                .pyramid
                .record_build_in(
                    chain.compute(),
                    &self.targets.depth,
                    self.splat.as_ref().map(|s| s.visibility()),
                )
                .map_err(RenderError::Hiz)?;
            self.timer.end_chained(&mut chain, scope);
            self.record_opaque_phase(&mut chain, &frame_group, culls.late.as_ref(), PHASE_LATE)?;
        }

        // The transparent layer, back to front (see `render::transparent`).
        let far_raster = self.far_raster_inputs().is_some();
        let scope = self.begin_step(&mut chain, "cull transparent", !far_raster);
        if let Some(prepared) = &culls.transparent {
            self.cull.dispatch(chain.compute(), prepared);
        }
        let far_group = self.far_raster_inputs().map(|(raster, inputs)| {
            raster.record_all_args(chain.encoder(), &inputs);
            raster.bind_group(&inputs)
        });
        self.end_step(&mut chain, scope);

        let compute = self.fullscreen_in_compute();
        let scope = self.begin_step(&mut chain, "lighting", compute);
        self.record_fullscreen(&mut chain, &frame_group, false);
        self.end_step(&mut chain, scope);

        let scope = self.begin_step(&mut chain, "transparent", false);
        self.record_transparent(chain.encoder(), &frame_group, far_group.as_ref());
        self.end_step(&mut chain, scope);

        let scope = self.begin_step(&mut chain, "tonemap", compute);
        self.record_fullscreen(&mut chain, &frame_group, true);
        self.end_step(&mut chain, scope);
        drop(chain);
        self.timer.resolve(encoder);
        Ok(())
    }

    /// The frame's uniforms, its clears and every cull record's copies and clears, in
    /// `encoder` before the frame's compute chain, so that the dispatches after them can share
    /// compute passes. The frame's and the records' uniforms go through one staging buffer:
    /// creating a buffer (or `Queue::write_buffer`, which creates one) costs the CPU more than
    /// the copies (on the NVIDIA driver about 10 k and 34 k instructions).
    fn prepare_frame(
        &self,
        encoder: &mut CommandEncoder,
        frame_uniforms: &FrameUniforms,
    ) -> Result<FrameCulls, RenderError> {
        let (width, height) = (self.targets.width, self.targets.height);
        let camera = self.camera.cull_view(self.config.chunk_size, width, height);
        self.cull_frame.clear(encoder);
        if let Some(splat) = &self.splat {
            splat.clear(encoder);
        }
        if let Some(raster) = &self.far_raster {
            raster.clear(encoder);
        }
        let inputs = self.cull_inputs();
        let transparent_params = CullParams {
            from_list: true,
            ..self.cull_params(false, PHASE_TEST)
        };
        // The records in staging order: early, late (with occlusion culling), transparent.
        let mut records = vec![(CullLayer::Opaque, self.cull_params(true, PHASE_EARLY))];
        if self.occlusion.is_some() {
            records.push((CullLayer::Opaque, self.cull_params(true, PHASE_LATE)));
        }
        records.push((CullLayer::Transparent, transparent_params));
        let mut bytes = bytemuck::bytes_of(frame_uniforms).to_vec();
        let mut offsets = Vec::with_capacity(records.len());
        for (layer, params) in &records {
            offsets.push(bytes.len() as u64);
            let uniforms = self.cull.uniforms(&inputs, &camera, *layer, params);
            bytes.extend_from_slice(bytemuck::bytes_of(&uniforms));
        }
        let staging = self
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("frame uniforms staging"),
                contents: &bytes,
                usage: wgpu::BufferUsages::COPY_SRC,
            });
        let frame_bytes = size_of::<FrameUniforms>() as u64;
        encoder.copy_buffer_to_buffer(&staging, 0, &self.frame_uniforms, 0, frame_bytes);
        let staged = |record: usize| CullInputs {
            uniforms: UniformSource::Staged {
                buffer: &staging,
                offset: offsets[record],
            },
            ..inputs
        };
        let mut opaque = |commands, record: usize| {
            self.cull.prepare_with(
                encoder,
                &staged(record),
                &camera,
                CullLayer::Opaque,
                commands,
                &records[record].1,
            )
        };
        let early = opaque(&self.opaque_commands, 0)?;
        let late = match &self.occlusion {
            Some(o) => opaque(&o.late_commands, 1)?,
            None => None,
        };
        let last = records.len() - 1;
        let transparent = self.cull.prepare_ordered_with(
            encoder,
            &staged(last),
            &camera,
            CullLayer::Transparent,
            &self.transparent_commands,
            &records[last].1,
        )?;
        Ok(FrameCulls {
            early,
            late,
            transparent,
        })
    }

    /// Opens the timer scope of a step of the frame: inside the chain's compute pass when the
    /// step only dispatches (`dispatches_only`), on the encoder otherwise (so that a step of
    /// render passes does not open a compute pass for its timestamps).
    fn begin_step(
        &mut self,
        chain: &mut PassChain<'_>,
        label: &str,
        dispatches_only: bool,
    ) -> StepScope {
        let scope = if dispatches_only {
            self.timer.begin_chained(chain, label)
        } else {
            self.timer.begin(chain.encoder(), label)
        };
        StepScope {
            scope,
            dispatches_only,
        }
    }

    /// Closes a scope of [`begin_step`](Self::begin_step).
    fn end_step(&mut self, chain: &mut PassChain<'_>, step: StepScope) {
        if step.dispatches_only {
            self.timer.end_chained(chain, step.scope);
        } else {
            self.timer.end(chain.encoder(), step.scope);
        }
    }

    /// What every cull record of the frame reads.
    fn cull_inputs(&self) -> CullInputs<'_> {
        CullInputs {
            table: &self.table,
            nodes: Some(&self.nodes),
            frame: Some(&self.cull_frame),
            occlusion: self.occlusion.as_ref().map(|o| OcclusionInputs {
                visible: &o.visible,
                pyramid: o.pyramid.texture_view(),
            }),
            uniforms: UniformSource::Own,
        }
    }

    /// One opaque phase: the cull into its commands (`cull`, prepared by
    /// [`prepare_frame`](Self::prepare_frame); `None` when the table has no slots), the splat of
    /// the far nodes it listed, and the G-buffer pass of its meshed nodes (the early phase
    /// clears the G-buffer, the late one draws over it). Without occlusion culling the early
    /// phase draws every node.
    fn record_opaque_phase(
        &mut self,
        chain: &mut PassChain<'_>,
        frame_group: &wgpu::BindGroup,
        cull: Option<&PreparedCull>,
        phase: u32,
    ) -> Result<(), RenderError> {
        let late = phase == PHASE_LATE;
        let commands = match (&self.occlusion, late) {
            (Some(o), true) => &o.late_commands,
            _ => &self.opaque_commands,
        };
        let label =
            |name: &'static str, late_name: &'static str| if late { late_name } else { name };
        let scope = self.timer.begin_chained(chain, label("cull", "cull late"));
        if let Some(cull) = cull {
            self.cull.dispatch(chain.compute(), cull);
        }
        self.timer.end_chained(chain, scope);
        if let Some(raster) = self
            .quad_raster
            .as_ref()
            .filter(|_| self.quads_in_compute())
        {
            let scope = self
                .timer
                .begin_chained(chain, label("quad raster", "quad raster late"));
            raster.record_in(
                chain.compute(),
                &QuadRasterInputs {
                    frame_uniforms: &self.frame_uniforms,
                    commands,
                    quads: &self.gigabuffer,
                    visibility: self
                        .splat
                        .as_ref()
                        .expect("made with the rasteriser")
                        .visibility(),
                    width: self.targets.width,
                    height: self.targets.height,
                },
            )?;
            self.timer.end_chained(chain, scope);
        }
        let splat = self
            .splat
            .as_ref()
            .filter(|_| self.far_choice.path == FarPath::Splat);
        if let (Some(splat), Some(blocks)) = (splat, self.gigabuffer.page(DataKind::DrawBlocks, 0))
        {
            let scope = self
                .timer
                .begin_chained(chain, label("far splat", "far splat late"));
            splat.record_in(
                chain.compute(),
                &SplatInputs {
                    frame_uniforms: &self.frame_uniforms,
                    table: self.table.buffer(),
                    nodes: self.nodes.buffer(),
                    blocks,
                    frame: &self.cull_frame,
                },
            );
            self.timer.end_chained(chain, scope);
        }
        // On the compute opaque path with no smooth layer and no raster far draws nothing
        // is rasterised: the pass only clears the depth, which stays clear until a pass
        // draws (a full-screen clear costs ~0.16 ms on the H100's few raster units).
        let draws = !self.quads_in_compute() || self.has_smooth() || self.far_raster.is_some();
        if !draws && (late || self.depth_clear) {
            return Ok(());
        }
        // The raster far draws' commands are timed with the G-buffer pass that draws them.
        let encoder = chain.encoder();
        let scope = self.timer.begin(encoder, label("gbuffer", "gbuffer late"));
        let far_group = self.far_raster_inputs().map(|(raster, inputs)| {
            raster.record_phase_args(encoder, &inputs);
            raster.bind_group(&inputs)
        });
        self.record_gbuffer(encoder, frame_group, commands, !late, far_group.as_ref());
        self.timer.end(encoder, scope);
        self.depth_clear = !draws;
        Ok(())
    }

    /// The raster far draws and what they bind, when they are the far path and draw blocks
    /// are resident.
    fn far_raster_inputs(&self) -> Option<(&FarRaster, FarRasterInputs<'_>)> {
        let raster = self.far_raster.as_ref()?;
        let blocks = self.gigabuffer.page(DataKind::DrawBlocks, 0)?;
        Some((
            raster,
            FarRasterInputs {
                table: self.table.buffer(),
                nodes: self.nodes.buffer(),
                blocks,
                frame: &self.cull_frame,
            },
        ))
    }

    /// Records and submits one frame, waits for it, and returns its per-pass times.
    pub fn render(&mut self) -> Result<Vec<PassTime>, RenderError> {
        let mut encoder = self.device.create_command_encoder(&Default::default());
        self.record_frame(&mut encoder)?;
        self.submit_frame(encoder);
        self.collect_timings()
    }

    /// Finishes and submits `encoder` (holding a frame from
    /// [`record_frame`](Self::record_frame)), and tells the frame's timer which submission
    /// carried it, so that [`collect_oldest_timings`](Self::collect_oldest_timings) waits for
    /// that frame only.
    pub fn submit_frame(&mut self, encoder: CommandEncoder) -> wgpu::SubmissionIndex {
        let submission = self.queue.submit([encoder.finish()]);
        self.frame_submitted(submission.clone());
        submission
    }

    /// Tells the frame's timer which submission carried the last recorded frame, for callers
    /// that submit it themselves (with other command buffers; see
    /// [`submit_frame`](Self::submit_frame)).
    pub fn frame_submitted(&mut self, submission: wgpu::SubmissionIndex) {
        self.timer.submitted(submission);
    }

    /// The last submitted frame's per-pass times (waits for every submitted frame; the
    /// figures of older frames not yet collected are discarded).
    pub fn collect_timings(&mut self) -> Result<Vec<PassTime>, RenderError> {
        self.timer.collect().map_err(RenderError::Timer)
    }

    /// The oldest submitted frame's per-pass times, waiting for that frame only; `None` when
    /// every frame was collected. A loop that keeps one frame in flight records frame `n + 1`,
    /// submits it with [`submit_frame`](Self::submit_frame), then collects frame `n` here, so
    /// the CPU's work on a frame overlaps the GPU's on the one before. At most
    /// [`FRAMES_IN_FLIGHT`](crate::timing::FRAMES_IN_FLIGHT) frames wait; older ones are
    /// dropped uncollected.
    pub fn collect_oldest_timings(&mut self) -> Result<Option<Vec<PassTime>>, RenderError> {
        self.timer.collect_oldest().map_err(RenderError::Timer)
    }

    /// Submitted frames whose times were not collected yet.
    pub fn frames_in_flight(&self) -> usize {
        self.timer.frames_in_flight()
    }

    /// Clears the compute rasteriser's counters (`OpaquePath::Compute`; nothing otherwise), so
    /// that [`Renderer::read_quad_raster_stats`] counts from here (record it before a frame).
    pub fn clear_quad_raster_stats(&self, encoder: &mut CommandEncoder) {
        if let Some(raster) = &self.quad_raster {
            raster.clear_stats(encoder);
        }
    }

    /// The compute rasteriser's counters since [`Renderer::clear_quad_raster_stats`]: quads,
    /// pixel centres tested and hit, big quads and tiles (`None` on the raster opaque path;
    /// blocks until the GPU is done; for tests and benchmarks).
    pub fn read_quad_raster_stats(&self) -> Result<Option<QuadRasterStats>, RenderError> {
        let Some(raster) = &self.quad_raster else {
            return Ok(None);
        };
        Ok(Some(raster.read_stats(&self.device, &self.queue)?))
    }

    /// The last submitted frame's cull counters (nodes per level and representation, culled
    /// nodes, primitives drawn) and the splat's (blocks until the GPU is done; for tests and
    /// benchmarks).
    pub fn read_frame_stats(&self) -> Result<(CullStats, SplatStats), RenderError> {
        let words: Vec<u32> = bytemuck::pod_collect_to_vec(&crate::readback::read_buffer(
            &self.device,
            &self.queue,
            self.cull_frame.stats(),
            0,
            self.cull_frame.stats().size(),
        )?);
        Ok((
            CullStats::from_words(&words),
            SplatStats::from_words(&words),
        ))
    }
}

/// The frame's cull records, prepared ([`Renderer::prepare_frame`]); `None` where a record has
/// nothing to dispatch.
struct FrameCulls {
    early: Option<PreparedCull>,
    /// With occlusion culling only.
    late: Option<PreparedCull>,
    transparent: Option<PreparedCull>,
}

/// A timer scope of one step of the frame, and where its timestamps go.
struct StepScope {
    scope: TimerScope,
    dispatches_only: bool,
}
