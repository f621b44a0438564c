//! `--flight SECONDS`: a scripted camera flight over the streamed terrain, headless, with the
//! frame times it took.
//!
//! The path is fixed ([`FlightPath`]): from above the origin, forward at
//! [`FlightPath::SPEED`] blocks per second with the heading swinging 45 degrees either way and
//! back once a minute, climbing [`FlightPath::CLIMB`] blocks per second, looking 12 degrees
//! down. Camera `i` is the path at `i / 60` seconds, so every run sees the same cameras; frames
//! are paced to at most 60 per second, so on a fast machine the streaming sees real time (on a
//! slow one the flight takes longer than its seconds, and reports both).
//!
//! Per frame it measures the **CPU time** (streaming work on the frame's thread: plans, uploads
//! and frees; then recording and submitting the frame), the **GPU time** (the sum of the
//! renderer's per-pass timestamps, only where the adapter has timestamp queries: otherwise
//! "no timestamps", never a CPU stand-in) and the **frame time**. Frames overlap as in a
//! windowed renderer: the CPU records and submits frame `n`, then waits for the GPU to finish
//! frame `n - 1`, so one frame is in flight while the next is prepared. A frame holds the
//! 60 Hz pace when both its loop time (its CPU time plus that wait) and its GPU time fit in
//! 1/60 s; the frame time is the larger of the two. The first view is loaded before the flight starts
//! (its time is reported apart) and one untimed frame drawn (first-use costs of pipelines and
//! bind groups are not streaming's); nodes streamed per second count the uploads during the
//! flight.

use std::time::{Duration, Instant};

use glam::DVec3;
use gpu_backend::{GpuContext, TimingPath};
use serde::Serialize;

use crate::edits::{Carver, SharedWorld};
use crate::headless::{draw_frame, load};
use crate::pass_times::{PassPercentiles, PassSeries};
use crate::stream::{StreamError, StreamSettings, StreamStatus};
use crate::view::{OPAQUE_TRIAL_FRAMES, StreamedView};
use render_model::camera::Camera;

/// Frames per second of the flight's clock.
pub const FLIGHT_HZ: f64 = 60.0;

/// The scripted path (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlightPath {
    /// Where the flight starts, blocks.
    pub start: DVec3,
    /// Heading at the start, radians (0 looks along -z).
    pub yaw: f64,
}

impl FlightPath {
    /// Forward speed, blocks per second.
    pub const SPEED: f64 = 48.0;
    /// Climb, blocks per second.
    pub const CLIMB: f64 = 2.0;
    /// Pitch of the view, radians (12 degrees down).
    pub const PITCH: f64 = -12.0 * std::f64::consts::PI / 180.0;

    /// The path starting `height` blocks above the origin, heading along -z.
    pub fn over_origin(height: f64) -> FlightPath {
        FlightPath {
            start: DVec3::new(0.5, height, 0.5),
            yaw: 0.0,
        }
    }

    /// The camera of every frame of `seconds` ([`FLIGHT_HZ`] per second, at least one), with
    /// vertical field of view `fov_y`.
    pub fn cameras(&self, seconds: f64, fov_y: f64) -> Vec<Camera> {
        let frames = ((seconds * FLIGHT_HZ).round() as usize).max(1);
        let dt = 1.0 / FLIGHT_HZ;
        let mut pos = self.start;
        (0..frames)
            .map(|i| {
                let t = i as f64 * dt;
                let yaw = self.yaw
                    + std::f64::consts::FRAC_PI_4 * (std::f64::consts::TAU * t / 60.0).sin();
                let camera = camera_at(pos, yaw, Self::PITCH, fov_y);
                pos += DVec3::new(-yaw.sin(), 0.0, -yaw.cos()) * Self::SPEED * dt;
                pos.y += Self::CLIMB * dt;
                camera
            })
            .collect()
    }
}

