//! Shared helpers for the cross-crate integration tests in `tests/`.

use std::path::PathBuf;

use gpu_backend::test_support::skip;

/// The folder of shared sample data (`../shared/data/<kind>` beside the checkout), if present.
///
/// Sample data is never copied into the repository. When it is missing, a test under CI
/// (`CI=true`) must fail, and anywhere else it may skip with one clear line: this function
/// panics under CI, and elsewhere prints `skipped: <test>: no sample data (<path>)` (see
/// [`skip`]) and returns `None`.
pub fn sample_data(kind: &str) -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/data")
        .join(kind);
    if dir.is_dir() {
        return Some(dir);
    }
    skip(&format!(
        "no sample data ({}; CI must have ../shared beside the checkout)",
        dir.display()
    ));
    None
}

/// Every `.vox` file of the shared sample data, sorted by name (empty when skipped).
pub fn sample_vox_files() -> Vec<PathBuf> {
    let Some(dir) = sample_data("vox") else {
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
