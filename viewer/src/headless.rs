//! The streamed terrain without a window: loading the first view (with progress reports) and
//! rendering frames of it, on a headless device.
//!
//! Nothing is drawn before the first plan is committed; until then the view flushes its
//! uploads to the GPU by itself ([`StreamedView::update`]).

use std::time::{Duration, Instant};

use gpu_backend::{GpuContext, PassTime};
use render_model::camera::Camera;

use crate::stream::{StreamError, StreamStatus};
use crate::view::StreamedView;

/// How often the progress callback is called while loading.
pub const PROGRESS_EVERY: Duration = Duration::from_millis(500);

/// Records and submits one frame of `view` and waits for it: its per-pass times.
pub fn draw_frame(ctx: &GpuContext, view: &mut StreamedView) -> Result<Vec<PassTime>, StreamError> {
    let renderer = view.renderer_mut();
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    renderer
        .record_frame(&mut encoder)
        .map_err(StreamError::Renderer)?;
    ctx.queue.submit([encoder.finish()]);
    renderer.collect_timings().map_err(StreamError::Renderer)
}

/// Streams `view` around `camera` until it has settled ([`StreamStatus::settled`]: the
/// resident nodes are exactly the committed view's) with no replacement loading (or `timeout`
/// passes: an error). `progress` gets the status every
/// [`PROGRESS_EVERY`] and once at the end.
pub fn load(
    view: &mut StreamedView,
    camera: &Camera,
    timeout: Duration,
    mut progress: impl FnMut(&StreamStatus),
) -> Result<(), StreamError> {
    let started = Instant::now();
    let mut reported = started;
    loop {
        view.update(camera)?;
        let (status, next) = view.status();
        if status.settled() && next.is_none() {
            view.renderer_mut()
                .flush_uploads()
                .map_err(StreamError::Renderer)?;
            progress(&status);
            return Ok(());
        }
        if reported.elapsed() >= PROGRESS_EVERY {
            reported = Instant::now();
            progress(&status);
        }
        if started.elapsed() > timeout {
            return Err(StreamError::TimedOut {
                seconds: timeout.as_secs(),
                progress: status.progress_line(),
            });
        }
        std::thread::sleep(Duration::from_millis(1));
    }
}
