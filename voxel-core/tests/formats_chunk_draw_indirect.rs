//! `ChunkDrawIndirect`: wgpu's DrawIndexedIndirect order, then the chunk; every pattern decodes.

use proptest::prelude::*;
use voxel_core::ChunkCoord;
use voxel_core::formats::{ChunkDrawIndirect, ChunkDrawIndirectFields};

#[test]
fn byte_layout_is_draw_indexed_indirect_then_chunk() {
    let fields = ChunkDrawIndirectFields {
        index_count: 6,
        instance_count: 1,
        first_index: 12,
        base_vertex: -4,
        first_instance: 9,
        chunk: ChunkCoord::new(-1, 0, 7),
    };
    let packed = ChunkDrawIndirect::encode(&fields);
    let words: [u32; 8] = bytemuck::cast(packed);
    assert_eq!(words, [6, 1, 12, (-4i32) as u32, 9, u32::MAX, 0, 7]);
    assert_eq!(packed.decode(), fields);
}

proptest! {
    #[test]
    fn every_bit_pattern_round_trips(bytes in any::<[u8; 32]>()) {
        let packed: ChunkDrawIndirect = bytemuck::pod_read_unaligned(&bytes);
        let fields = packed.decode();
        let again = ChunkDrawIndirect::encode(&fields);
        prop_assert_eq!(again, packed);
        prop_assert_eq!(bytemuck::bytes_of(&again), &bytes[..]);
        prop_assert_eq!(again.decode(), fields);
    }
}
