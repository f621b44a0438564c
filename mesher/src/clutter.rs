//! Clutter placement: [`ClutterUnit`]s (grass blades, pebbles, flowers) on the top faces of
//! clutter-bearing blocks, deterministic per world position.
//!
//! # Where clutter grows
//!
//! On the top face of every block of class `ClutterBearing` whose top neighbour is **air**.
//! A clutter-bearing block under water or glass shows its top face but grows nothing: sprites
//! drawn inside a transparent volume would be sorted and lit as if in air. (The `HAS_CLUTTER`
//! flag of [`surface_blocks`](fn@crate::surface_blocks) follows the same rule.) The top neighbour
//! of the chunk's highest layer comes from the padded border, so a chunk gathered from a world
//! sees the chunk above it.
//!
//! # Determinism
//!
//! Everything about the clutter of one top face comes from one 64-bit hash of the block's
//! world position and the seed ([`clutter_hash`]), never from the chunk it was meshed in, a
//! counter, or a random hasher. The same world gives the same units, in world space, whatever
//! the chunk size or the split into chunks.
//!
//! For a face with hash `h`:
//!
//! - **count**: `floor(density)` units, plus one more when `h >> 40` (24 bits) is below
//!   `round(frac(density) * 2^24)`; the expected count is `density` (up to `2^-24`);
//! - unit `i` (from 0) draws its own hash `u = splitmix64(h ^ i)` and takes, low bits first:
//!
//! | bits of `u` | use                                                                  |
//! | ----------- | -------------------------------------------------------------------- |
//! | 0..16       | x offset on the face: `(2048 + bits * 15 / 16) / 65536` (integer     |
//! |             | division), in `[1/32, 31/32)`                                        |
//! | 16..32      | z offset on the face, likewise                                       |
//! | 32..34      | variant `0..4`: `kind = (block id mod 64) * 4 + variant`             |
//! | 34..38      | `scale_step` `0..16`                                                 |
//! | 38..42      | `seed` `0..16`                                                       |
//! | 42..57      | tint: red, green, blue each `255 - (5 bits)`, alpha 255              |
//!
//! # The units
//!
//! - `position`: chunk-local `(x + dx, y + 1, z + dz)` for the block at chunk-local `(x, y, z)`,
//!   quantized with [`clutter_extent`] (the chunk edge, **not** the padded edge: clutter never
//!   lies on the apron, and the smaller extent halves the quantization step). The decoded
//!   position is within `clutter_extent(size).max_error()` of the exact one on each axis.
//!   The offsets keep 1/32 voxel from the face's edges, far more than that bound (at most
//!   0.0005 voxel), so `floor` of a decoded x or z is always its block's, and every offset is a
//!   multiple of 1/65536, so the exact position is an `f32` in every chunk split.
//! - `normal`: `+Y`, octahedral (decodes exactly to `(0, 1, 0)`).
//! - `uv`, `uv_size`: the backend's clutter atlas is a 16 x 16 grid of sprites; `kind` `k` is
//!   cell `(k mod 16, k / 16)`, so `uv = (k mod 16, k / 16) / 16`, and `uv_size` is `15 / 255`
//!   on both axes (the cell size `1 / 16` rounded *down* to unorm8, so a sprite never samples
//!   its neighbour cell).

use alloc::vec::Vec;
use core::fmt;

use glam::{Vec2, Vec3};
use voxel_core::formats::quantize::{unorm16_encode, unorm16x2_encode};
use voxel_core::formats::{ClutterUnit, UnormExtent, oct16_encode};
use voxel_core::{ChunkCoord, ChunkSize, MaterialClass, PaddedChunk};

use crate::surface_blocks::exposure::{chunk_is_empty, chunk_is_full, inner_mask};
use crate::{BlockClasses, MeshError};

/// How much clutter to place, and the seed that varies it. Built with [`ClutterParams::new`],
/// which checks the density, so a `ClutterParams` is always valid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClutterParams {
    density: f32,
    seed: u64,
}

/// A clutter density that is NaN or outside `0.0..=ClutterParams::MAX_DENSITY`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InvalidClutterDensity {
    /// The rejected value.
    pub value: f32,
}

impl fmt::Display for InvalidClutterDensity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "clutter density {} is not in 0.0..={} units per face",
            self.value,
            ClutterParams::MAX_DENSITY
        )
    }
}

#[cfg(feature = "std")]
impl std::error::Error for InvalidClutterDensity {}

impl ClutterParams {
    /// The largest density: 8 units per top face.
    pub const MAX_DENSITY: f32 = 8.0;

