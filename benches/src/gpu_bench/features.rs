//! `gpu_bench --features`: what each image feature costs on the GPU against what it changes in
//! the picture, on one renderer of the benchmark's terrain at one setting.
//!
//! The switchable features are anti-aliasing (FXAA), sun shadows with sky visibility, distance
//! haze and grass. Rows: none of them, each alone, all of them. Each row's cost is its GPU
//! frame less the frame without any; its effect is its image against the image without any
//! (mean absolute error, share of pixels off by more than 8/255). The rows run twice, the
//! second time in reverse order, and each figure is the mean of the two medians, so that a
//! drift of the GPU's clocks during the run does not favour the rows measured first.
//!
//! What every frame draws whatever the switches (palette colours, the sky, water and glass)
//! is in the "none" row's passes. The camera is still, so the shadow grid is filled once and
//! kept ([`ShadowPass::needs_fill`]): a row's shadow cost is the trace's. A moving camera
//! refills it every frame (the viewer's `--flight --shadows on` times it as `shadow grid`).
//!
//! [`ShadowPass::needs_fill`]: gpu_backend::render::passes::shadow::ShadowPass::needs_fill

use serde::{Deserialize, Serialize};

use gpu_backend::GpuContext;
use gpu_backend::render::Renderer;
use render_model::lighting::Lighting;
use render_model::lighting::shadow::ShadowSettings;

use super::{BenchError, PassMedian, image_error, measure};

/// Which image features a row turns on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct FeatureSet {
    /// FXAA of the final image.
    pub antialias: bool,
    /// Sun shadows and sky visibility (`ShadowSettings::default()`).
    pub shadows: bool,
    /// Distance haze at the terrain's half side.
    pub haze: bool,
    /// Grass and flowers (the grass pass).
    pub grass: bool,
}

impl FeatureSet {
    /// Every feature on.
    pub const ALL: FeatureSet = FeatureSet {
        antialias: true,
        shadows: true,
        haze: true,
        grass: true,
    };

    /// The rows of the table: none, each alone, all.
    pub fn rows() -> Vec<(&'static str, FeatureSet)> {
        let none = FeatureSet::default();
        vec![
            ("none", none),
            (
                "anti-aliasing (FXAA)",
                FeatureSet {
                    antialias: true,
                    ..none
                },
            ),
            (
                "sun shadows and sky visibility",
                FeatureSet {
                    shadows: true,
                    ..none
                },
            ),
            ("distance haze", FeatureSet { haze: true, ..none }),
            (
                "grass",
                FeatureSet {
                    grass: true,
                    ..none
                },
            ),
            ("all", FeatureSet::ALL),
        ]
    }
}

/// One row of the table.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FeatureRow {
    /// What the row turns on, in words.
    pub name: String,
    /// The switches.
    pub features: FeatureSet,
    /// GPU time of the frame, microseconds (the sum of the pass timestamps).
    pub gpu_total_us: f64,
    /// `gpu_total_us` less the row without any feature's.
    pub added_us: f64,
    /// GPU time of the passes that exist only with a feature on, microseconds, by label.
    pub feature_passes: Vec<(String, f64)>,
    /// GPU time of every pass, microseconds, by label in frame order (means of the medians):
    /// where a row's added time goes beyond its own passes.
    #[serde(default)]
    pub passes: Vec<(String, f64)>,
    /// CPU time to record and submit the frame (the calling thread's), microseconds.
    pub cpu_thread_us: f64,
    /// Mean absolute difference from the image without any feature, 8-bit steps.
    pub mean_abs: f64,
    /// Share of pixels (0..=1) off by more than 8/255 from the image without any feature.
    pub share_over_8: f64,
}

/// The table and what it was measured on.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FeatureReport {
    /// The adapter, as wgpu names it.
    pub adapter: String,
    /// The setting, in words (terrain, budget, paths, size).
    pub setting: String,
    /// Timed frames per row and round.
    pub frames: usize,
    /// The rows, [`FeatureSet::rows`] order.
    pub rows: Vec<FeatureRow>,
}

/// Pass labels that only a feature's frames have.
const FEATURE_PASSES: [&str; 4] = ["shadow grid", "shadow trace", "grass", "antialias"];

