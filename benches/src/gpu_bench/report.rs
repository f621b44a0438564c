//! The GPU benchmark's results: one [`RunReport`] per measured setting, medians, the Markdown
//! tables and the JSON document.

use std::fmt::Write;

use serde::Serialize;

use super::image_error::ImageError;

/// The median GPU time of one pass over a run's timed frames.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PassMedian {
    /// The pass's timer label (`cull`, `far splat`, `gbuffer`, `lighting`, ...).
    pub label: String,
    /// Median, microseconds.
    pub micros: f64,
}

/// What the cull and the splat counted in a run's last frame.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct DrawnCounts {
    /// Nodes selected at their level (all levels).
    pub selected: u32,
    /// Selected nodes per level (index = level; trailing zeros cut).
    pub selected_per_level: Vec<u32>,
    /// Selected nodes outside the frustum.
    pub frustum_culled: u32,
    /// Selected nodes hidden by the depth pyramid.
    pub occluded: u32,
    /// Nodes drawn from quads.
    pub mesh_nodes: u32,
    /// Nodes drawn from surface blocks.
    pub far_nodes: u32,
    /// Opaque quads drawn (skirts included).
    pub mesh_quads: u32,
    /// Transparent quads drawn.
    pub transparent_quads: u32,
    /// Smooth quads drawn.
    pub smooth_quads: u32,
    /// Far blocks drawn (skirt blocks included).
    pub far_blocks: u32,
    /// Pixel centres the splat tested.
    pub splat_pixels: u32,
    /// Blocks the splat skipped (too large on screen, or at the near plane).
    pub splat_skipped: u32,
    /// The compute rasteriser's counters over one frame (both phases), on the compute opaque
    /// path.
    pub quad_raster: Option<QuadRasterCounts>,
    /// Chunks whose clutter the grass pass drew (0 without clutter).
    pub grass_chunks: u32,
    /// Clutter units the grass pass drew (before the per-blade fade; 0 without clutter).
    pub grass_units: u32,
}

/// What the compute quad rasteriser did in one frame (`gpu_backend`'s `QuadRasterStats`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct QuadRasterCounts {
    /// Quads read from the drawn commands.
    pub quads: u32,
    /// Quads with a non-empty pixel box.
    pub visible: u32,
    /// Pixel centres tested by the quads pass.
    pub local_pixels: u32,
    /// Quads drawn through the tile list.
    pub big: u32,
    /// Pixel centres tested by the tiles pass.
    pub tile_pixels: u32,
    /// Pixel centres that hit a quad.
    pub hits: u32,
    /// Tile entries of the frame's last phase.
    pub tiles: u32,
}

impl DrawnCounts {
    /// The share of selected nodes in the frustum that occlusion culling removed.
    pub fn occluded_fraction(&self) -> f64 {
        let in_frustum = self.selected.saturating_sub(self.frustum_culled);
        f64::from(self.occluded) / f64::from(in_frustum.max(1))
    }
}

/// One measured setting.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RunReport {
    /// The error budget, pixels; `None` for full detail (level 0 only, meshes only).
    pub budget_px: Option<f32>,
    /// The far path (`Off`, `Splat`, ...).
    pub far: String,
    /// Nodes whose cells span at most this many pixels are far-drawn.
    pub far_cell_px: f32,
    /// How the full-screen passes ran (`Compute` or `Fragment`).
    pub fullscreen: String,
    /// Two-phase occlusion culling on.
    pub occlusion: bool,
    /// How the opaque quads were drawn (`Raster` or `Compute`).
    pub opaque: String,
    /// Median GPU time per pass.
    pub passes: Vec<PassMedian>,
    /// Sum of the pass medians, microseconds.
    pub gpu_total_us: f64,
    /// Median wall-clock time to record and submit a frame, microseconds.
    pub cpu_frame_us: f64,
    /// Median CPU time of the recording thread over the same span, microseconds (leaves out
    /// the time slices a busy machine gives to other processes).
    pub cpu_thread_us: f64,
    /// The part of `cpu_thread_us` spent in `CommandEncoder::finish`, microseconds (median).
    pub cpu_finish_us: f64,
    /// The part of `cpu_thread_us` spent in `Queue::submit`, microseconds (median).
    pub cpu_submit_us: f64,
    /// What the last frame drew.
    pub drawn: DrawnCounts,
    /// Error against the full-detail frame, when one was rendered.
    pub image_error: Option<ImageErrorReport>,
}

/// [`ImageError`] for the JSON document.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ImageErrorReport {
    /// Mean absolute error on 8-bit RGB.
    pub mean_abs: f64,
    /// Share of pixels off by more than 8/255.
    pub share_over_8: f64,
}

impl From<ImageError> for ImageErrorReport {
    fn from(e: ImageError) -> Self {
        ImageErrorReport {
            mean_abs: e.mean_abs,
            share_over_8: e.share_over_8,
        }
    }
}

/// The scene every run of one benchmark invocation shares.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct SceneSummary {
    /// The adapter.
    pub adapter: String,
    /// Block columns per side.
    pub side: u32,
    /// Chunk edge.
    pub chunk_edge: u32,
    /// Output size.
    pub width: u32,
    /// Output size.
    pub height: u32,
    /// Chunks per level of the whole terrain.
    pub chunks_per_level: Vec<usize>,
    /// Nodes resident per level.
    pub resident_per_level: Vec<usize>,
    /// Quads resident (both layers and skirts).
    pub resident_quads: u64,
    /// Draw-block words resident (blocks, skirt blocks, hiding masks).
    pub resident_draw_block_words: u64,
    /// Far-draw blocks resident (surface and skirt blocks; the rest of the words are the
    /// nodes' hiding masks).
    pub resident_far_blocks: u64,
    /// GPU bytes by kind: name, bytes.
    pub resident_bytes: Vec<(String, u64)>,
    /// Seconds to generate, downsample and mesh.
    pub generate_seconds: f64,
    /// Seconds to downsample the coarser levels.
    pub downsample_seconds: f64,
    /// Seconds to mesh the resident nodes.
    pub mesh_seconds: f64,
    /// Milliseconds of CPU to upload everything.
    pub upload_ms: f64,
    /// Timed frames per run.
    pub frames: usize,
}

