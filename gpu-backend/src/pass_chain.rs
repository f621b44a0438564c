//! A frame's consecutive compute work recorded into one compute pass.
//!
//! **Why.** wgpu-core turns every pass into two command buffers of the driver (the pass, and one
//! in front of it holding the barriers into the pass) and the encoder-level commands between
//! passes into a third. Begin, end and submit of those command buffers cost the CPU more than
//! the dispatches themselves (on the NVIDIA driver, a frame whose every step has its own pass
//! spends a seventh of its recording instructions on them). Within one
//! compute pass wgpu still places a barrier between dependent dispatches, so steps that only
//! dispatch can share a pass.
//!
//! A [`PassChain`] holds the frame's encoder and at most one open compute pass:
//! [`compute`](PassChain::compute) returns the open pass (opening one when none is), and
//! [`encoder`](PassChain::encoder) ends it and returns the encoder, for copies, clears and
//! render passes. A step that only dispatches records into `compute()`; its clears and copies
//! belong before the chain starts (or in a shader, as the first thing its first dispatch
//! does).
//!
//! ```text
//! let mut chain = PassChain::new(&mut encoder, "frame compute");
//! cull.dispatch(chain.compute(), &prepared);          // one pass ...
//! pyramid.record_build_in(chain.compute(), ...)?;     // ... the same pass
//! record_render_pass(chain.encoder());                // ends it
//! ```

use wgpu::{CommandEncoder, ComputePass};

/// The frame's encoder with at most one open compute pass (see the [module docs](self)).
pub struct PassChain<'e> {
    encoder: &'e mut CommandEncoder,
    /// The open pass. `'static` because it lives beside the encoder it borrows; wgpu keeps
    /// the encoder locked while the pass is open, and [`PassChain::encoder`] ends it first.
    pass: Option<ComputePass<'static>>,
    label: &'static str,
    opened: u32,
}

impl<'e> PassChain<'e> {
    /// A chain over `encoder` whose compute passes are labelled `label`.
    pub fn new(encoder: &'e mut CommandEncoder, label: &'static str) -> PassChain<'e> {
        PassChain {
            encoder,
            pass: None,
            label,
            opened: 0,
        }
    }

    /// The open compute pass, opened here when none is.
    pub fn compute(&mut self) -> &mut ComputePass<'static> {
        if self.pass.is_none() {
            self.opened += 1;
        }
        let (encoder, label) = (&mut *self.encoder, self.label);
        self.pass.get_or_insert_with(|| {
            encoder
                .begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(label),
                    timestamp_writes: None,
                })
                .forget_lifetime()
        })
    }

    /// The encoder, for work outside compute passes: ends the open compute pass first.
    pub fn encoder(&mut self) -> &mut CommandEncoder {
        self.pass = None;
        self.encoder
    }

    /// Compute passes this chain has opened so far: how the frame's work is grouped (fewer
    /// passes cost the CPU less).
    pub fn passes_opened(&self) -> u32 {
        self.opened
    }
}

impl std::fmt::Debug for PassChain<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PassChain")
            .field("label", &self.label)
            .field("open", &self.pass.is_some())
            .field("opened", &self.opened)
            .finish_non_exhaustive()
    }
}

impl Drop for PassChain<'_> {
    fn drop(&mut self) {
        // Ends the open pass, unlocking the encoder.
        self.pass = None;
    }
}
