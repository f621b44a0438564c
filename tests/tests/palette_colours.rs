//! Palette colours reach the screen: a wall of blocks, one colour each, lit head-on (the sun
//! behind the camera, along the wall's normal), rendered on the GPU (lavapipe in CI) and by
//! the CPU reference; every block's colour must be within CIEDE2000 3 of its palette colour,
//! and a grey ramp must come out in order.
//!
//! The colours: every colour of the sample models' palettes (as opaque materials: glass and
//! emission change what a colour looks like on purpose), and made sets of pure and half
//! hues, dark and pale colours and a grey ramp.

use glam::DVec3;
use gpu_backend::DeviceOptions;
use gpu_backend::render::{Renderer, RendererConfig};
use gpu_backend::test_support::headless_or_skip;
use render_model::camera::Camera;
use render_model::colour_difference::srgb8_difference;
use render_model::lighting::{COMPRESSION_START, Lighting, linear_to_srgb8};
use viewer::deferred_reference::render_deferred;
use viewer::gpu_view::upload_world;
use viewer::reference_raycast::cast_ray;
use voxel_core::storage::{PaletteChunk, WorldMap};
use voxel_core::{BlockId, ChunkSize, Material, MaterialPalette, WorldPos};

/// Blocks per wall row (and rows at most).
const COLUMNS: i32 = 16;
/// Image side, pixels: 16 pixels per block.
const SIDE: u32 = 256;
/// The bar.
const MAX_DIFFERENCE: f64 = 3.0;

/// A wall of `colours` (at most 256), row by row from the top left, its palette, and the
/// block id of each colour.
fn wall(colours: &[[u8; 3]]) -> (WorldMap<PaletteChunk>, MaterialPalette, Vec<BlockId>) {
    assert!(colours.len() <= (COLUMNS * COLUMNS) as usize);
    let mut palette = MaterialPalette::new();
    let mut world = WorldMap::new(ChunkSize::S16);
    let ids = colours
        .iter()
        .enumerate()
        .map(|(i, &[r, g, b])| {
            let id = palette
                .push(Material::opaque(r, g, b))
                .expect("palette room");
            let (x, y) = (i as i32 % COLUMNS, COLUMNS - 1 - i as i32 / COLUMNS);
            world.set_block(WorldPos::new(x, y, 0), id);
            id
        })
        .collect();
    (world, palette, ids)
}

/// Looking straight down -z at the wall's front faces (z = 1), the wall filling the view.
fn camera() -> Camera {
    let distance = 48.0;
    Camera {
        voxel: WorldPos::new(8, 8, 48),
        fraction: DVec3::ZERO,
        yaw: 0.0,
        pitch: 0.0,
        fov_y: 2.0 * (8.0f64 / (distance - 1.0)).atan(),
        near: Camera::DEFAULT_NEAR,
    }
}

/// The sun behind the camera: the wall is lit head-on.
fn head_on() -> Lighting {
    Lighting {
        sun_direction: [0.0, 0.0, 1.0],
        ..Lighting::default()
    }
}

/// Per block id, the pixels well inside its face (their four neighbours show the same
/// block), found by the reference's rays.
fn interior_pixels(
    world: &WorldMap<PaletteChunk>,
    palette: &MaterialPalette,
    cam: &Camera,
) -> Vec<(BlockId, usize)> {
    let block_at = |p| world.get_block(p);
    let hit: Vec<Option<BlockId>> = (0..SIDE * SIDE)
        .map(|i| {
            let dir = cam.ray_direction(i % SIDE, i / SIDE, SIDE, SIDE);
            cast_ray(&block_at, palette, cam.voxel, cam.fraction, dir, 200.0).map(|h| h.block)
        })
        .collect();
    let at = |x: u32, y: u32| hit[(y * SIDE + x) as usize];
    let mut inside = Vec::new();
    for y in 1..SIDE - 1 {
        for x in 1..SIDE - 1 {
            let Some(id) = at(x, y) else { continue };
            let same = [(x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1)]
                .iter()
                .all(|&(u, v)| at(u, v) == Some(id));
            if same {
                inside.push((id, (y * SIDE + x) as usize));
            }
        }
    }
    inside
}

/// Per colour, the median rendered colour of its block's interior pixels in `rgba`.
fn rendered_colours(rgba: &[u8], ids: &[BlockId], inside: &[(BlockId, usize)]) -> Vec<[u8; 3]> {
    ids.iter()
        .map(|&id| {
            let mut pixels: Vec<[u8; 3]> = inside
                .iter()
                .filter(|(b, _)| *b == id)
                .map(|&(_, i)| [rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]])
                .collect();
            assert!(
                pixels.len() >= 16,
                "block {id:?} shows {} pixels",
                pixels.len()
            );
            pixels.sort_by_key(|p| u32::from(p[0]) + u32::from(p[1]) + u32::from(p[2]));
            pixels[pixels.len() / 2]
        })
        .collect()
}

