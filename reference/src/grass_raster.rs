//! The CPU reference of the grass pass: every clutter unit's two crossed quads
//! ([`render_model::grass::unit_corners`]) rasterised for a [`Camera`] into a depth-tested
//! image and shaded with the deferred lighting model's CPU twin. The ground truth of the grass
//! pass's image tests.
//!
//! **Geometry**, as the GPU pass computes it: a corner goes camera-relative as `(chunk - eye
//! chunk) * edge - eye offset + local` (small terms only), then through
//! [`Camera::view_projection`]. Each quad is the triangles (0, 1, 2) and (0, 2, 3), both faces
//! drawn, rasterised at pixel centres with edge functions; depth is reversed-Z `z / w`,
//! interpolated linearly in screen space, kept when nearer (`>`). A triangle reaching behind
//! the near plane is left out (the tests keep grass in front of it). The sprite coordinates
//! are interpolated perspective-correctly.
//!
//! **Colour**, as the G-buffer holds it: [`sprite_colour`] of the unit's kind and tint (no
//! cover: the pixel keeps what it had), rounded to 8 bits as the albedo target rounds it,
//! decoded from sRGB and shaded with [`shade`] (the unit's up direction as the normal, full
//! ambient occlusion, no emission); empty pixels show the sky background; every pixel goes
//! out through [`output_rgba8`].

use glam::Vec3;
use render_model::Camera;
use render_model::grass::{GrassFrame, corner_sprite, sprite_colour, unit_corners};
use render_model::lighting::sky::sky_background;
use render_model::lighting::{Lighting, output_rgba8, shade, srgb_to_linear};
use voxel_core::formats::{ClutterUnit, ClutterUnitFields, UnormExtent};
use voxel_core::{ChunkCoord, ChunkSize};

/// One chunk's clutter.
#[derive(Clone, Copy, Debug)]
pub struct GrassChunk<'a> {
    /// The chunk (level 0).
    pub coord: ChunkCoord,
    /// Its units, positions over `0..=edge` (`mesher::clutter_extent`).
    pub units: &'a [ClutterUnit],
}

/// What the grass reference draws: colour and depth per pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct GrassImage {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// Row-major RGBA8, sRGB-encoded.
    pub rgba: Vec<u8>,
    /// Row-major reversed-Z depth, 0 where nothing is drawn.
    pub depth: Vec<f32>,
}

/// One projected corner: screen position, depth, `1 / w`, sprite coordinates.
#[derive(Clone, Copy, Debug)]
struct Screen {
    x: f32,
    y: f32,
    depth: f32,
    inv_w: f32,
    sprite: [f32; 2],
}

/// Renders the clutter of `chunks` (chunks of `size`) for `camera` in `frame` at `width x
/// height` (see the [module docs](self)).
pub fn render_grass(
    chunks: &[GrassChunk<'_>],
    size: ChunkSize,
    camera: &Camera,
    lighting: &Lighting,
    frame: &GrassFrame,
    width: u32,
    height: u32,
) -> GrassImage {
    let pixels = width as usize * height as usize;
    let view_proj = camera.view_projection(width, height);
    let eye = camera.eye(size);
    let edge = size.edge() as f32;
    let near = camera.near as f32;
    let mut colour: Vec<[f32; 3]> = (0..pixels as u32)
        .map(|i| {
            let dir = camera.ray_direction(i % width, i / width, width, height);
            sky_background(lighting, dir.as_vec3().to_array())
        })
        .collect();
    let mut depth = vec![0.0f32; pixels];
    let extent = UnormExtent::new(edge).unwrap_or(UnormExtent::UNIT);
    let project = |p: Vec3| -> [f32; 4] {
        let m = &view_proj;
        std::array::from_fn(|r| ((m[0][r] * p.x + m[1][r] * p.y) + m[2][r] * p.z) + m[3][r])
    };
    for chunk in chunks {
        let rel = [
            chunk.coord.x.wrapping_sub(eye.chunk.x),
            chunk.coord.y.wrapping_sub(eye.chunk.y),
            chunk.coord.z.wrapping_sub(eye.chunk.z),
        ];
        let origin = Vec3::new(
            rel[0] as f32 * edge - eye.offset[0],
            rel[1] as f32 * edge - eye.offset[1],
            rel[2] as f32 * edge - eye.offset[2],
        );
        for unit in chunk.units {
            let fields: ClutterUnitFields = unit.decode(extent);
            let quads = unit_corners(&fields, -origin, frame);
            let tint = fields.tint.map(|c| f32::from(c) / 255.0);
            let normal = fields.normal.normalize_or(Vec3::Y).to_array();
            for quad in &quads {
                let corners: [Option<Screen>; 4] = std::array::from_fn(|k| {
                    let clip = project(origin + quad[k]);
                    (clip[3] > near).then(|| Screen {
                        x: (clip[0] / clip[3] * 0.5 + 0.5) * width as f32,
                        y: (0.5 - clip[1] / clip[3] * 0.5) * height as f32,
                        depth: clip[2] / clip[3],
                        inv_w: 1.0 / clip[3],
                        sprite: corner_sprite(k),
                    })
                });
                for tri in [[0, 1, 2], [0, 2, 3]] {
                    let Some(t) = tri
                        .map(|k| corners[k])
                        .into_iter()
                        .collect::<Option<Vec<_>>>()
                    else {
                        continue;
                    };
                    let target = Target {
                        width,
                        height,
                        lighting,
                        colour: &mut colour,
                        depth: &mut depth,
                    };
                    target.triangle(
                        [t[0], t[1], t[2]],
                        fields.kind,
                        [tint[0], tint[1], tint[2]],
                        normal,
                    );
                }
            }
        }
    }
    GrassImage {
        width,
        height,
        rgba: colour.iter().flat_map(|&c| output_rgba8(c)).collect(),
        depth,
    }
}

/// Where triangles are drawn.
struct Target<'a> {
    width: u32,
    height: u32,
    lighting: &'a Lighting,
    colour: &'a mut [[f32; 3]],
    depth: &'a mut [f32],
}

