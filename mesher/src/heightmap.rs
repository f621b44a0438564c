//! Heightmap cubes (SBgl): a node's terrain reduced to its columns' top surface, one box per
//! column (split where the block id changes), drawn by the GPU as boxes synthesised in the
//! vertex shader. A box is a [`ShellRun`], so heightmap nodes draw through the shell pass.
//!
//! # The rule
//!
//! The terrain is read as a heightmap: each column is solid from below up to its highest
//! opaque voxel, air above. For a column `(x, z)` of the node, from its padded neighbourhood:
//!
//! - `t`: its highest opaque voxel inside the node; none, and the column draws nothing here
//!   (the node below draws its top);
//! - its top face is drawn when the voxel above `t` (the apron above the node included) is not
//!   opaque;
//! - its box goes down to the lowest height at which a side neighbour has air: the lowest of
//!   the four neighbours' tops plus one (a neighbour column without opaque voxels in the
//!   padded range counts as the node's floor), never below the node's floor. A column on the
//!   node's border whose neighbour across it is not higher reaches [`SKIRT_VOXELS`] further
//!   down on that side, which covers the cracks against a neighbour drawn at another level of
//!   detail (the greedy path's skirts);
//! - the box is split into runs of one block id from the top down (an air or transparent
//!   voxel inside it takes the id of the voxel above: heightmap columns have no holes), and
//!   at each side's *foot*, the voxel at which the side first shows above its neighbour's top;
//! - a run's side is drawn where the neighbour on that side has air at the run's height, or
//!   where it faces the node's border; the run that starts at a side's foot carries the foot
//!   (`ShellRun`'s feet), which the GPU shades with the meshers' ambient occlusion of a step.
//!
//! What a heightmap cannot show is not drawn: caves and overhangs under a column's top, and
//! the underside of anything. Transparent blocks (water, glass) are not boxes: the transparent
//! greedy quads draw them.

use alloc::vec::Vec;
use voxel_core::formats::FaceDirection;
pub use voxel_core::formats::ShellRun;
use voxel_core::{BlockId, PaddedChunk};

use crate::{BlockClasses, MeshError};

/// Voxels a border column's outward side reaches below its box: a neighbour one level of
/// detail coarser has voxels twice as tall, so two voxels cover its height error.
pub const SKIRT_VOXELS: usize = 2;

/// The four side directions, in the order of the neighbour offsets of [`heightmap_boxes`].
const SIDES: [FaceDirection; 4] = [
    FaceDirection::PosX,
    FaceDirection::NegX,
    FaceDirection::PosZ,
    FaceDirection::NegZ,
];

/// Appends to `out` the heightmap boxes of the node whose padded neighbourhood is `padded`
/// (see the [module docs](self) for the rule), as [`ShellRun`]s in chunk-local voxels,
/// columns in `x`, then `z` order, each column's runs from the top down.
///
/// # Errors
///
/// [`MeshError::UnknownBlock`] for a voxel of the node the rule reads (its columns from the
/// top down to their highest opaque voxel) whose id has no material; on error
/// `out` is left as it was.
///
/// ```
/// use mesher::heightmap::heightmap_boxes;
/// use mesher::BlockClasses;
/// use voxel_core::{BlockId, ChunkSize, Material, MaterialPalette, PaddedChunk};
///
/// let mut palette = MaterialPalette::new();
/// let stone = palette.push(Material::opaque(128, 128, 128))?;
/// let classes = BlockClasses::from_palette(&palette);
/// // Flat ground 3 voxels deep, one pillar 2 voxels higher at (4, 4).
/// let chunk = PaddedChunk::from_fn(ChunkSize::S8, |x, y, z| {
///     let top = if (x, z) == (5, 5) { 5 } else { 3 };
///     if y <= top { stone } else { BlockId::AIR }
/// });
/// let mut boxes = Vec::new();
/// heightmap_boxes(&chunk, &classes, &mut boxes)?;
/// let pillar = boxes.iter().find(|b| (b.x, b.z) == (4, 4)).unwrap();
/// assert_eq!((pillar.y, pillar.height, pillar.width()), (3, 2, 1));
/// // Equal columns merge along x: each row is its two border columns (which reach down as
/// // skirts) and its inner ones, two rows are whole, and the pillar splits its row.
/// assert_eq!(boxes.len(), 22);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn heightmap_boxes(
    padded: &PaddedChunk,
    classes: &BlockClasses,
    out: &mut Vec<ShellRun>,
) -> Result<(), MeshError> {
    let start = out.len();
    let result = extract(padded, classes, out);
    if result.is_err() {
        out.truncate(start);
    }
    result
}

