//! Unorm quantization: the stated error bound, exact ends, code round trips, rejected input.

use glam::{Vec2, Vec3};
use proptest::prelude::*;
use voxel_core::ChunkSize;
use voxel_core::formats::FormatError;
use voxel_core::formats::UnormExtent;
use voxel_core::formats::quantize::{
    UNORM8_STEP, UNORM16_STEP, unorm8_decode, unorm8_encode, unorm16_decode, unorm16_encode,
    unorm16x2_decode, unorm16x2_encode, unorm16x3_decode, unorm16x3_encode,
};

fn extent(e: f32) -> UnormExtent {
    UnormExtent::new(e).unwrap()
}

/// `|decode(encode(v)) - v|`, in f64 so the check itself does not round.
fn unorm16_error(v: f32, e: UnormExtent) -> f64 {
    let code = unorm16_encode(v, e).unwrap();
    (f64::from(unorm16_decode(code, e)) - f64::from(v)).abs()
}

#[test]
fn stated_bound_is_half_a_step_plus_two_epsilons() {
    let e = extent(64.0);
    let expected = 64.0 * (0.5 / 65535.0 + 2.0 * f64::from(f32::EPSILON));
    assert!((f64::from(e.max_error()) - expected).abs() < 1e-12);
    // Half a step of a padded 62^3 chunk is about 0.0005 voxels.
    assert!(e.max_error() < 0.00051 && e.max_error() > 0.00048);
    assert_eq!(UnormExtent::padded_chunk(ChunkSize::S62).get(), 64.0);
    assert_eq!(UnormExtent::padded_chunk(ChunkSize::S8).get(), 10.0);
}

#[test]
fn padded_lattice_codes_integers_exactly() {
    let scales = [
        (ChunkSize::S8, 4096u32),
        (ChunkSize::S16, 2048),
        (ChunkSize::S32, 1024),
        (ChunkSize::S62, 1024),
    ];
    assert_eq!(ChunkSize::ALL.len(), scales.len());
    for (size, scale) in scales {
        let e = UnormExtent::padded_lattice(size);
        assert_eq!(e.get(), 65535.0 / scale as f32, "{size:?}");
        let p = size.padded_edge() as f32;
        // Covers every position up to p - 1/2, and the next power of two would not.
        assert!(e.get() >= p - 0.5 && 65535.0 / ((2 * scale) as f32) < p - 0.5);
        for x in 0..size.padded_edge() as u32 {
            let code = unorm16_encode(x as f32, e).unwrap();
            assert_eq!(u32::from(code), x * scale, "{size:?} {x}");
            // Decoded within 4 f32 steps of 64 (about 3e-5 voxels).
            let back = unorm16_decode(code, e);
            assert!(
                (back - x as f32).abs() <= 4.0 * 64.0 * f32::EPSILON,
                "{x}: {back}"
            );
        }
    }
}

#[test]
fn every_code_round_trips_and_the_ends_are_exact() {
    for e in [
        1.0f32,
        3.7,
        10.0,
        34.0,
        64.0,
        1000.0,
        1e-30,
        3e38,
        f32::MIN_POSITIVE,
    ] {
        let e = extent(e);
        assert_eq!(unorm16_decode(0, e), 0.0);
        assert_eq!(unorm16_decode(u16::MAX, e), e.get(), "extent {}", e.get());
        assert_eq!(unorm16_encode(e.get(), e), Ok(u16::MAX));
        assert_eq!(unorm16_encode(0.0, e), Ok(0));
        let mut previous = -1.0f32;
        for code in 0..=u16::MAX {
            let v = unorm16_decode(code, e);
            assert!(v > previous, "decode must be strictly increasing");
            previous = v;
            assert_eq!(unorm16_encode(v, e), Ok(code), "extent {}", e.get());
        }
    }
    for code in 0..=u8::MAX {
        assert_eq!(unorm8_encode(unorm8_decode(code)), Ok(code));
    }
    assert_eq!(unorm8_decode(255), 1.0);
    assert_eq!(65535.0 * UNORM16_STEP, 1.0);
    assert_eq!(255.0 * UNORM8_STEP, 1.0);
}

#[test]
fn rounding_is_to_the_nearest_code() {
    let e = extent(65535.0);
    // With extent 65535 a code is one unit: 2.49 -> 2, 2.5 -> 3 (ties up), 2.51 -> 3.
    assert_eq!(unorm16_encode(2.49, e), Ok(2));
    assert_eq!(unorm16_encode(2.5, e), Ok(3));
    assert_eq!(unorm16_encode(2.51, e), Ok(3));
    assert_eq!(unorm16_encode(65534.6, e), Ok(65535));
    assert_eq!(unorm8_encode(0.5), Ok(128));
    assert_eq!(unorm8_encode(0.4990), Ok(127));
}

