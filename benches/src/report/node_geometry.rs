//! The node geometry section: the terrain meshed as greedy quads, vertical shells and heightmap
//! cubes,
//! read from `gpu_bench --geometry --json` files ([`GeometryReport`]), one per opaque path.

use std::fmt::Write;
use std::path::{Path, PathBuf};

use super::ReportError;
use crate::gpu_bench::geometry::{GeometryReport, geometry_markdown};

/// Reads a `gpu_bench --geometry --json` file; an unreadable file, bad JSON or a table
/// without rows is an error that names the file.
pub fn load(path: &Path) -> Result<GeometryReport, ReportError> {
    let bad = |what: String| ReportError(format!("{}: {what}", path.display()));
    let text = std::fs::read_to_string(path).map_err(|e| bad(e.to_string()))?;
    let report: GeometryReport = serde_json::from_str(&text).map_err(|e| bad(e.to_string()))?;
    if report.rows.is_empty() {
        return Err(bad("the geometry table has no rows".to_owned()));
    }
    Ok(report)
}

/// The section's body: each table with how to read it, or a line saying none was measured.
pub fn section(s: &mut String, reports: &[(PathBuf, GeometryReport)]) {
    if reports.is_empty() {
        let _ = writeln!(
            s,
            "Not measured in this run (`--geometry-json`, from `gpu_bench --geometry --json`).\n"
        );
        return;
    }
    let _ = writeln!(
        s,
        "The same terrain with its opaque surface as greedy quads (8 bytes a quad), as SBgl's \
         vertical shells (8 bytes a run, drawn as boxes the vertex shader makes, the 3 faces \
         toward the eye: 6 triangles a run) or as SBgl's heightmap cubes (one such box per \
         column top, split by block, equal columns merged along x): made by \
         `scripts/gpu/frame.sh geometry`. Greedy and shells keep the same transparent quads, \
         skirts and far-draw data; heightmap nodes keep only their transparent quads (the \
         boxes draw every distance and their border columns are the skirts) and no AO. Shells \
         win where columns are tall and thin (fewer instances for the same surface); on open \
         terrain they hold about as many instances as quads. Heightmap cubes need an order of \
         magnitude fewer bytes but cannot show caves or overhangs. Both submit more triangles \
         than greedy, which costs most on a GPU with few raster units; a GPU with many raster \
         units (a consumer part) draws them nearly free, so there the bytes decide. The table \
         with no node far-drawn (far threshold 0.01 px) isolates the heightmap rule's image \
         difference from the far splat's.\n"
    );
    for (path, report) in reports {
        let _ = writeln!(s, "From `{}`:\n", path.display());
        s.push_str(&geometry_markdown(report));
        s.push('\n');
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_files_are_refused_by_name() {
        let path = std::env::temp_dir().join(format!("geometry_load_{}.json", std::process::id()));
        for (text, why) in [
            (r#"{"adapter":"a","setting":"s","fr"#, "EOF"),
            (
                r#"{"adapter":"a","setting":"s","frames":1,"rows":[]}"#,
                "no rows",
            ),
        ] {
            std::fs::write(&path, text).unwrap();
            let e = load(&path).unwrap_err();
            assert!(
                e.0.contains(&path.display().to_string()) && e.0.contains(why),
                "{e}"
            );
        }
        std::fs::remove_file(&path).ok();
        let mut s = String::new();
        section(&mut s, &[]);
        assert!(s.starts_with("Not measured"));
    }
}
