//! The voxmesh command as a user meets it: bad input exits non-zero with a message naming the
//! problem and writes nothing (an existing output is left as it was); good input writes the
//! file, the stats match it, hidden nodes stay out unless asked for, materials arrive as glTF
//! PBR, and the result does not depend on the thread count.

mod support;

use std::path::Path;

use support::writer::VoxWriter;
use support::{read_glb, s, text, voxmesh, voxmesh_ok, write_vox};

/// Runs voxmesh expecting failure; checks that stderr names every part of `parts`, that
/// `output` still holds `before` (or does not exist), and that no stray file was left in its
/// folder. Returns stderr.
fn fails(args: &[&str], output: &Path, before: Option<&[u8]>, parts: &[&str]) -> String {
    let dir = output.parent().unwrap();
    let listing = |d: &Path| {
        let mut names: Vec<String> = std::fs::read_dir(d)
            .map(|r| {
                r.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                    .collect()
            })
            .unwrap_or_default();
        names.sort();
        names
    };
    let files_before = listing(dir);
    let out = voxmesh(args);
    let stderr = text(&out.stderr);
    assert!(
        !out.status.success(),
        "voxmesh {args:?} succeeded:\n{stderr}"
    );
    assert!(
        !stderr.contains("panicked"),
        "voxmesh {args:?} panicked:\n{stderr}"
    );
    for part in parts {
        assert!(
            stderr.contains(part),
            "voxmesh {args:?}: stderr does not name {part:?}:\n{stderr}"
        );
    }
    assert_eq!(
        std::fs::read(output).ok().as_deref(),
        before,
        "{args:?} touched the output"
    );
    assert_eq!(listing(dir), files_before, "{args:?} left files behind");
    stderr
}

#[test]
fn malformed_vox_files_fail_with_the_problem_named_and_write_nothing() {
    let dir = support::temp_dir();
    let out = dir.path().join("out.glb");
    // An earlier result that a failed run must not replace.
    std::fs::write(&out, b"earlier result").unwrap();
    let earlier: Option<&[u8]> = Some(b"earlier result");

    let mut outside = VoxWriter::new();
    outside.model([2, 2, 2], &[[0, 0, 0, 1], [0, 2, 1, 3]]);
    let mut zero_size = VoxWriter::new();
    zero_size.model([4, 0, 4], &[]);
    let mut negative = VoxWriter::new();
    negative.model([4, -2, 4], &[]);
    let mut huge = VoxWriter::new();
    huge.model([300, 4, 4], &[]);
    let mut index_zero = VoxWriter::new();
    index_zero.model([2, 2, 2], &[[1, 1, 1, 0]]);
    let mut lying = VoxWriter::new();
    lying.model([2, 2, 2], &[[0, 0, 0, 1]]);
    let mut lying_bytes = lying.bytes();
    let count_at = lying.offset_of(1) + 12;
    lying_bytes[count_at..count_at + 4].copy_from_slice(&5u32.to_le_bytes());
    let mut no_model = VoxWriter::new();
    no_model.palette(&[[9, 9, 9, 255]; 256]);
    let valid = support::material_scene().bytes();
    // Each value finite, the emission they make not: it would be written as `null`.
    let mut blinding = VoxWriter::new();
    blinding
        .model([1, 1, 1], &[[0, 0, 0, 1]])
        .matl(1, &[("_type", "_emit"), ("_emit", "2"), ("_flux", "3e38")]);

    let cases: Vec<(&str, Vec<u8>, Vec<&str>)> = vec![
        (
            "outside.vox",
            outside.bytes(),
            vec!["model 0", "voxel 1", "(0, 2, 1)", "outside"],
        ),
        ("zero.vox", zero_size.bytes(), vec!["model 0", "4 x 0 x 4"]),
        (
            "negative.vox",
            negative.bytes(),
            vec!["model 0", "4 x -2 x 4"],
        ),
        ("huge.vox", huge.bytes(), vec!["model 0", "300 x 4 x 4"]),
        (
            "zero-index.vox",
            index_zero.bytes(),
            vec!["model 0", "(1, 1, 1)", "colour index 0"],
        ),
        (
            "lying.vox",
            lying_bytes,
            vec!["model 0", "5 voxels", "'XYZI' at byte 44"],
        ),
        ("no-model.vox", no_model.bytes(), vec!["no model"]),
        (
            "cut.vox",
            valid[..valid.len() / 2].to_vec(),
            vec!["truncated", "at byte"],
        ),
        ("empty.vox", Vec::new(), vec!["not a MagicaVoxel file"]),
        (
            "blinding.vox",
            blinding.bytes(),
            vec!["material 1", "emission", "2 x (1 + 3000"],
        ),
    ];
    for (name, bytes, parts) in cases {
        let input = dir.path().join(name);
        std::fs::write(&input, &bytes).unwrap();
        let mut named = parts.clone();
        named.push(name);
        fails(&[s(&input), "-o", s(&out)], &out, earlier, &named);
    }
    // The cut file names the chunk it cuts.
    let input = dir.path().join("cut.vox");
    let stderr = fails(&[s(&input), "-o", s(&out)], &out, earlier, &[]);
    assert!(stderr.contains("chunk '"), "{stderr}");
}

