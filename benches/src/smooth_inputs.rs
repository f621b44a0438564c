//! Inputs of the smooth mesher benches (`benches/smooth.rs`): density grids and a NoCubes chunk.
//!
//! - [`sphere_34`] and [`sine_34`] are `fast-surface-nets`' own benchmark shapes (its
//!   `bench/src/bench.rs`: `x^2 + y^2 + z^2 - 0.9` and `sin(5 pi x / 2) + sin(5 pi y / 2) +
//!   sin(5 pi z / 2)` over the domain `[-1, 1]^3`), sampled on the padded grid of a 32^3 chunk
//!   (34^3 samples, `2 i / 32 - 1`) instead of its 18^3.
//! - [`terrain_62`]: the padded grid of a 62^3 chunk (64^3 samples) of rolling hills with 3-D
//!   noise overhangs and caves.
//! - [`to_i8`]: the `i8` version of a grid, as `mesher::smooth::quantize_density` makes it.
//! - [`nocubes_chunk`]: the terrain chunk of [`crate::inputs::chunks`] at 62^3 with its border,
//!   and [`nocubes_palette`], the terrain palette with its soils smoothable.

use voxel_core::{ChunkSize, MaterialClass, MaterialPalette, PaddedChunk, gather_neighbourhood};

use crate::inputs::chunks::{TERRAIN_CENTRE, terrain_world};

/// A density grid: `dims` samples per axis, x fastest; negative is inside.
#[derive(Clone, Debug, PartialEq)]
pub struct DensityGrid {
    /// Samples along x, y, z.
    pub dims: [u32; 3],
    /// `dims[0] * dims[1] * dims[2]` densities.
    pub samples: Vec<f32>,
}

impl DensityGrid {
    /// The grid of `f(x, y, z)` over sample coordinates.
    pub fn from_fn(dims: [u32; 3], f: impl Fn(f32, f32, f32) -> f32) -> Self {
        let [dx, dy, dz] = dims;
        let mut samples = Vec::with_capacity((dx * dy * dz) as usize);
        for z in 0..dz {
            for y in 0..dy {
                for x in 0..dx {
                    samples.push(f(x as f32, y as f32, z as f32));
                }
            }
        }
        DensityGrid { dims, samples }
    }
}

/// `fast-surface-nets`' domain: sample `i` of a grid of `n` cells (plus padding) at `2 i / n - 1`.
fn into_domain(n: u32, a: f32) -> f32 {
    2.0 * a / n as f32 - 1.0
}

/// The peer's sphere benchmark on 34^3 samples: `x^2 + y^2 + z^2 - 0.9` (radius 0.95, about
/// 15 samples).
pub fn sphere_34() -> DensityGrid {
    DensityGrid::from_fn([34; 3], |x, y, z| {
        let [x, y, z] = [x, y, z].map(|a| into_domain(32, a));
        x * x + y * y + z * z - 0.9
    })
}

/// The peer's sine benchmark on 34^3 samples (frequency 5).
pub fn sine_34() -> DensityGrid {
    DensityGrid::from_fn([34; 3], |x, y, z| {
        let wave = |a: f32| (into_domain(32, a) / 2.0 * 5.0 * core::f32::consts::PI).sin();
        wave(x) + wave(y) + wave(z)
    })
}

/// Hills around y = 30 (amplitude about 12) with 3-D noise that carves overhangs and caves, on
/// the padded grid of a 62^3 chunk (64^3 samples). Densities are roughly distance / 4, so the
/// `i8` version keeps about 30 steps per voxel near the surface.
pub fn terrain_62() -> DensityGrid {
    DensityGrid::from_fn([64; 3], |x, y, z| {
        let hills = 30.0 + 12.0 * (fbm2(x * 0.03, z * 0.03) - 0.5) * 2.0;
        let carve = value_noise3(x * 0.11, y * 0.11, z * 0.11) - 0.5;
        (y - hills) * 0.25 + carve * 2.4
    })
}

/// `round(clamp(d, -1, 1) * 127)`, ties away from zero: `mesher::smooth::quantize_density`.
pub fn to_i8(samples: &[f32]) -> Vec<i8> {
    samples
        .iter()
        .map(|&d| {
            let d = d.clamp(-1.0, 1.0) * 127.0;
            (d + if d >= 0.0 { 0.5 } else { -0.5 }) as i8
        })
        .collect()
}

/// The terrain palette (`voxel_scene::TerrainBlocks`) with grass, dirt, sand and snow
/// smoothable; stone stays a cube and water is transparent.
pub fn nocubes_palette() -> MaterialPalette {
    let (mut palette, blocks) = voxel_scene::TerrainBlocks::palette();
    for id in [blocks.grass, blocks.dirt, blocks.sand, blocks.snow] {
        let material = *palette.get(id).expect("the terrain palette has its ids");
        palette
            .set(id, material.with_class(MaterialClass::Smoothable))
            .expect("not air");
    }
    palette
}

/// The 62^3 terrain chunk [`TERRAIN_CENTRE`] with its one-voxel border.
pub fn nocubes_chunk() -> PaddedChunk {
    let world = terrain_world(ChunkSize::S62, |c| c);
    let mut padded = PaddedChunk::new(ChunkSize::S62);
    gather_neighbourhood(&world, TERRAIN_CENTRE, &mut padded);
    padded
}

fn hash3(x: i32, y: i32, z: i32) -> f32 {
    let mut h = (x as u32).wrapping_mul(0x8DA6_B343)
        ^ (y as u32).wrapping_mul(0xD816_3841)
        ^ (z as u32).wrapping_mul(0xCB1A_B31F);
    h ^= h >> 13;
    h = h.wrapping_mul(0x5BD1_E995);
    h ^= h >> 15;
    (h >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

fn smooth(t: f32) -> f32 {
    t * t * (3.0 - 2.0 * t)
}

/// Value noise in `0..1`: hashed lattice values, smoothstep-trilinear in between.
fn value_noise3(x: f32, y: f32, z: f32) -> f32 {
    let (fx, fy, fz) = (x.floor(), y.floor(), z.floor());
    let (ix, iy, iz) = (fx as i32, fy as i32, fz as i32);
    let (tx, ty, tz) = (smooth(x - fx), smooth(y - fy), smooth(z - fz));
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let plane = |dz: i32| {
        let row = |dy: i32| {
            lerp(
                hash3(ix, iy + dy, iz + dz),
                hash3(ix + 1, iy + dy, iz + dz),
                tx,
            )
        };
        lerp(row(0), row(1), ty)
    };
    lerp(plane(0), plane(1), tz)
}

/// Three octaves of 2-D value noise, in `0..1`.
fn fbm2(x: f32, z: f32) -> f32 {
    let mut sum = 0.0;
    let mut weight = 0.5;
    let mut freq = 1.0;
    for octave in 0..3 {
        sum += weight * value_noise3(x * freq, 17.0 * octave as f32, z * freq);
        weight *= 0.5;
        freq *= 2.0;
    }
    sum / 0.875
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_cross_the_surface() {
        for g in [sphere_34(), sine_34(), terrain_62()] {
            assert_eq!(g.samples.len(), g.dims.iter().product::<u32>() as usize);
            assert!(g.samples.iter().any(|&d| d < 0.0) && g.samples.iter().any(|&d| d > 0.0));
        }
        assert_eq!(terrain_62(), terrain_62());
        assert_eq!(
            to_i8(&[-2.0, -0.004, 0.0, 0.5, 1.0]),
            vec![-127, -1, 0, 64, 127]
        );
    }
}
