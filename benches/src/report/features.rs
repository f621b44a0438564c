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

#[cfg(test)]
mod tests {
    use super::*;

    /// Writes `text` to a file of its own under the temporary folder.
    fn file(name: &str, text: &str) -> std::path::PathBuf {
        let path =
            std::env::temp_dir().join(format!("features_load_{}_{name}.json", std::process::id()));
        std::fs::write(&path, text).expect("temporary file");
        path
    }

    #[test]
    fn bad_files_are_refused_by_name() {
        let missing = std::env::temp_dir().join("features_load_no_such_file.json");
        let e = load(&missing).unwrap_err();
        assert!(e.0.contains("features_load_no_such_file.json"), "{e}");
        for (name, text, why) in [
            ("garbage", "\u{1}not json", "expected value"),
            (
                "empty",
                r#"{"adapter":"a","setting":"s","frames":1,"rows":[]}"#,
                "no rows",
            ),
            ("truncated", r#"{"adapter":"a","setting":"s","fr"#, "EOF"),
        ] {
            let path = file(name, text);
            let e = load(&path).unwrap_err();
            assert!(
                e.0.contains(&path.display().to_string()) && e.0.contains(why),
                "{name}: {e}"
            );
            std::fs::remove_file(path).ok();
        }
    }

    #[test]
    fn the_committed_table_loads_and_renders() {
        let path =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/data/gpu_bench_features.json");
        let report = load(&path).expect("the committed table");
        let mut s = String::new();
        section(&mut s, Some(&report), Some(&path));
        assert!(s.contains("| none |") && s.contains("| all |"), "{s}");
        let mut absent = String::new();
        section(&mut absent, None, None);
        assert!(absent.starts_with("Not measured"), "{absent}");
    }
}
