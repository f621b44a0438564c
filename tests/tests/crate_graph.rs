//! The crate graph the design states: the CPU render model and the reference renderers link no
//! GPU API, and the backend reads formats only (it never links the mesher). Read from
//! `cargo tree` over the normal dependencies (dev-dependencies may use anything).

use std::process::Command;

/// The crates `package` links, by name, from `cargo tree -e normal` (offline, locked).
fn normal_dependencies(package: &str) -> Vec<String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_owned());
    let out = Command::new(cargo)
        .args([
            "tree",
            "--offline",
            "--locked",
            "-e",
            "normal",
            "--prefix",
            "none",
            "--format",
            "{p}",
            "-p",
            package,
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("cargo runs");
    assert!(
        out.status.success(),
        "cargo tree -p {package} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .expect("utf-8")
        .lines()
        .filter_map(|l| l.split_whitespace().next().map(str::to_owned))
        .collect()
}

fn assert_lacks(package: &str, forbidden: &str) {
    let deps = normal_dependencies(package);
    assert!(
        deps.len() > 2,
        "cargo tree -p {package} listed only {deps:?}: the reader is broken"
    );
    assert!(
        !deps.iter().any(|d| d == forbidden),
        "{package} links {forbidden}: {deps:?}"
    );
}

#[test]
fn the_render_model_links_no_gpu_api() {
    assert_lacks("render-model", "wgpu");
    assert_lacks("render-model", "gpu-backend");
}

#[test]
fn the_reference_renderers_link_no_gpu_api() {
    assert_lacks("voxel-reference", "wgpu");
    assert_lacks("voxel-reference", "gpu-backend");
}

#[test]
fn the_backend_does_not_link_the_mesher() {
    assert_lacks("gpu-backend", "mesher");
}

#[test]
fn the_world_links_no_gpu_api_and_no_library_below_links_it() {
    assert_lacks("voxel-world", "wgpu");
    assert_lacks("voxel-world", "gpu-backend");
    assert_lacks("voxel-world", "render-model");
    for below in [
        "voxel-core",
        "mesher",
        "voxel-scene",
        "render-model",
        "gpu-backend",
    ] {
        assert_lacks(below, "voxel-world");
    }
}

#[test]
fn the_reader_sees_what_a_crate_links() {
    let deps = normal_dependencies("gpu-backend");
    for expected in ["wgpu", "voxel-core", "render-model"] {
        assert!(deps.iter().any(|d| d == expected), "{expected} in {deps:?}");
    }
}
