//! Greedy quad counts: exactly those of `block-mesh`'s greedy algorithm (written plainly in the
//! support module, with the same scan and growth order) on face keys of id alone when AO is
//! off, and of id plus corner AO when it is on. The tests crate compares against the real
//! `block-mesh` crate.

mod blocky_support;

use blocky_support::*;
use mesher::BlockClasses;
use mesher::blocky::{BlockyMesh, GreedyMesher};
use proptest::prelude::*;

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
}
