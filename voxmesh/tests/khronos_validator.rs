//! The Khronos glTF validator (npm `gltf-validator`, run with node) finds no error and no
//! warning in what voxmesh writes: every sample model in every mode, scenes with every
//! material kind, and the terrain.
//!
//! `scripts/install-gltf-validator.sh` (run by the test command) installs node and the
//! validator under `.tools/gltf-validator/`; the environment variable `GLTF_VALIDATOR` names
//! another installation folder. Without them the test prints one `skipped:` line, except
//! under `CI=true`, where their absence is a failure.

mod support;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

use support::{s, voxmesh_ok, write_vox};

/// The validator's folder and node, or `None` (after a skip line) when either is missing.
fn validator() -> Option<PathBuf> {
    let dir = std::env::var_os("GLTF_VALIDATOR").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("../.tools/gltf-validator"),
        PathBuf::from,
    );
    let have_package = dir
        .join("node_modules/gltf-validator/package.json")
        .is_file();
    let have_node = Command::new("node")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if have_package && have_node {
        return Some(dir);
    }
    let why = format!(
        "no glTF validator (node found: {have_node}; package in {}: {have_package}); \
         scripts/install-gltf-validator.sh installs both",
        dir.display()
    );
    if std::env::var("CI").is_ok_and(|v| v == "true") {
        panic!("{why}");
    }
    // Straight to standard error: the harness hides `eprintln!` of passing tests.
    let test = std::thread::current()
        .name()
        .unwrap_or("(unnamed test)")
        .to_owned();
    let _ = writeln!(std::io::stderr().lock(), "skipped: {test}: {why}");
    None
}

#[test]
fn the_khronos_validator_reports_no_error_on_any_output() {
    let Some(validator_dir) = validator() else {
        return;
    };
    let dir = support::temp_dir();
    let mut files: Vec<PathBuf> = Vec::new();
    let mut run = |input: &str, name: &str, extra: &[&str]| {
        let out = dir.path().join(format!("{name}.glb"));
        let mut args = vec![input, "-o", s(&out)];
        args.extend_from_slice(extra);
        voxmesh_ok(&args);
        files.push(out);
    };
    let modes: [(&str, &[&str]); 5] = [
        ("faces", &["--mode", "faces"]),
        ("greedy", &["--mode", "greedy"]),
        ("greedy-ao", &["--mode", "greedy", "--ao", "--chunk", "16"]),
        ("smooth", &["--mode", "smooth", "--chunk", "62"]),
        ("lod1", &["--lod", "1", "--scale", "0.1"]),
    ];
    let samples = support::samples::sample_vox_files();
    for path in &samples {
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        for (mode, extra) in modes {
            run(s(path), &format!("{stem}-{mode}"), extra);
        }
    }
    let materials = write_vox(dir.path(), "materials.vox", &support::material_scene());
    for (mode, extra) in modes {
        run(s(&materials), &format!("materials-{mode}"), extra);
    }
    run(s(&materials), "materials-hidden", &["--hidden", "--ao"]);
    run("terrain:3:64", "terrain-greedy", &["--ao"]);
    run("terrain:3:64", "terrain-smooth", &["--mode", "smooth"]);

    let output = Command::new("node")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/validate.cjs"))
        .args(&files)
        .env("GLTF_VALIDATOR", &validator_dir)
        .output()
        .expect("node runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "the validator failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let reports: Vec<serde_json::Value> = stdout
        .lines()
        .map(|l| serde_json::from_str(l).expect("one JSON report per line"))
        .collect();
    assert_eq!(reports.len(), files.len(), "one report per file");
    let mut bad = Vec::new();
    for report in &reports {
        if report["errors"] != 0 || report["warnings"] != 0 {
            bad.push(report.to_string());
        }
    }
    eprintln!(
        "glTF validator {}: {} files ({} sample models x {} modes and more), {} with errors or warnings",
        reports[0]["validator"],
        reports.len(),
        samples.len(),
        modes.len(),
        bad.len()
    );
    assert!(bad.is_empty(), "validator findings:\n{}", bad.join("\n"));
}
