//! Levels of detail: downsampling 2x per level, and crack-free borders between levels.
//!
//! # Downsampling rule
//!
//! A chunk at level `k + 1` covers `2 x 2 x 2` chunks of level `k`; each of its voxels stands
//! for `2 x 2 x 2` voxels ("children") of the finer level:
//!
//! 1. if any child is opaque, the coarse voxel takes the opaque id that occurs most often among
//!    the children (ties: the id found in the upper half first, so grass-topped ground stays
//!    grass on top, then the smaller id);
//! 2. otherwise, if any child is transparent, the most common transparent id (same tie rule);
//! 3. otherwise it is air.
//!
//! A coarse voxel is air only when all its children are, so a surface one voxel thin (a wall, a
//! floor, a leaf layer) is never lost at any level: it thickens to the coarse voxel size instead.
//! Volume can grow by up to one coarse voxel per surface; it never shrinks.
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

pub mod nodes;
pub mod skirts;

#[cfg(feature = "parallel")]
pub use nodes::mesh_nodes;
pub use nodes::{NodeMesh, NodeMesher, NodeSettings, downsample_levels, mesh_nodes_sequential};
pub use skirts::{Skirts, skirt_blocks, skirt_quads};

/// Picks the coarse id for 8 children, by the rule in the [module docs](self). Indices 4..8 are
/// the upper half (`dy = 1`). Returns the id of a child the palette does not know as an error.
fn coarse_id(children: &[BlockId; 8], classes: &BlockClasses) -> Result<BlockId, BlockId> {
    // Rank = (count, occurs in the upper half, smaller id): the largest rank wins.
    let rank = |id: BlockId| {
        let count = children.iter().filter(|&&c| c == id).count();
        (count, children[4..].contains(&id), core::cmp::Reverse(id))
    };
    let mut best_opaque: Option<BlockId> = None;
    let mut best_transparent: Option<BlockId> = None;
    for &id in children {
        let slot = match classes.class(id) {
            None => return Err(id),
            Some(MaterialClass::Air) => continue,
            Some(MaterialClass::Transparent) => &mut best_transparent,
            Some(_) => &mut best_opaque,
        };
        if slot.is_none_or(|best| rank(id) > rank(best)) {
            *slot = Some(id);
        }
    }
    Ok(best_opaque.or(best_transparent).unwrap_or(BlockId::AIR))
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
        // Majority opaque wins.
        assert_eq!(
            coarse_id(&[stone, stone, stone, a, grass, a, a, a], &c),
            Ok(stone)
        );
        // A tie goes to the id in the upper half.
        assert_eq!(
            coarse_id(&[stone, stone, a, a, grass, grass, a, a], &c),
            Ok(grass)
        );
        // Opaque beats a transparent majority; a lone opaque child keeps a thin surface.
        assert_eq!(
            coarse_id(
                &[water, water, water, water, water, water, water, stone],
                &c
            ),
            Ok(stone)
        );
        assert_eq!(coarse_id(&[water, a, a, a, a, a, a, a], &c), Ok(water));
        assert_eq!(coarse_id(&[a; 8], &c), Ok(a));
        assert_eq!(
            coarse_id(&[a, a, a, BlockId(99), a, a, a, a], &c),
            Err(BlockId(99))
        );
        // Equal counts, both in the upper half: the smaller id.
        assert_eq!(coarse_id(&[a, a, a, a, grass, stone, a, a], &c), Ok(stone));
    }
}