#[test]
fn bad_command_lines_and_unwritable_outputs_fail_cleanly() {
    let dir = support::temp_dir();
    let out = dir.path().join("out.glb");
    fails(
        &["missing.vox", "-o", s(&out)],
        &out,
        None,
        &["missing.vox", "cannot read"],
    );
    fails(&["terrain:1:0", "-o", s(&out)], &out, None, &["side \"0\""]);
    fails(
        &["terrain:1:20", "-o", s(&dir.path().join("x.stl"))],
        &out,
        None,
        &[".glb or .obj"],
    );
    fails(
        &["terrain:1:20", "-o", s(&out), "--chunk", "20"],
        &out,
        None,
        &["16, 32 or 62"],
    );
    // A folder that does not exist is not created.
    let nested = dir.path().join("no/such/folder/out.glb");
    let stderr = text(&voxmesh(&["terrain:1:20", "-o", s(&nested)]).stderr);
    assert!(
        stderr.contains("cannot write") && stderr.contains("no/such/folder"),
        "{stderr}"
    );
    assert!(!dir.path().join("no").exists());
    // --stats over the input is refused before anything runs.
    let vox = write_vox(dir.path(), "in.vox", &support::material_scene());
    let before = std::fs::read(&vox).unwrap();
    fails(
        &[s(&vox), "-o", s(&out), "--stats", s(&vox)],
        &out,
        None,
        &["named twice"],
    );
    assert_eq!(std::fs::read(&vox).unwrap(), before);
    // A failing --stats write leaves the mesh unwritten too.
    let stats = dir.path().join("missing-folder/stats.json");
    fails(
        &[s(&vox), "-o", s(&out), "--stats", s(&stats)],
        &out,
        None,
        &["stats.json"],
    );
}

#[test]
fn a_scene_with_everything_hidden_is_an_error_that_suggests_hidden() {
    let dir = support::temp_dir();
    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]])
        .transform(0, &[], 1, 0, &[])
        .shape(1, &[], &[0])
        .layer(0, &[("_hidden", "1")]);
    let input = write_vox(dir.path(), "hidden.vox", &w);
    let out = dir.path().join("out.glb");
    fails(
        &[s(&input), "-o", s(&out)],
        &out,
        None,
        &["no visible voxel", "--hidden"],
    );
    voxmesh_ok(&[s(&input), "-o", s(&out), "--hidden"]);
    assert_eq!(
        read_glb(&out)
            .iter()
            .map(|p| p.triangles.len())
            .sum::<usize>(),
        12
    );
}

#[test]
fn stats_match_the_written_file() {
    let dir = support::temp_dir();
    let input = write_vox(dir.path(), "m.vox", &support::material_scene());
    let out = dir.path().join("m.glb");
    let stats = dir.path().join("m.json");
    let (stdout, stderr) = voxmesh_ok(&[s(&input), "-o", s(&out), "--stats", s(&stats), "--ao"]);
    assert!(stdout.contains("wrote"), "{stdout}");
    // The hidden node is reported to the user.
    assert!(stderr.contains("1 hidden scene nodes"), "{stderr}");
    let json: serde_json::Value = serde_json::from_slice(&std::fs::read(&stats).unwrap()).unwrap();
    let primitives = read_glb(&out);
    let triangles: usize = primitives.iter().map(|p| p.triangles.len()).sum();
    let vertices: usize = primitives.iter().map(|p| p.positions.len()).sum();
    let scene =
        voxel_scene::vox::load_vox_file(&input, voxel_core::ChunkSize::S32, 1 << 20).unwrap();
    assert_eq!(json["triangles"], triangles);
    assert_eq!(json["vertices"], vertices);
    assert_eq!(json["quads"], triangles / 2);
    assert_eq!(json["input_voxels"], scene.voxel_count);
    assert_eq!(json["chunks"], scene.world.len());
    assert_eq!(json["output_bytes"], std::fs::metadata(&out).unwrap().len());
    assert!(json["meshing_seconds"].as_f64().unwrap() > 0.0);
    assert_eq!(
        (json["mode"].as_str(), json["ao"].as_bool()),
        (Some("greedy"), Some(true))
    );
}

