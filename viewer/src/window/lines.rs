//! The overlay's statistics lines: frame rate and times, per-pass GPU times, what is resident
//! and visible per representation, primitives drawn, GPU memory by kind, streaming progress,
//! where the camera is.

use render_model::cull::CullStats;

use super::camera::FlyCamera;
use super::gpu::{Drawn, GpuWindow};
use super::stats::FrameStats;
use crate::view::StreamedView;

/// MiB of `bytes`.
fn mib(bytes: u64) -> f64 {
    bytes as f64 / f64::from(1u32 << 20)
}

/// Counts per level from level 1 up, trailing zeros dropped: `[n1, n2, ...]`.
fn lod_levels(per_level: &[u32]) -> String {
    let mut levels: Vec<u32> = per_level.iter().skip(1).copied().collect();
    while levels.last() == Some(&0) {
        levels.pop();
    }
    format!("{levels:?}")
}

/// The overlay's lines (see the [module docs](self)).
pub(super) fn overlay_lines(
    stats: &FrameStats,
    gpu: &GpuWindow,
    camera: &FlyCamera,
) -> Vec<String> {
    let ms = |ns: u64| ns as f64 / 1e6;
    let mut lines = vec![
        format!(
            "{:.1} fps   CPU frame {:.2} ms",
            stats.fps(),
            stats.cpu_frame_time().as_secs_f64() * 1e3
        ),
        format!(
            "GPU passes ({}): {:.2} ms",
            if gpu.gpu_timestamps() {
                "timestamps"
            } else {
                "CPU wall clock"
            },
            ms(stats.passes_total_ns())
        ),
    ];
    lines.extend(
        stats
            .passes()
            .iter()
            .map(|p| format!("  {:<16} {:>7.3} ms", p.label, ms(p.nanoseconds))),
    );
    match gpu.drawn() {
        Drawn::Fixed { counts, .. } => {
            lines.push(format!(
                "chunks {}   {:.1} MiB resident",
                counts.chunks,
                mib(counts.bytes)
            ));
            lines.push(format!(
                "quads {}   smooth quads {}",
                counts.quads, counts.smooth_quads
            ));
        }
        Drawn::Streamed(view) => streamed_lines(&mut lines, view, gpu.cull_stats()),
    }
    let p = camera.position();
    let (w, h) = gpu.size();
    lines.push(format!(
        "eye {:.1} {:.1} {:.1}   speed {:.1}/s   {w}x{h}",
        p.x, p.y, p.z, camera.speed
    ));
    lines
}

/// Residency, visibility, primitives, memory and streaming of a streamed view.
fn streamed_lines(lines: &mut Vec<String>, view: &StreamedView, cull: Option<&CullStats>) {
    let renderer = view.renderer();
    let (status, next) = view.status();
    let per_level = renderer.chunks_per_level();
    lines.push(format!(
        "resident: {} level-0 meshes, LOD levels 1.. {}, {} nodes drawing nothing",
        per_level[0],
        lod_levels(&per_level),
        status.resident_nodes.saturating_sub(status.drawn_nodes)
    ));
    if let Some(c) = cull {
        lines.push(format!(
            "visible: level 0 {}, LOD {}; {} meshed, {} far-drawn; {} off screen, {} occluded",
            c.per_level[0],
            lod_levels(&c.per_level),
            c.mesh_nodes,
            c.far_nodes,
            c.frustum_culled,
            c.occluded
        ));
        lines.push(format!(
            "primitives: {} quads, {} transparent, {} smooth, {} far blocks",
            c.mesh_quads, c.transparent_quads, c.smooth_quads, c.far_blocks
        ));
    }
    let memory: Vec<String> = renderer
        .resident_bytes()
        .into_iter()
        .filter(|(_, bytes)| *bytes > 0)
        .map(|(kind, bytes)| format!("{kind} {:.1}", mib(bytes)))
        .collect();
    for chunk in memory.chunks(3) {
        lines.push(format!("GPU MiB: {}", chunk.join(", ")));
    }
    let streamer = view.streamer();
    let budget = match (status.budget_px, status.memory_floor_px) {
        (Some(b), Some(floor)) => format!("{b:.2} px (raised to fit memory, floor {floor:.2})"),
        (Some(b), None) => format!("{b:.2} px"),
        (None, _) => "-".to_owned(),
    };
    lines.push(format!(
        "budget {budget}; far draws {:?}",
        streamer.far_choice().path
    ));
    if let Some(note) = &status.memory_note {
        lines.push(format!("memory: {note}"));
    }
    if status.clutter_nodes > 0 {
        lines.push(format!(
            "grass: {} units on {} nodes within its reach",
            status.clutter_units, status.clutter_nodes
        ));
    }
    lines.push(status.progress_line());
    if let Some(next) = next {
        lines.push(format!("switching: {}", next.progress_line()));
    }
}