    /// Parameters for `density` expected units per top face and a `seed`. NaN, negative and
    /// larger-than-[`MAX_DENSITY`](Self::MAX_DENSITY) densities are an error (not clamped).
    pub fn new(density: f32, seed: u64) -> Result<ClutterParams, InvalidClutterDensity> {
        if (0.0..=Self::MAX_DENSITY).contains(&density) {
            Ok(ClutterParams { density, seed })
        } else {
            Err(InvalidClutterDensity { value: density })
        }
    }

    /// Expected units per top face, `0.0..=8.0`.
    #[inline]
    pub fn density(&self) -> f32 {
        self.density
    }

    /// The seed.
    #[inline]
    pub fn seed(&self) -> u64 {
        self.seed
    }
}

/// Reusable output of [`place_clutter`]. [`clear`](Self::clear) and every placement keep the
/// capacity.
///
/// Units are ordered by the chunk-local z, y, x of their block (x fastest), then by their index
/// on the face.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ClutterLayer {
    units: Vec<ClutterUnit>,
}

impl ClutterLayer {
    /// An empty layer.
    pub fn new() -> Self {
        Self::default()
    }

    /// Empties the layer, keeping capacity.
    pub fn clear(&mut self) {
        self.units.clear();
    }

    /// The units.
    #[inline]
    pub fn units(&self) -> &[ClutterUnit] {
        &self.units
    }

    /// Number of units.
    #[inline]
    pub fn len(&self) -> usize {
        self.units.len()
    }

    /// True when no unit was placed.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.units.is_empty()
    }
}

/// The extent clutter positions of a chunk of `size` are quantized with: the chunk edge, in
/// voxels. Decode with `ClutterUnit::decode(clutter_extent(size))`.
pub fn clutter_extent(size: ChunkSize) -> UnormExtent {
    // Edges are 8..=62: finite, normal and positive, so this never takes the fallback.
    UnormExtent::new(size.edge() as f32).unwrap_or(UnormExtent::padded_chunk(size))
}

/// One step of SplitMix64 (Steele, Lea, Flood 2014): add the golden-ratio increment, then the
/// variant-13 finalizer. A bijection on `u64`.
#[inline]
fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The hash of the top face of the block at world position `world` (as `i64`, so that every
/// chunk coordinate times its edge fits; equal to the block's `WorldPos` wherever that exists):
///
/// ```text
/// h = splitmix64(seed)
/// h = splitmix64(h ^ x as u64); h = splitmix64(h ^ y as u64); h = splitmix64(h ^ z as u64)
/// ```
///
/// (`as u64` is the two's-complement bit pattern.)
#[inline]
pub fn clutter_hash(world: [i64; 3], seed: u64) -> u64 {
    world
        .iter()
        .fold(splitmix64(seed), |h, &c| splitmix64(h ^ c as u64))
}

/// The gap between a unit and its face's edges, in 1/65536 voxel: 1/32 voxel.
const MARGIN: u64 = 2048;

/// Size of one atlas cell, rounded down to unorm8: `15 / 255`.
const UV_SIZE_CODE: u8 = 15;

/// Places clutter on the top faces of the clutter-bearing blocks of `chunk` (chunk `coord` of
/// its world; its size is `chunk.size()`), replacing what `out` held. See the
/// [module docs](crate::clutter) for where units go and what they hold.
///
/// Cost: a word operation per padded row to find the blocks with air above
/// (`occupied & !occupied_above`), a class lookup per such block, and a hash per clutter-bearing
/// top face. With density 0, no clutter-bearing material in the palette, an empty chunk or a
/// full one (every face neighbour occupied), it returns after at most a scan of the masks.
///
/// # Errors
///
/// [`MeshError::UnknownBlock`] for a block with air above whose id has no material (such a block
/// is exposed; only blocks with air above are read, and none in the early returns above).
/// `out` is then left empty.
///
/// ```
/// use mesher::{BlockClasses, ClutterLayer, ClutterParams, clutter_extent, place_clutter};
/// use voxel_core::{BlockId, ChunkCoord, ChunkSize, Material, MaterialClass, MaterialPalette};
/// use voxel_core::PaddedChunk;
///
/// let mut palette = MaterialPalette::new();
/// let grass = palette
///     .push(Material::opaque(40, 160, 40).with_class(MaterialClass::ClutterBearing))?;
/// let classes = BlockClasses::from_palette(&palette);
/// // A flat floor of grass at chunk-local y = 0.
/// let chunk = PaddedChunk::from_fn(ChunkSize::S16, |_, y, _| {
///     if y <= 1 { grass } else { BlockId::AIR }
/// });
/// let params = ClutterParams::new(2.0, 7)?;
/// let mut out = ClutterLayer::new();
/// place_clutter(&chunk, &classes, ChunkCoord::new(0, 0, 0), &params, &mut out)?;
/// assert_eq!(out.len(), 2 * 16 * 16);
/// let unit = out.units()[0].decode(clutter_extent(ChunkSize::S16));
/// assert!((unit.position.y - 1.0).abs() < 1e-3);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn place_clutter(
    chunk: &PaddedChunk,
    classes: &BlockClasses,
    coord: ChunkCoord,
    params: &ClutterParams,
    out: &mut ClutterLayer,
) -> Result<(), MeshError> {
    out.clear();
    // Nothing to place: no density, no clutter-bearing material, no block, or no block with air
    // above (a full chunk whose face neighbours are all occupied).
    if params.density == 0.0
        || !classes.any_clutter_bearing()
        || chunk_is_empty(chunk)
        || chunk_is_full(chunk)
    {
        return Ok(());
    }
    let result = place(chunk, classes, coord, params, &mut out.units);
    if result.is_err() {
        out.clear();
    }
    result
}

