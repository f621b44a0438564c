//! The prop reference on real and hand-made glTF props: each rendered to a PNG under the
//! test's target folder (`CARGO_TARGET_TMPDIR/prop-images/`) to be looked at, with checks on
//! what the image must show; and the far-origin rule: the same scene at `2^30` renders bit for
//! bit like at the origin.

use std::io::Write;
use std::path::PathBuf;

use glam::DVec3;
use render_model::props::PropPlacement;
use render_model::{Camera, Lighting};
use voxel_core::WorldPos;
use voxel_reference::prop_raster::{PlacedProp, PropFrame, render_props};
use voxel_scene::props::{PropLimits, PropModel, load_prop_bytes};

const IDENTITY: [[f32; 4]; 4] = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

/// The shared sample `name`; `None` after a skip line when the folder is missing outside CI
/// (under `CI=true` its absence fails).
fn sample(name: &str) -> Option<Vec<u8>> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data/gltf");
    if !dir.is_dir() {
        assert!(
            !std::env::var("CI").is_ok_and(|v| v == "true"),
            "sample data folder {} is missing; CI must have ../shared beside the checkout",
            dir.display()
        );
        let test = std::thread::current().name().unwrap_or("?").to_owned();
        let _ = writeln!(std::io::stderr().lock(), "skipped: {test}: no sample data");
        return None;
    }
    Some(std::fs::read(dir.join(name)).expect("sample file"))
}

fn save(frame: &PropFrame, name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("prop-images");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    let file = std::fs::File::create(&path).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), frame.width, frame.height);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header()
        .unwrap()
        .write_image_data(&frame.rgba)
        .unwrap();
    eprintln!("wrote {}", path.display());
    path
}

/// A camera with its eye at `eye` (world), looking at `target`.
fn look_at(eye: DVec3, target: DVec3) -> Camera {
    let d = (target - eye).normalize();
    let yaw = (-d.x).atan2(-d.z);
    let pitch = d.y.asin();
    let floor = eye.floor();
    Camera::new(
        WorldPos::new(floor.x as i32, floor.y as i32, floor.z as i32),
        eye - floor,
        yaw,
        pitch,
        0.8,
    )
}

fn base64(bytes: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in bytes.chunks(3) {
        let w = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for i in 0..4 {
            s.push(if i <= c.len() {
                char::from(T[(w >> (18 - 6 * i) & 63) as usize])
            } else {
                '='
            });
        }
    }
    s
}

/// An 8 x 8 checker PNG: white and `colour`.
fn checker_png(colour: [u8; 3]) -> Vec<u8> {
    let mut rgba = Vec::new();
    for y in 0..8 {
        for x in 0..8 {
            let c = if (x + y) % 2 == 0 {
                [255, 255, 255]
            } else {
                colour
            };
            rgba.extend([c[0], c[1], c[2], 255]);
        }
    }
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, 8, 8);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.write_header().unwrap().write_image_data(&rgba).unwrap();
    }
    out
}

/// A unit cube centred on the origin (24 vertices, normals, uvs), as glTF with data URIs;
/// textured with a checker when `texture`, else red like the Khronos Box, with its Z-up
/// to Y-up node matrix above the mesh node.
fn cube_gltf(texture: bool) -> Vec<u8> {
    let mut pos = Vec::new();
    let mut nrm = Vec::new();
    let mut uv = Vec::new();
    let mut idx: Vec<u16> = Vec::new();
    for axis in 0..3 {
        for sign in [1.0f32, -1.0] {
            let n: [f32; 3] = std::array::from_fn(|i| if i == axis { sign } else { 0.0 });
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let base = (pos.len() / 3) as u16;
            for (a, b) in [(-0.5f32, -0.5f32), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
                let mut p = [0.0f32; 3];
                p[axis] = 0.5 * sign;
                p[u] = a;
                p[v] = b;
                pos.extend(p);
                nrm.extend(n);
                uv.extend([a + 0.5, 0.5 - b]);
            }
            // Counter-clockwise seen from outside: (u, v, n) is right-handed for sign +1.
            if sign > 0.0 {
                idx.extend([0, 1, 2, 0, 2, 3].map(|i| base + i));
            } else {
                idx.extend([0, 2, 1, 0, 3, 2].map(|i| base + i));
            }
        }
    }
    let mut bin: Vec<u8> = Vec::new();
    for f in pos.iter().chain(&nrm).chain(&uv) {
        bin.extend(f.to_le_bytes());
    }
    for i in &idx {
        bin.extend(i.to_le_bytes());
    }
    let (p, n, t, i) = (pos.len() * 4, nrm.len() * 4, uv.len() * 4, idx.len() * 2);
    let mut material = serde_json::json!({
        "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.0, 0.0, 1.0], "metallicFactor": 0.0}
    });
    let mut extra = serde_json::json!({});
    if texture {
        material = serde_json::json!({
            "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0}
        });
        extra = serde_json::json!({
            "images": [{"uri": format!("data:image/png;base64,{}", base64(&checker_png([40, 90, 200])))}],
            "samplers": [{"magFilter": 9728, "minFilter": 9728}],
            "textures": [{"source": 0, "sampler": 0}]
        });
    }
    let mut json = serde_json::json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": bin.len(), "uri": format!("data:application/octet-stream;base64,{}", base64(&bin))}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": p},
            {"buffer": 0, "byteOffset": p, "byteLength": n},
            {"buffer": 0, "byteOffset": p + n, "byteLength": t},
            {"buffer": 0, "byteOffset": p + n + t, "byteLength": i}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 24, "type": "VEC3"},
            {"bufferView": 1, "componentType": 5126, "count": 24, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 24, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 36, "type": "SCALAR"}
        ],
        "materials": [material],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]}],
        "nodes": [
            {"children": [1], "matrix": [1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1]},
            {"mesh": 0}
        ],
        "scenes": [{"nodes": [0]}], "scene": 0
    });
    for (k, v) in extra.as_object().unwrap() {
        json[k] = v.clone();
    }
    json.to_string().into_bytes()
}

