//! The image features' section: each feature's GPU cost against its effect on the picture,
//! read from a `gpu_bench --features --json` file ([`FeatureReport`]).

use std::fmt::Write;
use std::path::Path;

use super::ReportError;
use crate::gpu_bench::features::{FeatureReport, features_markdown};

/// Reads a `gpu_bench --features --json` file; an unreadable file, bad JSON or a table
/// without rows is an error that names the file.
pub fn load(path: &Path) -> Result<FeatureReport, ReportError> {
    let bad = |what: String| ReportError(format!("{}: {what}", path.display()));
    let text = std::fs::read_to_string(path).map_err(|e| bad(e.to_string()))?;
    let report: FeatureReport = serde_json::from_str(&text).map_err(|e| bad(e.to_string()))?;
    if report.rows.is_empty() {
        return Err(bad("the feature table has no rows".to_owned()));
    }
    if let Some(row) = report
        .rows
        .iter()
        .find(|r| !(r.gpu_total_us.is_finite() && r.mean_abs.is_finite()))
    {
        return Err(bad(format!(
            "row {:?} has a figure that is not a number",
            row.name
        )));
    }
    Ok(report)
}

/// The section's body: the table and how to read it, or a line saying it was not measured.
pub fn section(s: &mut String, report: Option<&FeatureReport>, source: Option<&Path>) {
    let (Some(report), Some(source)) = (report, source) else {
        let _ = writeln!(
            s,
            "Not measured in this run (`--features-json`, from `gpu_bench --features --json`).\n"
        );
        return;
    };
    let _ = writeln!(
        s,
        "What each image feature costs on the GPU against how much it changes the picture, read \
         from `{}` (made by `scripts/gpu/frame.sh features`: `gpu_bench --features`). \"added\" \
         is the frame's GPU time less the frame without any feature; the image difference is \
         against that frame too. Palette colours, the sky and water and glass are in every \
         row. The camera is still, so the shadow grid is filled once; a moving camera \
         refills it every frame (BENCHMARKS.md has the flight's `shadow grid`).\n",
        source.display()
    );
    s.push_str(&features_markdown(report));
    s.push('\n');
}
