//! Closed inputs give closed meshes: with an air border, the signed volume enclosed by the
//! opaque layer (divergence theorem over the quads' `corners()`, counter-clockwise from outside)
//! equals the number of opaque voxels in the chunk, for greedy quads and for unit faces.

mod blocky_support;

use blocky_support::*;
use mesher::BlockClasses;
use mesher::blocky::{BlockyMesh, GreedyMesher};
use proptest::prelude::*;

const IDS: &[u16] = &[STONE, DIRT, WATER, GLASS, GRASS, SAND];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn opaque_mesh_encloses_the_opaque_voxels(
        size in sizes(), seed in any::<u64>(), fill in fills(), transparent in any::<bool>(), ao in any::<bool>()
    ) {
        let padded = random_chunk(size, seed, fill, IDS, true);
        let classes = BlockClasses::from_palette(&palette(transparent));
        let want = opaque_voxels(&padded, &classes);
        let mut mesher = GreedyMesher::new().with_ambient_occlusion(ao);
        let mut mesh = BlockyMesh::new();
        mesher.mesh(&padded, &classes, &mut mesh).unwrap();
        prop_assert_eq!(six_times_volume(&mesh.opaque), 6 * want);
        mesher.visible_faces(&padded, &classes, &mut mesh).unwrap();
        prop_assert_eq!(six_times_volume(&mesh.opaque), 6 * want);
    }
}

#[test]
fn a_single_voxel_is_a_unit_cube() {
    for size in voxel_core::ChunkSize::ALL {
        let e = size.edge();
        let padded = voxel_core::PaddedChunk::from_fn(size, |x, y, z| {
            voxel_core::BlockId(u16::from([x, y, z] == [e, 1, e / 2 + 1]))
        });
        let classes = BlockClasses::from_palette(&palette(false));
        let mut mesh = BlockyMesh::new();
        GreedyMesher::new()
            .mesh(&padded, &classes, &mut mesh)
            .unwrap();
        assert_eq!(mesh.opaque.counts(), [1; 6]);
        assert_eq!(six_times_volume(&mesh.opaque), 6);
        for q in mesh.opaque.iter() {
            assert_eq!(q.decode().unwrap().ao, [3; 4]);
        }
    }
}
