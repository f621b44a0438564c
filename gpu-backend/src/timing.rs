//! Per-pass GPU time: timestamp queries where the device has them, CPU wall time otherwise.
//!
//! One API for both paths ([`GpuCapabilities::timing`] picks):
//!
//! ```text
//! let scope = timer.begin(&mut encoder, "cull");
//! cull.record(&mut encoder, ...);
//! timer.end(&mut encoder, scope);
//! // or, for a pass of its own: timestamp_writes: timer.compute_pass_writes("lighting")
//! timer.resolve(&mut encoder);
//! queue.submit([encoder.finish()]);
//! for PassTime { label, nanoseconds } in timer.collect()? { ... }
//! ```
//!
//! **[`TimingPath::GpuTimestamps`].** Each scope owns two queries of one timestamp query set.
//! [`begin`](GpuTimer::begin) and [`end`](GpuTimer::end) write them with
//! `CommandEncoder::write_timestamp` when `TIMESTAMP_QUERY_INSIDE_ENCODERS` is enabled, and
//! otherwise as the begin / end write of an empty compute pass (plain `TIMESTAMP_QUERY`
//! suffices). [`compute_pass_writes`](GpuTimer::compute_pass_writes) and
//! [`render_pass_writes`](GpuTimer::render_pass_writes) give a pass descriptor's
//! `timestamp_writes` instead, timing exactly that pass. [`begin_chained`](GpuTimer::begin_chained)
//! and [`end_chained`](GpuTimer::end_chained) time a step of a
//! [`PassChain`]: with `TIMESTAMP_QUERY_INSIDE_PASSES` they write
//! into the chain's open compute pass, so the steps of a frame keep sharing it; otherwise they
//! fall back to `begin` / `end` on the chain's encoder. [`resolve`](GpuTimer::resolve) resolves
//! the used queries and copies them to a mappable buffer; [`collect`](GpuTimer::collect) waits,
//! reads them and converts ticks with the queue's timestamp period. Scope time is GPU time
//! between the two writes; a backwards pair (which drivers may give around reordered work)
//! reads as 0.
//!
//! **[`TimingPath::Cpu`].** No GPU clock: [`begin`](GpuTimer::begin) submits what the encoder
//! holds so far (swapping in a fresh encoder), waits for the GPU to go idle and starts a wall
//! clock; [`end`](GpuTimer::end) submits the scope's work alone, waits, and stops the clock.
//! So each scope's figure is its own submission's wall time, including submission and driver
//! overhead and the wait, and the frame is serialized: a fallback for measurement, not for
//! shipping. Pass-descriptor writes return `None` on this path; time such passes with
//! `begin` / `end` around them.
//!
//! Scopes past the capacity given to [`GpuTimer::new`] are not timed (counted in
//! [`GpuTimer::untimed_scopes`]).
//!
//! **Frames in flight.** Each [`resolve`](GpuTimer::resolve) closes a frame and queues it; its
//! queries are copied to one of [`FRAMES_IN_FLIGHT`] readback buffers, so a loop that overlaps
//! the CPU's next frame with the GPU's current one can read each frame's times later:
//! [`collect_oldest`](GpuTimer::collect_oldest) waits for the oldest queued frame only (for the
//! submission given to [`submitted`](GpuTimer::submitted), when one was), while
//! [`collect`](GpuTimer::collect) waits for all of them and returns the newest. A frame resolved
//! while every readback buffer is still queued pushes the oldest frame out uncollected (counted
//! in [`GpuTimer::dropped_frames`]).

use std::collections::VecDeque;
use std::fmt;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use wgpu::{
    Buffer, BufferDescriptor, BufferUsages, CommandEncoder, CommandEncoderDescriptor,
    ComputePassTimestampWrites, Device, QuerySet, Queue, RenderPassTimestampWrites,
    SubmissionIndex,
};

use crate::device::alloc::AllocError;
use crate::device::{GpuCapabilities, GpuContext, TimingPath};
use crate::pass_chain::PassChain;

/// One timed scope.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PassTime {
    /// The label given to `begin` or to the pass writes.
    pub label: String,
    /// Duration, nanoseconds (GPU time, or wall time on the CPU path).
    pub nanoseconds: u64,
}