/// The whole benchmark's output.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BenchReport {
    /// The scene.
    pub scene: SceneSummary,
    /// One entry per measured setting.
    pub runs: Vec<RunReport>,
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

fn budget_label(budget: Option<f32>) -> String {
    budget.map_or("full".to_owned(), |b| format!("{b} px"))
}

/// The Markdown tables of `report`: time per pass, and what was drawn with its image error.
pub fn markdown(report: &BenchReport) -> String {
    let mut labels: Vec<String> = Vec::new();
    for run in &report.runs {
        for p in &run.passes {
            if !labels.contains(&p.label) {
                labels.push(p.label.clone());
            }
        }
    }
    let mut out =
        String::from("| budget | far | far px | screen passes | occlusion | opaque quads |");
    for label in &labels {
        let _ = write!(out, " {label} µs |");
    }
    out.push_str(
        " GPU total µs | CPU frame µs | CPU thread µs | of it finish µs | of it submit µs |\n|",
    );
    for _ in 0..labels.len() + 11 {
        out.push_str(" ---: |");
    }
    out.push('\n');
    for r in &report.runs {
        let _ = write!(
            out,
            "| {} | {} | {} | {} | {} | {} |",
            budget_label(r.budget_px),
            r.far,
            r.far_cell_px,
            r.fullscreen,
            if r.occlusion { "on" } else { "off" },
            r.opaque
        );
        for label in &labels {
            match r.passes.iter().find(|p| &p.label == label) {
                Some(p) => {
                    let _ = write!(out, " {:.1} |", p.micros);
                }
                None => out.push_str(" - |"),
            }
        }
        let _ = writeln!(
            out,
            " {:.1} | {:.1} | {:.1} | {:.1} | {:.1} |",
            r.gpu_total_us, r.cpu_frame_us, r.cpu_thread_us, r.cpu_finish_us, r.cpu_submit_us
        );
    }
    out.push_str(
        "\n| budget | far | far px | selected per level | mesh nodes | far nodes | quads | far \
         blocks | grass units | splat pixels | raster pixels tested / hit / tiles | frustum-culled | occluded | MAE | > 8/255 |\n",
    );
    out.push_str("| ---: | ---: | ---: | :--- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
    for r in &report.runs {
        let d = &r.drawn;
        let (mae, share) = r.image_error.map_or(("-".to_owned(), "-".to_owned()), |e| {
            (
                format!("{:.3}", e.mean_abs),
                format!("{:.3} %", 100.0 * e.share_over_8),
            )
        });
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:?} | {} | {} | {} | {} | {} | {} | {} | {} | {} ({:.1} %) | {} | {} |",
            budget_label(r.budget_px),
            r.far,
            r.far_cell_px,
            d.selected_per_level,
            d.mesh_nodes,
            d.far_nodes,
            d.mesh_quads + d.transparent_quads + d.smooth_quads,
            d.far_blocks,
            d.grass_units,
            d.splat_pixels,
            d.quad_raster.map_or("-".to_owned(), |q| format!(
                "{} / {} / {}",
                u64::from(q.local_pixels) + u64::from(q.tile_pixels),
                q.hits,
                q.tiles
            )),
            d.frustum_culled,
            d.occluded,
            100.0 * d.occluded_fraction(),
            mae,
            share
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
    fn tables_have_a_row_per_run_and_json_round_trips_the_figures() {
        let run = RunReport {
            budget_px: Some(1.0),
            far: "Splat".to_owned(),
            far_cell_px: 4.0,
            fullscreen: "Compute".to_owned(),
            occlusion: false,
            opaque: "Raster".to_owned(),
            passes: vec![PassMedian {
                label: "cull".to_owned(),
                micros: 3.0,
            }],
            gpu_total_us: 3.0,
            cpu_frame_us: 4.0,
            cpu_thread_us: 3.5,
            cpu_finish_us: 1.0,
            cpu_submit_us: 1.5,
            drawn: DrawnCounts {
                selected: 10,
                frustum_culled: 2,
                occluded: 4,
                ..Default::default()
            },
            image_error: Some(ImageErrorReport {
                mean_abs: 0.5,
                share_over_8: 0.001,
            }),
        };
        assert!((run.drawn.occluded_fraction() - 0.5).abs() < 1e-12);
        let report = BenchReport {
            scene: SceneSummary::default(),
            runs: vec![
                run.clone(),
                RunReport {
                    budget_px: None,
                    image_error: None,
                    ..run
                },
            ],
        };
        let table = markdown(&report);
        assert!(table.contains(
            "| 1 px | Splat | 4 | Compute | off | Raster | 3.0 | 3.0 | 4.0 | 3.5 | 1.0 | 1.5 |"
        ));
        assert!(table.contains("| full |"));
        assert!(table.contains("0.500 | 0.100 %"));
        let json = serde_json::to_value(&report).unwrap();
        assert_eq!(json["runs"][0]["gpu_total_us"], 3.0);
        assert_eq!(json["runs"][1]["budget_px"], serde_json::Value::Null);
    }
}