/// Renders the wall of `colours` on the GPU (when there is one) and the CPU; returns the
/// rendered colours of each, in `colours`' order.
fn render_wall(colours: &[[u8; 3]]) -> Vec<(&'static str, Vec<[u8; 3]>)> {
    let (world, palette, ids) = wall(colours);
    let cam = camera();
    let lighting = head_on();
    let inside = interior_pixels(&world, &palette, &cam);
    let mut out = Vec::new();
    if let Some(ctx) = headless_or_skip(&DeviceOptions::default()) {
        let config = RendererConfig::new(SIDE, SIDE, ChunkSize::S16);
        let mut renderer = Renderer::new(&ctx, &config, &palette).expect("renderer");
        upload_world(&mut renderer, &world, &palette).expect("upload");
        renderer.set_camera(&cam);
        renderer
            .set_lighting(&lighting)
            .expect("head-on lighting renders");
        renderer.render().expect("frame");
        let frame = renderer.read_image().expect("readback");
        out.push(("GPU", rendered_colours(&frame.rgba, &ids, &inside)));
    }
    let block_at = |p| world.get_block(p);
    let cpu = render_deferred(&block_at, &palette, &cam, &lighting, SIDE, SIDE, 200.0);
    out.push(("CPU", rendered_colours(&cpu.rgba, &ids, &inside)));
    out
}

/// Checks every colour of `colours` (in walls of 256) on both renderers; returns the largest
/// difference seen.
fn check_colours(set: &str, colours: &[[u8; 3]]) -> f64 {
    let mut worst: f64 = 0.0;
    let mut failures = Vec::new();
    for part in colours.chunks((COLUMNS * COLUMNS) as usize) {
        for (renderer, rendered) in render_wall(part) {
            for (&want, &got) in part.iter().zip(&rendered) {
                let d = srgb8_difference(want, got);
                worst = worst.max(d);
                if d > MAX_DIFFERENCE {
                    failures.push(format!(
                        "{renderer}: {want:?} renders {got:?} (CIEDE2000 {d:.2})"
                    ));
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{set}: {} colours off by more than {MAX_DIFFERENCE}:\n{}",
        failures.len(),
        failures.join("\n")
    );
    eprintln!(
        "{set}: {} colours, largest CIEDE2000 {worst:.2}",
        colours.len()
    );
    worst
}

/// A colour of hue `h` degrees, HSV saturation `s` and value `v` (`0..=1`), 8-bit sRGB.
fn hsv(h: f64, s: f64, v: f64) -> [u8; 3] {
    let c = v * s;
    let x = c * (1.0 - ((h / 60.0).rem_euclid(2.0) - 1.0).abs());
    let (r, g, b) = match (h / 60.0) as u32 % 6 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = v - c;
    [r, g, b].map(|ch| ((ch + m) * 255.0).round() as u8)
}

#[test]
fn made_colours_render_as_their_palette_colour() {
    let mut colours = Vec::new();
    for i in 0..24 {
        let h = f64::from(i) * 15.0;
        colours.push(hsv(h, 1.0, 1.0)); // pure hues
        colours.push(hsv(h, 0.5, 0.8)); // half hues
        colours.push(hsv(h, 0.8, 0.25)); // dark
        colours.push(hsv(h, 0.15, 1.0)); // pale
    }
    // The named colours: gold, orange, water blue, grey 128.
    colours.extend([
        [252, 204, 48],
        [255, 160, 40],
        [60, 120, 220],
        [128, 128, 128],
    ]);
    colours.extend([
        [3, 2, 1],
        [12, 6, 30],
        [255, 255, 255],
        [250, 250, 245],
        [1, 1, 1],
    ]);
    check_colours("made colours", &colours);
}

#[test]
fn a_grey_ramp_renders_in_order() {
    let ramp: Vec<[u8; 3]> = (0..=255u8).step_by(3).map(|g| [g; 3]).collect();
    check_colours("grey ramp", &ramp);
    // Below the tonemap's knee every step shows; above it highlights are compressed (a step
    // of 3 codes becomes about 1) and neighbours may round to one code, never reverse.
    let knee = linear_to_srgb8(COMPRESSION_START);
    for (renderer, rendered) in render_wall(&ramp) {
        for (pair, want) in rendered.windows(2).zip(ramp.windows(2)) {
            let ordered = if want[1][0] < knee {
                pair[0][1] < pair[1][1]
            } else {
                pair[0][1] <= pair[1][1]
            };
            assert!(
                ordered,
                "{renderer}: grey {} renders {:?}, grey {} renders {:?}: out of order",
                want[0][0], pair[0], want[1][0], pair[1]
            );
        }
    }
}

#[test]
fn sample_model_palettes_render_as_their_palette_colour() {
    let files = tests::sample_vox_files();
    for path in &files {
        let vox = viewer::scene::vox::load_vox_file(path, ChunkSize::S16, 1 << 24)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut colours: Vec<[u8; 3]> = vox.palette.as_slice()[1..]
            .iter()
            .map(|m| [m.colour[0], m.colour[1], m.colour[2]])
            .collect();
        colours.sort_unstable();
        colours.dedup();
        check_colours(&path.display().to_string(), &colours);
    }
}
