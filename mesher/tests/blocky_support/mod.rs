//! Plain brute-force references for the blocky meshers, written voxel by voxel with no bit
//! tricks, and the random chunks the property tests feed them.
#![allow(
    dead_code,
    reason = "each test file uses a different part of the support module"
)]

use std::collections::{HashMap, HashSet};

use mesher::BlockClasses;
use mesher::blocky::BlockyMesh;
use voxel_core::{
    BlockId, ChunkSize, FaceDirection, Material, MaterialClass, MaterialPalette, PaddedChunk,
};

mod reference;
pub(crate) use reference::*;

/// Block ids of the test palette.
pub(crate) const STONE: u16 = 1;
pub(crate) const DIRT: u16 = 2;
pub(crate) const WATER: u16 = 3;
pub(crate) const GLASS: u16 = 4;
pub(crate) const GRASS: u16 = 5;
pub(crate) const SAND: u16 = 6;
/// Not in the palette.
pub(crate) const UNKNOWN: u16 = 40;

/// A palette with opaque, clutter-bearing and two transparent materials.
pub(crate) fn palette(with_transparent: bool) -> MaterialPalette {
    let mut p = MaterialPalette::new();
    let t = |m: Material| {
        if with_transparent {
            m.with_class(MaterialClass::Transparent)
        } else {
            m
        }
    };
    p.push(Material::opaque(100, 100, 100)).unwrap(); // 1 stone
    p.push(Material::opaque(120, 80, 50)).unwrap(); // 2 dirt
    p.push(t(Material::opaque(0, 0, 255))).unwrap(); // 3 water
    p.push(t(Material::opaque(200, 200, 255))).unwrap(); // 4 glass
    p.push(Material::opaque(0, 255, 0).with_class(MaterialClass::ClutterBearing))
        .unwrap(); // 5
    p.push(Material::opaque(250, 230, 150).with_class(MaterialClass::Smoothable))
        .unwrap(); // 6
    p
}

/// The deterministic generator of the chunks' contents.
pub(crate) use voxel_scene::rng::Rng;

/// How a random chunk is filled.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Fill {
    /// Each voxel independently: air with probability `air_percent`, else one of `ids`.
    Noise { air_percent: u64 },
    /// Boxes of random ids dropped into air: large flat faces, so quads merge.
    Boxes { count: u32 },
    /// A height field of stone and dirt with water above it up to a level: terrain-like.
    Terrain,
    /// A 3-D checkerboard: voxel `(x, y, z)` is air iff `x + y + z` is odd, else one of `ids`
    /// (one id for the whole chunk with probability 1/2): every face is visible and alone.
    /// `holes_percent` of the even voxels are air too: the faces stay alone, but lines with
    /// the same faces get different front neighbourhoods, so AO varies from line to line.
    Checkerboard { holes_percent: u64 },
    /// A window of a Menger sponge of `level` (a fractal of holes of every size down to one
    /// voxel) at a random offset, in one of `ids` or in three of them by 9^3 block.
    Menger { level: u32 },
    /// A window of a random foliage scene (`voxel_scene::detailed::foliage`: trees, leaves
    /// with holes, grass blades, vines), its 12 ids mapped onto `ids`.
    Foliage,
    /// A window of a random flat maze (`voxel_scene::detailed::flat_maze`: a floor under low
    /// walls, one id) in one of `ids`, its floor across axis `normal` (0 = x, 1 = y, 2 = z):
    /// slabs and rows that are nearly all solid, with few faces.
    FlatMaze { normal: usize },
}

