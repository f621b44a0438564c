//! The `lod` body: downsampling (one coarse chunk, and a world near any coordinate) and the
//! border preparation.

use std::collections::BTreeSet;

use mesher::lod::{downsample_chunk, downsample_world, prepare_lod_border};
use mesher::{BlockClasses, MeshError, SurfaceBlocks};
use voxel_core::storage::{DenseChunk, VoxelStorage, WorldMap};
use voxel_core::{BlockId, ChunkCoord, ChunkSize, FaceDirection, LocalPos, PaddedChunk};

use super::input::{ChunkInput, chunk_input};
use super::{chunk_positions, id_at};

/// Bytes before the chunk input: byte 0 bits 0-5 the sides at the same level (bit
/// `FaceDirection::index`), bit 6 one finer chunk of another size; byte 1 which of the 8 finer
/// chunks exist (bit `dx + 2 dy + 4 dz`); bytes 2-13 the world's base chunk coordinate
/// (3 x `i32`, little-endian).
const PARAMS_LEN: usize = 14;

/// The coarse id of 8 children (indices 4..8 the upper half), by the rule in the docs of
/// `mesher::lod`, written independently: the deciding half is the upper half when any of its
/// children is not air, else the lower half; its most common opaque id (ties: the smaller id),
/// else its most common transparent id (same ties), else air. `Err` with the first unknown
/// child, whichever half decides.
fn reference_coarse(children: [BlockId; 8], classes: &BlockClasses) -> Result<BlockId, BlockId> {
    if let Some(&id) = children.iter().find(|&&id| classes.class(id).is_none()) {
        return Err(id);
    }
    let half = if children[4..].iter().all(|id| id.is_air()) {
        &children[..4]
    } else {
        &children[4..]
    };
    for transparent in [false, true] {
        let best = half
            .iter()
            .copied()
            .filter(|&id| !id.is_air() && classes.is_transparent(id) == transparent)
            .max_by_key(|&id| {
                let count = half.iter().filter(|&&c| c == id).count();
                (count, std::cmp::Reverse(id))
            });
        if let Some(id) = best {
            return Ok(id);
        }
    }
    Ok(BlockId::AIR)
}

/// The 8 children of coarse voxel `c` of a coarse chunk of edge `e`: `read(d, local)` reads
/// voxel `local` of the finer chunk at offset `d` (`0..2` per axis). Order: `dz`, then `dx`
/// within the lower half (`dy = 0`), then the upper half.
fn children(e: u32, c: [u32; 3], read: impl Fn([u32; 3], [u32; 3]) -> BlockId) -> [BlockId; 8] {
    std::array::from_fn(|k| {
        let (dx, dz, dy) = (k as u32 & 1, (k as u32 >> 1) & 1, k as u32 >> 2);
        let fine = [2 * c[0] + dx, 2 * c[1] + dy, 2 * c[2] + dz];
        read(fine.map(|f| f / e), fine.map(|f| f % e))
    })
}

fn local(p: [u32; 3]) -> LocalPos {
    LocalPos {
        x: p[0] as u8,
        y: p[1] as u8,
        z: p[2] as u8,
    }
}

/// The finer chunk `k` (`dx + 2 dy + 4 dz`): the input chunk's voxels read `3 k` voxels along
/// the padded storage order, so the 8 chunks differ.
fn finer_chunk(padded: &PaddedChunk, k: u32, size: ChunkSize) -> DenseChunk {
    let voxels = padded.voxels();
    let p = padded.padded_edge() as u32;
    DenseChunk::from_fn(size, |l| {
        let i = (u32::from(l.x) + 1) + p * ((u32::from(l.y) + 1) + p * (u32::from(l.z) + 1));
        voxels[(i + 3 * k) as usize % voxels.len()]
    })
}