/// The viewer's camera at `pos` looking along `yaw`, `pitch`.
fn camera_at(pos: DVec3, yaw: f64, pitch: f64, fov_y: f64) -> Camera {
    let floor = pos.floor();
    Camera {
        voxel: voxel_core::WorldPos::new(floor.x as i32, floor.y as i32, floor.z as i32),
        fraction: pos - floor,
        yaw,
        pitch,
        fov_y,
        near: Camera::DEFAULT_NEAR,
    }
}

/// The camera's eye, world blocks.
fn eye_of(camera: &Camera) -> DVec3 {
    let v = camera.voxel;
    DVec3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z)) + camera.fraction
}

/// p50, p99 and the largest of a set of times, milliseconds (nearest rank).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Percentiles {
    /// Median.
    pub p50_ms: f64,
    /// 99th percentile.
    pub p99_ms: f64,
    /// Largest.
    pub max_ms: f64,
}

impl Percentiles {
    /// The percentiles of `samples` (milliseconds), `None` when there are none.
    pub fn of(samples: &[f64]) -> Option<Percentiles> {
        let mut sorted: Vec<f64> = samples.to_vec();
        sorted.sort_by(f64::total_cmp);
        let rank = |q: f64| {
            let i = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
            sorted[i - 1]
        };
        (!sorted.is_empty()).then(|| Percentiles {
            p50_ms: rank(0.5),
            p99_ms: rank(0.99),
            max_ms: rank(1.0),
        })
    }
}

/// What a flight measured (also its JSON form).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FlightReport {
    /// The adapter it ran on.
    pub adapter: String,
    /// Frame width, pixels.
    pub width: u32,
    /// Frame height, pixels.
    pub height: u32,
    /// The flight's own seconds (frames / 60).
    pub seconds: f64,
    /// Frames drawn.
    pub frames: usize,
    /// Wall-clock seconds the frames took (at least `seconds`: frames are paced).
    pub wall_seconds: f64,
    /// Seconds to load the first view, before the flight.
    pub first_view_seconds: f64,
    /// Nodes resident after the first view loaded.
    pub first_view_nodes: usize,
    /// Bytes of node data resident once the first view is loaded.
    pub first_view_bytes: u64,
    /// CPU time per frame.
    pub cpu_frame: Percentiles,
    /// GPU time per frame (sum of the pass timestamps), `None` without timestamps.
    pub gpu_frame: Option<Percentiles>,
    /// The grass pass's GPU time per frame (its `grass` timestamps), `None` without
    /// timestamps or without clutter (`--clutter off`).
    pub grass_frame: Option<Percentiles>,
    /// `"timestamps"`, or `"no timestamps"` and why.
    pub gpu_timing: String,
    /// Each pass's GPU time, in frame order (empty without timestamps).
    pub gpu_passes: Vec<PassPercentiles>,
    /// The larger of the frame's loop time (its CPU time plus the wait for the frame before
    /// it, which stays in flight while this one is prepared) and its GPU time.
    pub frame: Percentiles,
    /// The loop time alone: CPU time plus the wait for the frame in flight.
    pub loop_frame: Percentiles,
    /// Nodes uploaded during the flight.
    pub streamed_nodes: u64,
    /// Bytes uploaded during the flight.
    pub streamed_bytes: u64,
    /// Nodes uploaded per wall-clock second of flight.
    pub streamed_nodes_per_second: f64,
    /// Anchor or budget moves committed during the flight.
    pub commits: u64,
    /// Frames that drew with a selected node missing (0 by construction; checked).
    pub frames_with_holes: usize,
    /// The budget the memory forced at the end of the flight, pixels, when it did.
    pub memory_floor_px: Option<f32>,
    /// Why the memory last forced a coarser budget (the refusal, named), when it did.
    pub memory_note: Option<String>,
    /// Streamed radius, blocks.
    pub radius: u32,
    /// Error budget asked for, pixels.
    pub budget_px: f32,
    /// Node edge, blocks.
    pub node_blocks: u32,
    /// Far threshold: nodes whose cells span at most this many pixels are far-drawn.
    pub far_cell_px: f32,
    /// The far path and why.
    pub far: String,
    /// Mesher mode.
    pub mesher: String,
    /// How opaque quads were drawn: `Raster` or `Compute`, or with `--opaque auto` the
    /// measured choice (`auto: compute (GPU time per frame: ...)`).
    pub opaque: String,
    /// The edits made along the path (`--edits-per-second`), when asked for.
    pub edits: Option<EditFigures>,
}

