//! `DrawBlock`: exact bit layout, round trips, rejected positions and flags.

use proptest::prelude::*;
use voxel_core::BlockId;
use voxel_core::formats::{DrawBlock, DrawBlockFields, DrawBlockFlags, FormatError};

fn fields() -> impl Strategy<Value = DrawBlockFields> {
    ([0u32..16, 0..16, 0..16], 0u8..16, any::<u16>()).prop_map(|(position, flags, block)| {
        DrawBlockFields {
            position,
            flags: DrawBlockFlags::from_bits(flags).unwrap(),
            block: BlockId(block),
        }
    })
}

#[test]
fn bit_layout_is_flags_then_xyz_then_block() {
    let fields = DrawBlockFields {
        position: [1, 2, 3],
        flags: DrawBlockFlags::TRANSPARENT | DrawBlockFlags::HAS_CLUTTER,
        block: BlockId(0xABCD),
    };
    let packed = DrawBlock::encode(&fields).unwrap();
    assert_eq!(packed.bits, 0xABCD_3219);
    assert_eq!(bytemuck::bytes_of(&packed), &[0x19, 0x32, 0xCD, 0xAB]);
    assert_eq!(packed.decode(), fields);

    let max = DrawBlockFields {
        position: [15, 15, 15],
        flags: DrawBlockFlags::ALL,
        block: BlockId(u16::MAX),
    };
    assert_eq!(DrawBlock::encode(&max).unwrap().bits, u32::MAX);
}

#[test]
fn positions_above_15_are_rejected_naming_the_axis() {
    for (axis, name) in [
        "DrawBlock.position.x",
        "DrawBlock.position.y",
        "DrawBlock.position.z",
    ]
    .into_iter()
    .enumerate()
    {
        let mut fields = DrawBlockFields::default();
        fields.position[axis] = 15;
        assert!(DrawBlock::encode(&fields).is_ok());
        for bad in [16, u32::MAX] {
            fields.position[axis] = bad;
            assert_eq!(
                DrawBlock::encode(&fields),
                Err(FormatError::IntegerOutOfRange {
                    field: name,
                    value: bad.into(),
                    min: 0,
                    max: 15,
                })
            );
        }
    }
}

#[test]
fn flags_accept_only_four_bits() {
    assert_eq!(DrawBlockFlags::from_bits(15), Ok(DrawBlockFlags::ALL));
    assert_eq!(
        DrawBlockFlags::from_bits(16),
        Err(FormatError::IntegerOutOfRange {
            field: "DrawBlock.flags",
            value: 16,
            min: 0,
            max: 15,
        })
    );
    let f = DrawBlockFlags::EMISSIVE | DrawBlockFlags::SMOOTH;
    assert_eq!(f.bits(), 0b0110);
    assert!(f.contains(DrawBlockFlags::SMOOTH));
    assert!(!f.contains(DrawBlockFlags::TRANSPARENT));
    assert!(!f.contains(DrawBlockFlags::EMISSIVE | DrawBlockFlags::TRANSPARENT));
}

proptest! {
    #[test]
    fn encode_then_decode_is_identity(fields in fields()) {
        prop_assert_eq!(DrawBlock::encode(&fields).unwrap().decode(), fields);
    }

    #[test]
    fn every_bit_pattern_decodes_and_re_encodes_to_itself(bytes in any::<[u8; 4]>()) {
        let packed: DrawBlock = bytemuck::pod_read_unaligned(&bytes);
        let fields = packed.decode();
        prop_assert!(fields.position.iter().all(|&a| a < 16));
        prop_assert_eq!(DrawBlock::encode(&fields), Ok(packed));
    }
}
