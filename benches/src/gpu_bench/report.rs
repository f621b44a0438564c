//! The GPU benchmark's results: one [`SceneReport`] per scene, medians, and the Markdown table.

use std::fmt::Write;

/// The median GPU time of one pass over a scene's timed frames.
#[derive(Clone, Debug, PartialEq)]
pub struct PassMedian {
    /// The pass's timer label (`cull`, `gbuffer`, `lighting`, `transparent`, `tonemap`).
    pub label: String,
    /// Median, microseconds.
    pub micros: f64,
}

/// One scene's measurements.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneReport {
    /// Resident chunks.
    pub chunks: usize,
    /// Resident greedy quads (both layers).
    pub quads: u64,
    /// Block columns per side of the square the chunks cover.
    pub covered_side: u32,
    /// Bytes of the quad gigabuffer in use.
    pub quad_bytes: u64,
    /// Chunk-table bytes per resident chunk (one `MeshedChunkInfo`).
    pub table_bytes_per_chunk: u64,
    /// Cull-output bytes per table slot (command slots: args + records).
    pub command_bytes_per_chunk: u64,
    /// CPU time to upload the chunks this scene added, milliseconds.
    pub upload_cpu_ms: f64,
    /// Wall time of the frame that flushed those uploads, milliseconds.
    pub flush_frame_ms: f64,
    /// Median GPU time per pass.
    pub passes: Vec<PassMedian>,
    /// Median CPU time to record and submit a frame, microseconds.
    pub cpu_frame_us: f64,
}

impl SceneReport {
    /// Quad-gigabuffer bytes per resident quad (8 when nothing but the packed quads is stored).
    pub fn bytes_per_quad(&self) -> f64 {
        self.quad_bytes as f64 / self.quads.max(1) as f64
    }

    /// Per-chunk overhead on top of the quads: table record plus command slots.
    pub fn overhead_per_chunk(&self) -> u64 {
        self.table_bytes_per_chunk + self.command_bytes_per_chunk
    }

    /// All resident bytes (quads, table, command slots) per chunk.
    pub fn bytes_per_chunk(&self) -> f64 {
        self.quad_bytes as f64 / self.chunks.max(1) as f64 + self.overhead_per_chunk() as f64
    }

    /// The median of pass `label`, microseconds.
    pub fn pass(&self, label: &str) -> Option<f64> {
        self.passes
            .iter()
            .find(|p| p.label == label)
            .map(|p| p.micros)
    }

    /// The sum of every pass's median, microseconds.
    pub fn gpu_total_us(&self) -> f64 {
        self.passes.iter().map(|p| p.micros).sum()
    }
}

/// The median of `values` (the upper one of an even count); 0 for none.
pub fn median(values: &mut [u64]) -> u64 {
    if values.is_empty() {
        return 0;
    }
    values.sort_unstable();
    values[values.len() / 2]
}

/// Per-label medians of frames given as `(label, nanoseconds)` lists, in the first frame's
/// label order.
pub fn pass_medians(frames: &[Vec<(String, u64)>]) -> Vec<PassMedian> {
    let Some(first) = frames.first() else {
        return Vec::new();
    };
    first
        .iter()
        .map(|(label, _)| {
            let mut values: Vec<u64> = frames
                .iter()
                .flat_map(|f| f.iter().filter(|(l, _)| l == label).map(|(_, ns)| *ns))
                .collect();
            PassMedian {
                label: label.clone(),
                micros: median(&mut values) as f64 / 1e3,
            }
        })
        .collect()
}

/// The Markdown table of `reports` (one row per scene).
pub fn markdown_table(reports: &[SceneReport]) -> String {
    let labels: Vec<String> = reports
        .first()
        .map(|r| r.passes.iter().map(|p| p.label.clone()).collect())
        .unwrap_or_default();
    let mut out = String::from("| chunks | columns | quads | B/quad | B/chunk |");
    for label in &labels {
        let _ = write!(out, " {label} µs |");
    }
    out.push_str(" GPU total µs | CPU frame µs | upload ms |\n|");
    for _ in 0..labels.len() + 8 {
        out.push_str(" ---: |");
    }
    out.push('\n');
    for r in reports {
        let _ = write!(
            out,
            "| {} | {}² | {} | {:.2} | {:.0} |",
            r.chunks,
            r.covered_side,
            r.quads,
            r.bytes_per_quad(),
            r.bytes_per_chunk()
        );
        for label in &labels {
            let _ = write!(out, " {:.1} |", r.pass(label).unwrap_or(f64::NAN));
        }
        let _ = writeln!(
            out,
            " {:.1} | {:.1} | {:.1} |",
            r.gpu_total_us(),
            r.cpu_frame_us,
            r.upload_cpu_ms
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians_per_label() {
        let frames = vec![
            vec![("cull".to_owned(), 30), ("gbuffer".to_owned(), 100)],
            vec![("cull".to_owned(), 10), ("gbuffer".to_owned(), 300)],
            vec![("cull".to_owned(), 20), ("gbuffer".to_owned(), 200)],
        ];
        let medians = pass_medians(&frames);
        assert_eq!(medians.len(), 2);
        assert_eq!(medians[0].label, "cull");
        assert!((medians[0].micros - 0.02).abs() < 1e-12);
        assert!((medians[1].micros - 0.2).abs() < 1e-12);
        assert_eq!(median(&mut []), 0);
    }

    #[test]
    fn table_has_a_row_per_scene_and_the_byte_figures() {
        let report = SceneReport {
            chunks: 2,
            quads: 100,
            covered_side: 16,
            quad_bytes: 800,
            table_bytes_per_chunk: 112,
            command_bytes_per_chunk: 312,
            upload_cpu_ms: 1.0,
            flush_frame_ms: 2.0,
            passes: vec![PassMedian {
                label: "cull".to_owned(),
                micros: 3.0,
            }],
            cpu_frame_us: 4.0,
        };
        assert_eq!(report.bytes_per_quad(), 8.0);
        assert_eq!(report.bytes_per_chunk(), 400.0 + 424.0);
        let table = markdown_table(&[report.clone(), report]);
        assert_eq!(table.lines().count(), 4);
        assert!(table.contains("cull µs"));
        assert!(table.contains("| 2 | 16² | 100 | 8.00 | 824 | 3.0 |"));
    }
}
