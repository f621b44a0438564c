//! The CPU reference's rays: one ray per pixel, marched voxel by voxel (Amanatides & Woo DDA),
//! and the frame of pixels they fill. [`deferred_reference`](crate::deferred_reference)
//! shades what they hit.
//!
//! Slow and simple on purpose: the ground truth the GPU renderer's images are compared
//! against, and the headless viewer's renderer without a GPU. It never sees a
//! large coordinate in floating point: the camera position is split into an integer voxel and a
//! fraction, and rays step through integer voxel coordinates from there, so a scene near
//! (2^30, 2^30, 2^30) renders exactly like the same scene at the origin.

use glam::DVec3;
use rayon::prelude::*;
use voxel_core::{BlockId, MaterialClass, MaterialPalette, WorldPos};

/// What one ray hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// The first opaque block on the ray.
    pub block: BlockId,
    /// The voxel it is in.
    pub voxel: WorldPos,
    /// The outward normal of the face the ray entered through.
    pub normal: [i32; 3],
    /// Distance from the eye, in voxels.
    pub distance: f64,
    /// Transparent blocks crossed before it, front to back (at most [`MAX_LAYERS`]).
    pub transparent: [Option<BlockId>; MAX_LAYERS],
}

/// One transparent surface a ray entered: the first voxel of a run of one transparent id.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TransparentEntry {
    /// The transparent block.
    pub block: BlockId,
    /// The voxel the ray entered.
    pub voxel: WorldPos,
    /// The outward normal of the face it entered through.
    pub normal: [i32; 3],
    /// Distance from the eye to the entry point, in voxels.
    pub distance: f64,
}

/// Everything one ray met: the first opaque hit (if any within range) and the transparent
/// surfaces in front of it, front to back (at most [`MAX_LAYERS`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trace {
    /// The first opaque block, or `None` for sky.
    pub hit: Option<Hit>,
    /// Transparent surfaces crossed before the hit (or before the ray gave up).
    pub layers: [Option<TransparentEntry>; MAX_LAYERS],
}

/// Transparent surfaces a ray blends before it stops looking further.
pub const MAX_LAYERS: usize = 2;

/// A rendered image: sRGB8 colour plus the eye distance per pixel (`f32::INFINITY` for sky).
#[derive(Clone, Debug, PartialEq)]
pub struct RenderedImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major RGBA8, sRGB-encoded.
    pub rgba: Vec<u8>,
    /// Row-major distance to the first opaque surface, in voxels.
    pub depth: Vec<f32>,
}

/// Marches one ray from the camera through voxels given by `block_at`, up to `max_distance`
/// voxels. Returns `None` for sky (nothing opaque within range, or the ray left the i32 world).
pub fn cast_ray(
    block_at: &impl Fn(WorldPos) -> BlockId,
    palette: &MaterialPalette,
    origin_voxel: WorldPos,
    origin_fraction: DVec3,
    direction: DVec3,
    max_distance: f64,
) -> Option<Hit> {
    trace_ray(
        block_at,
        palette,
        origin_voxel,
        origin_fraction,
        direction,
        max_distance,
    )
    .hit
}

/// [`cast_ray`], also returning the transparent surfaces met when no opaque block is hit.
pub fn trace_ray(
    block_at: &impl Fn(WorldPos) -> BlockId,
    palette: &MaterialPalette,
    origin_voxel: WorldPos,
    origin_fraction: DVec3,
    direction: DVec3,
    max_distance: f64,
) -> Trace {
    // Integer voxel coordinates in i64, so stepping past the i32 edge is detected, not wrapped.
    let mut cell = [
        i64::from(origin_voxel.x),
        i64::from(origin_voxel.y),
        i64::from(origin_voxel.z),
    ];
    let frac = origin_fraction.to_array();
    let dir = direction.to_array();
    let mut step = [0i64; 3];
    let mut t_max = [f64::INFINITY; 3];
    let mut t_delta = [f64::INFINITY; 3];
    for axis in 0..3 {
        if dir[axis] > 0.0 {
            step[axis] = 1;
            t_delta[axis] = 1.0 / dir[axis];
            t_max[axis] = (1.0 - frac[axis]) * t_delta[axis];
        } else if dir[axis] < 0.0 {
            step[axis] = -1;
            t_delta[axis] = -1.0 / dir[axis];
            t_max[axis] = frac[axis] * t_delta[axis];
        }
    }
    let mut transparent = [None; MAX_LAYERS];
    let mut entries = [None; MAX_LAYERS];
    let mut layers = 0;
    let mut last_transparent = None;
    let mut normal = [0i32; 3];
    let mut distance = 0.0;
    let sky = |entries| Trace {
        hit: None,
        layers: entries,
    };
    loop {
        let (Ok(x), Ok(y), Ok(z)) = (
            i32::try_from(cell[0]),
            i32::try_from(cell[1]),
            i32::try_from(cell[2]),
        ) else {
            return sky(entries);
        };
        let voxel = WorldPos::new(x, y, z);
        let block = block_at(voxel);
        if !block.is_air() {
            match palette.class(block) {
                Ok(MaterialClass::Transparent) => {
                    // Water next to water shows no face: blend each run of one id once.
                    if last_transparent != Some(block) && layers < MAX_LAYERS {
                        transparent[layers] = Some(block);
                        entries[layers] = Some(TransparentEntry {
                            block,
                            voxel,
                            normal,
                            distance,
                        });
                        layers += 1;
                    }
                    last_transparent = Some(block);
                }
                Ok(class) if class.is_opaque() => {
                    return Trace {
                        hit: Some(Hit {
                            block,
                            voxel,
                            normal,
                            distance,
                            transparent,
                        }),
                        layers: entries,
                    };
                }
                // Air-classed or unknown ids are drawn as nothing, like air.
                _ => last_transparent = None,
            }
        } else {
            last_transparent = None;
        }
        let axis = if t_max[0] < t_max[1] {
            if t_max[0] < t_max[2] { 0 } else { 2 }
        } else if t_max[1] < t_max[2] {
            1
        } else {
            2
        };
        distance = t_max[axis];
        if distance > max_distance {
            return sky(entries);
        }
        cell[axis] += step[axis];
        t_max[axis] += t_delta[axis];
        normal = [0; 3];
        normal[axis] = -step[axis] as i32;
    }
}

