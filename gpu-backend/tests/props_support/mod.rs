//! Helpers of the prop image tests: the shared glTF samples, a renderer on the local adapter,
//! cameras framing a model, the GPU frame and the CPU reference
//! (`voxel_reference::prop_raster`) of one placed model, and their comparison.
//!
//! **Tolerance** ([`compare`]): pixels whose 3 x 3 neighbourhood in the reference mixes prop
//! and sky (the silhouette band) are not compared, and their coverage may differ on at most
//! 20 % of that band (the rasteriser's fill rule against the reference's edge functions);
//! coverage must match on every other pixel; colour within 6 codes per channel on all but
//! 1 % of the compared pixels (the G-buffer's 8-bit sRGB albedo, the GPU's bilinear
//! filtering's 8-bit weights, normals interpolated on the GPU and in the reference);
//! reversed-Z depth within 0.1 % relative. A failure writes `gpu.png`, `cpu.png` and
//! `diff.png` under `target/image-tests/props-<name>/`.

#![allow(dead_code, reason = "each test binary uses a different subset")]

use std::io::Write;
use std::path::PathBuf;

use glam::DVec3;
use gpu_backend::DeviceOptions;
use gpu_backend::render::{FrameImage, Renderer, RendererConfig};
use gpu_backend::test_support::headless_or_skip;
use render_model::props::PropPlacement;
use render_model::{Camera, Lighting};
use voxel_core::{ChunkSize, Material, MaterialPalette, WorldPos};
use voxel_reference::prop_raster::{PlacedProp, PropFrame, render_props};
use voxel_scene::props::{PropLimits, PropModel, load_prop_bytes};

pub(crate) const W: u32 = 128;
pub(crate) const H: u32 = 96;

pub(crate) const IDENTITY: [[f32; 4]; 4] = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

/// The shared sample `name`; `None` after a skip line when the folder is missing outside CI
/// (under `CI=true` its absence fails).
pub(crate) fn sample(name: &str) -> Option<PropModel> {
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
    let bytes = std::fs::read(dir.join(name)).expect("sample file");
    Some(load_prop_bytes(&bytes, &PropLimits::default()).expect("loads"))
}

pub(crate) fn palette() -> MaterialPalette {
    let mut p = MaterialPalette::new();
    p.push(Material::opaque(120, 120, 130)).unwrap();
    p
}

/// A camera with its eye at `eye` (world), looking at `target`.
pub(crate) fn look_at(eye: DVec3, target: DVec3) -> Camera {
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

/// A camera looking at the model's bounds from the front-right, above.
pub(crate) fn camera_for(model: &PropModel, offset: i32) -> Camera {
    camera_at(model, offset, 1.0)
}

/// The same view from `distance` times as far (below 1: nearer).
pub(crate) fn camera_at(model: &PropModel, offset: i32, distance: f64) -> Camera {
    let b = model.bounds.expect("placed geometry");
    let c = DVec3::from_array(std::array::from_fn(|i| {
        f64::from(b.min[i] + b.max[i]) / 2.0
    }));
    let r = (0..3)
        .map(|i| f64::from(b.max[i] - b.min[i]))
        .fold(0.0, f64::max);
    let mut cam = look_at(c + DVec3::new(0.7, 0.6, 1.6) * (r * distance), c);
    cam.voxel = WorldPos::new(
        cam.voxel.x + offset,
        cam.voxel.y + offset,
        cam.voxel.z + offset,
    );
    cam
}

pub(crate) fn renderer(occlusion: bool) -> Option<Renderer> {
    let ctx = headless_or_skip(&DeviceOptions::default())?;
    let mut config = RendererConfig::new(W, H, ChunkSize::S16);
    config.antialias = false;
    config.occlusion = occlusion;
    let mut r = Renderer::new(&ctx, &config, &palette()).unwrap();
    r.set_lighting(&Lighting::default()).unwrap();
    Some(r)
}

pub(crate) fn placement(at: i32) -> PropPlacement {
    PropPlacement::new(WorldPos::new(at, at, at), IDENTITY).unwrap()
}

pub(crate) fn cpu(model: &PropModel, placement: PropPlacement, camera: &Camera) -> PropFrame {
    render_props(
        &[PlacedProp { model, placement }],
        camera,
        &Lighting::default(),
        W,
        H,
    )
}

pub(crate) fn gpu(r: &mut Renderer, camera: &Camera) -> FrameImage {
    r.set_camera(camera);
    r.render().unwrap();
    r.read_image().unwrap()
}

pub(crate) fn drawn(depth: &[f32]) -> usize {
    depth.iter().filter(|d| **d > 0.0).count()
}

pub(crate) fn write_png(path: &PathBuf, rgba: &[u8]) {
    let file = std::fs::File::create(path).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), W, H);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header().unwrap().write_image_data(rgba).unwrap();
}