/// The LOD stages on arbitrary chunks ([`ChunkInput`], after [`PARAMS_LEN`] bytes):
///
/// - `downsample_chunk` of up to 8 finer chunks (missing ones are air) into a coarse chunk that
///   held other voxels: every coarse voxel follows the documented rule (against
///   [`reference_coarse`]); an unknown id fails naming a child of the first coarse voxel (z, y,
///   x order) that has one, at twice that voxel's position; a finer chunk of another size
///   fails with `BadShape` (or with an unknown id read before it);
/// - `downsample_world` of the same chunks placed at the base coordinate plus their offsets
///   (any `i32`; chunks that would leave the range are left out): exactly the coarse chunks
///   that are not all air, each voxel by the rule; unknown ids fail naming one;
/// - `prepare_lod_border`: the padding of exactly the sides not at the same level is cleared,
///   every other voxel kept, the occupancy masks follow the voxels, and the surface blocks of
///   the prepared chunk include every non-air voxel on a cleared side.
pub(crate) fn lod(data: &[u8]) {
    let Some(params) = data.get(..PARAMS_LEN) else {
        return;
    };
    let Some(input) = chunk_input(&data[PARAMS_LEN..]) else {
        return;
    };
    let ChunkInput {
        padded, classes, ..
    } = &input;
    let size = padded.size();
    let mismatched = params[0] & 0x40 != 0;
    let present = params[1];
    let word = |at: usize| {
        i32::from_le_bytes([params[at], params[at + 1], params[at + 2], params[at + 3]])
    };
    let base = [word(2), word(6), word(10)];

    let other = if size == ChunkSize::S8 {
        ChunkSize::S16
    } else {
        ChunkSize::S8
    };
    let fine: Vec<Option<DenseChunk>> = (0..8u32)
        .map(|k| {
            let chunk_size = if mismatched && k == present.trailing_zeros() {
                other
            } else {
                size
            };
            ((present >> k) & 1 == 1).then(|| finer_chunk(padded, k, chunk_size))
        })
        .collect();
    check_downsample_chunk(&fine, classes, size);
    if !mismatched {
        check_downsample_world(&fine, classes, size, base);
    }
    check_border(padded, classes, params[0] & 0x3F);
}

/// The `downsample_chunk` part of [`lod`].
fn check_downsample_chunk(fine: &[Option<DenseChunk>], classes: &BlockClasses, size: ChunkSize) {
    let e = size.edge();
    let chunk_at = |d: [u32; 3]| fine[(d[0] + 2 * d[1] + 4 * d[2]) as usize].as_ref();
    let mut out = DenseChunk::filled(size, BlockId(7));
    let result = downsample_chunk(|dx, dy, dz| chunk_at([dx, dy, dz]), classes, &mut out);
    let read = |d: [u32; 3], l: [u32; 3]| {
        chunk_at(d).map_or(BlockId::AIR, |c| c.get(local(l)).expect("inside the chunk"))
    };
    if fine.iter().flatten().any(|c| c.size() != size) {
        // Rows before the odd chunk may already fail on an unknown id.
        match result {
            Err(MeshError::BadShape { .. }) => {}
            Err(MeshError::UnknownBlock { id, .. }) => {
                assert!(classes.class(id).is_none(), "{id:?} is known");
            }
            other => panic!("a finer chunk of another size gave {other:?}"),
        }
        return;
    }
    let coarse: Vec<[u32; 3]> = (0..e)
        .flat_map(|z| (0..e).flat_map(move |y| (0..e).map(move |x| [x, y, z])))
        .collect();
    match result {
        Ok(()) => {
            for &c in &coarse {
                let want = reference_coarse(children(e, c, read), classes)
                    .unwrap_or_else(|id| panic!("{id:?} under {c:?} is unknown, yet no error"));
                assert_eq!(out.get(local(c)), Ok(want), "coarse voxel {c:?}");
            }
        }
        Err(MeshError::UnknownBlock { id, position }) => {
            assert!(classes.class(id).is_none(), "{id:?} is known");
            let first = coarse
                .iter()
                .find(|&&c| reference_coarse(children(e, c, read), classes).is_err())
                .expect("an unknown child somewhere");
            assert_eq!(
                position,
                first.map(|a| 2 * a),
                "not the first coarse voxel with one"
            );
            assert!(
                children(e, *first, read).contains(&id),
                "{id:?} is not a child of {first:?}"
            );
        }
        Err(other) => panic!("unexpected error {other:?}"),
    }
}

