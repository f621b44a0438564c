//! Submitting a recorded frame, collecting its pass times, and reading its counters back.

use wgpu::CommandEncoder;

use render_model::cull::CullStats;
use render_model::quad_raster::QuadRasterStats;

use super::Renderer;
use crate::render::error::RenderError;
use crate::render::passes::far_splat::SplatStats;
use crate::timing::PassTime;

impl Renderer {
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
        if let Some(raster) = &self.passes.quad_raster {
            raster.clear_stats(encoder);
        }
    }

    /// The compute rasteriser's counters since [`Renderer::clear_quad_raster_stats`]: quads,
    /// pixel centres tested and hit, big quads and tiles (`None` on the raster opaque path;
    /// blocks until the GPU is done; for tests and benchmarks).
    pub fn read_quad_raster_stats(&self) -> Result<Option<QuadRasterStats>, RenderError> {
        let Some(raster) = &self.passes.quad_raster else {
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
            self.passes.culls.frame().stats(),
            0,
            self.passes.culls.frame().stats().size(),
        )?);
        Ok((
            CullStats::from_words(&words),
            SplatStats::from_words(&words),
        ))
    }

    /// The last frame's per-pixel sun and sky visibility (row-major, the shadow pass's
    /// words), or `None` when no frame has had shadows on.
    pub fn read_shadow_visibility(
        &self,
    ) -> Result<Option<Vec<render_model::lighting::shadow::Visibility>>, RenderError> {
        let Some(shadow) = &self.passes.shadow else {
            return Ok(None);
        };
        let buffer = shadow.visibility();
        let bytes =
            crate::readback::read_buffer(&self.device, &self.queue, buffer, 0, buffer.size())?;
        let words: Vec<u32> = bytemuck::pod_collect_to_vec(&bytes);
        Ok(Some(
            words
                .into_iter()
                .map(render_model::lighting::shadow::Visibility::unpack)
                .collect(),
        ))
    }
}
