//! Greedy quads: exactly those of `block-mesh`'s greedy algorithm (written plainly in the
//! support module, with the same scan and growth order) on face keys of id alone when AO is
//! off, and of id plus corner AO when it is on: the same count at every size, and the same
//! quads, face for face, at 8^3 and 16^3, where the reference is quick enough to run on many
//! chunks. The tests crate compares against the real `block-mesh` crate.

mod blocky_support;

use blocky_support::*;
use mesher::BlockClasses;
use mesher::blocky::{BlockyMesh, GreedyMesher};
use proptest::prelude::*;
use voxel_core::ChunkSize;

const IDS: &[u16] = &[STONE, DIRT, WATER, GLASS, GRASS];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(40))]

    #[test]
    fn greedy_counts_equal_the_reference_greedy(
        size in sizes(), seed in any::<u64>(), fill in fills(), transparent in any::<bool>(), ao in any::<bool>()
    ) {
        let padded = random_chunk(size, seed, fill, IDS, false);
        let classes = BlockClasses::from_palette(&palette(transparent));
        let mut mesh = BlockyMesh::new();
        GreedyMesher::new().with_ambient_occlusion(ao).mesh(&padded, &classes, &mut mesh).unwrap();
        let (o, t) = reference_greedy_count(&padded, &classes, ao);
        prop_assert_eq!((mesh.opaque.len(), mesh.transparent.len()), (o, t));
    }

    #[test]
    fn small_chunks_have_the_reference_greedy_s_quads(
        small in any::<bool>(), seed in any::<u64>(), fill in fills(), transparent in any::<bool>(), ao in any::<bool>()
    ) {
        let size = if small { ChunkSize::S8 } else { ChunkSize::S16 };
        let padded = random_chunk(size, seed, fill, IDS, false);
        let classes = BlockClasses::from_palette(&palette(transparent));
        let mut mesh = BlockyMesh::new();
        GreedyMesher::new().with_ambient_occlusion(ao).mesh(&padded, &classes, &mut mesh).unwrap();
        let (o, t) = reference_greedy_quads(&padded, &classes, ao);
        prop_assert_eq!(quad_cells(&mesh.opaque), o);
        prop_assert_eq!(quad_cells(&mesh.transparent), t);
    }
}