/// What the edits of a flight cost and how soon they were on screen.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EditFigures {
    /// Spheres asked for per second of flight.
    pub per_second: f64,
    /// Spheres applied.
    pub spheres: usize,
    /// Nodes the committed view drew that were rebuilt and swapped in before the next frame.
    pub swapped_at_once: usize,
    /// Resident nodes out of view handed to the workers to rebuild.
    pub rebuilt_later: usize,
    /// CPU time per frame with edits: applying them, re-meshing and swapping the shown nodes.
    pub cpu: Percentiles,
    /// Of it, the world's part: filling the chunks the edits reach, writing them, the dirty
    /// set and the coarse voxels.
    pub world: Percentiles,
    /// Of it, re-meshing and swapping the shown nodes.
    pub rebuild: Percentiles,
    /// The most shown nodes one frame's edits swapped.
    pub most_swapped: usize,
    /// Edit to screen: from the edit call to the end of the GPU work of the frame drawn right
    /// after it, which shows it. With timestamps: the time from the edit call until that
    /// frame is submitted and the frame before it is done (its GPU work cannot start
    /// earlier), plus its own GPU time. Without: the time until the loop next waits for that
    /// frame (which also holds the next frame's CPU time: an upper bound).
    pub latency: Percentiles,
}

impl FlightReport {
    /// The report as the lines the viewer prints.
    pub fn lines(&self) -> Vec<String> {
        let p = |p: &Percentiles| {
            format!(
                "p50 {:.2} ms  p99 {:.2} ms  max {:.2} ms",
                p.p50_ms, p.p99_ms, p.max_ms
            )
        };
        vec![
            format!(
                "flight: {} frames ({:.1} s of flight in {:.1} s) at {}x{} on {}; radius {} \
                 blocks, budget {} px, {}^3 nodes, far draws {} (cells up to {} px), {} meshes, \
                 opaque path {}",
                self.frames,
                self.seconds,
                self.wall_seconds,
                self.width,
                self.height,
                self.adapter,
                self.radius,
                self.budget_px,
                self.node_blocks,
                self.far,
                self.far_cell_px,
                self.mesher,
                self.opaque
            ),
            format!(
                "flight: first view {} nodes in {:.2} s",
                self.first_view_nodes, self.first_view_seconds
            ),
            format!("flight: CPU per frame  {}", p(&self.cpu_frame)),
            match &self.gpu_frame {
                Some(g) => format!("flight: GPU per frame  {}", p(g)),
                None => format!("flight: GPU per frame  {}", self.gpu_timing),
            },
            self.pass_line(),
            match &self.grass_frame {
                Some(g) => format!("flight: grass pass per frame  {}", p(g)),
                None => "flight: grass pass per frame  - (clutter off or no timestamps)".to_owned(),
            },
            format!(
                "flight: frame (max of loop and GPU; one frame in flight)  {}",
                p(&self.frame)
            ),
            format!(
                "flight: loop per frame (CPU plus the wait for the frame in flight)  {}",
                p(&self.loop_frame)
            ),
            format!(
                "flight: streamed {} nodes ({:.1} MiB), {:.1} nodes/s, {} view moves, {} frames \
                 with holes",
                self.streamed_nodes,
                self.streamed_bytes as f64 / f64::from(1u32 << 20),
                self.streamed_nodes_per_second,
                self.commits,
                self.frames_with_holes
            ),
        ]
        .into_iter()
        .chain(self.edits.as_ref().map(|e| {
            format!(
                "flight: edits {} spheres of radius {} ({}/s): {} shown nodes swapped before \
                 the next frame (at most {} in one), {} rebuilt later; CPU per frame with edits \
                 {} (the world {}, re-meshing and swapping {}); edit to screen {}",
                e.spheres,
                Carver::RADIUS,
                e.per_second,
                e.swapped_at_once,
                e.most_swapped,
                e.rebuilt_later,
                p(&e.cpu),
                p(&e.world),
                p(&e.rebuild),
                p(&e.latency)
            )
        }))
        .chain(self.memory_note.as_ref().map(|note| {
            format!(
                "flight: memory forced a budget of {:.2} px: {note}",
                self.memory_floor_px.unwrap_or(0.0)
            )
        }))
        .collect()
    }
}

