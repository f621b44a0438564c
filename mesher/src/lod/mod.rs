//! Levels of detail: downsampling 2x per level, and crack-free borders between levels.
//!
//! # Downsampling rule
//!
//! A chunk at level `k + 1` covers `2 x 2 x 2` chunks of level `k`; each of its voxels stands
//! for `2 x 2 x 2` voxels ("children") of the finer level. A coarse voxel shows what is on top
//! of its children, the face most views of terrain see:
//!
//! 1. the *deciding half* is the upper half (the 4 children with `dy = 1`) if any of them is not
//!    air, else the lower half;
//! 2. if any child of the deciding half is opaque, the coarse voxel takes the opaque id that
//!    occurs most often there (ties: the smaller id);
//! 3. otherwise, if any is transparent, the most common transparent id (same tie rule);
//! 4. otherwise (all 8 children air) it is air.
//!
//! So grass-topped ground stays grass on top whatever lies under it, and a lake stays water
//! at every level (its sand bottom sinks by up to one coarse voxel instead of rising to the
//! surface). A coarse voxel is air only when all its children are, so a surface one voxel thin
//! (a wall, a floor, a leaf layer) is never lost at any level: it thickens to the coarse voxel
//! size instead (an opaque floor under a transparent layer in the same coarse voxel shows as
//! that transparent layer). Volume can grow by up to one coarse voxel per surface; it never
//! shrinks.
//!
//! # Borders between levels
//!
//! Where a chunk's neighbour is drawn at another level, the two do not agree voxel by voxel, so
//! face culling across that border could leave a hole (each side hiding its border faces behind
//! voxels the other side does not draw). The rule here is transition faces: before meshing, the
//! padding on such sides is cleared to air ([`prepare_lod_border`]), so the chunk emits all of
//! its border faces there and its mesh is closed on that side by itself. Two closed surfaces
//! cannot have a crack between them; the price is extra faces only along level borders (back
//! faces of the pair face away from each other and are culled by the GPU).
//!
//! A renderer whose levels change as the camera moves would have to re-mesh every chunk along a
//! moving level border under that rule. [`skirts`] gives the same closure without re-meshing:
//! each chunk is meshed once against its real neighbours, and per side the faces and blocks
//! that clearing that side's padding would add are kept apart ([`skirt_quads`],
//! [`skirt_blocks`]); the renderer draws a side's skirt only while the neighbour there is drawn
//! at another level.

use alloc::vec;
use alloc::vec::Vec;

use voxel_core::storage::{DenseChunk, PaletteChunk, VoxelStorage, WorldMap};
use voxel_core::{BlockId, ChunkCoord, FaceDirection, LocalPos, MaterialClass, PaddedChunk};

use crate::{BlockClasses, MeshError};

pub mod geometry;
pub mod nodes;
pub mod skirts;

pub use geometry::{Geometry, GeometryCounts, geometry_counts};
#[cfg(feature = "parallel")]
pub use nodes::mesh_nodes;
pub use nodes::{NodeMesh, NodeMesher, NodeSettings, downsample_levels, mesh_nodes_sequential};
pub use skirts::{Skirts, skirt_blocks, skirt_quads};

/// Picks the coarse id for 8 children, by the rule in the [module docs](self). Indices 4..8 are
/// the upper half (`dy = 1`). Returns the id of a child the palette does not know as an error.
fn coarse_id(children: &[BlockId; 8], classes: &BlockClasses) -> Result<BlockId, BlockId> {
    let upper = &children[4..];
    let half = if upper.iter().any(|id| !id.is_air()) {
        upper
    } else {
        &children[..4]
    };
    // Rank = (count in the deciding half, smaller id): the largest rank wins.
    let rank = |id: BlockId| {
        let count = half.iter().filter(|&&c| c == id).count();
        (count, core::cmp::Reverse(id))
    };
    // Every child's id must be known, whichever half decides.
    if let Some(&unknown) = children.iter().find(|&&id| classes.class(id).is_none()) {
        return Err(unknown);
    }
    let mut best_opaque: Option<BlockId> = None;
    let mut best_transparent: Option<BlockId> = None;
    for &id in half {
        let slot = match classes.class(id) {
            None | Some(MaterialClass::Air) => continue,
            Some(MaterialClass::Transparent) => &mut best_transparent,
            Some(_) => &mut best_opaque,
        };
        if slot.is_none_or(|best| rank(id) > rank(best)) {
            *slot = Some(id);
        }
    }
    Ok(best_opaque.or(best_transparent).unwrap_or(BlockId::AIR))
}

