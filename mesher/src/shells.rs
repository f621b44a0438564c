//! Vertical shells (SBgl): the exposed voxels of every `(x, z)` column merged along y into runs,
//! one 8-byte [`ShellRun`] instance per run.
//!
//! A *run* is a maximal stack of consecutive exposed voxels of one block id in one column
//! (exposed: at least one visible face, under the visible-face rules; see
//! [the exposure rules](mod@crate::surface_blocks#exposure)). Buried voxels and air end a run,
//! and so does a change of id. For a column of a hillside:
//!
//! ```text
//!   y   column (x, z)     exposed?          runs
//!   5   .  air            -
//!   4   G  grass          yes (top)         G: y = 4, height 1
//!   3   D  dirt           yes (side)        -+
//!   2   D  dirt           yes (side)         | D: y = 1, height 3
//!   1   D  dirt           yes (side)        -+
//!   0   D  dirt           no (buried)       (none)
//! ```

use alloc::vec::Vec;
use core::mem::{offset_of, size_of};

use bytemuck::{Pod, Zeroable};
use voxel_core::formats::{FaceDirection, WgslMember, WgslStruct, WgslType};
use voxel_core::{BlockId, PaddedChunk};

use crate::surface_blocks::exposure::{ExposureScratch, eq_mask, nothing_exposed};
use crate::{BlockClasses, MeshError};

/// One vertical run of exposed voxels of one block id: a box of `1 x height x 1` voxels whose
/// visible sides the GPU draws.
///
/// ```text
/// byte 0     1     2     3      4           6       7          8
///      +-----+-----+-----+------+-----------+-------+----------+
///      |  x  |  z  |  y  |height|  block id | sides | reserved |
///      +-----+-----+-----+------+-----------+-------+----------+
/// ```
///
/// | byte | field      | range            | meaning                                              |
/// | ---- | ---------- | --------------- | ------------------------------------------------------ |
/// | 0    | `x`        | `0..edge`       | chunk-local column x                                   |
/// | 1    | `z`        | `0..edge`       | chunk-local column z                                   |
/// | 2    | `y`        | `0..edge`       | chunk-local y of the run's lowest voxel                |
/// | 3    | `height`   | `1..=edge - y`  | voxels in the run, stored as is (never 0; at most 62)  |
/// | 4..6 | `block`    | any `u16`       | the [`BlockId`] of every voxel of the run              |
/// | 6    | `sides`    | `1..64`         | bit `d`: box face `d` is visible somewhere on the run  |
/// | 7    | `reserved` | 0               | written as 0; readers ignore it                        |
///
/// `sides` uses the [`FaceDirection::index`] order: bit 0 +x, 1 -x, 2 +y (top of the highest
/// voxel), 3 -y (bottom of the lowest voxel), 4 +z, 5 -z. The faces between the run's own
/// voxels are never visible (they touch an equal id), so the box's six faces are the only ones.
///
/// WGSL reads the 8 bytes as two `u32` words ([`ShellRun::WGSL_LAYOUT`]):
/// `xzyh = x | z << 8 | y << 16 | height << 24` and `block_sides = block | sides << 16`.
///
/// # Drawing
///
/// One instanced, non-indexed draw of 36 vertices per run (6 faces x 2 triangles), instance =
/// run. The vertex shader picks face `vertex_index / 6`; if that face's `sides` bit is clear it
/// emits a degenerate triangle (all three vertices at the same clip position), otherwise a
/// corner of the face of the box `[x, x + 1] x [y, y + height] x [z, z + 1]` (chunk-local; add
/// the chunk origin relative to the camera). A side bit stands for the whole side of the box:
/// the parts of that side whose voxels' faces are hidden are drawn too. They lie against a
/// hiding neighbour (opaque, or for a transparent run the same transparent id), so for opaque
/// runs the depth test removes them; a transparent run may show such an inner face where its
/// side is only partly exposed. Shells are a far-draw format: the cost is 8 bytes and at most
/// 12 triangles per run instead of one quad per face.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct ShellRun {
    /// Chunk-local x of the column.
    pub x: u8,
    /// Chunk-local z of the column.
    pub z: u8,
    /// Chunk-local y of the lowest voxel of the run.
    pub y: u8,
    /// Voxels in the run, `1..=62`, stored as is.
    pub height: u8,
    /// Block id of every voxel of the run.
    pub block: u16,
    /// Visible box faces, bit [`FaceDirection::index`].
    pub sides: u8,
    /// Always 0.
    pub reserved: u8,
}

const _: () = assert!(size_of::<ShellRun>() == 8, "ShellRun must be 8 bytes");

