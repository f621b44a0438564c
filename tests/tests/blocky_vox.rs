//! The blocky meshers on the MagicaVoxel sample models (`../shared/data/vox/`), cut into chunks:
//!
//! - every chunk's greedy quads cover exactly the visible unit faces of a brute-force reference
//!   (position, direction, id and corner AO), without overlap;
//! - the whole model is closed (it sits in air), so the signed volume enclosed by the opaque
//!   quads of all its chunks together equals its opaque voxel count, for 62^3 and 16^3 chunks
//!   alike: chunk borders are seamless.

use std::collections::HashSet;

use mesher::BlockClasses;
use mesher::blocky::{BlockyMesh, GreedyMesher};
use voxel_core::formats::PackedQuadFields;
use voxel_core::{BlockId, ChunkSize, FaceDirection, PaddedChunk, gather_neighbourhood};

type Face = ([u32; 3], u8, u16, [u8; 4]);

fn get(padded: &PaddedChunk, q: [i64; 3]) -> u16 {
    let p = padded.padded_edge() as i64;
    if q.iter().any(|&a| a < 0 || a >= p) {
        return 0;
    }
    padded.get(q[0] as u32, q[1] as u32, q[2] as u32).unwrap().0
}

/// Visible unit faces of the chunk interior by brute force: (opaque, transparent).
fn reference(padded: &PaddedChunk, classes: &BlockClasses) -> (HashSet<Face>, HashSet<Face>) {
    let solid = |id: u16| id != 0 && !classes.is_transparent(BlockId(id));
    let e = padded.size().edge() as i64;
    let (mut opaque, mut transparent) = (HashSet::new(), HashSet::new());
    for z in 1..=e {
        for y in 1..=e {
            for x in 1..=e {
                let id = get(padded, [x, y, z]);
                if id == 0 {
                    continue;
                }
                let see_through = classes.is_transparent(BlockId(id));
                for face in FaceDirection::ALL {
                    let n = face.normal().map(i64::from);
                    let front = [x + n[0], y + n[1], z + n[2]];
                    let nb = get(padded, front);
                    let visible = if see_through {
                        nb == 0 || (classes.is_transparent(BlockId(nb)) && nb != id)
                    } else {
                        !solid(nb)
                    };
                    if !visible {
                        continue;
                    }
                    let swap = matches!(
                        face,
                        FaceDirection::PosX | FaceDirection::PosY | FaceDirection::NegZ
                    );
                    let ao = [(0i64, 0i64), (1, 0), (1, 1), (0, 1)].map(|(a, b)| {
                        let (du, dv) = if swap { (b, a) } else { (a, b) };
                        let mut w = front;
                        w[face.width_axis()] += 2 * du - 1;
                        let mut h = front;
                        h[face.height_axis()] += 2 * dv - 1;
                        let mut c = w;
                        c[face.height_axis()] += 2 * dv - 1;
                        let (s1, s2, c) = (
                            solid(get(padded, w)),
                            solid(get(padded, h)),
                            solid(get(padded, c)),
                        );
                        if s1 && s2 {
                            0
                        } else {
                            3 - (u8::from(s1) + u8::from(s2) + u8::from(c))
                        }
                    });
                    let f = ([x as u32, y as u32, z as u32], face.index(), id, ao);
                    if see_through {
                        transparent.insert(f);
                    } else {
                        opaque.insert(f);
                    }
                }
            }
        }
    }
    (opaque, transparent)
}

/// Unit faces covered by a layer's quads, failing on overlap.
fn covered(layer: &mesher::QuadLayer) -> HashSet<Face> {
    let mut out = HashSet::new();
    for q in layer.iter() {
        let f: PackedQuadFields = q.decode().unwrap();
        for j in 0..f.height {
            for i in 0..f.width {
                let mut pos = f.position.map(|a| a + 1);
                pos[f.face.width_axis()] += i;
                pos[f.face.height_axis()] += j;
                assert!(
                    out.insert((pos, f.face.index(), f.block.0, f.ao)),
                    "overlap at {pos:?}"
                );
            }
        }
    }
    out
}

/// Six times the signed volume enclosed by a layer (divergence theorem over the corners of each
/// quad's two counter-clockwise triangles), in world units relative to the chunk origin.
fn six_volume(layer: &mesher::QuadLayer, origin: [i64; 3]) -> i64 {
    let mut six_v = 0;
    for q in layer.iter() {
        let c = q
            .decode()
            .unwrap()
            .corners()
            .map(|c| [0, 1, 2].map(|a| i64::from(c[a]) + origin[a]));
        for [a, b, d] in [[c[0], c[1], c[2]], [c[0], c[2], c[3]]] {
            six_v += a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0])
                + a[2] * (b[0] * d[1] - b[1] * d[0]);
        }
    }
    six_v
}

#[test]
fn sample_models_mesh_to_exactly_their_visible_faces_and_close() {
    let files = tests::sample_vox_files();
    for path in &files {
        for size in [ChunkSize::S62, ChunkSize::S16] {
            let scene = viewer::scene::vox::load_vox_file(path, size, 1 << 24)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let classes = BlockClasses::from_palette(&scene.palette);
            let mut mesher = GreedyMesher::new();
            let mut mesh = BlockyMesh::new();
            let mut padded = PaddedChunk::new(size);
            let mut six_v = 0i64;
            let mut opaque_voxels = 0i64;
            let mut quads = 0;
            let e = i64::from(size.edge());
            for (coord, chunk) in scene.world.iter() {
                gather_neighbourhood(&scene.world, coord, &mut padded);
                mesher.mesh(&padded, &classes, &mut mesh).unwrap();
                quads += mesh.len();
                let origin = [coord.x, coord.y, coord.z].map(|c| i64::from(c) * e);
                six_v += six_volume(&mesh.opaque, origin);
                use voxel_core::storage::VoxelStorage;
                opaque_voxels += chunk
                    .iter()
                    .filter(|(_, id)| !id.is_air() && !classes.is_transparent(*id))
                    .count() as i64;
                // The brute-force reference is slow: check every chunk at 62^3 only.
                if size == ChunkSize::S62 {
                    let (o, t) = reference(&padded, &classes);
                    assert_eq!(
                        covered(&mesh.opaque),
                        o,
                        "{}: opaque faces of {coord:?}",
                        path.display()
                    );
                    assert_eq!(
                        covered(&mesh.transparent),
                        t,
                        "{}: transparent faces of {coord:?}",
                        path.display()
                    );
                }
            }
            assert_eq!(
                six_v,
                6 * opaque_voxels,
                "{} at {size:?}: not closed",
                path.display()
            );
            eprintln!(
                "{}: {} chunks of {}^3, {opaque_voxels} opaque voxels, {quads} quads",
                path.file_name().unwrap().to_string_lossy(),
                scene.world.len(),
                size.edge()
            );
        }
    }
}
