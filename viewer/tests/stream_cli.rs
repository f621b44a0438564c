//! The streamed terrain from the command line: the headless PNG (with its progress lines) and
//! `--flight` (percentiles printed, the same figures as JSON). Small sizes on the local Vulkan
//! adapter; without one each test prints `skipped: ...` (and fails under `CI=true`).

mod support;

use std::time::Duration;

use gpu_backend::render::OpaquePath;
use gpu_backend::{DeviceOptions, GpuContext};
use support::{have_adapter, read_png, run_viewer, text};
use viewer::headless::{draw_frame, load};
use viewer::scene::{Terrain, TerrainBlocks, terrain_view};
use viewer::stream::StreamSettings;
use viewer::view::StreamedView;

/// A fresh folder for this test's files.
fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("viewer-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    dir
}

/// The headless frame of the streamed terrain is the view loaded and drawn here in the test
/// process the same way (the command line's settings, its first camera, `headless::load`,
/// one frame): at most 0.5% of the pixels more than 16 apart (nodes finish in another order
/// in the two processes, which can change which of two coplanar skirt quads wins a pixel).
///
/// The fault it catches: a PNG that is not the loaded view's frame (another frame, or the
/// frame's rows in the wrong order), which a size check lets through. Planted (`write_png`
/// given the rows bottom-up), this test failed with "streamed: 88.05% of the pixels differ
/// from the reference by more than 16".
#[test]
fn the_headless_frame_streams_the_terrain_first() {
    if !have_adapter() {
        return;
    }
    let dir = temp_dir("stream-png");
    let out = dir.join("frame.png");
    let out_arg = out.to_string_lossy().into_owned();
    let output = run_viewer(
        &[
            "--headless",
            "--width",
            "64",
            "--height",
            "40",
            "--radius",
            "96",
            // One opaque path: `auto` keeps whichever measures faster, run to run.
            "--opaque",
            "raster",
            "--out",
            &out_arg,
        ],
        None,
    );
    let (stdout, stderr) = (text(&output.stdout), text(&output.stderr));
    assert!(output.status.success(), "{stdout}\n{stderr}");
    assert!(
        stderr.contains("viewer: streamed: ") && stderr.contains("nodes resident"),
        "progress on stderr: {stderr}"
    );
    assert!(
        stdout.contains("terrain streamed to a radius of 96 blocks")
            && stdout.contains("GPU renderer"),
        "{stdout}"
    );
    let decoder = png::Decoder::new(std::io::Cursor::new(std::fs::read(&out).unwrap()));
    let info = decoder.read_info().unwrap();
    assert_eq!((info.info().width, info.info().height), (64, 40));
    support::assert_shows(
        &read_png(&out),
        &streamed_reference(64, 40, 96),
        0.005,
        "streamed",
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// What the headless viewer draws of the streamed terrain with `--radius radius --opaque
/// raster` and otherwise default flags, drawn here.
fn streamed_reference(width: u32, height: u32, radius: u32) -> Vec<u8> {
    let ctx = GpuContext::new_headless(&DeviceOptions::default()).expect("an adapter");
    let settings = StreamSettings {
        radius,
        opaque: OpaquePath::Raster,
        ..StreamSettings::default()
    };
    let terrain = Terrain::new(settings.seed, TerrainBlocks::palette().1);
    let camera = terrain_view(&terrain);
    let mut view = StreamedView::new(&ctx, &settings, width, height).unwrap();
    load(&mut view, &camera, Duration::from_secs(300), |_| {}).unwrap();
    draw_frame(&ctx, &mut view).unwrap();
    view.renderer().read_image().unwrap().rgba
}

/// A `(p50, p99, max)` object of the report.
fn percentiles(json: &serde_json::Value, name: &str) -> [f64; 3] {
    ["p50_ms", "p99_ms", "max_ms"].map(|k| {
        json[name][k]
            .as_f64()
            .unwrap_or_else(|| panic!("{name}.{k} in {json}"))
    })
}

#[test]
fn a_flight_prints_percentiles_and_writes_them_as_json() {
    if !have_adapter() {
        return;
    }
    let dir = temp_dir("flight");
    let json_path = dir.join("flight.json");
    let json_arg = json_path.to_string_lossy().into_owned();
    let output = run_viewer(
        &[
            // Meshes only: lavapipe's far splat is the slow part on a loaded 2-core machine.
            "--flight", "2", "--width", "64", "--height", "36", "--radius", "64", "--far", "off",
            "--json", &json_arg,
        ],
        None,
    );
    let (stdout, stderr) = (text(&output.stdout), text(&output.stderr));
    assert!(output.status.success(), "{stdout}\n{stderr}");
    for label in [
        "CPU per frame",
        "frame (max of loop and GPU",
        "loop per frame",
    ] {
        let line = stdout
            .lines()
            .find(|l| l.contains(label))
            .unwrap_or_else(|| panic!("no {label:?} line in:\n{stdout}"));
        assert!(
            line.contains("p50") && line.contains("p99") && line.contains("max"),
            "{line}"
        );
    }
    let gpu = stdout
        .lines()
        .find(|l| l.contains("GPU per frame"))
        .expect("a GPU line");
    assert!(
        gpu.contains("p99") || gpu.contains("no timestamps"),
        "{gpu}"
    );
    assert!(stdout.contains("nodes/s"), "{stdout}");
    // The default `--opaque auto` chose a path at the first view, and says how.
    assert!(stdout.contains("opaque path auto: "), "{stdout}");

    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json_path).unwrap()).unwrap();
    assert_eq!(json["frames"], 120);
    assert_eq!(json["seconds"], 2.0);
    assert_eq!(
        (json["width"].as_u64(), json["height"].as_u64()),
        (Some(64), Some(36))
    );
    assert!(
        json["wall_seconds"].as_f64().unwrap() >= 2.0 - 1e-9,
        "paced to 60 Hz"
    );
    for name in ["cpu_frame", "frame", "loop_frame"] {
        let [p50, p99, max] = percentiles(&json, name);
        assert!(
            0.0 < p50 && p50 <= p99 && p99 <= max,
            "{name}: {p50} {p99} {max}"
        );
    }
    // A frame is the larger of its loop time and its GPU time.
    let frame_max = percentiles(&json, "frame")[2];
    assert!(frame_max >= percentiles(&json, "loop_frame")[2]);
    if json["gpu_timing"] == "timestamps" {
        let [p50, p99, max] = percentiles(&json, "gpu_frame");
        assert!(0.0 < p50 && p50 <= p99 && p99 <= max);
        assert!(frame_max >= max, "frame max {frame_max} < GPU max {max}");
        assert!(gpu.contains(&format!("{p50:.2} ms")), "{gpu} vs the JSON");
        // Where the GPU frame goes: each pass, at most the frame it is part of.
        let passes = json["gpu_passes"].as_array().expect("per-pass times");
        let labels: Vec<&str> = passes
            .iter()
            .map(|p| p["label"].as_str().unwrap())
            .collect();
        for pass in ["cull", "lighting", "tonemap"] {
            assert!(labels.contains(&pass), "{pass} missing from {labels:?}");
        }
        for pass in passes {
            let [p50, _, pass_max] = percentiles(pass, "time");
            assert!(0.0 < p50 && pass_max <= max + 1e-9, "{pass}");
        }
        let line = stdout
            .lines()
            .find(|l| l.contains("GPU per pass (p50/p99 ms)  "))
            .unwrap_or_else(|| panic!("no per-pass line in:\n{stdout}"));
        assert!(line.contains("lighting "), "{line}");
    } else {
        assert!(json["gpu_frame"].is_null());
    }
    assert!(json["first_view_nodes"].as_u64().unwrap() > 0);
    assert!(json["streamed_nodes_per_second"].as_f64().unwrap() >= 0.0);
    assert!(
        json["commits"].as_u64().unwrap() > 0,
        "the anchor moved: {json}"
    );
    assert_eq!(json["frames_with_holes"], 0);
    assert_eq!(json["radius"], 64);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_streaming_flags_are_refused_by_name() {
    for (args, named) in [
        (&["--radius", "4"][..], "radius"),
        (&["--budget", "-2"][..], "error budget"),
        (&["--far", "lasers"][..], "far-draw path"),
        (&["--flight", "-1"][..], "flight time"),
        (&["--flight", "1", "--vox", "x.vox"][..], "--vox"),
    ] {
        let output = run_viewer(args, None);
        let stderr = text(&output.stderr);
        assert!(!output.status.success(), "{args:?} accepted");
        assert!(stderr.contains(named), "{args:?}: {stderr}");
    }
}