fn place(
    chunk: &PaddedChunk,
    classes: &BlockClasses,
    coord: ChunkCoord,
    params: &ClutterParams,
    units: &mut Vec<ClutterUnit>,
) -> Result<(), MeshError> {
    let size = chunk.size();
    let e = size.edge_usize();
    let p = chunk.padded_edge();
    let extent = clutter_extent(size);
    let voxels = chunk.voxels();
    let columns = chunk.columns();
    let inner = inner_mask(size);
    let normal = oct16_encode(Vec3::Y)?;
    let uv_size = [UV_SIZE_CODE; 2];

    let whole = params.density as u32;
    // round(frac(density) * 2^24); the product is non-negative, so + 0.5 and truncation round.
    let fraction =
        ((f64::from(params.density) - f64::from(whole)) * f64::from(1u32 << 24) + 0.5) as u32;
    let edge = i64::from(size.edge());
    let origin = [coord.x, coord.y, coord.z].map(|c| i64::from(c) * edge);

    // The atlas corner of each column / row of cells, `(i / 16)` as unorm16.
    let mut cell_codes = [0u16; 16];
    for (i, code) in cell_codes.iter_mut().enumerate() {
        *code = unorm16x2_encode(Vec2::splat(i as f32 / 16.0))?[0];
    }
    for pz in 1..=e {
        for py in 1..=e {
            let r = py + p * pz;
            let mut tops = columns[r] & !columns[r + 1] & inner;
            while tops != 0 {
                let px = tops.trailing_zeros() as usize;
                tops &= tops - 1;
                let id = voxels[px + p * r];
                match classes.class(id) {
                    Some(MaterialClass::ClutterBearing) => {}
                    Some(_) => continue,
                    None => {
                        return Err(MeshError::UnknownBlock {
                            id,
                            position: [px as u32, py as u32, pz as u32],
                        });
                    }
                }
                let local = [px - 1, py - 1, pz - 1];
                let world = [0, 1, 2].map(|a| origin[a] + local[a] as i64);
                let h = clutter_hash(world, params.seed);
                let count = whole + u32::from(((h >> 40) as u32) < fraction);
                let top = unorm16_encode(py as f32, extent)?;
                for i in 0..count {
                    let u = splitmix64(h ^ u64::from(i));
                    let offset = |shift: u32| {
                        let k = ((u >> shift) & 0xFFFF) * 15 / 16;
                        (MARGIN + k) as f32 * (1.0 / 65536.0)
                    };
                    let x = unorm16_encode(local[0] as f32 + offset(0), extent)?;
                    let z = unorm16_encode(local[2] as f32 + offset(16), extent)?;
                    let variant = ((u >> 32) & 3) as u16;
                    let kind = ((id.0 & 0x3F) << 2) | variant;
                    let scale_step = ((u >> 34) & 0xF) as u16;
                    let seed = ((u >> 38) & 0xF) as u16;
                    // 255 minus 5 random bits per colour channel, alpha 255 (RGBA8, red low).
                    let channel = |shift: u32| 255 - ((u >> shift) & 0x1F) as u32;
                    let tint = channel(42) | channel(47) << 8 | channel(52) << 16 | 0xFF00_0000;
                    units.push(ClutterUnit {
                        position: [x, top, z],
                        normal,
                        settings: kind | scale_step << 8 | seed << 12,
                        uv: [
                            cell_codes[usize::from(kind % 16)],
                            cell_codes[usize::from(kind / 16)],
                        ],
                        uv_size,
                        tint,
                    });
                }
            }
        }
    }
    Ok(())
}