fn extract(
    padded: &PaddedChunk,
    classes: &BlockClasses,
    out: &mut Vec<ShellRun>,
) -> Result<(), MeshError> {
    let e = padded.size().edge_usize();
    let p = padded.padded_edge();
    let voxels = padded.voxels();
    let at = |px: usize, py: usize, pz: usize| voxels[px + p * (py + p * pz)];
    let opaque = |px: usize, py: usize, pz: usize| -> Result<bool, MeshError> {
        let id = at(px, py, pz);
        match classes.class(id) {
            Some(class) => Ok(class.is_opaque()),
            None if id == BlockId::AIR => Ok(false),
            None => Err(MeshError::UnknownBlock {
                id,
                position: [px as u32, py as u32, pz as u32],
            }),
        }
    };
    // ground[px + p * pz]: one past the highest opaque padded y of the padded column, 0 if none.
    let mut ground = alloc::vec![0usize; p * p];
    for pz in 0..p {
        for px in 0..p {
            let corner = (px == 0 || px == p - 1) && (pz == 0 || pz == p - 1);
            if corner {
                continue;
            }
            for py in (0..p).rev() {
                let inner = (1..=e).contains(&px) && (1..=e).contains(&pz);
                // Apron voxels of unknown ids read as not opaque: only the node's own voxels
                // are checked, as the meshers do.
                let solid = if inner && (1..=e).contains(&py) {
                    opaque(px, py, pz)?
                } else {
                    classes.is_opaque(at(px, py, pz))
                };
                if solid {
                    ground[px + p * pz] = py + 1;
                    break;
                }
            }
        }
    }
    let mut column = Vec::new();
    let mut open: Vec<usize> = Vec::new();
    let mut next_open: Vec<usize> = Vec::new();
    for pz in 1..=e {
        open.clear();
        for px in 1..=e {
            column.clear();
            column_runs(&ground, &at, classes, [px, pz], e, &mut column);
            next_open.clear();
            for &run in &column {
                match open.iter().copied().find(|&i| extends(out[i], run)) {
                    Some(i) => {
                        out[i] = widen(out[i], run);
                        next_open.push(i);
                    }
                    None => {
                        next_open.push(out.len());
                        out.push(run);
                    }
                }
            }
            core::mem::swap(&mut open, &mut next_open);
        }
    }
    Ok(())
}

/// Where one side of a column is drawn, in padded y.
#[derive(Clone, Copy)]
struct Side {
    /// The lowest voxel whose face on this side is drawn (`p`: none).
    from: usize,
    /// The voxel at which the side becomes visible above a solid voxel in front (`p`: none):
    /// a run starts there, with this side's foot.
    foot: usize,
}

/// Pushes the runs of the node's column at padded `[px, pz]` to `out` (the rule of the
/// [module docs](self)); `ground` holds one past the highest opaque padded y of each padded
/// column, 0 if none.
fn column_runs(
    ground: &[usize],
    at: &impl Fn(usize, usize, usize) -> BlockId,
    classes: &BlockClasses,
    [px, pz]: [usize; 2],
    e: usize,
    out: &mut Vec<ShellRun>,
) {
    let p = e + 2;
    let top_above = ground[px + p * pz];
    // The highest opaque voxel inside the node, padded y in 1..=e.
    let Some(t) = (1..=e.min(top_above))
        .rev()
        .find(|&py| classes.is_opaque(at(px, py, pz)))
    else {
        return;
    };
    let top_face = !classes.is_opaque(at(px, t + 1, pz));
    let neighbours = [
        (px + 1, pz, px == e),
        (px - 1, pz, px == 1),
        (px, pz + 1, pz == e),
        (px, pz - 1, pz == 1),
    ];
    let sides = neighbours.map(|(nx, nz, border)| {
        let solid_to = ground[nx + p * nz];
        let air_from = solid_to.max(1);
        let from = if border && air_from <= t + 1 {
            air_from.saturating_sub(SKIRT_VOXELS).max(1)
        } else {
            air_from
        };
        let foot = if solid_to >= 1 && air_from <= t {
            air_from
        } else {
            p
        };
        Side { from, foot }
    });
    let bottom = sides.iter().map(|s| s.from).min().unwrap_or(p).min(t);
    if !top_face && bottom > t {
        return;
    }
    push_runs(out, at, classes, [px, pz], [bottom, t], top_face, &sides);
}