impl ShellRun {
    /// The WGSL struct `ShellRun { xzyh: u32, block_sides: u32 }` (layout in the type docs).
    pub const WGSL_LAYOUT: WgslStruct = WgslStruct {
        name: "ShellRun",
        size: size_of::<ShellRun>(),
        members: &[
            WgslMember {
                name: "xzyh",
                offset: offset_of!(ShellRun, x),
                ty: WgslType::U32,
            },
            WgslMember {
                name: "block_sides",
                offset: offset_of!(ShellRun, block),
                ty: WgslType::U32,
            },
        ],
    };

    /// The WGSL twin of this struct, with a decode helper.
    pub const WGSL: &'static str = "\
struct ShellRun {
    xzyh: u32,
    block_sides: u32,
}

// x, y, z of the lowest voxel (chunk-local), height, block id, side bits.
fn shell_run_min(r: ShellRun) -> vec3<u32> {
    return vec3<u32>(r.xzyh & 0xffu, (r.xzyh >> 16u) & 0xffu, (r.xzyh >> 8u) & 0xffu);
}
fn shell_run_height(r: ShellRun) -> u32 { return r.xzyh >> 24u; }
fn shell_run_block(r: ShellRun) -> u32 { return r.block_sides & 0xffffu; }
fn shell_run_has_side(r: ShellRun, face: u32) -> bool {
    return ((r.block_sides >> (16u + face)) & 1u) != 0u;
}
";

    /// A run with these fields and `reserved` 0. (Nothing is checked: any values make a valid
    /// `ShellRun`; the extractor only makes runs with `height >= 1` and `sides != 0`.)
    #[inline]
    pub fn new(x: u8, z: u8, y: u8, height: u8, block: u16, sides: u8) -> ShellRun {
        #[cfg(target_endian = "little")]
        {
            // Built as one word: writing the 8 fields to memory one by one and reading them
            // back as a word to push it stalls store forwarding, once per run, which on chunks
            // of many short runs (random fills) costs more than the extraction itself.
            let word = u64::from(x)
                | u64::from(z) << 8
                | u64::from(y) << 16
                | u64::from(height) << 24
                | u64::from(block) << 32
                | u64::from(sides) << 48;
            bytemuck::cast(word.to_le_bytes())
        }
        #[cfg(not(target_endian = "little"))]
        {
            ShellRun {
                x,
                z,
                y,
                height,
                block,
                sides,
                reserved: 0,
            }
        }
    }

    /// The block id.
    #[inline]
    pub fn block_id(self) -> BlockId {
        BlockId(self.block)
    }

    /// True if the box's `face` is visible somewhere along the run.
    #[inline]
    pub fn has_side(self, face: FaceDirection) -> bool {
        (self.sides >> face.index()) & 1 != 0
    }

    /// Chunk-local positions of the run's voxels, bottom to top.
    pub fn voxels(self) -> impl Iterator<Item = [u32; 3]> {
        let (x, y, z) = (u32::from(self.x), u32::from(self.y), u32::from(self.z));
        (y..y + u32::from(self.height)).map(move |y| [x, y, z])
    }
}

/// Reusable output of [`vertical_shells`]. [`clear`](Self::clear) and every extraction keep the
/// capacity.
///
/// Runs are ordered by z, then by the y just above their top, then by x. That order is
/// deterministic but not part of the contract.
#[derive(Clone, Debug, Default)]
pub struct ShellRuns {
    runs: Vec<ShellRun>,
    scratch: ExposureScratch,
}

impl ShellRuns {
    /// An empty buffer.
    pub fn new() -> Self {
        Self::default()
    }

    /// Empties the list, keeping capacity.
    pub fn clear(&mut self) {
        self.runs.clear();
    }

    /// The runs.
    #[inline]
    pub fn runs(&self) -> &[ShellRun] {
        &self.runs
    }

    /// Number of runs.
    #[inline]
    pub fn len(&self) -> usize {
        self.runs.len()
    }

    /// True when no voxel is exposed.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.runs.is_empty()
    }
}

