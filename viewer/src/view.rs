//! [`StreamedView`]: the streamed terrain as the window and the headless modes see it, one
//! streamer drawing and, after a control that changes what nodes hold or how they are drawn,
//! a second one loading behind it.
//!
//! ```text
//!  apply(controls) ─► budget changed      ─► the streamers re-plan (no re-meshing)
//!                  └► mesher, far, layers ─► a new Streamer (new renderer) streams the same
//!                                             view; the old one keeps drawing until the new
//!                                             one has committed, then it is dropped
//! ```
//!
//! So a change never shows a hole or a half-switched terrain. Both streamers share one node
//! memory ([`NodeMemory`], the settings' `memory_bytes`): the new one loads in what the old
//! one leaves, at a raised budget if the view does not fit twice, and once it is swapped in
//! (the old one's nodes given back) it plans at the asked budget again.

use gpu_backend::GpuContext;
use gpu_backend::render::{OpaqueChoice, OpaquePath, Renderer};
use render_model::camera::Camera;

use crate::controls::Controls;
use crate::edits::SharedWorld;
use crate::stream::Invalidated;
use crate::stream::{NodeMemory, StreamError, StreamSettings, StreamStatus, Streamer};
use voxel_world::Edit;

/// Frames per opaque path that `--opaque auto` draws to choose (see
/// [`StreamedView::choose_opaque_path`]).
pub const OPAQUE_TRIAL_FRAMES: usize = 8;

/// The streamer that draws, and the one replacing it (see the [module docs](self)).
#[derive(Debug)]
pub struct StreamedView {
    current: Streamer,
    next: Option<Streamer>,
    size: (u32, u32),
    /// The node memory both streamers share.
    memory: NodeMemory,
    /// The opaque path measured with `--opaque auto`, kept for replacement renderers.
    opaque_choice: Option<OpaqueChoice>,
    /// The world both streamers build from.
    world: SharedWorld,
}

impl StreamedView {
    /// A view of the terrain of `settings` drawing `width x height`, unedited.
    pub fn new(
        ctx: &GpuContext,
        settings: &StreamSettings,
        width: u32,
        height: u32,
    ) -> Result<StreamedView, StreamError> {
        let world = SharedWorld::new(settings.seed, settings.chunk, settings.top_level())
            .map_err(|e| StreamError::Edit(e.to_string()))?;
        StreamedView::with_world(ctx, settings, width, height, world)
    }

    /// A view of `world` (the terrain of `settings`' seed, edited or loaded) drawing
    /// `width x height`.
    pub fn with_world(
        ctx: &GpuContext,
        settings: &StreamSettings,
        width: u32,
        height: u32,
        world: SharedWorld,
    ) -> Result<StreamedView, StreamError> {
        let memory = NodeMemory::new(settings.memory_bytes);
        let current =
            Streamer::with_world(ctx, settings, width, height, memory.clone(), world.clone())?;
        Ok(StreamedView {
            current,
            next: None,
            size: (width, height),
            memory,
            opaque_choice: None,
            world,
        })
    }

    /// The world the view draws.
    pub fn world(&self) -> &SharedWorld {
        &self.world
    }

    /// Applies `edits` to the world (all or none: a refused edit changes nothing and is an
    /// error naming it) and makes both streamers' nodes follow: the shown ones are swapped
    /// before this returns, so the next frame shows the edits (see
    /// `stream::streamer::edits`). Returns what the drawing streamer did.
    pub fn apply_edits(&mut self, edits: &[Edit]) -> Result<Invalidated, StreamError> {
        let started = std::time::Instant::now();
        let (dirty, version) = self
            .world
            .apply_versioned(edits)
            .map_err(|e| StreamError::Edit(e.to_string()))?;
        let world = started.elapsed();
        if dirty.is_empty() {
            return Ok(Invalidated {
                world,
                ..Invalidated::default()
            });
        }
        let mut done = self.current.invalidate(&dirty, version)?;
        done.world = world;
        if let Some(next) = &mut self.next {
            next.invalidate(&dirty, version)?;
        }
        Ok(done)
    }

