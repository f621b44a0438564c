//! The renderer's view options on a real device. The wireframe view: only the quads' edges
//! are drawn, lit as in the filled view; it looks the same on the raster and compute opaque
//! paths; turning it off gives the filled image back. The opaque path: `Auto` measures both
//! and keeps one, switching draws the same image, and a path the renderer lacks is an error.

use gpu_backend::render::{FrameImage, OpaquePath, RenderError, Renderer, RendererConfig};
use gpu_backend::test_support::{headless_or_skip, in_ci};
use gpu_backend::{DeviceOptions, GpuContext};
use render_model::camera::Camera;
use render_model::resident::ChunkMeshData;
use voxel_core::formats::ChunkLayersData;
use voxel_core::formats::{PackedQuad, PackedQuadFields};
use voxel_core::{
    BlockId, ChunkCoord, ChunkSize, FaceDirection, Material, MaterialPalette, WorldPos,
};

const SIZE: u32 = 96;

fn palette() -> MaterialPalette {
    let mut p = MaterialPalette::new();
    p.push(Material::opaque(200, 50, 50)).unwrap();
    p.push(Material::opaque(40, 160, 60)).unwrap();
    p
}

/// The chunk's floor as four 8 x 8 quads (two materials), so their shared edges cross at the
/// chunk's centre.
fn floor() -> Vec<PackedQuad> {
    [(0, 0), (8, 0), (0, 8), (8, 8)]
        .into_iter()
        .enumerate()
        .map(|(i, (x, z))| {
            PackedQuad::encode(&PackedQuadFields {
                position: [x, 0, z],
                width: 8,
                height: 8,
                face: FaceDirection::PosY,
                ao: [3; 4],
                block: BlockId(1 + (i as u16 & 1)),
            })
            .unwrap()
        })
        .collect()
}

/// Straight down at the centre of chunk (0, 0, 0) from 24 blocks above: the whole floor is in
/// view, with sky around it.
fn camera() -> Camera {
    Camera::new(
        WorldPos::new(8, 24, 8),
        glam::DVec3::from_array([0.0, 0.5, 0.0]),
        0.0,
        -std::f64::consts::FRAC_PI_2 + 1e-3,
        1.0,
    )
}

/// A renderer made with `path`, holding the floor, seen from above.
fn floor_renderer(ctx: &GpuContext, path: OpaquePath) -> Renderer {
    let mut config = RendererConfig::new(SIZE, SIZE, ChunkSize::S16);
    config.opaque = path;
    // The filled frame is compared pixel for pixel with the wireframe, which the antialias
    // pass never touches: keep it off the filled frame's silhouette too.
    config.antialias = false;
    let mut renderer = Renderer::new(ctx, &config, &palette()).unwrap();
    renderer.set_camera(&camera());
    let quads = floor();
    let mut layers = ChunkLayersData::default();
    layers.opaque_quads[FaceDirection::PosY.index() as usize] = &quads;
    renderer
        .upload_chunk(&ChunkMeshData {
            coord: ChunkCoord::new(0, 0, 0),
            lod: 0,
            layers,
        })
        .unwrap();
    renderer
}

/// A renderer on `path` holding the floor, and its filled and wireframe frames.
fn frames(ctx: &GpuContext, path: OpaquePath) -> (Renderer, FrameImage, FrameImage) {
    let mut renderer = floor_renderer(ctx, path);
    renderer.render().unwrap();
    let filled = renderer.read_image().unwrap();
    renderer.set_wireframe(true);
    assert!(renderer.wireframe());
    renderer.render().unwrap();
    let wire = renderer.read_image().unwrap();
    (renderer, filled, wire)
}

fn pixel(image: &FrameImage, x: u32, y: u32) -> [u8; 4] {
    let i = ((y * image.width + x) * 4) as usize;
    image.rgba[i..i + 4].try_into().unwrap()
}

fn close(a: [u8; 4], b: [u8; 4]) -> bool {
    a.iter().zip(&b).all(|(&a, &b)| a.abs_diff(b) <= 2)
}

/// Pixels whose colour differs from the sky's (the image corner is sky in both views).
fn surface_pixels(image: &FrameImage) -> Vec<(u32, u32)> {
    let sky = pixel(image, 0, 0);
    (0..SIZE)
        .flat_map(|y| (0..SIZE).map(move |x| (x, y)))
        .filter(|&(x, y)| !close(pixel(image, x, y), sky))
        .collect()
}

