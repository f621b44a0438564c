//! Shared helpers for the cross-crate integration tests in `tests/`.

use std::path::{Path, PathBuf};

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
    vox_files_in(&dir, "")
}

/// Every `.vox` file of the folder named by `BLOCKY_VOX_DIR`, sorted by name, when it is set
/// (as the blocky bench reads it): models of one's own, to check against the peers beside the
/// samples. Empty when it is not set; a set path that is not a folder of `.vox` files panics,
/// so that a mistyped path is never taken for a pass.
pub fn extra_vox_files() -> Vec<PathBuf> {
    let Some(dir) = std::env::var_os("BLOCKY_VOX_DIR").map(PathBuf::from) else {
        return Vec::new();
    };
    vox_files_in(&dir, "BLOCKY_VOX_DIR: ")
}

/// Every `.vox` file of `dir`, sorted by name; panics (the message starting with `context`)
/// if `dir` cannot be listed or holds none.
fn vox_files_in(dir: &Path, context: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{context}cannot list {}: {e}", dir.display()))
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "vox"))
        .collect();
    files.sort();
    assert!(
        !files.is_empty(),
        "{context}{} holds no .vox files",
        dir.display()
    );
    files
}