/// True when `run`, in the column after `open`'s last, continues `open` along x: the same
/// layer, block, top face and z feet, and no side drawn between them. The merged box draws the
/// OR of their z sides; where one of them has no such side it lies against a solid
/// neighbour, so the depth test hides it.
fn extends(open: ShellRun, run: ShellRun) -> bool {
    let top = 1 << FaceDirection::PosY.index();
    let pos_x = 1 << FaceDirection::PosX.index();
    let neg_x = 1 << FaceDirection::NegX.index();
    let z_feet = 0b1100;
    u32::from(open.x) + open.width() == u32::from(run.x)
        && open.z == run.z
        && (open.y, open.height, open.block) == (run.y, run.height, run.block)
        && open.side_mask() & top == run.side_mask() & top
        && open.feet() & z_feet == run.feet() & z_feet
        && open.side_mask() & pos_x == 0
        && run.side_mask() & neg_x == 0
}

/// `open` widened by `run`'s column (see [`extends`]): the sides and feet of both (`run` adds
/// the +x side and foot, `open` keeps its -x ones).
fn widen(open: ShellRun, run: ShellRun) -> ShellRun {
    let width = open.width() as u8 + 1;
    ShellRun {
        sides: open.sides | run.sides,
        ..open
    }
    .with_width(width)
}

