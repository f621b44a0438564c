//! `BlockVertex`: byte layout, quantization within the stated bounds, every bit pattern decodes.

use glam::{Vec2, Vec3};
use proptest::prelude::*;
use voxel_core::BlockId;
use voxel_core::formats::{
    BlockVertex, BlockVertexFields, FormatError, OCT16_MAX_ERROR_DEGREES, UnormExtent, oct16_decode,
};

/// Angle between two vectors in degrees, computed in f64 with `atan2(|a x b|, a . b)`.
fn angle_degrees(a: Vec3, b: Vec3) -> f64 {
    let a = a.to_array().map(f64::from);
    let b = b.to_array().map(f64::from);
    let cross = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let sin = (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt();
    sin.atan2(a[0] * b[0] + a[1] * b[1] + a[2] * b[2])
        .to_degrees()
}

fn any_extent() -> impl Strategy<Value = UnormExtent> {
    prop_oneof![Just(10.0f32), Just(34.0), Just(64.0), 1.0f32..1000.0]
        .prop_map(|e| UnormExtent::new(e).unwrap())
}

fn unit_interval() -> impl Strategy<Value = f32> {
    prop_oneof![Just(0.0f32), Just(1.0), 0.0f32..=1.0]
}

fn fields(extent: UnormExtent) -> impl Strategy<Value = BlockVertexFields> {
    let e = extent.get();
    (
        [0.0f32..=e, 0.0f32..=e, 0.0f32..=e],
        [-1.0f32..=1.0, -1.0f32..=1.0, -1.0f32..=1.0],
        [unit_interval(), unit_interval()],
        any::<u16>(),
        any::<u16>(),
    )
        .prop_filter("normal too short", |(_, n, ..)| {
            Vec3::from_array(*n).length() > 1e-3
        })
        .prop_map(|(p, n, uv, block, extra)| BlockVertexFields {
            position: Vec3::from_array(p),
            normal: Vec3::from_array(n),
            uv: Vec2::from_array(uv),
            block: BlockId(block),
            extra,
        })
}

#[test]
fn byte_layout_matches_the_documentation() {
    let extent = UnormExtent::new(64.0).unwrap();
    let fields = BlockVertexFields {
        position: Vec3::new(0.0, 64.0, 32.0),
        normal: Vec3::X,
        uv: Vec2::new(0.0, 1.0),
        block: BlockId(7),
        extra: 0xBEEF,
    };
    let packed = BlockVertex::encode(&fields, extent).unwrap();
    // 32 / 64 * 65535 = 32767.5 rounds up to 32768 = 0x8000; +X is octahedral code (127, 0).
    let expected: [u8; 16] = [
        0x00, 0x00, 0xFF, 0xFF, 0x00, 0x80, 0x7F, 0x00, 0x00, 0x00, 0xFF, 0xFF, 0x07, 0x00, 0xEF,
        0xBE,
    ];
    assert_eq!(bytemuck::bytes_of(&packed), &expected);
    let back = packed.decode(extent);
    assert_eq!(back.position.x, 0.0);
    assert_eq!(back.position.y, 64.0);
    assert_eq!(back.normal, Vec3::X);
    assert_eq!(back.uv, Vec2::new(0.0, 1.0));
    assert_eq!((back.block, back.extra), (BlockId(7), 0xBEEF));
}

#[test]
fn out_of_range_fields_are_rejected_naming_the_field() {
    let extent = UnormExtent::new(64.0).unwrap();
    let good = BlockVertexFields {
        position: Vec3::splat(64.0),
        normal: Vec3::Y,
        uv: Vec2::ONE,
        block: BlockId(1),
        extra: 0,
    };
    assert!(BlockVertex::encode(&good, extent).is_ok());

    let above = f32::from_bits(64f32.to_bits() + 1);
    let bad = BlockVertexFields {
        position: Vec3::new(1.0, above, 1.0),
        ..good
    };
    assert_eq!(
        BlockVertex::encode(&bad, extent),
        Err(FormatError::QuantizeOutOfRange {
            field: "BlockVertex.position",
            value: above,
            extent: 64.0,
        })
    );
    let bad = BlockVertexFields {
        normal: Vec3::ZERO,
        ..good
    };
    assert_eq!(
        BlockVertex::encode(&bad, extent),
        Err(FormatError::InvalidNormal {
            field: "BlockVertex.normal",
            value: [0.0; 3],
        })
    );
    let bad = BlockVertexFields {
        uv: Vec2::new(0.5, 1.5),
        ..good
    };
    assert_eq!(
        BlockVertex::encode(&bad, extent),
        Err(FormatError::QuantizeOutOfRange {
            field: "BlockVertex.uv",
            value: 1.5,
            extent: 1.0,
        })
    );
    let bad = BlockVertexFields {
        position: Vec3::new(f32::NAN, 0.0, 0.0),
        ..good
    };
    assert!(matches!(
        BlockVertex::encode(&bad, extent),
        Err(FormatError::QuantizeOutOfRange { field: "BlockVertex.position", value, .. })
            if value.is_nan()
    ));
}

proptest! {
    #[test]
    fn decode_of_encode_is_within_the_stated_bounds(
        (extent, fields) in any_extent().prop_flat_map(|e| (Just(e), fields(e)))
    ) {
        let back = BlockVertex::encode(&fields, extent).unwrap().decode(extent);
        for axis in 0..3 {
            let err = (f64::from(back.position[axis]) - f64::from(fields.position[axis])).abs();
            prop_assert!(err <= f64::from(extent.max_error()), "axis {axis}: {err}");
        }
        let angle = angle_degrees(fields.normal, back.normal);
        prop_assert!(angle <= f64::from(OCT16_MAX_ERROR_DEGREES), "normal off by {angle}");
        prop_assert!((back.uv - fields.uv).abs().max_element() <= UnormExtent::UNIT.max_error());
        prop_assert_eq!(back.block, fields.block);
        prop_assert_eq!(back.extra, fields.extra);
    }

    #[test]
    fn every_bit_pattern_decodes_and_re_encodes(bytes in any::<[u8; 16]>(), extent in any_extent()) {
        let packed: BlockVertex = bytemuck::pod_read_unaligned(&bytes);
        let fields = packed.decode(extent);
        prop_assert!((fields.normal.length() - 1.0).abs() <= 4.0 * f32::EPSILON);
        prop_assert!(fields.position.min_element() >= 0.0);
        prop_assert!(fields.position.max_element() <= extent.get());
        prop_assert!(fields.uv.min_element() >= 0.0 && fields.uv.max_element() <= 1.0);
        let again = BlockVertex::encode(&fields, extent).unwrap();
        // Lossless fields re-encode bit for bit; the normal code may become its folded twin,
        // which decodes to the same direction.
        prop_assert_eq!(again.position, packed.position);
        prop_assert_eq!(again.uv, packed.uv);
        prop_assert_eq!((again.block, again.extra), (packed.block, packed.extra));
        let (n0, n1) = (oct16_decode(packed.normal), oct16_decode(again.normal));
        prop_assert!((n0 - n1).abs().max_element() <= 2.0 * f32::EPSILON);
    }
}
