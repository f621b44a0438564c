//! Vertical shells (SBgl): the exposed voxels of every `(x, z)` column merged along y into runs,
//! one 8-byte [`ShellRun`] instance per run (a `voxel-core` packed format, re-exported here).
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
pub use voxel_core::formats::ShellRun;
use voxel_core::{BlockId, PaddedChunk};

use crate::surface_blocks::exposure::{ExposureScratch, eq_mask, nothing_exposed};
use crate::{BlockClasses, MeshError};

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
