//! `ClutterUnit`: byte layout, settings split, quantization bounds, every bit pattern decodes.

use glam::{Vec2, Vec3};
use proptest::prelude::*;
use voxel_core::formats::{
    ClutterUnit, ClutterUnitFields, FormatError, OCT16_MAX_ERROR_DEGREES, UnormExtent, oct16_decode,
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

fn extent() -> UnormExtent {
    UnormExtent::new(34.0).unwrap()
}

fn unit_interval() -> impl Strategy<Value = f32> {
    prop_oneof![Just(0.0f32), Just(1.0), 0.0f32..=1.0]
}

fn fields() -> impl Strategy<Value = ClutterUnitFields> {
    (
        [0.0f32..=34.0, 0.0f32..=34.0, 0.0f32..=34.0],
        [-1.0f32..=1.0, -1.0f32..=1.0, -1.0f32..=1.0],
        (any::<u8>(), 0u8..16, 0u8..16),
        [unit_interval(), unit_interval()],
        [unit_interval(), unit_interval()],
        any::<[u8; 4]>(),
    )
        .prop_filter("normal too short", |(_, n, ..)| {
            Vec3::from_array(*n).length() > 1e-3
        })
        .prop_map(
            |(p, n, (kind, scale_step, seed), uv, uv_size, tint)| ClutterUnitFields {
                position: Vec3::from_array(p),
                normal: Vec3::from_array(n),
                kind,
                scale_step,
                seed,
                uv: Vec2::from_array(uv),
                uv_size: Vec2::from_array(uv_size),
                tint,
            },
        )
}

fn sample() -> ClutterUnitFields {
    ClutterUnitFields {
        position: Vec3::new(34.0, 0.0, 17.0),
        normal: Vec3::Y,
        kind: 0xAB,
        scale_step: 0x3,
        seed: 0xC,
        uv: Vec2::new(1.0, 0.0),
        uv_size: Vec2::new(1.0, 0.5),
        tint: [1, 2, 3, 4],
    }
}

#[test]
fn byte_layout_matches_the_documentation() {
    let packed = ClutterUnit::encode(&sample(), extent()).unwrap();
    assert_eq!(packed.settings, 0xC3AB);
    assert_eq!(packed.tint, 0x0403_0201);
    // +Y is octahedral code (0, 127); 0.5 in unorm8 is 128 (127.5 rounds up).
    let expected: [u8; 20] = [
        0xFF, 0xFF, 0x00, 0x00, 0x00, 0x80, 0x00, 0x7F, 0xAB, 0xC3, 0xFF, 0xFF, 0x00, 0x00, 0xFF,
        0x80, 1, 2, 3, 4,
    ];
    assert_eq!(bytemuck::bytes_of(&packed), &expected);
    let back = packed.decode(extent());
    assert_eq!((back.kind, back.scale_step, back.seed), (0xAB, 3, 0xC));
    assert_eq!(back.tint, [1, 2, 3, 4]);
    assert_eq!(back.normal, Vec3::Y);
    assert_eq!(back.position.x, 34.0);
}

#[test]
fn settings_edges_are_checked() {
    let mut f = sample();
    f.kind = u8::MAX;
    f.scale_step = 15;
    f.seed = 15;
    assert_eq!(
        ClutterUnit::encode(&f, extent()).unwrap().settings,
        u16::MAX
    );
    f.scale_step = 16;
    assert_eq!(
        ClutterUnit::encode(&f, extent()),
        Err(FormatError::IntegerOutOfRange {
            field: "ClutterUnit.scale_step",
            value: 16,
            min: 0,
            max: 15,
        })
    );
    f.scale_step = 0;
    f.seed = 16;
    assert_eq!(
        ClutterUnit::encode(&f, extent()),
        Err(FormatError::IntegerOutOfRange {
            field: "ClutterUnit.seed",
            value: 16,
            min: 0,
            max: 15,
        })
    );
}

#[test]
fn out_of_range_floats_are_rejected_naming_the_field() {
    type Mutation = fn(&mut ClutterUnitFields);
    let cases: [(Mutation, &str); 4] = [
        (|f| f.position.z = 34.5, "ClutterUnit.position"),
        (|f| f.uv.x = -0.25, "ClutterUnit.uv"),
        (|f| f.uv_size.y = 2.0, "ClutterUnit.uv_size"),
        (|f| f.uv_size.x = f32::INFINITY, "ClutterUnit.uv_size"),
    ];
    for (mutate, name) in cases {
        let mut f = sample();
        mutate(&mut f);
        assert!(
            matches!(
                ClutterUnit::encode(&f, extent()),
                Err(FormatError::QuantizeOutOfRange { field, .. }) if field == name
            ),
            "{name}"
        );
    }
    let mut f = sample();
    f.normal = Vec3::new(0.0, f32::NAN, 1.0);
    assert!(matches!(
        ClutterUnit::encode(&f, extent()),
        Err(FormatError::InvalidNormal {
            field: "ClutterUnit.normal",
            ..
        })
    ));
}

proptest! {
    #[test]
    fn decode_of_encode_is_within_the_stated_bounds(fields in fields()) {
        let back = ClutterUnit::encode(&fields, extent()).unwrap().decode(extent());
        let pos_err = (back.position - fields.position).abs().max_element();
        prop_assert!(pos_err <= extent().max_error());
        prop_assert!(angle_degrees(fields.normal, back.normal) <= f64::from(OCT16_MAX_ERROR_DEGREES));
        prop_assert_eq!(
            (back.kind, back.scale_step, back.seed, back.tint),
            (fields.kind, fields.scale_step, fields.seed, fields.tint)
        );
        prop_assert!((back.uv - fields.uv).abs().max_element() <= UnormExtent::UNIT.max_error());
        let size_err = (back.uv_size - fields.uv_size).abs().max_element();
        prop_assert!(size_err <= UnormExtent::UNIT.max_error_unorm8());
    }

    #[test]
    fn every_bit_pattern_decodes_and_re_encodes(bytes in any::<[u8; 20]>()) {
        let packed: ClutterUnit = bytemuck::pod_read_unaligned(&bytes);
        let fields = packed.decode(extent());
        prop_assert!((fields.normal.length() - 1.0).abs() <= 4.0 * f32::EPSILON);
        prop_assert!(fields.scale_step < 16 && fields.seed < 16);
        let again = ClutterUnit::encode(&fields, extent()).unwrap();
        prop_assert_eq!(again.position, packed.position);
        prop_assert_eq!(again.settings, packed.settings);
        prop_assert_eq!(again.uv, packed.uv);
        prop_assert_eq!(again.uv_size, packed.uv_size);
        prop_assert_eq!(again.tint, packed.tint);
        let (n0, n1) = (oct16_decode(packed.normal), oct16_decode(again.normal));
        prop_assert!((n0 - n1).abs().max_element() <= 2.0 * f32::EPSILON);
    }
}
