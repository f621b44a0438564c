//! The tradeoff report's library on tiny inputs: every section is written with numbers, the
//! plots are SVG files, and the GPU sweep committed in `docs/data/` is read.

use std::path::Path;

use benches::report::markdown::SECTIONS;
use benches::report::{Config, measure, write_report};

/// The text of `section` up to the next `## ` heading.
fn section<'a>(text: &'a str, heading: &str) -> &'a str {
    let start = text
        .find(heading)
        .unwrap_or_else(|| panic!("no section {heading:?}"));
    let rest = &text[start + heading.len()..];
    &rest[..rest.find("\n## ").unwrap_or(rest.len())]
}

/// True when `text` has a table row with at least one number in a cell.
fn has_numeric_row(text: &str) -> bool {
    text.lines().any(|l| {
        l.starts_with('|')
            && l.split('|')
                .any(|cell| cell.trim().trim_end_matches(" %").parse::<f64>().is_ok())
    })
}

/// The report measured on the terrain and one small sample model (`chr_knight.vox` of the
/// shared samples): every section has numbers. Without the samples it says so (`skipped:`
/// for the model's rows, a failure under `CI=true`); a sample folder without the model is a
/// failure that names it.
///
/// The fault it catches: a missing sample model dropped without a word, so the report's
/// model rows go untested while the test passes. Planted (the test asking for
/// `chr_knight_gone.vox`), the test failed with "the sample folder ... has no
/// chr_knight_gone.vox"; before, it passed on the terrain alone.
#[test]
fn tiny_report_has_every_section_with_numbers() {
    let mut config = Config::tiny();
    config.gpu_json = Some(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/data/gpu_bench_h100_budgets.json"),
    );
    config.features_json =
        Some(Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/data/gpu_bench_features.json"));
    config.geometry_json =
        vec![Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/data/gpu_bench_geometry.json")];
    // One small sample model, from the shared data beside the checkout.
    let model = "chr_knight.vox";
    match benches::mesh_inputs::vox_dir() {
        Some(dir) => {
            let knight = dir.join(model);
            assert!(
                knight.is_file(),
                "the sample folder {} has no {model}",
                dir.display()
            );
            config.vox_files.push(knight);
        }
        None => gpu_backend::test_support::skip(&format!(
            "no sample data (../shared/data/vox beside the checkout): the report's rows of \
             {model} are not measured"
        )),
    }
    let m = measure(&config, &|_| {}).expect("measurements");
    // Three modes at one chunk size, per input.
    assert_eq!(m.cpu.len(), 3 * (1 + config.vox_files.len()));
    assert!(
        m.cpu
            .iter()
            .all(|r| r.quads > 0 && r.bytes > 0 && r.chunks > 0)
    );
    // SurfaceNets errors are well under a voxel; quantization far under that.
    assert!(m.geometry.iter().all(|r| r.vertex.max < 0.5 && r.quads > 0));
    for (_, stat, bound) in &m.quantization.position {
        assert!(stat.count > 0 && stat.max <= f64::from(*bound) * 1.01);
    }
    let q = &m.quantization;
    assert!(q.oct16.max <= f64::from(voxel_core::formats::OCT16_MAX_ERROR_DEGREES));
    assert!(q.oct32.max <= f64::from(voxel_core::formats::OCT32_MAX_ERROR_DEGREES));
    // The view is the same at every offset (the raycaster is exact).
    assert!(m.extremes.iter().all(|r| r.pixels_differing == 0));
    assert!(m.extremes[0].terrain_share > 0.2);

    let out = std::env::temp_dir().join(format!("tradeoff_report_test_{}", std::process::id()));
    let text = write_report(&m, &out).expect("written");
    assert_eq!(
        std::fs::read_to_string(out.join("tradeoff.md")).unwrap(),
        text
    );
    for heading in SECTIONS {
        let body = section(&text, heading);
        if heading != "## Recommended defaults" {
            assert!(has_numeric_row(body), "{heading} has no numbers:\n{body}");
        }
    }
    assert!(section(&text, "## Recommended defaults").contains("| error budget | `"));
    for svg in [
        "cpu_time",
        "cpu_bytes",
        "surface_error",
        "image_error",
        "gpu_time",
    ] {
        let path = out.join("tradeoff").join(format!("{svg}.svg"));
        let body = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
        assert!(
            body.starts_with("<svg") && body.contains("<polyline"),
            "{svg}"
        );
    }
    std::fs::remove_dir_all(&out).ok();

    // Without a GPU file the image section says so.
    config.gpu_json = None;
    let mut m = m;
    m.config = config;
    m.image = None;
    let text = benches::report::markdown::render(&m, &[]);
    assert!(section(&text, "## Image").contains("No GPU figures in this run"));
}