#[test]
fn materials_arrive_as_gltf_pbr_and_colours_as_linear_vertex_colours() {
    let dir = support::temp_dir();
    let input = write_vox(dir.path(), "m.vox", &support::material_scene());
    let out = dir.path().join("m.glb");
    voxmesh_ok(&[s(&input), "-o", s(&out)]);
    let primitives = read_glb(&out);
    let scene =
        voxel_scene::vox::load_vox_file(&input, voxel_core::ChunkSize::S32, 1 << 20).unwrap();
    let linear = |index: usize| voxmesh::pbr::linear_rgb(scene.materials[index].colour);
    // Metal (index 4), lamp (5), glass (6), and one diffuse primitive for indices 1-3.
    assert_eq!(primitives.len(), 4);
    let metal = primitives
        .iter()
        .find(|p| p.metallic > 0.0)
        .expect("a metal primitive");
    assert_eq!(
        (metal.metallic, metal.roughness, metal.blend),
        (0.9, 0.25, false)
    );
    let glass = primitives
        .iter()
        .find(|p| p.blend)
        .expect("a glass primitive");
    assert!((glass.alpha - 0.4).abs() < 1e-6 && glass.roughness == 0.05);
    let lamp = primitives
        .iter()
        .find(|p| p.emission != [0.0; 3])
        .expect("a lamp");
    // _emit 0.8 * (1 + _flux 1.5) = 2: the colour at twice its strength.
    for (got, want) in lamp.emission.iter().zip(linear(5)) {
        assert!(
            (got - 2.0 * want).abs() < 1e-5,
            "{:?} vs {:?}",
            lamp.emission,
            linear(5)
        );
    }
    let diffuse = primitives
        .iter()
        .find(|p| !p.blend && p.metallic == 0.0 && p.emission == [0.0; 3])
        .expect("a diffuse primitive");
    assert_eq!(diffuse.roughness, 1.0);
    // Every diffuse vertex colour is one of indices 1-3, in linear light, to u16 precision.
    for c in &diffuse.colours {
        let matches = (1..=3).any(|i| (0..3).all(|k| (c[k] - linear(i)[k]).abs() < 1e-4));
        assert!(
            matches,
            "colour {c:?} is not a linear palette colour of indices 1-3"
        );
        assert_eq!(c[3], 1.0);
    }
}

#[test]
fn ambient_occlusion_darkens_corners_only_when_asked() {
    let dir = support::temp_dir();
    let input = write_vox(dir.path(), "m.vox", &support::material_scene());
    let plain = dir.path().join("plain.glb");
    let shaded = dir.path().join("ao.glb");
    voxmesh_ok(&[s(&input), "-o", s(&plain)]);
    voxmesh_ok(&[s(&input), "-o", s(&shaded), "--ao"]);
    let brightest = |path: &Path| -> (f32, f32) {
        let p = read_glb(path);
        let ratios: Vec<f32> = p
            .iter()
            .flat_map(|p| p.colours.iter().map(|c| c[0] + c[1] + c[2]))
            .collect();
        (
            ratios.iter().copied().fold(f32::INFINITY, f32::min),
            ratios.iter().copied().fold(0.0, f32::max),
        )
    };
    let (plain_min, _) = brightest(&plain);
    let (ao_min, _) = brightest(&shaded);
    // The darkest AO corner is at most AO_FLOOR of the darkest plain colour's brightness...
    assert!(
        ao_min < plain_min,
        "AO darkens some corner: {ao_min} vs {plain_min}"
    );
    // ...and never below the floor times the darkest colour.
    assert!(ao_min >= voxmesh::geometry::AO_FLOOR * plain_min * 0.999);
}