fn load(bytes: &[u8]) -> PropModel {
    load_prop_bytes(bytes, &PropLimits::default()).expect("loads")
}

fn render(model: &PropModel, anchor: WorldPos, camera: &Camera) -> PropFrame {
    let placed = PlacedProp {
        model,
        placement: PropPlacement::new(anchor, IDENTITY).unwrap(),
    };
    render_props(&[placed], camera, &Lighting::default(), 256, 192)
}

fn pixel(frame: &PropFrame, x: u32, y: u32) -> [u8; 4] {
    let at = ((y * frame.width + x) * 4) as usize;
    frame.rgba[at..at + 4].try_into().unwrap()
}

fn drawn(frame: &PropFrame) -> usize {
    frame.depth.iter().filter(|&&d| d > 0.0).count()
}

#[test]
fn the_red_box_shows_three_lit_faces() {
    let model = load(&cube_gltf(false));
    let cam = look_at(DVec3::new(1.6, 1.4, 2.5), DVec3::ZERO);
    let frame = render(&model, WorldPos::new(0, 0, 0), &cam);
    save(&frame, "box.png");
    let n = drawn(&frame);
    assert!(n > 4000 && n < 30000, "{n} pixels drawn");
    // The centre is the box, red; a corner is sky.
    let c = pixel(&frame, 128, 96);
    assert!(c[0] > 100 && c[1] < 60 && c[2] < 60, "{c:?}");
    assert_eq!(frame.depth[0], 0.0);
    // Three faces, three shades of red (the sun lights each differently).
    let mut reds: Vec<u8> = frame
        .rgba
        .chunks(4)
        .zip(&frame.depth)
        .filter(|(_, d)| **d > 0.0)
        .map(|(p, _)| p[0])
        .collect();
    reds.sort_unstable();
    reds.dedup();
    assert!(reds.len() >= 3, "{reds:?}");
}

#[test]
fn the_textured_box_shows_its_checker() {
    let model = load(&cube_gltf(true));
    let cam = look_at(DVec3::new(1.6, 1.4, 2.5), DVec3::ZERO);
    let frame = render(&model, WorldPos::new(0, 0, 0), &cam);
    save(&frame, "box_textured.png");
    // Both checker colours show: whitish and blue texels.
    let (mut white, mut blue) = (0, 0);
    for (p, d) in frame.rgba.chunks(4).zip(&frame.depth) {
        if *d > 0.0 {
            if p[0] > 150 && p[1] > 150 && p[2] > 150 {
                white += 1;
            }
            if u16::from(p[2]) > u16::from(p[0]) + 60 {
                blue += 1;
            }
        }
    }
    assert!(white > 1000 && blue > 1000, "white {white}, blue {blue}");
}

#[test]
fn the_duck_is_drawn_yellow_and_textured() {
    let Some(bytes) = sample("Duck.glb") else {
        return;
    };
    let model = load(&bytes);
    let cam = look_at(DVec3::new(0.9, 1.4, 2.6), DVec3::new(0.1, 0.8, 0.0));
    let frame = render(&model, WorldPos::new(0, 0, 0), &cam);
    save(&frame, "duck.png");
    let n = drawn(&frame);
    assert!(n > 5000, "{n} pixels drawn");
    let yellow = frame
        .rgba
        .chunks(4)
        .zip(&frame.depth)
        .filter(|(p, d)| **d > 0.0 && p[0] > 120 && p[1] > 90 && p[2] < 80)
        .count();
    assert!(yellow * 2 > n, "{yellow} of {n} drawn pixels are yellow");
}