/// Pushes the runs of column `[px, pz]` from padded `bottom` to `top`, split where the block id
/// changes and where a side's foot is.
fn push_runs(
    out: &mut Vec<ShellRun>,
    at: &impl Fn(usize, usize, usize) -> BlockId,
    classes: &BlockClasses,
    [px, pz]: [usize; 2],
    [bottom, top]: [usize; 2],
    top_face: bool,
    sides: &[Side; 4],
) {
    let mut run_top = top;
    let mut block = at(px, top, pz);
    let mut py = top;
    loop {
        let below = if py > bottom {
            let id = at(px, py - 1, pz);
            Some(if classes.is_opaque(id) { id } else { block })
        } else {
            None
        };
        let foot_here = sides.iter().any(|s| s.foot == py);
        if below != Some(block) || foot_here {
            let mut mask = 0u8;
            let mut feet = 0u8;
            for (s, side) in sides.iter().enumerate() {
                if side.from <= run_top {
                    mask |= 1 << SIDES[s].index();
                    if side.foot == py {
                        feet |= 1 << s;
                    }
                }
            }
            if top_face && run_top == top {
                mask |= 1 << FaceDirection::PosY.index();
            }
            if mask != 0 {
                let run = ShellRun::new(
                    (px - 1) as u8,
                    (pz - 1) as u8,
                    (py - 1) as u8,
                    (run_top - py + 1) as u8,
                    block.0,
                    mask,
                );
                out.push(run.with_feet(feet));
            }
            match below {
                Some(id) => {
                    block = id;
                    run_top = py - 1;
                }
                None => break,
            }
        }
        py -= 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use voxel_core::{ChunkSize, Material, MaterialPalette};

    fn palette() -> (BlockClasses, BlockId, BlockId, BlockId) {
        let mut palette = MaterialPalette::new();
        let stone = palette.push(Material::opaque(128, 128, 128)).unwrap();
        let grass = palette.push(Material::opaque(40, 160, 40)).unwrap();
        let water = palette
            .push(Material::opaque(40, 80, 200).with_class(voxel_core::MaterialClass::Transparent))
            .unwrap();
        (BlockClasses::from_palette(&palette), stone, grass, water)
    }

    fn boxes(chunk: &PaddedChunk, classes: &BlockClasses) -> Vec<ShellRun> {
        let mut out = Vec::new();
        heightmap_boxes(chunk, classes, &mut out).unwrap();
        out
    }

    /// The boxes over column `(x, z)`, top down.
    fn covering(out: &[ShellRun], x: u32, z: u8) -> Vec<ShellRun> {
        out.iter()
            .copied()
            .filter(|b| b.z == z && u32::from(b.x) <= x && x < u32::from(b.x) + b.width())
            .collect()
    }

    const TOP: u8 = 1 << 2;

    #[test]
    fn a_step_splits_by_block_and_shows_its_side() {
        let (classes, stone, grass, _) = palette();
        // Padded coordinates: ground up to py 2 for px <= 4, up to py 5 beyond, grass on top.
        let chunk = PaddedChunk::from_fn(ChunkSize::S8, |x, y, z| {
            let top = if x <= 4 { 2 } else { 5 };
            let _ = z;
            match y {
                y if y == top => grass,
                y if y < top => stone,
                _ => BlockId::AIR,
            }
        });
        let out = boxes(&chunk, &classes);
        // Column x = 4 (padded 5) is the high column beside the step down to x = 3.
        let col = covering(&out, 4, 3);
        assert_eq!(col.len(), 2, "{col:?}");
        assert_eq!((col[0].y, col[0].height, col[0].block), (4, 1, grass.0));
        assert_ne!(col[0].sides & 1 << FaceDirection::PosY.index(), 0);
        assert_ne!(col[0].sides & 1 << FaceDirection::NegX.index(), 0);
        // The stone under the grass shows on the step's side, down to one above x = 3's top.
        assert_eq!((col[1].y, col[1].height, col[1].block), (2, 2, stone.0));
        assert_eq!(col[1].side_mask(), 1 << FaceDirection::NegX.index());
        // Its -x side shows from its lowest voxel up, above x = 3's top: that is its foot; the
        // grass above continues the side, so it has no foot.
        assert_eq!((col[1].feet(), col[0].feet()), (0b10, 0));
        // The low side's grass is one box from the border (whose -x side shows) to the step;
        // the border column's stone skirt is its own box.
        let flat = covering(&out, 2, 3);
        assert_eq!(flat.len(), 1);
        assert_eq!((flat[0].x, flat[0].width(), flat[0].y), (0, 4, 1));
        assert_eq!(flat[0].side_mask(), TOP | 1 << FaceDirection::NegX.index());
        assert_eq!(covering(&out, 0, 3).len(), 2);
        // Equal columns merge: the high side's grass, x = 4..8, is one box.
        assert_eq!((col[0].x, col[0].width()), (4, 4));
    }

    #[test]
    fn border_columns_reach_down_as_skirts() {
        let (classes, stone, _, _) = palette();
        let chunk = PaddedChunk::from_fn(
            ChunkSize::S8,
            |_, y, _| {
                if y <= 4 { stone } else { BlockId::AIR }
            },
        );
        let out = boxes(&chunk, &classes);
        // The z = 0 row: one box, top at padded 4 (local 3), skirt from padded 5 - 2 = 3
        // (local 2), its four outward sides.
        let row = covering(&out, 0, 0);
        assert_eq!(row.len(), 1);
        assert_eq!((row[0].y, row[0].height, row[0].width()), (2, 2, 8));
        assert_eq!(row[0].side_mask(), 0b10_0111);
        // An inner row: the border columns' skirts, and the inner columns' tops.
        let inner = covering(&out, 3, 3);
        assert_eq!((inner[0].x, inner[0].y, inner[0].height), (1, 3, 1));
        assert_eq!((inner[0].width(), inner[0].side_mask()), (6, TOP));
        let west = covering(&out, 0, 3);
        assert_eq!((west[0].y, west[0].height, west[0].width()), (2, 2, 1));
    }

    #[test]
    fn buried_columns_and_water_draw_nothing() {
        let (classes, stone, _, water) = palette();
        // Solid through the node and its apron above: nothing shows.
        let buried = PaddedChunk::from_fn(ChunkSize::S8, |_, _, _| stone);
        assert!(boxes(&buried, &classes).is_empty());
        // Water over a floor: the floor's top faces, no water box.
        let pond = PaddedChunk::from_fn(ChunkSize::S8, |_, y, _| match y {
            0..=1 => stone,
            2..=3 => water,
            _ => BlockId::AIR,
        });
        let out = boxes(&pond, &classes);
        assert!(out.iter().all(|b| b.block == stone.0 && b.y == 0));
        for (x, z) in (0..8).flat_map(|x| (0..8u8).map(move |z| (x, z))) {
            let over = covering(&out, x, z);
            assert!(
                over.len() == 1 && over[0].side_mask() & TOP != 0,
                "({x}, {z})"
            );
        }
    }

    #[test]
    fn unknown_ids_are_named_and_leave_out_untouched() {
        let (classes, stone, _, _) = palette();
        let chunk = PaddedChunk::from_fn(ChunkSize::S8, |x, y, z| match (x, y, z) {
            (3, 1, 3) => BlockId(999),
            (_, 0, _) => stone,
            _ => BlockId::AIR,
        });
        let mut out = alloc::vec![ShellRun::default()];
        let err = heightmap_boxes(&chunk, &classes, &mut out).unwrap_err();
        assert!(matches!(
            err,
            MeshError::UnknownBlock {
                id: BlockId(999),
                ..
            }
        ));
        assert_eq!(out.len(), 1);
    }
}
