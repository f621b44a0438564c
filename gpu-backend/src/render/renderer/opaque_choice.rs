//! The opaque path chosen by measurement ([`OpaquePath::Auto`]): the same frame drawn with
//! the raster pass and with the compute rasteriser, alternately, and the faster kept.
//!
//! Which path wins is the GPU's: consumer GPUs rasterise far faster than the compute parts of
//! the GPU machine (H100/H200), whose few raster units bound the raster pass by geometry. So
//! the choice is measured on the device, at the caller's view, with GPU timestamps; without
//! timestamps or without the compute rasteriser the raster path stays, and the choice says why.

use std::fmt;

use super::Renderer;
use super::config::OpaquePath;
use crate::render::error::RenderError;
use crate::timing::TimingSource;

/// What [`Renderer::measure_opaque_paths`] found and kept.
#[derive(Clone, Debug, PartialEq)]
pub struct OpaqueChoice {
    /// The path kept (`Raster` or `Compute`).
    pub path: OpaquePath,
    /// Median GPU milliseconds per frame on each path, `(raster, compute)`, when measured.
    pub measured_ms: Option<(f64, f64)>,
    /// Frames drawn per path.
    pub frames: usize,
    /// Why nothing was measured, when nothing was.
    pub unmeasured: Option<&'static str>,
}

impl fmt::Display for OpaqueChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = |p: OpaquePath| match p {
            OpaquePath::Compute => "compute",
            _ => "raster",
        };
        match (self.measured_ms, self.unmeasured) {
            (Some((raster, compute)), _) => write!(
                f,
                "{} (GPU time per frame: raster {raster:.2} ms, compute {compute:.2} ms; medians of \
                 {} frames each, alternated)",
                name(self.path),
                self.frames
            ),
            (None, Some(why)) => write!(f, "{} (not measured: {why})", name(self.path)),
            (None, None) => write!(f, "{}", name(self.path)),
        }
    }
}

impl Renderer {
    /// Draws the current view `frames` times with each opaque path, alternating (so both see
    /// the same machine state), and keeps the one with the lower median GPU time per frame.
    /// Blocks until the frames are done. Keeps the raster path, saying why, when the renderer
    /// has no compute rasteriser (see [`OpaquePath::Auto`]) or the device no timestamps.
    pub fn measure_opaque_paths(&mut self, frames: usize) -> Result<OpaqueChoice, RenderError> {
        let frames = frames.max(1);
        let unmeasured = if self.passes.quad_raster.is_none() {
            Some("the renderer has no compute rasteriser (it needs 64-bit atomic min/max)")
        } else if self.timer.source() != TimingSource::GpuTimestamps {
            Some("the device has no GPU timestamps to measure with")
        } else {
            None
        };
        if let Some(why) = unmeasured {
            self.view.opaque = OpaquePath::Raster;
            return Ok(OpaqueChoice {
                path: OpaquePath::Raster,
                measured_ms: None,
                frames: 0,
                unmeasured: Some(why),
            });
        }
        let paths = [OpaquePath::Raster, OpaquePath::Compute];
        let mut times: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
        // One untimed frame each first: pipelines and bind groups are made at first use.
        for path in paths {
            self.view.opaque = path;
            self.render()?;
        }
        for _ in 0..frames {
            for (i, path) in paths.into_iter().enumerate() {
                self.view.opaque = path;
                let passes = self.render()?;
                times[i].push(passes.iter().map(|p| p.nanoseconds as f64 / 1e6).sum());
            }
        }
        let [raster, compute] = times.map(|mut t| {
            t.sort_by(f64::total_cmp);
            t[t.len() / 2]
        });
        let path = if compute < raster {
            OpaquePath::Compute
        } else {
            OpaquePath::Raster
        };
        self.view.opaque = path;
        Ok(OpaqueChoice {
            path,
            measured_ms: Some((raster, compute)),
            frames,
            unmeasured: None,
        })
    }
}