/// A random padded chunk of `size`; `air_border` leaves the one-voxel border air.
pub(crate) fn random_chunk(
    size: ChunkSize,
    seed: u64,
    fill: Fill,
    ids: &[u16],
    air_border: bool,
) -> PaddedChunk {
    let p = size.padded_edge() as u32;
    let mut rng = Rng::new(seed);
    let mut padded = match fill {
        Fill::Noise { air_percent } => PaddedChunk::from_fn(size, |_, _, _| {
            if rng.below(100) < air_percent {
                BlockId::AIR
            } else {
                BlockId(ids[rng.below(ids.len() as u64) as usize])
            }
        }),
        Fill::Boxes { count } => {
            let mut padded = PaddedChunk::new(size);
            for _ in 0..count {
                let lo: [u32; 3] = core::array::from_fn(|_| rng.below(u64::from(p)) as u32);
                let ext: [u32; 3] =
                    core::array::from_fn(|_| 1 + rng.below(u64::from(p / 2)) as u32);
                let id = BlockId(ids[rng.below(ids.len() as u64) as usize]);
                let id = if rng.below(5) == 0 { BlockId::AIR } else { id };
                for z in lo[2]..(lo[2] + ext[2]).min(p) {
                    for y in lo[1]..(lo[1] + ext[1]).min(p) {
                        for x in lo[0]..(lo[0] + ext[0]).min(p) {
                            padded.set(x, y, z, id).unwrap();
                        }
                    }
                }
            }
            padded
        }
        Fill::Checkerboard { holes_percent } => {
            let single = rng.below(2) == 0;
            let first = ids[rng.below(ids.len() as u64) as usize];
            PaddedChunk::from_fn(size, |x, y, z| {
                if (x + y + z) % 2 == 1 || rng.below(100) < holes_percent {
                    BlockId::AIR
                } else if single {
                    BlockId(first)
                } else {
                    BlockId(ids[rng.below(ids.len() as u64) as usize])
                }
            })
        }
        Fill::Menger { level } => {
            // One id (the one-id passes, with AO off), or the shaded sponge's three mapped
            // onto `ids` (the keyed passes).
            if rng.below(2) == 0 {
                let sponge = voxel_scene::detailed::menger(level);
                let id = ids[rng.below(ids.len() as u64) as usize];
                window(size, &sponge, &mut rng, [0, 1, 2], |_| id)
            } else {
                let sponge = voxel_scene::detailed::menger_shaded(level);
                let shift = rng.below(ids.len() as u64) as usize;
                window(size, &sponge, &mut rng, [0, 1, 2], |id| {
                    ids[(usize::from(id) + shift) % ids.len()]
                })
            }
        }
        Fill::Foliage => {
            let dims = [48 + rng.below(48) as usize, 40, 48 + rng.below(48) as usize];
            let forest = voxel_scene::detailed::foliage(dims, rng.next_u64());
            window(size, &forest, &mut rng, [0, 1, 2], |id| {
                ids[usize::from(id) % ids.len()]
            })
        }
        Fill::FlatMaze { normal } => {
            let cells = 4 + rng.below(40) as usize;
            let maze =
                voxel_scene::detailed::flat_maze(cells, 1 + rng.below(3) as usize, rng.next_u64());
            let id = ids[rng.below(ids.len() as u64) as usize];
            // The maze's y (its height) along `normal`, and that axis along y.
            let mut axes = [0, 1, 2];
            axes.swap(1, normal);
            window(size, &maze, &mut rng, axes, |_| id)
        }
        Fill::Terrain => {
            let heights: Vec<u32> = (0..p * p).map(|_| rng.below(u64::from(p)) as u32).collect();
            let level = rng.below(u64::from(p)) as u32;
            PaddedChunk::from_fn(size, |x, y, z| {
                // Smooth the heights a little so there are flat runs.
                let h = heights[((x / 3) * 3 + p * ((z / 3) * 3)) as usize];
                if y < h.saturating_sub(3) {
                    BlockId(STONE)
                } else if y <= h {
                    BlockId(if ids.contains(&DIRT) { DIRT } else { ids[0] })
                } else if y <= level && ids.contains(&WATER) {
                    BlockId(WATER)
                } else {
                    BlockId::AIR
                }
            })
        }
    };
    if air_border {
        for z in 0..p {
            for y in 0..p {
                for x in 0..p {
                    if [x, y, z].iter().any(|&a| a == 0 || a == p - 1) {
                        padded.set(x, y, z, BlockId::AIR).unwrap();
                    }
                }
            }
        }
    }
    padded
}