/// Switches `renderer` to `features`; `haze_distance` is the haze's distance, blocks.
fn apply(
    renderer: &mut Renderer,
    features: FeatureSet,
    haze_distance: f32,
) -> Result<(), BenchError> {
    renderer.set_antialias(features.antialias);
    renderer.set_clutter(features.grass)?;
    let lighting = Lighting {
        shadows: if features.shadows {
            ShadowSettings::default()
        } else {
            ShadowSettings::OFF
        },
        haze_distance: if features.haze {
            haze_distance
        } else {
            f32::INFINITY
        },
        ..Lighting::default()
    };
    renderer
        .set_lighting(&lighting)
        .map_err(|e| BenchError::BadConfig(e.to_string()))
}

/// Measures the rows of [`FeatureSet::rows`] on `renderer` (set up, its terrain resident,
/// with a grass pass), `frames` timed frames per row and round.
pub fn bench_features(
    ctx: &GpuContext,
    renderer: &mut Renderer,
    frames: usize,
    haze_distance: f32,
    setting: String,
) -> Result<FeatureReport, BenchError> {
    if !haze_distance.is_finite() || haze_distance <= 0.0 {
        return Err(BenchError::BadConfig(format!(
            "haze distance {haze_distance} is not a positive number of blocks"
        )));
    }
    let rows = FeatureSet::rows();
    let mut totals = vec![Vec::new(); rows.len()];
    let mut cpu = vec![Vec::new(); rows.len()];
    let mut passes: Vec<Vec<PassMedian>> = vec![Vec::new(); rows.len()];
    let mut images = vec![None; rows.len()];
    for round in 0..2 {
        let order: Vec<usize> = if round == 0 {
            (0..rows.len()).collect()
        } else {
            (0..rows.len()).rev().collect()
        };
        for i in order {
            apply(renderer, rows[i].1, haze_distance)?;
            let (medians, cpu_frame, _, image) = measure(ctx, renderer, frames)?;
            totals[i].push(medians.iter().map(|p| p.micros).sum::<f64>());
            cpu[i].push(cpu_frame.thread_us);
            passes[i].extend(medians);
            images[i] = Some(image.rgba);
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let none_total = mean(&totals[0]);
    let none_image = images[0].clone().unwrap_or_default();
    let mut out = Vec::new();
    for (i, (name, features)) in rows.iter().enumerate() {
        let error = images[i]
            .as_deref()
            .and_then(|image| image_error(image, &none_image))
            .unwrap_or_default();
        // The mean of a pass's medians over the rounds (None: the row has no such pass).
        let pass_mean = |label: &str| {
            let times: Vec<f64> = passes[i]
                .iter()
                .filter(|p| p.label == label)
                .map(|p| p.micros)
                .collect();
            (!times.is_empty()).then(|| (label.to_owned(), mean(&times)))
        };
        let feature_passes = FEATURE_PASSES
            .iter()
            .filter_map(|&l| pass_mean(l))
            .collect();
        let mut labels: Vec<&str> = Vec::new();
        for p in &passes[i] {
            if !labels.contains(&p.label.as_str()) {
                labels.push(&p.label);
            }
        }
        let all_passes = labels.iter().filter_map(|&l| pass_mean(l)).collect();
        let total = mean(&totals[i]);
        out.push(FeatureRow {
            name: (*name).to_owned(),
            features: *features,
            gpu_total_us: total,
            added_us: total - none_total,
            feature_passes,
            passes: all_passes,
            cpu_thread_us: mean(&cpu[i]),
            mean_abs: error.mean_abs,
            share_over_8: error.share_over_8,
        });
    }
    apply(renderer, FeatureSet::ALL, haze_distance)?;
    Ok(FeatureReport {
        adapter: ctx.capabilities.adapter.to_string(),
        setting,
        frames,
        rows: out,
    })
}

/// The table as Markdown: a row per feature set, its GPU cost and its effect on the image.
pub fn features_markdown(report: &FeatureReport) -> String {
    let mut s = String::new();
    s.push_str(&format!(
        "{}; {}; {} timed frames per row, twice (forward, then reverse order), means of the \
         medians.\n\n",
        report.adapter, report.setting, report.frames
    ));
    s.push_str(
        "| features | GPU frame µs | added µs | the features' own passes µs | CPU µs | MAE vs none | pixels off > 8/255 |\n",
    );
    s.push_str("| --- | ---: | ---: | --- | ---: | ---: | ---: |\n");
    for row in &report.rows {
        let own = if row.feature_passes.is_empty() {
            "-".to_owned()
        } else {
            row.feature_passes
                .iter()
                .map(|(label, us)| format!("{label} {us:.1}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        s.push_str(&format!(
            "| {} | {:.1} | {:+.1} | {} | {:.0} | {:.2} | {:.1} % |\n",
            row.name,
            row.gpu_total_us,
            row.added_us,
            own,
            row.cpu_thread_us,
            row.mean_abs,
            row.share_over_8 * 100.0
        ));
    }
    s.push_str(&passes_changed(report));
    s
}

/// Per row, the passes whose GPU time differs from the row without any feature's by more
/// than [`PASS_CHANGE_US`] (a pass it lacks counts as 0): where each row's added time goes.
fn passes_changed(report: &FeatureReport) -> String {
    let Some(none) = report.rows.first() else {
        return String::new();
    };
    let time = |row: &FeatureRow, label: &str| {
        row.passes
            .iter()
            .find(|(l, _)| l == label)
            .map_or(0.0, |(_, us)| *us)
    };
    let mut s = String::from("\nPasses that changed against none, µs:\n\n");
    for row in report.rows.iter().skip(1) {
        let mut labels: Vec<&str> = row.passes.iter().map(|(l, _)| l.as_str()).collect();
        for (l, _) in &none.passes {
            if !labels.contains(&l.as_str()) {
                labels.push(l);
            }
        }
        let changed: Vec<String> = labels
            .iter()
            .filter_map(|&label| {
                let d = time(row, label) - time(none, label);
                (d.abs() > PASS_CHANGE_US).then(|| format!("{label} {d:+.1}"))
            })
            .collect();
        let list = if changed.is_empty() {
            "none".to_owned()
        } else {
            changed.join(", ")
        };
        s.push_str(&format!("- {}: {list}\n", row.name));
    }
    s
}

/// The change in a pass's time that [`passes_changed`] reports, microseconds.
const PASS_CHANGE_US: f64 = 5.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_none_each_alone_and_all() {
        let rows = FeatureSet::rows();
        assert_eq!(rows.first().map(|r| r.1), Some(FeatureSet::default()));
        assert_eq!(rows.last().map(|r| r.1), Some(FeatureSet::ALL));
        for (name, set) in &rows[1..rows.len() - 1] {
            let on = [set.antialias, set.shadows, set.haze, set.grass];
            assert_eq!(on.iter().filter(|&&b| b).count(), 1, "{name}");
        }
    }

    #[test]
    fn the_table_shows_cost_and_effect() {
        let report = FeatureReport {
            adapter: "test adapter".to_owned(),
            setting: "a setting".to_owned(),
            frames: 3,
            rows: vec![
                FeatureRow {
                    name: "none".to_owned(),
                    gpu_total_us: 1249.5,
                    passes: vec![("lighting".to_owned(), 50.0), ("hi-z".to_owned(), 9.0)],
                    ..FeatureRow::default()
                },
                FeatureRow {
                    name: "grass".to_owned(),
                    features: FeatureSet {
                        grass: true,
                        ..FeatureSet::default()
                    },
                    gpu_total_us: 1500.0,
                    added_us: 250.5,
                    feature_passes: vec![("grass".to_owned(), 240.0)],
                    passes: vec![
                        ("grass".to_owned(), 240.0),
                        ("lighting".to_owned(), 52.0),
                        ("hi-z".to_owned(), 17.5),
                    ],
                    cpu_thread_us: 400.0,
                    mean_abs: 3.25,
                    share_over_8: 0.125,
                },
            ],
        };
        let table = features_markdown(&report);
        assert!(table.contains("| grass | 1500.0 | +250.5 | grass 240.0 | 400 | 3.25 | 12.5 % |"));
        assert!(table.starts_with("test adapter; a setting; 3 timed frames"));
        // The lighting's 2 µs is under the threshold; the grass pass is new, hi-z grew.
        assert!(
            table.contains("- grass: grass +240.0, hi-z +8.5\n"),
            "{table}"
        );
    }
}