fn edge(a: &Screen, b: &Screen, x: f32, y: f32) -> f32 {
    (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x)
}

impl Target<'_> {
    fn triangle(self, v: [Screen; 3], kind: u8, tint: [f32; 3], normal: [f32; 3]) {
        let area = edge(&v[0], &v[1], v[2].x, v[2].y);
        if area == 0.0 || !area.is_finite() {
            return;
        }
        let lo_x = v
            .iter()
            .map(|s| s.x)
            .fold(f32::INFINITY, f32::min)
            .floor()
            .max(0.0);
        let hi_x = v
            .iter()
            .map(|s| s.x)
            .fold(f32::NEG_INFINITY, f32::max)
            .ceil()
            .min(self.width as f32);
        let lo_y = v
            .iter()
            .map(|s| s.y)
            .fold(f32::INFINITY, f32::min)
            .floor()
            .max(0.0);
        let hi_y = v
            .iter()
            .map(|s| s.y)
            .fold(f32::NEG_INFINITY, f32::max)
            .ceil()
            .min(self.height as f32);
        if !(lo_x < hi_x && lo_y < hi_y) {
            return;
        }
        for py in lo_y as u32..hi_y as u32 {
            for px in lo_x as u32..hi_x as u32 {
                let (x, y) = (px as f32 + 0.5, py as f32 + 0.5);
                // Barycentrics of either winding (both faces are drawn).
                let b = [
                    edge(&v[1], &v[2], x, y) / area,
                    edge(&v[2], &v[0], x, y) / area,
                    edge(&v[0], &v[1], x, y) / area,
                ];
                if b.iter().any(|&c| c < 0.0) {
                    continue;
                }
                let d = b[0] * v[0].depth + b[1] * v[1].depth + b[2] * v[2].depth;
                let at = py as usize * self.width as usize + px as usize;
                if !(d > self.depth[at] && d <= 1.0) {
                    continue;
                }
                let pw: [f32; 3] = std::array::from_fn(|i| b[i] * v[i].inv_w);
                let sum = pw[0] + pw[1] + pw[2];
                let s: [f32; 2] = std::array::from_fn(|i| {
                    (pw[0] * v[0].sprite[i] + pw[1] * v[1].sprite[i] + pw[2] * v[2].sprite[i]) / sum
                });
                let Some(albedo) = sprite_colour(kind, s, tint) else {
                    continue;
                };
                // The albedo target holds 8-bit sRGB codes.
                let albedo =
                    albedo.map(|c| srgb_to_linear((c.clamp(0.0, 1.0) * 255.0).round() as u8));
                self.colour[at] = shade(self.lighting, albedo, normal, 3.0, 0.0);
                self.depth[at] = d;
            }
        }
    }
}
