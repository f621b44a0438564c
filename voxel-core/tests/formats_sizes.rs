//! Sizes and alignments of the packed formats, and what an all-zero buffer decodes to.

use std::mem::{align_of, size_of};

use bytemuck::Zeroable;
use voxel_core::formats::{
    BlockVertex, ChunkDrawIndirect, ChunkDrawInfo, ChunkKind, ClutterUnit, DrawBlock,
    DrawBlockFlags, FaceDirection, FaceLayerRange, LayerRange, MeshedChunkInfo, PackedQuad,
    UnormExtent,
};
use voxel_core::{BlockId, ChunkCoord};

#[test]
fn sizes_are_the_documented_ones() {
    assert_eq!(size_of::<DrawBlock>(), 4);
    assert_eq!(size_of::<PackedQuad>(), 8);
    assert_eq!(size_of::<BlockVertex>(), 16);
    assert_eq!(size_of::<ClutterUnit>(), 20);
    assert_eq!(size_of::<ChunkDrawInfo>(), 24);
    assert_eq!(size_of::<MeshedChunkInfo>(), 112);
    assert_eq!(size_of::<ChunkDrawIndirect>(), 32);
    assert_eq!(size_of::<FaceLayerRange>(), 28);
    assert_eq!(size_of::<LayerRange>(), 8);
}

#[test]
fn alignments_allow_tight_arrays() {
    // A slice of each format is exactly `len * size` bytes, as the GPU arrays read it.
    assert_eq!(align_of::<DrawBlock>(), 4);
    assert_eq!(align_of::<PackedQuad>(), 4);
    assert_eq!(align_of::<BlockVertex>(), 2);
    assert_eq!(align_of::<ClutterUnit>(), 4);
    assert_eq!(align_of::<ChunkDrawInfo>(), 4);
    assert_eq!(align_of::<MeshedChunkInfo>(), 4);
    assert_eq!(align_of::<ChunkDrawIndirect>(), 4);
    let quads = [PackedQuad::zeroed(); 3];
    assert_eq!(bytemuck::cast_slice::<PackedQuad, u8>(&quads).len(), 24);
    let units = [ClutterUnit::zeroed(); 3];
    assert_eq!(bytemuck::cast_slice::<ClutterUnit, u32>(&units).len(), 15);
}

#[test]
fn zeroed_buffers_decode_to_the_documented_defaults() {
    let block = DrawBlock::zeroed().decode();
    assert_eq!(block.position, [0; 3]);
    assert_eq!(block.flags, DrawBlockFlags::EMPTY);
    assert_eq!(block.block, BlockId::AIR);

    let quad = PackedQuad::zeroed().decode().unwrap();
    assert_eq!((quad.width, quad.height), (1, 1));
    assert_eq!(quad.face, FaceDirection::PosX);
    assert_eq!(quad.ao, [0; 4]);

    let vertex = BlockVertex::zeroed().decode(UnormExtent::UNIT);
    assert_eq!(vertex.normal, glam::Vec3::Z);

    let info = ChunkDrawInfo::zeroed().decode().unwrap();
    assert_eq!(info.kind, ChunkKind::Empty);
    assert_eq!(info.draw_count, Some(0));
    assert_eq!(info.gigabuffer_index, Some(0));

    let meshed = MeshedChunkInfo::zeroed().decode().unwrap();
    assert_eq!(meshed.chunk, ChunkCoord::new(0, 0, 0));
    assert_eq!(meshed.opaque_quads.total(), 0);

    assert_eq!(ChunkDrawIndirect::zeroed().decode().instance_count, 0);
}
