//! glTF props on a real device against the CPU rasterisation of the same triangles
//! (`voxel_reference::prop_raster`): each sample (Duck always; Box and BoxTextured with the
//! `draco` feature), shown / hidden / moved / deleted by handle, a prop behind a wall culled by
//! the depth pyramid (its batch's drawn count read back: zero), and a prop at `2^30` from the
//! origin drawn like one at the origin (images equal).
//!
//! **Tolerance** ([`compare`]): pixels whose 3 x 3 neighbourhood in the reference mixes prop
//! and sky (the silhouette band) are not compared, and their coverage may differ on at most
//! 20 % of that band (the rasteriser's fill rule against the reference's edge functions);
//! coverage must match on every other pixel; colour within 6 codes per channel on all but
//! 1 % of the compared pixels (the G-buffer's 8-bit sRGB albedo, the GPU's bilinear
//! filtering's 8-bit weights, normals interpolated on the GPU and in the reference);
//! reversed-Z depth within 0.1 % relative. A failure writes `gpu.png`, `cpu.png` and
//! `diff.png` under `target/image-tests/props-<name>/`.

use std::io::Write;
use std::path::PathBuf;

use glam::DVec3;
use gpu_backend::DeviceOptions;
use gpu_backend::render::props::PropError;
use gpu_backend::render::{FrameImage, Renderer, RendererConfig};
use gpu_backend::test_support::headless_or_skip;
use render_model::props::PropPlacement;
use render_model::{Camera, Lighting};
use voxel_core::{ChunkSize, Material, MaterialPalette, WorldPos};
use voxel_reference::prop_raster::{PlacedProp, PropFrame, render_props};
use voxel_scene::props::{PropLimits, PropModel, load_prop_bytes};

const W: u32 = 128;
const H: u32 = 96;

const IDENTITY: [[f32; 4]; 4] = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