/// Merges the exposed voxels of every `(x, z)` column of `chunk` into vertical runs (see the
/// [module docs](crate::shells)), replacing what `out` held.
///
/// Cost: the exposure pass of [`surface_blocks`](fn@crate::surface_blocks) (word operations on the
/// padded row masks). All columns of a z slice advance together one row at a time: which runs
/// go on is a word operation on the exposed masks and a vectorized compare of each row with
/// the row below (same id?), side bits accumulate as six words per row, and only starting and
/// ending runs are touched one by one (a store, and a class check and a push). Empty chunks,
/// and full ones with no transparent material in the palette, return after a scan of the masks.
/// No allocation once `out` has grown.
///
/// # Errors
///
/// [`MeshError::UnknownBlock`] for an exposed voxel whose id has no material (the position is
/// that of the lowest voxel of its run); `out` is then left empty.
///
/// ```
/// use mesher::{BlockClasses, ShellRuns, vertical_shells};
/// use voxel_core::{BlockId, ChunkSize, Material, MaterialPalette, PaddedChunk};
///
/// let mut palette = MaterialPalette::new();
/// let stone = palette.push(Material::opaque(128, 128, 128))?;
/// let classes = BlockClasses::from_palette(&palette);
/// // A pillar of 3 stone voxels at chunk-local x = 2, z = 4, y = 0..3.
/// let chunk = PaddedChunk::from_fn(ChunkSize::S8, |x, y, z| {
///     if x == 3 && z == 5 && (1..=3).contains(&y) { stone } else { BlockId::AIR }
/// });
/// let mut out = ShellRuns::new();
/// vertical_shells(&chunk, &classes, &mut out)?;
/// let run = out.runs()[0];
/// assert_eq!((out.len(), run.x, run.z, run.y, run.height), (1, 2, 4, 0, 3));
/// assert_eq!(run.sides, 0b11_1111);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn vertical_shells(
    chunk: &PaddedChunk,
    classes: &BlockClasses,
    out: &mut ShellRuns,
) -> Result<(), MeshError> {
    out.clear();
    if nothing_exposed(chunk, classes) {
        return Ok(());
    }
    let result = extract(chunk, classes, out);
    if result.is_err() {
        out.clear();
    }
    result
}

fn extract(
    chunk: &PaddedChunk,
    classes: &BlockClasses,
    out: &mut ShellRuns,
) -> Result<(), MeshError> {
    let ShellRuns { runs, scratch } = out;
    let e = chunk.size().edge_usize();
    let p = chunk.padded_edge();
    let voxels = chunk.voxels();
    let exposure = scratch.prepare(chunk, classes);
    // Per z slice, all columns advance together, one padded row (fixed y) at a time:
    // `open` has bit px set iff column px has a run that reached the previous row, `start[px]`
    // is that run's lowest y, and `sides[d]` bit px the OR of face d over its voxels so far.
    let mut start = [0u8; 64];
    for pz in 1..=e {
        let mut open = 0u64;
        let mut sides = [0u64; 6];
        let mut below: &[BlockId] = &[];
        for py in 1..=e {
            let y = py - 1;
            let row = &voxels[p * (py + p * pz)..][..p];
            let faces = exposure.row_faces(py, pz);
            let exposed = faces.iter().fold(0, |acc, f| acc | f);
            // A run goes on where the voxel is exposed and holds the id of the one below.
            let going_on = if open == 0 {
                0
            } else {
                open & exposed & eq_mask(row, below)
            };
            let mut ended = open & !going_on;
            while ended != 0 {
                let px = ended.trailing_zeros() as usize;
                ended &= ended - 1;
                runs.push(close(voxels, classes, p, [px, pz], start[px], y, &sides)?);
            }
            let mut started = exposed & !going_on;
            while started != 0 {
                let px = started.trailing_zeros() as usize;
                started &= started - 1;
                start[px] = y as u8;
            }
            for (side, face) in sides.iter_mut().zip(faces) {
                *side = (*side & going_on) | face;
            }
            open = exposed;
            below = row;
        }
        while open != 0 {
            let px = open.trailing_zeros() as usize;
            open &= open - 1;
            runs.push(close(voxels, classes, p, [px, pz], start[px], e, &sides)?);
        }
    }
    Ok(())
}

/// The run of column `(px, pz)` (padded) from chunk-local `y = start` up to, not including,
/// `top`, with the side bits of column `px` in `sides`; checks its id against the palette.
#[inline]
fn close(
    voxels: &[BlockId],
    classes: &BlockClasses,
    p: usize,
    [px, pz]: [usize; 2],
    start: u8,
    top: usize,
    sides: &[u64; 6],
) -> Result<ShellRun, MeshError> {
    let py = usize::from(start) + 1;
    let block = voxels[px + p * (py + p * pz)];
    if classes.class(block).is_none() {
        return Err(MeshError::UnknownBlock {
            id: block,
            position: [px as u32, py as u32, pz as u32],
        });
    }
    let sides = sides
        .iter()
        .enumerate()
        .fold(0u8, |acc, (d, s)| acc | ((((s >> px) & 1) as u8) << d));
    Ok(ShellRun::new(
        (px - 1) as u8,
        (pz - 1) as u8,
        start,
        (top - usize::from(start)) as u8,
        block.0,
        sides,
    ))
}
