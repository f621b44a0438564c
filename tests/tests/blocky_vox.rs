//! The blocky meshers on the MagicaVoxel sample models (`../shared/data/vox/`), cut into chunks:
//!
//! - every chunk's greedy quads cover exactly the visible unit faces of a brute-force reference
//!   (position, direction, id and corner AO), without overlap;
//! - the whole model is closed (it sits in air), so the signed volume enclosed by the opaque
//!   quads of all its chunks together equals its opaque voxel count, for 62^3 and 16^3 chunks
//!   alike: chunk borders are seamless.

use mesher::BlockClasses;
use mesher::blocky::{BlockyMesh, GreedyMesher};
use voxel_core::{ChunkSize, PaddedChunk, gather_neighbourhood};

// The blocky meshers' brute-force reference, shared with their tests.
#[path = "../../mesher/tests/blocky_support/reference.rs"]
#[allow(
    dead_code,
    reason = "this test uses the face reference and coverage only"
)]
mod reference;
use reference::{covered, reference_faces};

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
                    let (o, t) = reference_faces(&padded, &classes, true);
                    assert_eq!(
                        covered(&mesh.opaque, size.edge()),
                        o,
                        "{}: opaque faces of {coord:?}",
                        path.display()
                    );
                    assert_eq!(
                        covered(&mesh.transparent, size.edge()),
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