/// The `downsample_world` part of [`lod`].
fn check_downsample_world(
    fine: &[Option<DenseChunk>],
    classes: &BlockClasses,
    size: ChunkSize,
    base: [i32; 3],
) {
    let e = size.edge();
    let mut world: WorldMap<DenseChunk> = WorldMap::new(size);
    for (k, chunk) in fine.iter().enumerate() {
        let d = [k & 1, (k >> 1) & 1, k >> 2].map(|a| a as i32);
        let coord = [0, 1, 2].map(|a| base[a].checked_add(d[a]));
        if let (Some(chunk), [Some(x), Some(y), Some(z)]) = (chunk, coord) {
            world
                .insert(ChunkCoord::new(x, y, z), chunk.clone())
                .expect("one size");
        }
    }
    let parents: BTreeSet<[i32; 3]> = world
        .iter()
        .map(|(c, _)| [c.x, c.y, c.z].map(|a| a.div_euclid(2)))
        .collect();
    // Voxel `l` of the finer chunk at offset `d` under coarse chunk `parent`. The eight finer
    // chunks are looked up once per parent: a lookup per voxel made a 62^3 input take half
    // a minute under the sanitizer.
    let read_parent = |parent: [i32; 3]| {
        let finer: [Option<&DenseChunk>; 8] = core::array::from_fn(|k| {
            let d = [k & 1, (k >> 1) & 1, k >> 2];
            let coord = [0, 1, 2].map(|a| i64::from(parent[a]) * 2 + d[a] as i64);
            let coord = coord.map(|a| i32::try_from(a).expect("2 * (c / 2) + 1 stays in range"));
            world.get(ChunkCoord::new(coord[0], coord[1], coord[2]))
        });
        move |d: [u32; 3], l: [u32; 3]| {
            finer[(d[0] + 2 * d[1] + 4 * d[2]) as usize]
                .map_or(BlockId::AIR, |c| c.get(local(l)).expect("inside the chunk"))
        }
    };
    let coarse_voxels: Vec<[u32; 3]> = (0..e)
        .flat_map(|z| (0..e).flat_map(move |y| (0..e).map(move |x| [x, y, z])))
        .collect();
    match downsample_world(&world, classes) {
        Ok(coarse) => {
            let mut non_air = 0;
            for &parent in &parents {
                let read = read_parent(parent);
                let want: Vec<BlockId> = coarse_voxels
                    .iter()
                    .map(|&c| {
                        reference_coarse(children(e, c, read), classes)
                            .unwrap_or_else(|id| panic!("{id:?} is unknown, yet no error"))
                    })
                    .collect();
                let got = coarse.get(ChunkCoord::new(parent[0], parent[1], parent[2]));
                if want.iter().all(|id| id.is_air()) {
                    assert!(
                        got.is_none(),
                        "the all-air coarse chunk {parent:?} is stored"
                    );
                    continue;
                }
                non_air += 1;
                let got = got.unwrap_or_else(|| panic!("coarse chunk {parent:?} is missing"));
                for (&c, &id) in coarse_voxels.iter().zip(&want) {
                    assert_eq!(
                        got.get(local(c)),
                        Ok(id),
                        "coarse voxel {c:?} of {parent:?}"
                    );
                }
            }
            assert_eq!(coarse.len(), non_air, "coarse chunks nothing covers");
        }
        Err(MeshError::UnknownBlock { id, position }) => {
            assert!(classes.class(id).is_none(), "{id:?} is known");
            let c = position.map(|a| a / 2);
            assert!(
                position.iter().all(|a| a % 2 == 0) && c.iter().all(|&a| a < e),
                "{position:?}"
            );
            let named = parents
                .iter()
                .any(|&parent| children(e, c, read_parent(parent)).contains(&id));
            assert!(named, "no coarse voxel at {c:?} has an {id:?} child");
        }
        Err(other) => panic!("unexpected error {other:?}"),
    }
}

/// The `prepare_lod_border` part of [`lod`]: `same_level` bit `d` set when side `d` keeps its
/// padding.
fn check_border(padded: &PaddedChunk, classes: &BlockClasses, same_level: u8) {
    let mut prepared = padded.clone();
    let same = |face: FaceDirection| (same_level >> face.index()) & 1 == 1;
    prepare_lod_border(&mut prepared, same);
    let p = padded.padded_edge() as u32;
    // The padding layer a voxel lies in on each side, if any.
    let cleared = |pos: [u32; 3]| {
        FaceDirection::ALL.into_iter().any(|face| {
            let layer = if face.is_positive() { p - 1 } else { 0 };
            !same(face) && pos[face.normal_axis()] == layer
        })
    };
    for z in 0..p {
        for y in 0..p {
            let mut mask = 0u64;
            for x in 0..p {
                let pos = [x, y, z];
                let want = if cleared(pos) {
                    BlockId::AIR
                } else {
                    id_at(padded, pos)
                };
                let got = id_at(&prepared, pos);
                assert_eq!(got, want, "voxel {pos:?}");
                mask |= u64::from(!got.is_air()) << x;
            }
            assert_eq!(
                prepared.column(y, z),
                Ok(mask),
                "occupancy mask of row ({y}, {z})"
            );
        }
    }
    // Every non-air voxel next to a cleared side shows that face: it is a surface block.
    let mut blocks = SurfaceBlocks::new();
    if mesher::surface_blocks(&prepared, classes, &mut blocks).is_ok() {
        let listed: BTreeSet<[u32; 3]> = blocks.iter_local().map(|(pos, _)| pos).collect();
        for pos in chunk_positions(&prepared) {
            let on_cleared_side = FaceDirection::ALL.into_iter().any(|face| {
                let n = face.normal();
                let beyond = [0, 1, 2].map(|a| pos[a] as i64 + i64::from(n[a]));
                beyond.iter().all(|&b| (0..i64::from(p)).contains(&b))
                    && cleared(beyond.map(|b| b as u32))
            });
            if on_cleared_side && !id_at(&prepared, pos).is_air() {
                let l = pos.map(|a| a - 1);
                assert!(
                    listed.contains(&l),
                    "{pos:?} on a cleared side is not drawn"
                );
            }
        }
    }
}