/// An image of `width x height` pixels whose colour and depth `pixel(px, py)` gives, rows in
/// parallel: the frame both CPU renderers share.
pub fn render_pixels(
    width: u32,
    height: u32,
    pixel: impl Fn(u32, u32) -> ([u8; 4], f32) + Sync,
) -> RenderedImage {
    let rows: Vec<(Vec<u8>, Vec<f32>)> = (0..height)
        .into_par_iter()
        .map(|py| {
            let mut rgba = Vec::with_capacity(width as usize * 4);
            let mut depth = Vec::with_capacity(width as usize);
            for px in 0..width {
                let (colour, distance) = pixel(px, py);
                rgba.extend_from_slice(&colour);
                depth.push(distance);
            }
            (rgba, depth)
        })
        .collect();
    let mut image = RenderedImage {
        width,
        height,
        rgba: Vec::with_capacity(width as usize * height as usize * 4),
        depth: Vec::with_capacity(width as usize * height as usize),
    };
    for (rgba, depth) in rows {
        image.rgba.extend_from_slice(&rgba);
        image.depth.extend_from_slice(&depth);
    }
    image
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deferred_reference::render_deferred;
    use render_model::{Camera, Lighting};
    use voxel_core::Material;

    fn one_block_palette() -> (MaterialPalette, BlockId) {
        let mut p = MaterialPalette::new();
        let id = p.push(Material::opaque(255, 0, 0)).unwrap();
        (p, id)
    }

    #[test]
    fn ray_hits_the_face_it_enters_at_the_right_distance() {
        let (palette, red) = one_block_palette();
        let at = |p: WorldPos| {
            if p == WorldPos::new(0, 0, -5) {
                red
            } else {
                BlockId::AIR
            }
        };
        let hit = cast_ray(
            &at,
            &palette,
            WorldPos::new(0, 0, 0),
            DVec3::splat(0.5),
            DVec3::NEG_Z,
            100.0,
        )
        .expect("the block is straight ahead");
        assert_eq!(hit.voxel, WorldPos::new(0, 0, -5));
        assert_eq!(hit.normal, [0, 0, 1]);
        assert!(
            (hit.distance - 4.5).abs() < 1e-9,
            "distance {}",
            hit.distance
        );
        assert!(
            cast_ray(
                &at,
                &palette,
                WorldPos::new(0, 0, 0),
                DVec3::splat(0.5),
                DVec3::Z,
                100.0
            )
            .is_none()
        );
    }

    #[test]
    fn a_scene_far_from_the_origin_renders_like_the_scene_at_the_origin() {
        let (palette, red) = one_block_palette();
        let far = 1 << 30;
        let scene = |offset: i32| {
            move |p: WorldPos| {
                let (x, y, z) = (
                    p.x.wrapping_sub(offset),
                    p.y.wrapping_sub(offset),
                    p.z.wrapping_sub(offset),
                );
                if (-3..=3).contains(&x) && (-3..=0).contains(&y) && (-12..=-6).contains(&z)
                    || y == -4
                {
                    red
                } else {
                    BlockId::AIR
                }
            }
        };
        let camera = |offset: i32| Camera {
            voxel: WorldPos::new(offset, offset + 2, offset),
            fraction: DVec3::new(0.25, 0.5, 0.75),
            yaw: 0.2,
            pitch: -0.3,
            fov_y: 1.0,
            near: Camera::DEFAULT_NEAR,
        };
        let lighting = Lighting {
            haze_distance: 40.0,
            ..Lighting::default()
        };
        let render = |offset: i32| {
            render_deferred(
                &scene(offset),
                &palette,
                &camera(offset),
                &lighting,
                48,
                32,
                64.0,
            )
        };
        let (near, far_img) = (render(0), render(far));
        assert_eq!(near, far_img);
        assert!(
            near.depth.iter().any(|d| d.is_finite()) && near.depth.iter().any(|d| d.is_infinite())
        );
    }

    #[test]
    fn rays_leaving_the_i32_world_are_sky_not_wrapped() {
        let (palette, red) = one_block_palette();
        // Solid everywhere except the start voxel: a wrapped ray would hit something.
        let at = |p: WorldPos| if p.x == i32::MAX { BlockId::AIR } else { red };
        let hit = cast_ray(
            &at,
            &palette,
            WorldPos::new(i32::MAX, 0, 0),
            DVec3::splat(0.5),
            DVec3::X,
            10.0,
        );
        assert!(hit.is_none());
    }
}