impl FlightReport {
    /// The per-pass line: each pass's p50 and p99, milliseconds, and the frames that ran it
    /// when some did not.
    fn pass_line(&self) -> String {
        if self.gpu_passes.is_empty() {
            return format!("flight: GPU per pass  {}", self.gpu_timing);
        }
        let passes: Vec<String> = self
            .gpu_passes
            .iter()
            .map(|p| {
                let frames = if p.frames < self.frames {
                    format!(" ({} frames)", p.frames)
                } else {
                    String::new()
                };
                format!(
                    "{} {:.3}/{:.3}{frames}",
                    p.label, p.time.p50_ms, p.time.p99_ms
                )
            })
            .collect();
        format!("flight: GPU per pass (p50/p99 ms)  {}", passes.join(", "))
    }
}

/// Flies the path for `seconds` at `width x height` over the terrain of `settings` on `ctx`.
/// `progress` gets a line while the first view loads.
pub fn fly(
    ctx: &GpuContext,
    settings: &StreamSettings,
    path: &FlightPath,
    seconds: f64,
    size: (u32, u32),
    progress: impl FnMut(&StreamStatus),
) -> Result<FlightReport, StreamError> {
    let world = SharedWorld::new(settings.seed, settings.chunk, settings.top_level())
        .map_err(|e| StreamError::Edit(e.to_string()))?;
    fly_over(ctx, settings, world, path, seconds, size, 0.0, progress)
}