#[test]
fn the_output_does_not_depend_on_the_thread_count() {
    let dir = support::temp_dir();
    let one = dir.path().join("one.glb");
    let four = dir.path().join("four.glb");
    for mode in ["greedy", "smooth"] {
        voxmesh_ok(&[
            "terrain:5:90",
            "-o",
            s(&one),
            "--threads",
            "1",
            "--mode",
            mode,
            "--chunk",
            "16",
        ]);
        voxmesh_ok(&[
            "terrain:5:90",
            "-o",
            s(&four),
            "--threads",
            "4",
            "--mode",
            mode,
            "--chunk",
            "16",
        ]);
        assert_eq!(
            std::fs::read(&one).unwrap(),
            std::fs::read(&four).unwrap(),
            "{mode}"
        );
    }
}

#[test]
fn smooth_mode_is_oriented_outwards_on_every_sample() {
    // NoCubes rounds edges and corners and thins one-voxel features, so volume is not exact:
    // on the samples it is 16 % (snow.vox, thin noise) to 99 % (monu1.vox) of the voxel
    // volume. What holds for all: the surface faces outwards (positive volume) and does not
    // grow past the voxels by more than rounding of concave corners allows.
    let dir = support::temp_dir();
    let out = dir.path().join("s.glb");
    for path in support::samples::sample_vox_files() {
        voxmesh_ok(&[s(&path), "-o", s(&out), "--mode", "smooth"]);
        let scene =
            voxel_scene::vox::load_vox_file(&path, voxel_core::ChunkSize::S32, 1 << 26).unwrap();
        let primitives = read_glb(&out);
        let all: Vec<_> = primitives.iter().collect();
        let volume = support::signed_volume(&all);
        let voxels = scene.voxel_count as f64;
        assert!(
            volume > 0.1 * voxels && volume <= voxels * 1.05,
            "{}: smooth volume {volume} for {voxels} voxels",
            path.display()
        );
    }
}

#[test]
fn smooth_mode_approximates_a_voxelised_sphere_better_than_cubes() {
    // A ball of radius 12 voxelised by voxel centres: the smooth surface's volume and area
    // come closer to the sphere's than the voxels' do (cubes overstate area by about 50 %).
    let r = 12.0f64;
    let n = 2 * r as u8 + 2;
    let mut voxels = Vec::new();
    for x in 0..n {
        for y in 0..n {
            for z in 0..n {
                let d = [x, y, z].map(|c| f64::from(c) + 0.5 - f64::from(n) / 2.0);
                if d.iter().map(|c| c * c).sum::<f64>() <= r * r {
                    voxels.push([x, y, z, 1]);
                }
            }
        }
    }
    let mut w = VoxWriter::new();
    w.model([i32::from(n); 3], &voxels);
    let dir = support::temp_dir();
    let input = write_vox(dir.path(), "ball.vox", &w);
    let smooth = dir.path().join("smooth.glb");
    let cubes = dir.path().join("cubes.glb");
    voxmesh_ok(&[s(&input), "-o", s(&smooth), "--mode", "smooth"]);
    voxmesh_ok(&[s(&input), "-o", s(&cubes), "--mode", "greedy"]);
    let measure = |path: &Path| {
        let p = read_glb(path);
        let all: Vec<_> = p.iter().collect();
        (support::signed_volume(&all), support::area(&all))
    };
    let (ball_volume, ball_area) = (
        4.0 / 3.0 * std::f64::consts::PI * r.powi(3),
        4.0 * std::f64::consts::PI * r * r,
    );
    let (sv, sa) = measure(&smooth);
    let (cv, ca) = measure(&cubes);
    let err = |got: f64, want: f64| (got / want - 1.0).abs();
    eprintln!(
        "sphere r {r}: smooth volume {sv:.1} area {sa:.1}; cubes {cv:.1} / {ca:.1}; ball {ball_volume:.1} / {ball_area:.1}"
    );
    assert!(
        err(sa, ball_area) < err(ca, ball_area),
        "smooth area {sa} vs cubes {ca}"
    );
    assert!(err(sa, ball_area) < 0.05, "smooth area {sa} vs {ball_area}");
    assert!(
        err(sv, ball_volume) < 0.05,
        "smooth volume {sv} vs {ball_volume}"
    );
}