/// The padded chunk of `size` at a random offset into `scene` (which may run past its sides,
/// where it is air), each id mapped by `map`; the scene's axis `a` runs along the chunk's
/// axis `axes[a]`.
fn window(
    size: ChunkSize,
    scene: &voxel_scene::detailed::VoxelBox,
    rng: &mut Rng,
    axes: [usize; 3],
    map: impl Fn(u16) -> u16,
) -> PaddedChunk {
    let origin: [i64; 3] = core::array::from_fn(|a| rng.below(scene.dims[a] as u64 + 4) as i64 - 4);
    PaddedChunk::from_fn(size, |x, y, z| {
        let at = [x, y, z].map(i64::from);
        match scene.get(core::array::from_fn(|a| origin[a] + at[axes[a]])) {
            0 => BlockId::AIR,
            id => BlockId(map(id)),
        }
    })
}

/// Checks a mesh against the reference: same unit faces (position, direction, id, AO) per
/// layer, no overlap, and (through `expand`) equal ids and AO within every quad, since each
/// covered face takes the quad's id and AO and must match the reference face there.
pub(crate) fn assert_matches_reference(
    mesh: &BlockyMesh,
    padded: &PaddedChunk,
    classes: &BlockClasses,
    ao: bool,
) {
    let e = padded.size().edge();
    let (opaque, transparent) = reference_faces(padded, classes, ao);
    let got_o = covered(&mesh.opaque, e);
    let got_t = covered(&mesh.transparent, e);
    assert_faces_eq(&got_o, &opaque, "opaque");
    assert_faces_eq(&got_t, &transparent, "transparent");
}

fn assert_faces_eq(got: &[UnitFace], want: &[UnitFace], what: &str) {
    if got == want {
        return;
    }
    let g: HashSet<_> = got.iter().collect();
    let w: HashSet<_> = want.iter().collect();
    let extra: Vec<_> = g.difference(&w).take(5).collect();
    let missing: Vec<_> = w.difference(&g).take(5).collect();
    panic!(
        "{what} layer differs from the reference: {} faces vs {}; extra {extra:?}; missing {missing:?}",
        got.len(),
        want.len()
    );
}

/// Signed volume enclosed by a layer's quads: the sum of `det(a, b, c) / 6` over the two
/// counter-clockwise triangles `(0, 1, 2)`, `(0, 2, 3)` of each quad's `corners()`
/// (divergence theorem). Exact in integers: returns six times the volume.
pub(crate) fn six_times_volume(layer: &mesher::QuadLayer) -> i64 {
    let mut six_v = 0i64;
    for q in layer.iter() {
        let c = q.decode().unwrap().corners().map(|c| c.map(i64::from));
        for [a, b, d] in [[c[0], c[1], c[2]], [c[0], c[2], c[3]]] {
            six_v += a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0])
                + a[2] * (b[0] * d[1] - b[1] * d[0]);
        }
    }
    six_v
}

/// Opaque voxels of the chunk interior.
pub(crate) fn opaque_voxels(padded: &PaddedChunk, classes: &BlockClasses) -> i64 {
    let e = padded.size().edge() as i64;
    let mut n = 0;
    for z in 1..=e {
        for y in 1..=e {
            for x in 1..=e {
                n += i64::from(solid(classes, voxel(padded, [x, y, z])));
            }
        }
    }
    n
}

/// `block-mesh`'s greedy algorithm, written plainly over a grid of face keys: per direction and
/// slice, scan cells with x fastest, then y, then z; at each unvisited visible cell grow along
/// `u` while cells are visible, unvisited and of equal key, then along `v` while whole rows
/// are. `u` is z for ±X and ±Y faces and x for ±Z faces (its `RIGHT_HANDED_Y_UP_CONFIG`).
/// Returns the quad count per layer (opaque, transparent).
pub(crate) fn reference_greedy_count(
    padded: &PaddedChunk,
    classes: &BlockClasses,
    ao: bool,
) -> (usize, usize) {
    let (opaque, transparent) = reference_greedy_quads(padded, classes, ao);
    (opaque.len(), transparent.len())
}

/// A quad as the faces it covers: direction, lowest voxel (padded coordinates), extent along
/// x, y and z (1 along the normal), id and corner AO. Sorted lists of these compare two
/// meshes quad by quad, whatever their order and their width and height axes.
pub(crate) type QuadCells = (u8, [u32; 3], [u32; 3], u16, [u8; 4]);