/// The coarse voxel of 8 children by the rule in the [module docs](self), for a caller that
/// updates single coarse voxels (an edited world's levels of detail) instead of whole chunks.
/// `children[dx + 2 * dz + 4 * dy]` is the child at offset `(dx, dy, dz)`, so indices 4..8 are
/// the upper half. The error is a child id the palette does not know.
pub fn coarse_voxel(children: &[BlockId; 8], classes: &BlockClasses) -> Result<BlockId, BlockId> {
    coarse_id(children, classes)
}

/// Downsamples the 8 finer chunks under one coarse chunk into `out` (same edge as the finer
/// chunks). `fine(dx, dy, dz)` returns the finer chunk at offset `(dx, dy, dz)` in `0..2`, or
/// `None` where it is missing (read as air).
pub fn downsample_chunk<'a, C: VoxelStorage + 'a>(
    fine: impl Fn(u32, u32, u32) -> Option<&'a C>,
    classes: &BlockClasses,
    out: &mut DenseChunk,
) -> Result<(), MeshError> {
    let size = out.size();
    let e = size.edge();
    let half = e / 2;
    let mut rows = [
        vec![BlockId::AIR; e as usize],
        vec![BlockId::AIR; e as usize],
    ];
    let mut upper = [
        vec![BlockId::AIR; e as usize],
        vec![BlockId::AIR; e as usize],
    ];
    for cz in 0..e {
        for cy in 0..e {
            // Children of coarse row (cy, cz): fine rows 2cy..2cy+1, 2cz..2cz+1 of one fine chunk
            // per half of the row (x below half, x above half).
            let (fy, fz) = ((2 * cy) % e, (2 * cz) % e);
            let (dy, dz) = ((2 * cy) / e, (2 * cz) / e);
            for cx_half in 0..2u32 {
                let chunk = fine(cx_half, dy, dz);
                for (k, (row, up)) in rows.iter_mut().zip(upper.iter_mut()).enumerate() {
                    let z = fz + k as u32;
                    match chunk {
                        Some(c) => {
                            c.copy_row(fy, z, row)
                                .map_err(|_| bad_size(c.size().edge_usize()))?;
                            c.copy_row(fy + 1, z, up)
                                .map_err(|_| bad_size(c.size().edge_usize()))?;
                        }
                        None => {
                            row.fill(BlockId::AIR);
                            up.fill(BlockId::AIR);
                        }
                    }
                }
                for cx in cx_half * half..(cx_half + 1) * half {
                    let fx = ((2 * cx) % e) as usize;
                    let children = [
                        rows[0][fx],
                        rows[0][fx + 1],
                        rows[1][fx],
                        rows[1][fx + 1],
                        upper[0][fx],
                        upper[0][fx + 1],
                        upper[1][fx],
                        upper[1][fx + 1],
                    ];
                    let id =
                        coarse_id(&children, classes).map_err(|id| MeshError::UnknownBlock {
                            id,
                            position: [2 * cx, 2 * cy, 2 * cz],
                        })?;
                    let local = LocalPos {
                        x: cx as u8,
                        y: cy as u8,
                        z: cz as u8,
                    };
                    out.set(local, id).map_err(|_| bad_size(e as usize))?;
                }
            }
        }
    }
    Ok(())
}

fn bad_size(edge: usize) -> MeshError {
    MeshError::BadShape {
        reason: "finer chunk edge differs from the coarse chunk edge",
        value: edge,
    }
}

/// The next coarser level of a whole world: every coarse chunk that covers at least one finer
/// chunk, downsampled by [`downsample_chunk`]; all-air results are left out.
pub fn downsample_world<C: VoxelStorage>(
    fine: &WorldMap<C>,
    classes: &BlockClasses,
) -> Result<WorldMap<PaletteChunk>, MeshError> {
    let size = fine.size();
    let mut parents: Vec<ChunkCoord> = fine
        .iter()
        .map(|(c, _)| ChunkCoord::new(c.x.div_euclid(2), c.y.div_euclid(2), c.z.div_euclid(2)))
        .collect();
    parents.sort_unstable();
    parents.dedup();
    let mut coarse = WorldMap::new(size);
    let mut scratch = DenseChunk::new(size);
    for parent in parents {
        // 2 * parent + d never overflows: parent came from a division by 2.
        let child = |dx: u32, dy: u32, dz: u32| {
            fine.get(ChunkCoord::new(
                parent.x * 2 + dx as i32,
                parent.y * 2 + dy as i32,
                parent.z * 2 + dz as i32,
            ))
        };
        scratch.fill(BlockId::AIR);
        downsample_chunk(child, classes, &mut scratch)?;
        if scratch.non_air_count() > 0 {
            coarse
                .insert(parent, PaletteChunk::from_dense(&scratch))
                .map_err(|_| bad_size(size.edge_usize()))?;
        }
    }
    Ok(coarse)
}