/// Where the figures come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimingSource {
    /// GPU timestamp queries.
    GpuTimestamps,
    /// CPU wall clock around per-scope submissions.
    CpuWallClock,
}

/// Why figures could not be collected.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum TimerError {
    /// Timestamp scopes were recorded but [`GpuTimer::resolve`] was not called after them.
    NotResolved,
    /// Waiting for or mapping the GPU results failed.
    Gpu(String),
}

impl fmt::Display for TimerError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TimerError::NotResolved => write!(
                f,
                "timestamp scopes were recorded after the last GpuTimer::resolve"
            ),
            TimerError::Gpu(message) => write!(f, "timing readback failed: {message}"),
        }
    }
}

impl std::error::Error for TimerError {}

/// A scope opened by [`GpuTimer::begin`]; pass it to [`GpuTimer::end`].
#[derive(Debug)]
#[must_use = "a scope is only timed once ended"]
pub struct TimerScope {
    index: Option<usize>,
}

#[derive(Debug)]
struct Scope {
    label: String,
    /// First of the scope's two queries (timestamp path).
    query: u32,
    /// Wall clock start and result (CPU path).
    started: Option<Instant>,
    elapsed: Option<Duration>,
    ended: bool,
}

/// Readback buffers of the timestamp path: how many resolved frames can wait to be collected.
pub const FRAMES_IN_FLIGHT: usize = 3;

#[derive(Debug)]
struct Timestamps {
    query_set: QuerySet,
    resolve: Buffer,
    /// One per frame in flight, used in turn.
    readbacks: Vec<Buffer>,
    /// The readback the next resolve copies into.
    next_readback: usize,
    period_ns: f32,
    inside_encoders: bool,
    inside_passes: bool,
}

/// A resolved frame waiting to be collected.
#[derive(Debug)]
struct QueuedFrame {
    scopes: Vec<Scope>,
    /// The readback holding its queries (timestamp path, at least one scope).
    readback: Option<usize>,
    /// The submission that carried its resolve, once told.
    submission: Option<SubmissionIndex>,
}

/// Times labelled scopes of a frame (see the [module docs](self)).
#[derive(Debug)]
pub struct GpuTimer {
    device: Device,
    queue: Queue,
    timestamps: Option<Timestamps>,
    max_scopes: u32,
    /// The frame being recorded.
    scopes: Vec<Scope>,
    /// Resolved frames, oldest first.
    queued: VecDeque<QueuedFrame>,
    untimed: u64,
    dropped: u64,
    error: Option<TimerError>,
}

impl GpuTimer {
    /// A timer for up to `max_scopes` scopes per frame (at most 2048: two queries each, 4096
    /// per query set), on the path `ctx.capabilities.timing` chose. Errors when the device
    /// refuses the resolve or readback buffers.
    pub fn new(ctx: &GpuContext, max_scopes: u32) -> Result<GpuTimer, AllocError> {
        GpuTimer::with_capabilities(&ctx.device, &ctx.queue, &ctx.capabilities, max_scopes)
    }

    /// [`new`](Self::new) from the parts of a context.
    pub fn with_capabilities(
        device: &Device,
        queue: &Queue,
        capabilities: &GpuCapabilities,
        max_scopes: u32,
    ) -> Result<GpuTimer, AllocError> {
        let max_scopes = max_scopes.clamp(1, wgpu::QUERY_SET_MAX_QUERIES / 2);
        let timestamps = match capabilities.timing {
            TimingPath::GpuTimestamps {
                inside_encoders,
                inside_passes,
                period_ns,
            } => {
                let queries = 2 * max_scopes;
                let bytes = u64::from(queries) * wgpu::QUERY_SIZE as u64;
                let buffer = |label: &str, usage: BufferUsages| {
                    crate::device::alloc::create_buffer(
                        device,
                        &BufferDescriptor {
                            label: Some(label),
                            size: bytes,
                            usage,
                            mapped_at_creation: false,
                        },
                    )
                };
                Some(Timestamps {
                    query_set: crate::device::alloc::create_query_set(
                        device,
                        &wgpu::QuerySetDescriptor {
                            label: Some("gpu timer"),
                            ty: wgpu::QueryType::Timestamp,
                            count: queries,
                        },
                    )?,
                    resolve: buffer(
                        "gpu timer resolve",
                        BufferUsages::QUERY_RESOLVE | BufferUsages::COPY_SRC,
                    )?,
                    readbacks: (0..FRAMES_IN_FLIGHT)
                        .map(|_| {
                            buffer(
                                "gpu timer readback",
                                BufferUsages::MAP_READ | BufferUsages::COPY_DST,
                            )
                        })
                        .collect::<Result<_, _>>()?,
                    next_readback: 0,
                    period_ns,
                    inside_encoders,
                    inside_passes,
                })
            }
            TimingPath::Cpu => None,
        };
        Ok(GpuTimer {
            device: device.clone(),
            queue: queue.clone(),
            timestamps,
            max_scopes,
            scopes: Vec::new(),
            queued: VecDeque::new(),
            untimed: 0,
            dropped: 0,
            error: None,
        })
    }