/// The quads of [`reference_greedy_count`]'s algorithm per layer (opaque, transparent), sorted.
pub(crate) fn reference_greedy_quads(
    padded: &PaddedChunk,
    classes: &BlockClasses,
    ao: bool,
) -> (Vec<QuadCells>, Vec<QuadCells>) {
    let (opaque, transparent) = reference_faces(padded, classes, ao);
    (
        greedy_quads(&opaque, padded),
        greedy_quads(&transparent, padded),
    )
}

/// A mesh layer's quads as [`QuadCells`], sorted.
pub(crate) fn quad_cells(layer: &mesher::QuadLayer) -> Vec<QuadCells> {
    let mut out = Vec::new();
    for quads in &layer.faces {
        for q in quads {
            let f = q.decode().expect("every emitted quad decodes");
            let mut extent = [1; 3];
            extent[f.face.width_axis()] = f.width;
            extent[f.face.height_axis()] = f.height;
            out.push((
                f.face.index(),
                f.position.map(|a| a + 1),
                extent,
                f.block.0,
                f.ao,
            ));
        }
    }
    out.sort();
    out
}

fn greedy_quads(faces: &[UnitFace], padded: &PaddedChunk) -> Vec<QuadCells> {
    let e = padded.size().edge();
    let mut key: HashMap<([u32; 3], u8), (u16, [u8; 4])> = HashMap::new();
    for f in faces {
        key.insert((f.pos, f.face), (f.id, f.ao));
    }
    let mut quads = Vec::new();
    for face in FaceDirection::ALL {
        let d = face.index();
        let n_axis = face.normal_axis();
        let u_axis = if n_axis == 2 { 0 } else { 2 };
        let v_axis = 3 - n_axis - u_axis;
        let mut visited = HashSet::new();
        for z in 1..=e {
            for y in 1..=e {
                for x in 1..=e {
                    let start = [x, y, z];
                    let Some(&k) = key.get(&(start, d)) else {
                        continue;
                    };
                    if visited.contains(&start) {
                        continue;
                    }
                    let at = |du: u32, dv: u32| {
                        let mut p = start;
                        p[u_axis] += du;
                        p[v_axis] += dv;
                        p
                    };
                    let ok = |p: [u32; 3], visited: &HashSet<[u32; 3]>| {
                        key.get(&(p, d)) == Some(&k) && !visited.contains(&p)
                    };
                    let mut w = 1;
                    while start[u_axis] + w <= e && ok(at(w, 0), &visited) {
                        w += 1;
                    }
                    let mut h = 1;
                    while start[v_axis] + h <= e && (0..w).all(|i| ok(at(i, h), &visited)) {
                        h += 1;
                    }
                    for j in 0..h {
                        for i in 0..w {
                            visited.insert(at(i, j));
                        }
                    }
                    let mut extent = [1; 3];
                    extent[u_axis] = w;
                    extent[v_axis] = h;
                    quads.push((d, start, extent, k.0, k.1));
                }
            }
        }
    }
    quads.sort();
    quads
}

/// Chunk sizes as a proptest strategy.
pub(crate) fn sizes() -> impl proptest::strategy::Strategy<Value = ChunkSize> {
    proptest::sample::select(ChunkSize::ALL.to_vec())
}

/// Fill kinds as a proptest strategy.
pub(crate) fn fills() -> impl proptest::strategy::Strategy<Value = Fill> {
    use proptest::prelude::*;
    prop_oneof![
        (0u64..=100).prop_map(|air_percent| Fill::Noise { air_percent }),
        (1u32..40).prop_map(|count| Fill::Boxes { count }),
        Just(Fill::Terrain),
        prop_oneof![Just(0u64), 1u64..=20]
            .prop_map(|holes_percent| Fill::Checkerboard { holes_percent }),
        (2u32..=4).prop_map(|level| Fill::Menger { level }),
        Just(Fill::Foliage),
        (0usize..3).prop_map(|normal| Fill::FlatMaze { normal }),
    ]
}
