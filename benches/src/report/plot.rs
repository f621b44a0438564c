//! The report's plots: line charts written as SVG with `plotters` (SVG backend only: no font
//! or bitmap dependencies, so it builds on a bare machine; text is left to the SVG viewer).

use std::path::Path;

use plotters::prelude::*;

use super::{Measurements, ReportError};

/// Folder of the plots, relative to the report's output folder.
pub const PLOT_DIR: &str = "tradeoff";

/// One written plot.
#[derive(Clone, Debug, PartialEq)]
pub struct Plot {
    /// Which section it belongs to (`cpu`, `geometry`, `image`).
    pub section: &'static str,
    /// Its caption.
    pub title: String,
    /// Its path relative to the report (`tradeoff/NAME.svg`).
    pub path: String,
}

/// A named series of points.
pub type Series = (String, Vec<(f64, f64)>);

const COLOURS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
];

fn plot_error(e: impl std::fmt::Debug) -> ReportError {
    ReportError(format!("plot: {e:?}"))
}

/// Draws `series` as lines with points into an SVG at `path`. With `x_log2`, x values are
/// log2 of the quantity and the axis is labelled with the quantity.
pub fn line_chart(
    path: &Path,
    title: &str,
    x_desc: &str,
    y_desc: &str,
    series: &[Series],
    x_log2: bool,
) -> Result<(), ReportError> {
    let points = series
        .iter()
        .flat_map(|(_, p)| p.iter())
        .filter(|p| p.1.is_finite());
    let (mut x0, mut x1, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    for &(x, y) in points {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y1 = y1.max(y);
    }
    if !x0.is_finite() {
        (x0, x1) = (0.0, 1.0);
    }
    if x1 <= x0 {
        x1 = x0 + 1.0;
    }
    let pad = (x1 - x0) * 0.05;
    let y1 = if y1 > 0.0 { y1 * 1.1 } else { 1.0 };
    let root = SVGBackend::new(path, (720, 420)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_error)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x0 - pad..x1 + pad, 0.0..y1)
        .map_err(plot_error)?;
    // Only powers of two are labelled on a log2 axis (the ticks between them stay blank).
    let log_label = |x: &f64| {
        if (x - x.round()).abs() < 1e-6 {
            format!("{}", 2f64.powf(x.round()))
        } else {
            String::new()
        }
    };
    let plain_label = |x: &f64| format!("{x}");
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_label_formatter(if x_log2 { &log_label } else { &plain_label })
        .draw()
        .map_err(plot_error)?;
    for (i, (name, pts)) in series.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let pts: Vec<(f64, f64)> = pts.iter().copied().filter(|p| p.1.is_finite()).collect();
        chart
            .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))
            .map_err(plot_error)?
            .label(name.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour));
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 3, colour.filled())))
            .map_err(plot_error)?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperLeft)
        .draw()
        .map_err(plot_error)?;
    root.present().map_err(plot_error)?;
    Ok(())
}

/// The CPU series: per mode, (chunk edge, `f` of the totals over every input).
fn cpu_series(m: &Measurements, f: impl Fn(f64, f64, f64) -> f64) -> Vec<Series> {
    super::cpu::MODES
        .iter()
        .map(|&(_, mode)| {
            let mut edges: Vec<u32> = m.cpu.iter().map(|r| r.chunk_edge).collect();
            edges.sort_unstable();
            edges.dedup();
            let pts = edges
                .iter()
                .map(|&e| {
                    let rows = m.cpu.iter().filter(|r| r.mode == mode && r.chunk_edge == e);
                    let (s, b, v) = rows.fold((0.0, 0.0, 0.0), |(s, b, v), r| {
                        (s + r.seconds, b + r.bytes as f64, v + r.voxels as f64)
                    });
                    (f64::from(e), f(s, b, v))
                })
                .collect();
            (mode.to_owned(), pts)
        })
        .collect()
}

/// Draws every plot of `m` into `dir`; returns what was written.
pub fn draw_all(m: &Measurements, dir: &Path) -> Result<Vec<Plot>, ReportError> {
    let mut plots = Vec::new();
    let mut add = |section: &'static str,
                   name: &str,
                   title: &str,
                   x: &str,
                   y: &str,
                   series: &[Series],
                   log2: bool|
     -> Result<(), ReportError> {
        let file = format!("{name}.svg");
        line_chart(&dir.join(&file), title, x, y, series, log2)?;
        plots.push(Plot {
            section,
            title: title.to_owned(),
            path: format!("{PLOT_DIR}/{file}"),
        });
        Ok(())
    };
    if !m.cpu.is_empty() {
        let per_mvoxel = |s: f64, _b: f64, v: f64| if v > 0.0 { s * 1e3 * 1e6 / v } else { 0.0 };
        add(
            "cpu",
            "cpu_time",
            "Meshing time per million voxels (all inputs, one thread)",
            "chunk edge (voxels)",
            "ms per million voxels",
            &cpu_series(m, per_mvoxel),
            false,
        )?;
        let bytes_per_voxel = |_s: f64, b: f64, v: f64| if v > 0.0 { b / v } else { 0.0 };
        add(
            "cpu",
            "cpu_bytes",
            "Packed mesh bytes per voxel (all inputs)",
            "chunk edge (voxels)",
            "bytes per voxel",
            &cpu_series(m, bytes_per_voxel),
            false,
        )?;
    }
    if !m.geometry.is_empty() {
        let mut series = Vec::new();
        for shape in ["sphere", "torus"] {
            let rows: Vec<_> = m.geometry.iter().filter(|r| r.shape == shape).collect();
            series.push((
                format!("{shape} mean"),
                rows.iter()
                    .map(|r| (f64::from(r.radius), r.vertex.mean))
                    .collect(),
            ));
            series.push((
                format!("{shape} max"),
                rows.iter()
                    .map(|r| (f64::from(r.radius), r.vertex.max))
                    .collect(),
            ));
        }
        add(
            "geometry",
            "surface_error",
            "SurfaceNets vertices: distance to the analytic surface",
            "radius (voxels; torus: minor radius)",
            "distance (voxels)",
            &series,
            false,
        )?;
    }
    if let Some(sweep) = &m.image {
        let rows: Vec<_> = sweep
            .rows
            .iter()
            .filter(|r| r.budget_px.is_some())
            .collect();
        let x = |r: &&super::image::BudgetRow| r.budget_px.unwrap_or(1.0).log2();
        add(
            "image",
            "image_error",
            "Image error against full detail",
            "error budget (px)",
            "MAE (/255) and % of pixels > 8/255",
            &[
                (
                    "mean abs error (/255)".to_owned(),
                    rows.iter()
                        .map(|r| (x(r), r.mean_abs.unwrap_or(f64::NAN)))
                        .collect(),
                ),
                (
                    "% pixels off > 8/255".to_owned(),
                    rows.iter()
                        .map(|r| (x(r), r.share_over_8.unwrap_or(f64::NAN) * 100.0))
                        .collect(),
                ),
            ],
            true,
        )?;
        let mut series = vec![(
            "budget".to_owned(),
            rows.iter().map(|r| (x(r), r.gpu_us / 1e3)).collect(),
        )];
        if let Some(full) = sweep.full() {
            series.push((
                "full detail".to_owned(),
                rows.iter().map(|r| (x(r), full.gpu_us / 1e3)).collect(),
            ));
        }
        add(
            "image",
            "gpu_time",
            "GPU time per frame",
            "error budget (px)",
            "GPU ms",
            &series,
            true,
        )?;
    }
    Ok(plots)
}
