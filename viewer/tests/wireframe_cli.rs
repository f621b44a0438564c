//! `--wireframe` from the command line: the headless frame draws the meshes' quad edges (the
//! same view otherwise), and the flag is refused with `--cpu`, which has no meshes to outline.

mod support;

use support::{have_adapter, read_png, run_viewer, text};

/// Renders the streamed terrain headless (meshes only) with `extra` flags; the PNG's RGBA.
fn frame(dir: &std::path::Path, name: &str, extra: &[&str]) -> Vec<u8> {
    let out = dir.join(format!("{name}.png"));
    let out_arg = out.to_string_lossy().into_owned();
    let mut args = vec![
        "--headless",
        "--width",
        "160",
        "--height",
        "100",
        "--radius",
        "96",
        "--far",
        "off",
        "--camera",
        "20,40,20,30,-50",
        "--fov",
        "50",
        "--out",
        &out_arg,
    ];
    args.extend_from_slice(extra);
    let output = run_viewer(&args, None);
    let (stdout, stderr) = (text(&output.stdout), text(&output.stderr));
    assert!(output.status.success(), "{stdout}\n{stderr}");
    read_png(&out)
}

#[test]
fn the_wireframe_frame_outlines_the_meshes_of_the_same_view() {
    if !have_adapter() {
        return;
    }
    let dir = std::env::temp_dir().join(format!("viewer-wireframe-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let filled = frame(&dir, "filled", &[]);
    let wire = frame(&dir, "wire", &["--wireframe"]);
    assert_eq!(filled.len(), wire.len());
    let pixels = filled.len() / 4;
    let differ = filled
        .chunks(4)
        .zip(wire.chunks(4))
        .filter(|(a, b)| a.iter().zip(*b).any(|(a, b)| a.abs_diff(*b) > 8))
        .count();
    // Inside each quad the wireframe shows what lies behind it (sky, or faces further back,
    // often of the same grass colour); at this close view over a tenth of the pixels change.
    assert!(
        differ * 10 > pixels,
        "{differ} of {pixels} pixels differ between the filled and the wireframe frame"
    );
    assert!(differ < pixels, "the edges are drawn");
    let again = frame(&dir, "filled-again", &[]);
    assert_eq!(
        again, filled,
        "the filled frame does not depend on an earlier run"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn wireframe_with_the_cpu_raycaster_is_refused() {
    let output = run_viewer(&["--headless", "--cpu", "--wireframe"], None);
    let stderr = text(&output.stderr);
    assert!(!output.status.success());
    assert!(
        stderr.contains("--wireframe") && stderr.contains("--cpu"),
        "{stderr}"
    );
}