/// The shared sample `name`; `None` after a skip line when the folder is missing outside CI
/// (under `CI=true` its absence fails).
fn sample(name: &str) -> Option<PropModel> {
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

fn palette() -> MaterialPalette {
    let mut p = MaterialPalette::new();
    p.push(Material::opaque(120, 120, 130)).unwrap();
    p
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

/// A camera looking at the model's bounds from the front-right, above.
fn camera_for(model: &PropModel, offset: i32) -> Camera {
    camera_at(model, offset, 1.0)
}

/// The same view from `distance` times as far (below 1: nearer).
fn camera_at(model: &PropModel, offset: i32, distance: f64) -> Camera {
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

fn renderer(occlusion: bool) -> Option<Renderer> {
    let ctx = headless_or_skip(&DeviceOptions::default())?;
    let mut config = RendererConfig::new(W, H, ChunkSize::S16);
    config.antialias = false;
    config.occlusion = occlusion;
    let mut r = Renderer::new(&ctx, &config, &palette()).unwrap();
    r.set_lighting(&Lighting::default()).unwrap();
    Some(r)
}

fn placement(at: i32) -> PropPlacement {
    PropPlacement::new(WorldPos::new(at, at, at), IDENTITY).unwrap()
}

fn cpu(model: &PropModel, placement: PropPlacement, camera: &Camera) -> PropFrame {
    render_props(
        &[PlacedProp { model, placement }],
        camera,
        &Lighting::default(),
        W,
        H,
    )
}

fn gpu(r: &mut Renderer, camera: &Camera) -> FrameImage {
    r.set_camera(camera);
    r.render().unwrap();
    r.read_image().unwrap()
}

fn drawn(depth: &[f32]) -> usize {
    depth.iter().filter(|d| **d > 0.0).count()
}

fn write_png(path: &PathBuf, rgba: &[u8]) {
    let file = std::fs::File::create(path).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), W, H);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header().unwrap().write_image_data(rgba).unwrap();
}

/// Checks `g` against `c` under the tolerance of the [module docs](self); on failure writes
/// the PNGs and panics naming the folder.
fn compare(name: &str, g: &FrameImage, c: &PropFrame) {
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

fn sample_matches(name: &str) {
    sample_matches_from(name, 1.0);
}

/// [`sample_matches`] with the camera `distance` times as far as [`camera_for`]'s.
fn sample_matches_from(name: &str, distance: f64) {
    let Some(model) = sample(name) else {
        return;
    };
    let Some(mut r) = renderer(false) else {
        return;
    };
    let id = r.add_prop_model(&model).unwrap();
    r.create_prop(id, placement(0)).unwrap();
    let cam = camera_at(&model, 0, distance);
    let g = gpu(&mut r, &cam);
    let c = cpu(&model, placement(0), &cam);
    assert!(
        drawn(&c.depth) > 1000,
        "{name}: the reference draws the prop"
    );
    compare(name, &g, &c);
}

#[test]
fn the_duck_matches_its_cpu_rasterisation() {
    sample_matches("Duck.glb");
}

#[cfg(feature = "draco")]
#[test]
fn the_draco_boxes_match_their_cpu_rasterisation() {
    sample_matches("Box.glb");
    // Near enough that most of the 256-texel logo is magnified. Its sampler minifies with
    // NEAREST_MIPMAP_LINEAR (nearest, as prop textures have one mip level) and magnifies
    // with LINEAR; the GPU picks per pixel quad from the uv derivatives, the reference always
    // filters with the magnification filter, so where the texture is minified (the whole
    // face at the usual distance, which shrinks the logo some 6 times) the logo's sharp
    // edges differ by up to a full step.
    sample_matches_from("BoxTextured.glb", 0.45);
}

#[test]
fn props_are_shown_hidden_moved_and_deleted_by_handle() {
    let Some(model) = sample("Duck.glb") else {
        return;
    };
    let Some(mut r) = renderer(false) else {
        return;
    };
    let id = r.add_prop_model(&model).unwrap();
    let prop = r.create_prop(id, placement(0)).unwrap();
    let cam = camera_for(&model, 0);
    let shown = gpu(&mut r, &cam);
    assert!(drawn(&shown.depth) > 1000);

    r.set_prop_visible(prop, false).unwrap();
    assert_eq!(drawn(&gpu(&mut r, &cam).depth), 0, "hidden: nothing drawn");
    r.set_prop_visible(prop, true).unwrap();
    assert_eq!(
        gpu(&mut r, &cam).rgba,
        shown.rgba,
        "shown again: the same image"
    );

    // Moved: the image of the moved prop, as the reference draws it there.
    let moved = PropPlacement::new(WorldPos::new(0, 0, -1), IDENTITY).unwrap();
    r.set_prop_placement(prop, moved).unwrap();
    let g = gpu(&mut r, &cam);
    assert_ne!(g.rgba, shown.rgba, "moved: the image changes");
    compare("moved", &g, &cpu(&model, moved, &cam));

    r.delete_prop(prop).unwrap();
    assert_eq!(drawn(&gpu(&mut r, &cam).depth), 0, "deleted: nothing drawn");
    assert!(matches!(
        r.delete_prop(prop),
        Err(PropError::StaleProp(p)) if p == prop
    ));
    assert!(matches!(
        r.set_prop_visible(prop, true),
        Err(PropError::StaleProp(_))
    ));
    assert!(matches!(
        r.set_prop_placement(prop, moved),
        Err(PropError::StaleProp(_))
    ));
    // A model id that was never added is refused by name.
    let unknown = gpu_backend::render::props::PropModelId(7);
    assert!(matches!(
        r.create_prop(unknown, placement(0)),
        Err(PropError::UnknownModel(m)) if m == unknown
    ));
    // A new prop reusing the index does not revive the old handle.
    let again = r.create_prop(id, placement(0)).unwrap();
    assert_ne!(again, prop);
    assert!(r.set_prop_visible(prop, false).is_err());
    assert!(r.set_prop_visible(again, false).is_ok());
}

#[test]
fn a_duck_at_two_to_the_thirty_renders_like_one_at_the_origin() {
    let Some(model) = sample("Duck.glb") else {
        return;
    };
    let far = 1 << 30;
    let mut images = Vec::new();
    for at in [0, far] {
        let Some(mut r) = renderer(false) else {
            return;
        };
        let id = r.add_prop_model(&model).unwrap();
        r.create_prop(id, placement(at)).unwrap();
        images.push(gpu(&mut r, &camera_for(&model, at)));
    }
    assert!(drawn(&images[0].depth) > 1000);
    assert!(images[0].rgba == images[1].rgba, "colour differs at 2^30");
    assert!(images[0].depth == images[1].depth, "depth differs at 2^30");
}

/// A 16 x 16 wall facing +z at z = 9 in chunk (0, 0, 0), and the duck at z = 4 behind it or
/// at z = 11 in front of it, seen from z = 15 with occlusion culling: behind, the cull keeps
/// none of its instances (read back) and the image shows only the wall; in front, it keeps
/// them, and without the wall too.
#[test]
fn a_prop_behind_a_wall_is_occlusion_culled() {
    use gpu_backend::render::RenderError;
    use render_model::resident::ChunkMeshData;
    use voxel_core::formats::{ChunkLayersData, PackedQuad, PackedQuadFields};
    use voxel_core::{BlockId, ChunkCoord, FaceDirection};
    let Some(model) = sample("Duck.glb") else {
        return;
    };
    let wall = [PackedQuad::encode(&PackedQuadFields {
        position: [0, 0, 8],
        width: 16,
        height: 16,
        face: FaceDirection::PosZ,
        ao: [3; 4],
        block: BlockId(1),
    })
    .unwrap()];
    let mut counts = Vec::new();
    for (z, walled) in [(4, true), (11, true), (4, false)] {
        let Some(mut r) = renderer(true) else {
            return;
        };
        if walled {
            let mut layers = ChunkLayersData::default();
            layers.opaque_quads[FaceDirection::PosZ.index() as usize] = &wall;
            r.upload_chunk(&ChunkMeshData {
                coord: ChunkCoord::new(0, 0, 0),
                lod: 0,
                layers,
            })
            .unwrap();
        }
        let id = r.add_prop_model(&model).unwrap();
        let at = PropPlacement::new(WorldPos::new(8, 6, z), IDENTITY).unwrap();
        r.create_prop(id, at).unwrap();
        let cam = look_at(DVec3::new(8.5, 7.0, 15.5), DVec3::new(8.5, 6.5, 0.0));
        // The first frame's early phase draws nothing (nothing was visible before): the
        // pyramid holds the wall from the second frame on.
        for _ in 0..3 {
            gpu(&mut r, &cam);
        }
        let drawn: Result<u64, RenderError> = r.read_props_drawn();
        counts.push(drawn.unwrap());
    }
    assert_eq!(counts[0], 0, "behind the wall: no instance drawn");
    assert!(counts[1] > 0, "in front of the wall: drawn ({counts:?})");
    assert!(counts[2] > 0, "no wall: drawn ({counts:?})");
}