    /// One frame's streaming for both streamers; swaps in the new one once it has committed.
    /// Returns true when it swapped (the renderer changed: a caller that set the renderer up,
    /// e.g. its fullscreen path, does it again).
    pub fn update(&mut self, camera: &Camera) -> Result<bool, StreamError> {
        self.current.update(camera)?;
        if !self.current.ready() {
            // Nothing of it is drawn yet, so no frame flushes its uploads.
            self.current
                .renderer_mut()
                .flush_uploads()
                .map_err(StreamError::Renderer)?;
        }
        if let Some(next) = &mut self.next {
            // The replacement loads in the memory the drawn view leaves: no cache beside it.
            self.current.drop_cache()?;
            next.update(camera)?;
            next.renderer_mut()
                .flush_uploads()
                .map_err(StreamError::Renderer)?;
            if next.ready() {
                self.current = self.next.take().expect("checked above");
                // The old streamer's nodes went back to the shared memory with it.
                self.current.retry_asked_budget();
                if let Some(choice) = &self.opaque_choice {
                    self.current
                        .renderer_mut()
                        .set_opaque_path(choice.path)
                        .map_err(StreamError::Renderer)?;
                }
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// With [`OpaquePath::Auto`] in the settings: draws the current view `frames` times with
    /// each opaque path and keeps the faster, for this renderer and every replacement (see
    /// `Renderer::measure_opaque_paths`). `None` when the settings name a path, or once
    /// chosen. Call it once the view is [`ready`](Self::ready), so the frames draw the view.
    pub fn choose_opaque_path(
        &mut self,
        frames: usize,
    ) -> Result<Option<OpaqueChoice>, StreamError> {
        if self.settings().opaque != OpaquePath::Auto || self.opaque_choice.is_some() {
            return Ok(None);
        }
        let choice = self
            .current
            .renderer_mut()
            .measure_opaque_paths(frames)
            .map_err(StreamError::Renderer)?;
        if let Some(next) = &mut self.next {
            next.renderer_mut()
                .set_opaque_path(choice.path)
                .map_err(StreamError::Renderer)?;
        }
        self.opaque_choice = Some(choice.clone());
        Ok(Some(choice))
    }

    /// The opaque path measured by [`choose_opaque_path`](Self::choose_opaque_path), once.
    pub fn opaque_choice(&self) -> Option<&OpaqueChoice> {
        self.opaque_choice.as_ref()
    }

    /// True once the drawing streamer has committed a plan (frames show no hole).
    pub fn ready(&self) -> bool {
        self.current.ready()
    }

    /// The drawing streamer.
    pub fn streamer(&self) -> &Streamer {
        &self.current
    }

    /// The streamer loading behind it, while there is one.
    pub fn replacement(&self) -> Option<&Streamer> {
        self.next.as_ref()
    }

    /// The node memory both streamers share.
    pub fn memory(&self) -> &NodeMemory {
        &self.memory
    }

    /// The drawing renderer.
    pub fn renderer(&self) -> &Renderer {
        self.current.renderer()
    }

    /// The drawing renderer, mutably.
    pub fn renderer_mut(&mut self) -> &mut Renderer {
        self.current.renderer_mut()
    }

    /// The settings the view is heading for (the replacement's while one loads).
    pub fn settings(&self) -> &StreamSettings {
        self.next.as_ref().unwrap_or(&self.current).settings()
    }

    /// The controls the view is heading for.
    pub fn controls(&self) -> Controls {
        Controls::of(self.settings())
    }

    /// Applies `controls`: a new budget is planned by the streamers; a new mesher mode, far
    /// path or set of layers starts a replacement streamer (replacing one still loading, or
    /// dropping it when the controls go back to what is drawn).
    /// A control the device cannot run (e.g. a far path it lacks) is an error naming why,
    /// and changes nothing.
    pub fn apply(&mut self, ctx: &GpuContext, controls: &Controls) -> Result<(), StreamError> {
        let settings = controls
            .applied_to(self.settings())
            .validate()
            .map_err(StreamError::Settings)?;
        if !Controls::of(self.current.settings()).needs_restream(controls) {
            // Back to what is drawn: the replacement, if any, is not needed.
            self.next = None;
        } else if self.controls().needs_restream(controls) {
            let (width, height) = self.size;
            // A replaced replacement gives its nodes back to the shared memory when dropped.
            let memory = self.memory.clone();
            self.next = Some(Streamer::with_world(
                ctx,
                &settings,
                width,
                height,
                memory,
                self.world.clone(),
            )?);
        }
        if controls.budget_px != self.current.settings().budget_px {
            self.current.set_budget(controls.budget_px)?;
        }
        if let Some(next) = &mut self.next
            && controls.budget_px != next.settings().budget_px
        {
            next.set_budget(controls.budget_px)?;
        }
        Ok(())
    }

    /// Follows a new output size (both renderers).
    pub fn resize(&mut self, width: u32, height: u32) -> Result<(), StreamError> {
        self.size = (width, height);
        for streamer in std::iter::once(&mut self.current).chain(self.next.as_mut()) {
            streamer
                .renderer_mut()
                .resize(width, height)
                .map_err(StreamError::Renderer)?;
        }
        Ok(())
    }

    /// The drawing streamer's status, and the replacement's while one loads.
    pub fn status(&self) -> (StreamStatus, Option<StreamStatus>) {
        (
            self.current.status(),
            self.next.as_ref().map(Streamer::status),
        )
    }
}