/// [`fly`] over `world`, carving `edits_per_second` spheres of air along the path
/// ([`Carver`]; none for 0) and measuring how soon each frame's edits are on screen.
#[allow(clippy::too_many_arguments)]
pub fn fly_over(
    ctx: &GpuContext,
    settings: &StreamSettings,
    world: SharedWorld,
    path: &FlightPath,
    seconds: f64,
    (width, height): (u32, u32),
    edits_per_second: f64,
    mut progress: impl FnMut(&StreamStatus),
) -> Result<FlightReport, StreamError> {
    let fov_y = 70f64.to_radians();
    let cameras = path.cameras(seconds, fov_y);
    let mut carver = Carver::new(edits_per_second, FLIGHT_HZ).map_err(StreamError::Edit)?;
    let terrain = voxel_scene::Terrain::new(settings.seed, voxel_scene::TerrainBlocks::palette().1);
    let mut view = StreamedView::with_world(ctx, settings, width, height, world)?;
    let loading = Instant::now();
    load(
        &mut view,
        &cameras[0],
        Duration::from_secs(1800),
        &mut progress,
    )?;
    let first_view_seconds = loading.elapsed().as_secs_f64();
    let first_view_nodes = view.streamer().status().resident_nodes;
    let first_view_bytes = view.streamer().status().node_bytes;
    // `--opaque auto`: measured at the first view, before the flight.
    let opaque = match view.choose_opaque_path(OPAQUE_TRIAL_FRAMES)? {
        Some(choice) => format!("auto: {choice}"),
        None => format!("{:?}", settings.opaque),
    };
    // One untimed frame: first-use costs (pipelines, bind groups) are not streaming's.
    draw_frame(ctx, &mut view)?;
    let before = view.streamer().counters();
    let timestamps = matches!(ctx.capabilities.timing, TimingPath::GpuTimestamps { .. });
    let (mut cpu, mut gpu, mut loop_frame) = (Vec::new(), Vec::new(), Vec::new());
    let mut pass_series = PassSeries::default();
    let mut grass = Vec::new();
    let mut gpu_ms = |passes: Vec<gpu_backend::PassTime>| -> f64 {
        pass_series.push(&passes);
        let ms = |p: &gpu_backend::PassTime| p.nanoseconds as f64 / 1e6;
        grass.push(
            passes
                .iter()
                .filter(|p| p.label == "grass")
                .map(ms)
                .sum::<f64>(),
        );
        passes.iter().map(ms).sum()
    };
    let mut frames_with_holes = 0;
    let (mut edit_cpu, mut latency) = (Vec::new(), Vec::new());
    // Frames with edits: their index and the time from the edit call to the loop's end (the
    // frame submitted, the one before it done).
    let mut edit_frames: Vec<(usize, f64)> = Vec::new();
    let (mut spheres, mut swapped, mut queued, mut most_swapped) = (0, 0, 0, 0);
    let (mut world_ms, mut rebuild_ms) = (Vec::new(), Vec::new());
    // The start of the edits drawn by the frame in flight, if it had any.
    let mut edits_in_flight: Option<Instant> = None;
    let started = Instant::now();
    for (i, camera) in cameras.iter().enumerate() {
        let frame_started = Instant::now();
        let edits = if edits_per_second > 0.0 {
            carver.next_frame(eye_of(camera), camera.yaw, &terrain)
        } else {
            Vec::new()
        };
        let edits_started = (!edits.is_empty()).then(Instant::now);
        if !edits.is_empty() {
            let done = view.apply_edits(&edits)?;
            spheres += edits.len();
            swapped += done.swapped;
            queued += done.queued;
            most_swapped = most_swapped.max(done.swapped);
            world_ms.push(done.world.as_secs_f64() * 1e3);
            rebuild_ms.push(done.rebuild.as_secs_f64() * 1e3);
            edit_cpu.push(frame_started.elapsed().as_secs_f64() * 1e3);
        }
        view.update(camera)?;
        let renderer = view.renderer_mut();
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        renderer
            .record_frame(&mut encoder)
            .map_err(StreamError::Renderer)?;
        renderer.submit_frame(encoder);
        cpu.push(frame_started.elapsed().as_secs_f64() * 1e3);
        // One frame stays in flight: wait for the frame before this one.
        if renderer.frames_in_flight() > 1
            && let Some(passes) = renderer
                .collect_oldest_timings()
                .map_err(StreamError::Renderer)?
        {
            gpu.push(gpu_ms(passes));
        }
        // The frame before is done: its edits are on screen.
        if let Some(start) = edits_in_flight.take() {
            latency.push(start.elapsed().as_secs_f64() * 1e3);
        }
        if let Some(start) = edits_started {
            edit_frames.push((i, start.elapsed().as_secs_f64() * 1e3));
        }
        edits_in_flight = edits_started;
        loop_frame.push(frame_started.elapsed().as_secs_f64() * 1e3);
        // Checked outside the timed part: it walks every selected node.
        frames_with_holes += usize::from(!view.streamer().holes().is_empty());
        let due = started + Duration::from_secs_f64((i + 1) as f64 / FLIGHT_HZ);
        if let Some(wait) = due.checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
    }
    while let Some(passes) = view
        .renderer_mut()
        .collect_oldest_timings()
        .map_err(StreamError::Renderer)?
    {
        gpu.push(gpu_ms(passes));
    }
    if let Some(start) = edits_in_flight.take() {
        latency.push(start.elapsed().as_secs_f64() * 1e3);
    }
    let wall_seconds = started.elapsed().as_secs_f64();
    if timestamps && gpu.len() == cameras.len() {
        latency = edit_frames
            .iter()
            .map(|&(i, until_submitted)| until_submitted + gpu[i])
            .collect();
    }
    // Frame i's GPU time is gpu[i] (collected in order); without timestamps they are zeros.
    let frame: Vec<f64> = loop_frame
        .iter()
        .enumerate()
        .map(|(i, &l)| l.max(gpu.get(i).copied().unwrap_or(0.0)))
        .collect();
    let after = view.streamer().counters();
    // A swap (none happens without a control change) would reset the counters.
    let streamed_nodes = after.uploaded.saturating_sub(before.uploaded);
    let none = Percentiles {
        p50_ms: 0.0,
        p99_ms: 0.0,
        max_ms: 0.0,
    };
    Ok(FlightReport {
        adapter: ctx.capabilities.adapter.to_string(),
        width,
        height,
        seconds: cameras.len() as f64 / FLIGHT_HZ,
        frames: cameras.len(),
        wall_seconds,
        first_view_seconds,
        first_view_nodes,
        first_view_bytes,
        cpu_frame: Percentiles::of(&cpu).unwrap_or(none),
        gpu_frame: if timestamps {
            Percentiles::of(&gpu)
        } else {
            None
        },
        grass_frame: if timestamps && settings.clutter {
            Percentiles::of(&grass)
        } else {
            None
        },
        gpu_timing: if timestamps {
            "timestamps".to_owned()
        } else {
            "no timestamps (the adapter has no timestamp queries; no GPU figure is given)"
                .to_owned()
        },
        gpu_passes: pass_series.percentiles(),
        frame: Percentiles::of(&frame).unwrap_or(none),
        loop_frame: Percentiles::of(&loop_frame).unwrap_or(none),
        streamed_nodes,
        streamed_bytes: after.uploaded_bytes.saturating_sub(before.uploaded_bytes),
        streamed_nodes_per_second: streamed_nodes as f64 / wall_seconds.max(1e-9),
        commits: after.commits.saturating_sub(before.commits),
        frames_with_holes,
        memory_floor_px: view.streamer().status().memory_floor_px,
        memory_note: view.streamer().status().memory_note,
        radius: settings.radius,
        budget_px: settings.budget_px,
        node_blocks: settings.chunk.edge(),
        far_cell_px: settings.far_cell_px,
        far: view.streamer().far_choice().to_string(),
        mesher: settings.mesher.name().to_owned(),
        opaque,
        edits: (edits_per_second > 0.0).then(|| EditFigures {
            per_second: edits_per_second,
            spheres,
            swapped_at_once: swapped,
            rebuilt_later: queued,
            cpu: Percentiles::of(&edit_cpu).unwrap_or(none),
            world: Percentiles::of(&world_ms).unwrap_or(none),
            rebuild: Percentiles::of(&rebuild_ms).unwrap_or(none),
            most_swapped,
            latency: Percentiles::of(&latency).unwrap_or(none),
        }),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_path_is_fixed_and_flies_forward_turning_and_climbing() {
        let path = FlightPath::over_origin(60.0);
        let a = path.cameras(20.0, 1.2);
        assert_eq!(a, path.cameras(20.0, 1.2), "deterministic");
        assert_eq!(a.len(), 1200);
        let pos = |c: &Camera| {
            let v = c.voxel;
            DVec3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z)) + c.fraction
        };
        let (first, last) = (pos(&a[0]), pos(&a[1199]));
        assert!(
            (last.y - first.y - 2.0 * 1199.0 / 60.0).abs() < 1e-6,
            "climbs"
        );
        assert!(
            first.z - last.z > 500.0,
            "forward along -z: {first} -> {last}"
        );
        let yaws: Vec<f64> = a.iter().map(|c| c.yaw).collect();
        assert!(yaws.iter().any(|&y| y > 0.5), "turns");
        assert_eq!(path.cameras(0.0, 1.0).len(), 1);
    }

    #[test]
    fn percentiles_take_the_nearest_rank() {
        let samples: Vec<f64> = (1..=100).map(f64::from).collect();
        let p = Percentiles::of(&samples).unwrap();
        assert_eq!((p.p50_ms, p.p99_ms, p.max_ms), (50.0, 99.0, 100.0));
        assert_eq!(Percentiles::of(&[]), None);
        let one = Percentiles::of(&[3.0]).unwrap();
        assert_eq!((one.p50_ms, one.max_ms), (3.0, 3.0));
    }
}