/// Outputs get the mode a plain `File::create` gives them: a new file `0o666` less the
/// umask (run under three umasks), an existing one keeps its mode.
///
/// The fault it catches: writing through a temporary file of the default mode (`0o600`, as
/// `NamedTempFile::new_in` makes it) and renaming it into place. Planted, this test failed
/// with "umask 022: out.glb has mode 600, expected 644".
#[cfg(unix)]
#[test]
fn outputs_follow_the_umask() {
    use std::os::unix::fs::PermissionsExt;
    let dir = support::temp_dir();
    let input = write_vox(dir.path(), "m.vox", &support::material_scene());
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    let run_under = |umask: &str, args: &[&str]| {
        // The umask of the voxmesh process alone: a shell sets it and runs voxmesh.
        let out = std::process::Command::new("sh")
            .arg("-c")
            .arg(format!("umask {umask} && exec \"$0\" \"$@\""))
            .arg(env!("CARGO_BIN_EXE_voxmesh"))
            .args(args)
            .output()
            .expect("sh runs");
        assert!(out.status.success(), "{}", text(&out.stderr));
    };
    for (umask, want) in [("022", 0o644), ("027", 0o640), ("077", 0o600)] {
        let sub = dir.path().join(format!("umask-{umask}"));
        std::fs::create_dir(&sub).unwrap();
        let glb = sub.join("out.glb");
        let obj = sub.join("out.obj");
        let stats = sub.join("stats.json");
        run_under(umask, &[s(&input), "-o", s(&glb), "--stats", s(&stats)]);
        run_under(umask, &[s(&input), "-o", s(&obj)]);
        for file in [glb, stats, obj.clone(), obj.with_extension("mtl")] {
            assert_eq!(
                mode(&file),
                want,
                "umask {umask}: {} has mode {:o}, expected {want:o}",
                file.file_name().unwrap().to_string_lossy(),
                mode(&file)
            );
        }
    }
    // An existing output keeps its own mode, whatever the umask.
    let existing = dir.path().join("existing.glb");
    std::fs::write(&existing, b"old").unwrap();
    std::fs::set_permissions(&existing, std::fs::Permissions::from_mode(0o604)).unwrap();
    run_under("077", &[s(&input), "-o", s(&existing)]);
    assert_eq!(mode(&existing), 0o604);
    assert_ne!(std::fs::read(&existing).unwrap(), b"old");
}

/// Two voxels of one model at one position: the file is meshed as MagicaVoxel shows it (the
/// later voxel wins: a 2 x 1 x 1 model of colours 3 and 4, not 3 and 2), and stderr carries a
/// note with the count.
#[test]
fn repeated_voxels_are_meshed_with_the_later_one_and_noted() {
    let dir = support::temp_dir();
    let mut w = VoxWriter::new();
    w.model(
        [2, 1, 1],
        &[[0, 0, 0, 2], [1, 0, 0, 3], [0, 0, 0, 5], [0, 0, 0, 4]],
    );
    let input = write_vox(dir.path(), "repeated.vox", &w);
    let out = dir.path().join("repeated.glb");
    let stats = dir.path().join("stats.json");
    let (_, stderr) = voxmesh_ok(&[s(&input), "-o", s(&out), "--stats", s(&stats)]);
    assert!(
        stderr.contains("voxmesh: note: 2 voxels repeat a position within their model"),
        "{stderr}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&stats).unwrap()).unwrap();
    assert_eq!(json["input_voxels"], 2);
    // The voxel at x = 0 has colour 4 (the last of 2, 5, 4), the one at x = 1 colour 3: the
    // vertices of each half carry that colour (the default palette's, in linear light).
    let scene =
        voxel_scene::vox::load_vox_bytes(&w.bytes(), voxel_core::ChunkSize::S16, 16).unwrap();
    let linear = |index: usize| voxmesh::pbr::linear_rgb(scene.materials[index].colour);
    let (left, right) = (linear(4), linear(3));
    assert_ne!(left, linear(5));
    let primitives = read_glb(&out);
    let mut seen = [false; 2];
    for p in &primitives {
        for (position, colour) in p.positions.iter().zip(&p.colours) {
            let want = if position[0] < 0.5 {
                left
            } else if position[0] > 1.5 {
                right
            } else {
                continue;
            };
            let rgb = [colour[0], colour[1], colour[2]];
            assert!(
                rgb.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-3),
                "vertex at {position:?} has colour {rgb:?}, expected {want:?}"
            );
            seen[usize::from(position[0] > 1.5)] = true;
        }
    }
    assert_eq!(seen, [true, true]);
}
