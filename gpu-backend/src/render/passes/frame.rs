//! What every pass of a frame reads ([`FrameCtx`]) and where it records ([`Recorder`]: the
//! frame's encoder, its open compute pass and the frame's GPU timer).

use wgpu::{BindGroup, Buffer, CommandEncoder, ComputePass, Device, Queue};

use super::shared::Shared;
use super::targets::RenderTargets;
use crate::pass_chain::PassChain;
use crate::residency::Residency;
use crate::timing::{GpuTimer, TimerScope};

/// One opaque phase of a frame. Without occlusion culling a frame has only the early phase,
/// which draws every node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// The nodes visible last frame (every node without occlusion culling); clears the depth.
    Early,
    /// Every other node, tested against the early phase's depth pyramid; draws over the early
    /// phase's depth.
    Late,
}

impl Phase {
    /// `name` in the early phase, `late_name` in the late one (timer labels).
    pub fn label(self, name: &'static str, late_name: &'static str) -> &'static str {
        match self {
            Phase::Early => name,
            Phase::Late => late_name,
        }
    }
}

/// What every pass of one frame reads: the device, the resident nodes, the targets, the
/// frame's uniforms and the choices of this frame. Passes hand each other their outputs as
/// arguments (the cull's commands, the splat's visibility buffers), so the frame's data flow
/// reads in [`Renderer::record_frame`](crate::render::Renderer::record_frame).
#[derive(Debug)]
pub struct FrameCtx<'a> {
    /// The device.
    pub device: &'a Device,
    /// The queue.
    pub queue: &'a Queue,
    /// The resident nodes: gigabuffer pages and tables.
    pub residency: &'a Residency,
    /// The frame's render targets.
    pub targets: &'a RenderTargets,
    /// What the passes share: bind group layouts, the frame uniforms and materials, the quad
    /// index buffer, the bind group cache.
    pub shared: &'a Shared,
    /// Group 0 of every renderer pipeline: frame uniforms and materials.
    pub frame_group: &'a BindGroup,
    /// The opaque visibility buffer of the frame (64-bit words), when it has one: the far
    /// splat's, which the compute rasteriser also draws into.
    pub visibility: Option<&'a Buffer>,
    /// Meshes are drawn as their quads' edges.
    pub wireframe: bool,
    /// The opaque greedy quads go through the compute rasteriser this frame.
    pub quads_in_compute: bool,
}

impl FrameCtx<'_> {
    /// The output size, pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.targets.width, self.targets.height)
    }
}

/// A timer scope opened by [`Recorder::begin`], and where its timestamps go.
#[derive(Debug)]
pub struct StepScope {
    scope: TimerScope,
    dispatches_only: bool,
}

/// Where a frame's passes record: the frame's encoder with at most one open compute pass
/// ([`PassChain`]: consecutive dispatches share one), and the frame's timer.
pub struct Recorder<'e, 't> {
    chain: PassChain<'e>,
    timer: &'t mut GpuTimer,
}

impl std::fmt::Debug for Recorder<'_, '_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Recorder")
            .field("compute_passes_opened", &self.chain.passes_opened())
            .finish_non_exhaustive()
    }
}

impl<'e, 't> Recorder<'e, 't> {
    /// A recorder over `encoder`, timing with `timer`.
    pub fn new(encoder: &'e mut CommandEncoder, timer: &'t mut GpuTimer) -> Recorder<'e, 't> {
        Recorder {
            chain: PassChain::new(encoder, "frame compute"),
            timer,
        }
    }

    /// The open compute pass (opened here when none is).
    pub fn compute(&mut self) -> &mut ComputePass<'static> {
        self.chain.compute()
    }

    /// The encoder, for copies, clears and render passes (ends the open compute pass).
    pub fn encoder(&mut self) -> &mut CommandEncoder {
        self.chain.encoder()
    }

    /// Opens the timer scope of a step labelled `label`: inside the open compute pass when the
    /// step only dispatches (`dispatches_only`), on the encoder otherwise (so that a step of
    /// render passes does not open a compute pass for its timestamps).
    pub fn begin(&mut self, label: &str, dispatches_only: bool) -> StepScope {
        let scope = if dispatches_only {
            self.timer.begin_chained(&mut self.chain, label)
        } else {
            self.timer.begin(self.chain.encoder(), label)
        };
        StepScope {
            scope,
            dispatches_only,
        }
    }

    /// Closes a scope of [`begin`](Self::begin).
    pub fn end(&mut self, step: StepScope) {
        if step.dispatches_only {
            self.timer.end_chained(&mut self.chain, step.scope);
        } else {
            self.timer.end(self.chain.encoder(), step.scope);
        }
    }

    /// Runs `record` inside a timer scope labelled `label` (see [`begin`](Self::begin)).
    pub fn step<T>(
        &mut self,
        label: &str,
        dispatches_only: bool,
        record: impl FnOnce(&mut Self) -> T,
    ) -> T {
        let scope = self.begin(label, dispatches_only);
        let out = record(self);
        self.end(scope);
        out
    }

    /// Ends the open compute pass and records the timer's resolve: the frame's last commands.
    pub fn finish(self) {
        let Recorder { mut chain, timer } = self;
        timer.resolve(chain.encoder());
    }
}
