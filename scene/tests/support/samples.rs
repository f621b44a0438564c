//! The shared sample models (`../shared/data/vox/` and `gltf/` beside the checkout), found the way every
//! test of the workspace finds them: under CI (`CI=true`) their absence fails the test;
//! elsewhere the test prints one `skipped: <test>: no sample data` line (visible in every run)
//! and passes.

#![allow(dead_code, reason = "each including test uses a different part")]

use std::io::Write;
use std::path::PathBuf;

/// Every `.vox` file of the shared sample data, sorted by name; empty (after printing a skip
/// line) when the folder is missing outside CI.
pub(crate) fn sample_vox_files() -> Vec<PathBuf> {
    let Some(dir) = sample_dir("vox") else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "vox"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "{} holds no .vox files", dir.display());
    files
}

/// The bytes of the shared glTF sample `name` (`../shared/data/gltf/<name>`); `None` (after
/// printing a skip line) when the folder is missing outside CI. A missing file inside a
/// present folder fails.
pub(crate) fn sample_gltf(name: &str) -> Option<Vec<u8>> {
    let path = sample_dir("gltf")?.join(name);
    Some(std::fs::read(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display())))
}

/// `../shared/data/<kind>` beside the checkout; `None` after a skip line when it is missing
/// outside CI.
pub(crate) fn sample_dir(kind: &str) -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/data")
        .join(kind);
    if !dir.is_dir() {
        if std::env::var("CI").is_ok_and(|v| v == "true") {
            panic!(
                "sample data folder {} is missing; CI must have ../shared beside the checkout",
                dir.display()
            );
        }
        // Straight to standard error: the harness hides `eprintln!` of passing tests.
        let test = std::thread::current()
            .name()
            .unwrap_or("(unnamed test)")
            .to_owned();
        let _ = writeln!(
            std::io::stderr().lock(),
            "skipped: {test}: no sample data ({})",
            dir.display()
        );
        return None;
    }
    Some(dir)
}