/// Checks `g` against `c` under the tolerance of the [module docs](self); on failure writes
/// the PNGs and panics naming the folder.
pub(crate) fn compare(name: &str, g: &FrameImage, c: &PropFrame) {
    let hit = |i: usize| c.depth[i] > 0.0;
    let (mut band, mut band_flips, mut flips, mut compared, mut colour_bad) = (0, 0, 0, 0, 0);
    let mut depth_bad = 0;
    let mut worst = 0u8;
    let mut diff = vec![0u8; (W * H * 4) as usize];
    for y in 0..H as i32 {
        for x in 0..W as i32 {
            let i = (y as u32 * W + x as u32) as usize;
            let mut mixed = false;
            for (dx, dy) in (-1..=1).flat_map(|dx| (-1..=1).map(move |dy| (dx, dy))) {
                let (nx, ny) = (x + dx, y + dy);
                if nx >= 0 && ny >= 0 && nx < W as i32 && ny < H as i32 {
                    mixed |= hit((ny as u32 * W + nx as u32) as usize) != hit(i);
                }
            }
            let gpu_hit = g.depth[i] > 0.0;
            if mixed {
                band += 1;
                band_flips += usize::from(gpu_hit != hit(i));
                continue;
            }
            if gpu_hit != hit(i) {
                flips += 1;
                diff[i * 4..i * 4 + 4].copy_from_slice(&[255, 0, 255, 255]);
                continue;
            }
            if !hit(i) {
                continue;
            }
            compared += 1;
            let d = (0..3)
                .map(|k| g.rgba[i * 4 + k].abs_diff(c.rgba[i * 4 + k]))
                .max()
                .unwrap();
            worst = worst.max(d);
            if d > 6 {
                colour_bad += 1;
                diff[i * 4..i * 4 + 4].copy_from_slice(&[255, 255, 0, 255]);
            } else {
                diff[i * 4..i * 4 + 4].copy_from_slice(&[d * 40, d * 40, d * 40, 255]);
            }
            if (g.depth[i] - c.depth[i]).abs() > 1e-3 * c.depth[i] {
                depth_bad += 1;
            }
        }
    }
    let ok = band_flips * 5 <= band
        && flips == 0
        && colour_bad * 100 <= compared
        && depth_bad == 0
        && compared > 200;
    eprintln!(
        "{name}: {compared} compared, worst colour {worst}, {colour_bad} over 6, {band_flips} of \
         {band} band pixels flipped, {flips} flips off the band, {depth_bad} depths off"
    );
    if !ok {
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../target/image-tests")
            .join(format!("props-{name}"));
        std::fs::create_dir_all(&dir).unwrap();
        write_png(&dir.join("gpu.png"), &g.rgba);
        write_png(&dir.join("cpu.png"), &c.rgba);
        write_png(&dir.join("diff.png"), &diff);
        panic!(
            "{name}: GPU image differs from the CPU reference; see {}",
            dir.display()
        );
    }
}