/// [`downsample_world`] with the coarse chunks computed in parallel on rayon's pool (the same
/// result).
#[cfg(feature = "parallel")]
pub fn downsample_world_parallel<C: VoxelStorage + Sync>(
    fine: &WorldMap<C>,
    classes: &BlockClasses,
) -> Result<WorldMap<PaletteChunk>, MeshError> {
    use rayon::prelude::*;

    let size = fine.size();
    let mut parents: Vec<ChunkCoord> = fine
        .iter()
        .map(|(c, _)| ChunkCoord::new(c.x.div_euclid(2), c.y.div_euclid(2), c.z.div_euclid(2)))
        .collect();
    parents.sort_unstable();
    parents.dedup();
    let chunks: Result<Vec<Option<(ChunkCoord, PaletteChunk)>>, MeshError> = parents
        .par_iter()
        .map(|&parent| {
            let child = |dx: u32, dy: u32, dz: u32| {
                fine.get(ChunkCoord::new(
                    parent.x * 2 + dx as i32,
                    parent.y * 2 + dy as i32,
                    parent.z * 2 + dz as i32,
                ))
            };
            let mut scratch = DenseChunk::new(size);
            downsample_chunk(child, classes, &mut scratch)?;
            Ok((scratch.non_air_count() > 0).then(|| (parent, PaletteChunk::from_dense(&scratch))))
        })
        .collect();
    let mut coarse = WorldMap::new(size);
    for (parent, chunk) in chunks?.into_iter().flatten() {
        coarse
            .insert(parent, chunk)
            .map_err(|_| bad_size(size.edge_usize()))?;
    }
    Ok(coarse)
}

/// Prepares a gathered neighbourhood for meshing at a level of detail: on every side whose
/// neighbour is drawn at another level (`same_level(face)` false), the padding is cleared so
/// the chunk emits its border faces there (see the [module docs](self)).
pub fn prepare_lod_border(padded: &mut PaddedChunk, same_level: impl Fn(FaceDirection) -> bool) {
    for face in FaceDirection::ALL {
        if !same_level(face) {
            padded.clear_padding_face(face);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use voxel_core::{Material, MaterialPalette};

    fn classes() -> (BlockClasses, BlockId, BlockId, BlockId) {
        let mut p = MaterialPalette::new();
        let stone = p.push(Material::opaque(1, 1, 1)).unwrap();
        let grass = p.push(Material::opaque(0, 200, 0)).unwrap();
        let water = p
            .push(Material::opaque(0, 0, 200).with_class(MaterialClass::Transparent))
            .unwrap();
        (BlockClasses::from_palette(&p), stone, grass, water)
    }

    #[test]
    fn coarse_id_follows_the_documented_rule() {
        let (c, stone, grass, water) = classes();
        let a = BlockId::AIR;
        // The upper half decides when it holds anything: grass on top of more stone.
        assert_eq!(
            coarse_id(&[stone, stone, stone, stone, grass, a, a, a], &c),
            Ok(grass)
        );
        // Majority within the deciding half; ties go to the smaller id.
        assert_eq!(
            coarse_id(&[a, a, a, a, grass, stone, stone, a], &c),
            Ok(stone)
        );
        assert_eq!(coarse_id(&[a, a, a, a, grass, stone, a, a], &c), Ok(stone));
        // An empty upper half: the lower half decides.
        assert_eq!(
            coarse_id(&[stone, grass, grass, a, a, a, a, a], &c),
            Ok(grass)
        );
        // Water over sand stays water; opaque beats transparent within the deciding half.
        assert_eq!(
            coarse_id(&[stone, stone, stone, stone, water, water, water, a], &c),
            Ok(water)
        );
        assert_eq!(
            coarse_id(&[a, a, a, a, water, water, water, stone], &c),
            Ok(stone)
        );
        assert_eq!(coarse_id(&[water, a, a, a, a, a, a, a], &c), Ok(water));
        assert_eq!(coarse_id(&[a; 8], &c), Ok(a));
        // Unknown ids are errors in either half.
        assert_eq!(
            coarse_id(&[a, a, a, BlockId(99), stone, a, a, a], &c),
            Err(BlockId(99))
        );
    }
}