#[test]
fn the_wireframe_draws_only_quad_edges_lit_as_the_filled_view() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let (mut renderer, filled, wire) = frames(&ctx, OpaquePath::Raster);
    let sky = pixel(&filled, 0, 0);
    assert_eq!(sky, pixel(&wire, 0, 0), "the corner is sky in both views");
    let filled_px = surface_pixels(&filled);
    let wire_px = surface_pixels(&wire);
    // The floor (16 blocks seen from 24 above at a 1 radian field of view) covers a square of
    // about 40 px; its wireframe is that square's outline plus the centre cross.
    assert!(filled_px.len() > 1000, "{} floor pixels", filled_px.len());
    assert!(
        !wire_px.is_empty() && wire_px.len() * 4 < filled_px.len(),
        "wireframe {} pixels against {} filled",
        wire_px.len(),
        filled_px.len()
    );
    // The centre cross: the shared edges of the four quads meet under the eye.
    let c = SIZE / 2;
    assert!(
        (c - 2..=c + 1).any(|x| !close(pixel(&wire, x, c + 8), sky)),
        "the edge between two quads is drawn"
    );
    // The middle of a quad (a quarter of the floor in from its corner) shows the sky.
    let quarter = (c as f32 - filled_px.iter().map(|p| c.abs_diff(p.0)).max().unwrap() as f32 / 2.0)
        .round() as u32;
    assert!(close(pixel(&wire, quarter, quarter), sky));
    assert!(!close(pixel(&filled, quarter, quarter), sky));
    // Every edge pixel is lit as the filled view lights the same point.
    for &(x, y) in &wire_px {
        assert!(
            close(pixel(&wire, x, y), pixel(&filled, x, y)),
            "({x}, {y}): {:?} against {:?}",
            pixel(&wire, x, y),
            pixel(&filled, x, y)
        );
    }
    // Off again: the filled image comes back.
    renderer.set_wireframe(false);
    renderer.render().unwrap();
    assert_eq!(renderer.read_image().unwrap().rgba, filled.rgba);

    // The compute opaque path draws the wireframe through the same G-buffer pass.
    if !has_compute_path(&ctx, "the wireframe on the compute opaque path") {
        return;
    }
    let (_, compute_filled, compute_wire) = frames(&ctx, OpaquePath::Compute);
    assert_eq!(
        compute_wire.rgba, wire.rgba,
        "wireframe alike on both paths"
    );
    assert_eq!(surface_pixels(&compute_filled).len(), filled_px.len());
}

/// Whether the device can run the compute opaque path (64-bit atomic min/max); otherwise
/// prints that `what` is not checked (CI's lavapipe has them, so there it fails instead).
fn has_compute_path(ctx: &GpuContext, what: &str) -> bool {
    if !ctx.capabilities.int64_atomics {
        assert!(!in_ci(), "CI's lavapipe has 64-bit atomic min/max");
        eprintln!(
            "{what} not checked: {} lacks 64-bit atomic min/max",
            ctx.capabilities.adapter
        );
    }
    ctx.capabilities.int64_atomics
}

/// Pixels of `a` and `b` that differ by more than 8/255 in a channel.
fn pixels_off(a: &FrameImage, b: &FrameImage) -> usize {
    a.rgba
        .chunks(4)
        .zip(b.rgba.chunks(4))
        .filter(|(a, b)| a.iter().zip(*b).any(|(a, b)| a.abs_diff(*b) > 8))
        .count()
}

#[test]
fn auto_measures_both_opaque_paths_and_keeps_one_that_draws_the_same_image() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    // A renderer made for the raster path alone cannot switch, and says why.
    let mut raster_only = floor_renderer(&ctx, OpaquePath::Raster);
    assert!(matches!(
        raster_only.set_opaque_path(OpaquePath::Compute),
        Err(RenderError::OpaquePathUnavailable(_))
    ));
    assert!(raster_only.set_opaque_path(OpaquePath::Auto).is_err());
    let choice = raster_only.measure_opaque_paths(2).unwrap();
    assert_eq!(choice.path, OpaquePath::Raster);
    assert!(choice.measured_ms.is_none() && choice.unmeasured.is_some());
    assert!(
        choice.to_string().starts_with("raster (not measured: "),
        "{choice}"
    );
    raster_only.render().unwrap();
    let raster_image = raster_only.read_image().unwrap();

    if !has_compute_path(&ctx, "Auto's measurement") {
        return;
    }
    let mut auto = floor_renderer(&ctx, OpaquePath::Auto);
    assert_eq!(
        auto.opaque_path(),
        OpaquePath::Raster,
        "raster until measured"
    );
    let choice = auto.measure_opaque_paths(3).unwrap();
    assert_eq!(auto.opaque_path(), choice.path);
    let (raster_ms, compute_ms) = choice.measured_ms.expect("lavapipe has timestamps");
    assert!(raster_ms > 0.0 && compute_ms > 0.0, "{choice}");
    let faster = if compute_ms < raster_ms {
        OpaquePath::Compute
    } else {
        OpaquePath::Raster
    };
    assert_eq!(choice.path, faster, "{choice}");
    // Either path draws the floor alike (the compute rasteriser matches the raster pass).
    for path in [OpaquePath::Raster, OpaquePath::Compute] {
        auto.set_opaque_path(path).unwrap();
        auto.render().unwrap();
        let image = auto.read_image().unwrap();
        let off = pixels_off(&image, &raster_image);
        assert!(
            off * 100 <= image.rgba.len() / 4,
            "{path:?}: {off} pixels off"
        );
    }
}