    /// Where this timer's figures come from.
    pub fn source(&self) -> TimingSource {
        match self.timestamps {
            Some(_) => TimingSource::GpuTimestamps,
            None => TimingSource::CpuWallClock,
        }
    }

    /// Scopes that were not timed because the frame had more than `max_scopes`.
    pub fn untimed_scopes(&self) -> u64 {
        self.untimed
    }

    /// Resolved frames pushed out uncollected because [`FRAMES_IN_FLIGHT`] were queued.
    pub fn dropped_frames(&self) -> u64 {
        self.dropped
    }

    /// Resolved frames not yet collected.
    pub fn frames_in_flight(&self) -> usize {
        self.queued.len()
    }

    /// A new scope's index and first query, or `None` when the frame is full.
    fn open(&mut self, label: &str) -> Option<(usize, u32)> {
        if self.scopes.len() as u32 >= self.max_scopes {
            self.untimed += 1;
            return None;
        }
        let index = self.scopes.len();
        let query = 2 * index as u32;
        self.scopes.push(Scope {
            label: label.to_owned(),
            query,
            started: None,
            elapsed: None,
            ended: false,
        });
        Some((index, query))
    }

    /// Opens a scope: everything recorded into `encoder` until [`end`](Self::end) is timed.
    /// On the CPU path this submits the encoder's earlier work and waits for it.
    pub fn begin(&mut self, encoder: &mut CommandEncoder, label: &str) -> TimerScope {
        let Some((index, query)) = self.open(label) else {
            return TimerScope { index: None };
        };
        match &self.timestamps {
            Some(t) if t.inside_encoders => encoder.write_timestamp(&t.query_set, query),
            Some(t) => {
                encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("gpu timer begin"),
                    timestamp_writes: Some(ComputePassTimestampWrites {
                        query_set: &t.query_set,
                        beginning_of_pass_write_index: Some(query),
                        end_of_pass_write_index: None,
                    }),
                });
            }
            None => {
                self.submit_and_wait(encoder);
                self.scopes[index].started = Some(Instant::now());
            }
        }
        TimerScope { index: Some(index) }
    }

    /// Closes `scope`. On the CPU path this submits the scope's work and waits for it.
    pub fn end(&mut self, encoder: &mut CommandEncoder, scope: TimerScope) {
        let Some(index) = scope.index else {
            return;
        };
        let query = self.scopes[index].query + 1;
        match &self.timestamps {
            Some(t) if t.inside_encoders => encoder.write_timestamp(&t.query_set, query),
            Some(t) => {
                encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("gpu timer end"),
                    timestamp_writes: Some(ComputePassTimestampWrites {
                        query_set: &t.query_set,
                        beginning_of_pass_write_index: None,
                        end_of_pass_write_index: Some(query),
                    }),
                });
            }
            None => {
                self.submit_and_wait(encoder);
                let scope = &mut self.scopes[index];
                scope.elapsed = scope.started.map(|s| s.elapsed());
            }
        }
        self.scopes[index].ended = true;
    }

    /// [`begin`](Self::begin) for a step of a [`PassChain`]: with
    /// `TIMESTAMP_QUERY_INSIDE_PASSES` the timestamp goes into the chain's open compute pass,
    /// so timing does not split the pass; otherwise as `begin` on the chain's encoder (which
    /// ends the open pass).
    pub fn begin_chained(&mut self, chain: &mut PassChain<'_>, label: &str) -> TimerScope {
        match &self.timestamps {
            Some(t) if t.inside_passes => {
                let Some((index, query)) = self.open(label) else {
                    return TimerScope { index: None };
                };
                let t = self.timestamps.as_ref().expect("matched above");
                chain.compute().write_timestamp(&t.query_set, query);
                TimerScope { index: Some(index) }
            }
            _ => self.begin(chain.encoder(), label),
        }
    }

    /// [`end`](Self::end) for a scope opened with [`begin_chained`](Self::begin_chained).
    pub fn end_chained(&mut self, chain: &mut PassChain<'_>, scope: TimerScope) {
        match &self.timestamps {
            Some(t) if t.inside_passes => {
                let Some(index) = scope.index else {
                    return;
                };
                chain
                    .compute()
                    .write_timestamp(&t.query_set, self.scopes[index].query + 1);
                self.scopes[index].ended = true;
            }
            _ => self.end(chain.encoder(), scope),
        }
    }

    /// Timestamp writes that time one compute pass as a scope labelled `label` (pass them as
    /// the descriptor's `timestamp_writes`). `None` on the CPU path or when the frame is full.
    pub fn compute_pass_writes(&mut self, label: &str) -> Option<ComputePassTimestampWrites<'_>> {
        self.timestamps.as_ref()?;
        let (index, query) = self.open(label)?;
        self.scopes[index].ended = true;
        let t = self.timestamps.as_ref()?;
        Some(ComputePassTimestampWrites {
            query_set: &t.query_set,
            beginning_of_pass_write_index: Some(query),
            end_of_pass_write_index: Some(query + 1),
        })
    }

    /// [`compute_pass_writes`](Self::compute_pass_writes) for a render pass.
    pub fn render_pass_writes(&mut self, label: &str) -> Option<RenderPassTimestampWrites<'_>> {
        self.timestamps.as_ref()?;
        let (index, query) = self.open(label)?;
        self.scopes[index].ended = true;
        let t = self.timestamps.as_ref()?;
        Some(RenderPassTimestampWrites {
            query_set: &t.query_set,
            beginning_of_pass_write_index: Some(query),
            end_of_pass_write_index: Some(query + 1),
        })
    }

    /// Closes the frame: records the resolve of its queries into `encoder` (timestamp path)
    /// and queues it for [`collect_oldest`](Self::collect_oldest) or
    /// [`collect`](Self::collect). Submit `encoder` before collecting, and pass the submission
    /// to [`submitted`](Self::submitted) so that collecting waits for this frame only.
    pub fn resolve(&mut self, encoder: &mut CommandEncoder) {
        let scopes = std::mem::take(&mut self.scopes);
        if self.queued.len() == FRAMES_IN_FLIGHT {
            // Readbacks are taken in turn, so after this at most two queued frames hold
            // one, the two taken last, and the next in turn is free.
            self.queued.pop_front();
            self.dropped += 1;
        }
        let used = 2 * scopes.len() as u32;
        let readback = match &mut self.timestamps {
            Some(t) if used > 0 => {
                let index = t.next_readback;
                t.next_readback = (index + 1) % FRAMES_IN_FLIGHT;
                encoder.resolve_query_set(&t.query_set, 0..used, &t.resolve, 0);
                let bytes = u64::from(used) * wgpu::QUERY_SIZE as u64;
                encoder.copy_buffer_to_buffer(&t.resolve, 0, &t.readbacks[index], 0, bytes);
                Some(index)
            }
            _ => None,
        };
        self.queued.push_back(QueuedFrame {
            scopes,
            readback,
            submission: None,
        });
    }

    /// Tells the timer which submission carried the last resolved frame, so that collecting it
    /// waits for that submission instead of for all work submitted so far.
    pub fn submitted(&mut self, submission: SubmissionIndex) {
        if let Some(frame) = self.queued.back_mut() {
            frame.submission.get_or_insert(submission);
        }
    }

    /// Waits for every queued frame and returns the newest one's ended scopes in the order
    /// they were opened (the older frames' figures are discarded); empty when no frame was
    /// resolved. On the CPU path an unresolved frame counts as resolved.
    pub fn collect(&mut self) -> Result<Vec<PassTime>, TimerError> {
        if let Some(error) = self.error.take() {
            self.scopes.clear();
            self.queued.clear();
            return Err(error);
        }
        if !self.scopes.is_empty() {
            if self.timestamps.is_some() {
                self.scopes.clear();
                self.queued.clear();
                return Err(TimerError::NotResolved);
            }
            self.queued.push_back(QueuedFrame {
                scopes: std::mem::take(&mut self.scopes),
                readback: None,
                submission: None,
            });
        }
        let mut newest = Vec::new();
        while let Some(frame) = self.queued.pop_front() {
            let last = self.queued.is_empty();
            if last {
                newest = self.read(frame)?;
            }
        }
        Ok(newest)
    }

    /// Waits for the oldest queued frame only and returns its ended scopes in the order they
    /// were opened; `None` when no frame is queued.
    pub fn collect_oldest(&mut self) -> Result<Option<Vec<PassTime>>, TimerError> {
        if let Some(error) = self.error.take() {
            return Err(error);
        }
        match self.queued.pop_front() {
            Some(frame) => self.read(frame).map(Some),
            None => Ok(None),
        }
    }

    /// One queued frame's times (waits for its submission on the timestamp path).
    fn read(&self, frame: QueuedFrame) -> Result<Vec<PassTime>, TimerError> {
        let ticks = match (&self.timestamps, frame.readback) {
            (Some(t), Some(index)) => {
                let count = 2 * frame.scopes.len() as u32;
                let ticks = read_ticks(&self.device, &t.readbacks[index], count, frame.submission)?;
                Some((ticks, t.period_ns))
            }
            _ => None,
        };
        Ok(frame
            .scopes
            .iter()
            .filter(|s| s.ended)
            .map(|s| {
                let nanoseconds = match &ticks {
                    Some((ticks, period_ns)) => {
                        let (start, end) = (ticks[s.query as usize], ticks[s.query as usize + 1]);
                        (end.saturating_sub(start) as f64 * f64::from(*period_ns)).round() as u64
                    }
                    None => s.elapsed.map_or(0, |d| d.as_nanos() as u64),
                };
                PassTime {
                    label: s.label.clone(),
                    nanoseconds,
                }
            })
            .collect())
    }

    /// CPU path: submits `encoder`'s work (leaving a fresh encoder) and waits for the GPU.
    fn submit_and_wait(&mut self, encoder: &mut CommandEncoder) {
        let fresh = self
            .device
            .create_command_encoder(&CommandEncoderDescriptor {
                label: Some("gpu timer (cpu path)"),
            });
        let done = std::mem::replace(encoder, fresh);
        self.queue.submit([done.finish()]);
        if let Err(e) = self.device.poll(wgpu::PollType::wait_indefinitely()) {
            self.error.get_or_insert(TimerError::Gpu(e.to_string()));
        }
    }
}

/// Maps `readback` and returns its first `count` timestamps, waiting for `submission` (all
/// submitted work when `None`).
fn read_ticks(
    device: &Device,
    readback: &Buffer,
    count: u32,
    submission: Option<SubmissionIndex>,
) -> Result<Vec<u64>, TimerError> {
    if count == 0 {
        return Ok(Vec::new());
    }
    let bytes = u64::from(count) * wgpu::QUERY_SIZE as u64;
    let slice = readback.slice(..bytes);
    let (sender, receiver) = mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |result| {
        // The receiver waits below.
        let _ = sender.send(result);
    });
    device
        .poll(wgpu::PollType::Wait {
            submission_index: submission,
            timeout: None,
        })
        .map_err(|e| TimerError::Gpu(e.to_string()))?;
    receiver
        .recv()
        .map_err(|e| TimerError::Gpu(e.to_string()))?
        .map_err(|e| TimerError::Gpu(e.to_string()))?;
    let ticks = {
        let view = slice
            .get_mapped_range()
            .map_err(|e| TimerError::Gpu(e.to_string()))?;
        bytemuck::pod_collect_to_vec::<u8, u64>(&view)
    };
    readback.unmap();
    Ok(ticks)
}