/// The two Khronos boxes of the shared samples (Draco-compressed: only with the `draco`
/// feature), seen like the hand-made ones: the red box red, the textured one showing the
/// Cesium logo texture (its mean colour is not the sky's).
#[cfg(feature = "draco")]
#[test]
fn the_draco_sample_boxes_render() {
    let cam = look_at(DVec3::new(1.6, 1.4, 2.5), DVec3::ZERO);
    for (name, png) in [
        ("Box.glb", "sample_box.png"),
        ("BoxTextured.glb", "sample_box_textured.png"),
    ] {
        let Some(bytes) = sample(name) else {
            return;
        };
        let model = load(&bytes);
        let frame = render(&model, WorldPos::new(0, 0, 0), &cam);
        save(&frame, png);
        let n = drawn(&frame);
        assert!(n > 4000 && n < 30000, "{name}: {n} pixels drawn");
        let c = pixel(&frame, 128, 96);
        if name == "Box.glb" {
            assert!(c[0] > 100 && c[1] < 60 && c[2] < 60, "{c:?}");
        } else {
            // The logo's green hills and blue sky, on white.
            let count = |f: &dyn Fn(&[u8]) -> bool| {
                frame
                    .rgba
                    .chunks(4)
                    .zip(&frame.depth)
                    .filter(|(p, d)| **d > 0.0 && f(p))
                    .count()
            };
            // By hue (the dominant channel well above the others), so the hills on the
            // faces turned from the sun, lit by the sky alone, count too.
            let dominant = |p: &[u8], c: usize| {
                let v = f32::from(p[c]);
                (0..3).all(|o| o == c || v > 1.25 * f32::from(p[o]) + 8.0)
            };
            let green = count(&|p| dominant(p, 1));
            let blue = count(&|p| dominant(p, 2));
            assert!(green > 500 && blue > 500, "green {green}, blue {blue}");
        }
    }
}

/// The far-origin rule: the duck at (2^30, 2^30, 2^30), seen from the same offset, is the
/// same image and the same depth, bit for bit.
#[test]
fn a_duck_at_two_to_the_thirty_renders_like_one_at_the_origin() {
    let Some(bytes) = sample("Duck.glb") else {
        return;
    };
    let model = load(&bytes);
    let near_cam = look_at(DVec3::new(0.9, 1.4, 2.6), DVec3::new(0.1, 0.8, 0.0));
    let near = render(&model, WorldPos::new(0, 0, 0), &near_cam);
    let far = 1 << 30;
    let far_cam = Camera {
        voxel: WorldPos::new(
            near_cam.voxel.x + far,
            near_cam.voxel.y + far,
            near_cam.voxel.z + far,
        ),
        ..near_cam
    };
    let far_frame = render(&model, WorldPos::new(far, far, far), &far_cam);
    assert!(drawn(&near) > 5000);
    assert!(near.rgba == far_frame.rgba, "colours differ");
    assert!(near.depth == far_frame.depth, "depths differ");
}

/// The cull twin against the reference's own depth: a small prop behind the duck is hidden
/// by the depth pyramid of the duck's image, one in front of it is not, one behind the eye is
/// outside the frustum.
#[test]
fn the_duck_hides_a_prop_behind_it_from_the_cull_twin() {
    use render_model::hiz::pyramid_reference;
    use render_model::props::{
        PROP_CULL_FRUSTUM, PROP_CULL_OCCLUSION, PropCullUniforms, PropHiz, PropPrimitiveDesc,
        PropRegistry,
    };
    let Some(bytes) = sample("Duck.glb") else {
        return;
    };
    let model = load(&bytes);
    let (eye, target) = (DVec3::new(0.9, 1.4, 2.6), DVec3::new(0.1, 0.8, 0.0));
    let cam = look_at(eye, target);
    let frame = render(&model, WorldPos::new(0, 0, 0), &cam);
    let levels = pyramid_reference(&frame.depth, frame.width, frame.height).unwrap();
    let mut registry = PropRegistry::new();
    let ball = registry.add_primitive(PropPrimitiveDesc {
        index_count: 3,
        first_index: 0,
        base_vertex: 0,
        sphere_centre: [0.0; 3],
        sphere_radius: 0.05,
    });
    let along = |t: f64| PropPlacement::at_world(eye + (target - eye) * t, IDENTITY).unwrap();
    let behind = registry.create(ball, 0, along(1.4), true).unwrap();
    let front = registry.create(ball, 0, along(0.5), true).unwrap();
    let _at_the_back_of_the_eye = registry.create(ball, 0, along(-0.5), true).unwrap();
    let u = PropCullUniforms::new(
        &cam,
        frame.width,
        frame.height,
        registry.slot_count(),
        registry.batch_count(),
        PROP_CULL_FRUSTUM | PROP_CULL_OCCLUSION,
    );
    let hiz = PropHiz {
        levels: &levels,
        width: frame.width,
        height: frame.height,
    };
    let (lists, _) = render_model::props::cull_props_reference(
        registry.instance_records(),
        registry.batch_records(),
        &u,
        Some(hiz),
    )
    .unwrap();
    let slot = |h| registry.get(h).unwrap().2;
    assert_eq!(lists[0], [slot(front)]);
    let u = PropCullUniforms {
        flags: PROP_CULL_FRUSTUM,
        ..u
    };
    let (lists, _) = render_model::props::cull_props_reference(
        registry.instance_records(),
        registry.batch_records(),
        &u,
        None,
    )
    .unwrap();
    let mut both = vec![slot(front), slot(behind)];
    both.sort_unstable();
    assert_eq!(lists[0], both);
}