#[test]
fn out_of_range_values_are_rejected_with_value_and_extent() {
    let e = extent(64.0);
    let above = f32::from_bits(64f32.to_bits() + 1);
    for bad in [
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        -1e-30,
        -1.0,
        above,
        1e9,
    ] {
        match unorm16_encode(bad, e) {
            Err(FormatError::QuantizeOutOfRange {
                field: "unorm16",
                value,
                extent,
            }) => {
                assert_eq!(value.to_bits(), bad.to_bits());
                assert_eq!(extent, 64.0);
            }
            other => panic!("{bad}: {other:?}"),
        }
    }
    assert_eq!(unorm16_encode(-0.0, e), Ok(0));
    assert!(matches!(
        unorm8_encode(1.0001),
        Err(FormatError::QuantizeOutOfRange {
            field: "unorm8",
            extent: 1.0,
            ..
        })
    ));
    assert!(matches!(
        unorm16x3_encode(Vec3::new(1.0, 65.0, f32::NAN), e),
        Err(FormatError::QuantizeOutOfRange { value: 65.0, .. })
    ));
    assert!(matches!(
        unorm16x2_encode(Vec2::new(0.5, -0.5)),
        Err(FormatError::QuantizeOutOfRange { value: -0.5, .. })
    ));
}

#[test]
fn invalid_extents_are_rejected() {
    for bad in [
        0.0f32,
        -0.0,
        -1.0,
        f32::NAN,
        f32::INFINITY,
        f32::MIN_POSITIVE / 2.0,
    ] {
        assert!(
            matches!(
                UnormExtent::new(bad),
                Err(FormatError::InvalidFloat { field: "extent", value, .. })
                    if value.to_bits() == bad.to_bits()
            ),
            "{bad}"
        );
    }
}

/// Extents from tiny to huge, weighted toward chunk-sized ones.
fn any_extent() -> impl Strategy<Value = UnormExtent> {
    prop_oneof![
        1.0f32..=128.0,
        f32::MIN_POSITIVE..=1.0,
        1.0f32..=f32::MAX,
        Just(64.0),
        Just(1.0),
    ]
    .prop_map(extent)
}

/// A value in `0..=extent`, with the two ends and their neighbours drawn often.
fn value_in(e: UnormExtent) -> impl Strategy<Value = f32> {
    let max = e.get();
    prop_oneof![
        Just(0.0),
        Just(max),
        Just(f32::from_bits(max.to_bits() - 1)),
        Just(f32::from_bits(1)),
        0.0f32..=max,
    ]
}

proptest! {
    #[test]
    fn unorm16_error_is_within_the_stated_bound(
        (e, v) in any_extent().prop_flat_map(|e| (Just(e), value_in(e)))
    ) {
        let err = unorm16_error(v, e);
        prop_assert!(
            err <= f64::from(e.max_error()),
            "extent {}, value {v}: error {err} > bound {}", e.get(), e.max_error()
        );
    }

    #[test]
    fn unorm8_error_is_within_the_stated_bound(v in value_in(UnormExtent::UNIT)) {
        let err = (f64::from(unorm8_decode(unorm8_encode(v).unwrap())) - f64::from(v)).abs();
        prop_assert!(err <= f64::from(UnormExtent::UNIT.max_error_unorm8()), "{v}: {err}");
    }

    #[test]
    fn vector_helpers_quantize_each_axis(
        (e, x, y, z) in any_extent().prop_flat_map(|e| (Just(e), value_in(e), value_in(e), value_in(e))),
        u in value_in(UnormExtent::UNIT),
        w in value_in(UnormExtent::UNIT),
    ) {
        let p = Vec3::new(x, y, z);
        let codes = unorm16x3_encode(p, e).unwrap();
        prop_assert_eq!(
            codes,
            [unorm16_encode(x, e).unwrap(), unorm16_encode(y, e).unwrap(), unorm16_encode(z, e).unwrap()]
        );
        let back = unorm16x3_decode(codes, e);
        for axis in 0..3 {
            let err = (f64::from(back[axis]) - f64::from(p[axis])).abs();
            prop_assert!(err <= f64::from(e.max_error()));
        }
        let uv = Vec2::new(u, w);
        let back = unorm16x2_decode(unorm16x2_encode(uv).unwrap());
        prop_assert!((back - uv).abs().max_element() <= UnormExtent::UNIT.max_error());
    }
}
