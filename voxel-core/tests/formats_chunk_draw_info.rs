//! `ChunkDrawInfo`: byte layout, -1 sentinels, rejected kinds and counts, round trips.

use proptest::prelude::*;
use voxel_core::ChunkCoord;
use voxel_core::formats::{ChunkDrawInfo, ChunkDrawInfoFields, ChunkKind, FormatError};

const I32_MAX: u32 = i32::MAX as u32;

fn sentinel() -> impl Strategy<Value = Option<u32>> {
    prop_oneof![
        Just(None),
        Just(Some(0)),
        Just(Some(I32_MAX)),
        (0..=I32_MAX).prop_map(Some)
    ]
}

fn fields() -> impl Strategy<Value = ChunkDrawInfoFields> {
    (any::<[i32; 3]>(), 0u32..3, sentinel(), sentinel()).prop_map(|(c, kind, draw, index)| {
        ChunkDrawInfoFields {
            chunk: ChunkCoord::new(c[0], c[1], c[2]),
            kind: ChunkKind::from_u32(kind).unwrap(),
            draw_count: draw,
            gigabuffer_index: index,
        }
    })
}

#[test]
fn byte_layout_and_sentinels() {
    let fields = ChunkDrawInfoFields {
        chunk: ChunkCoord::new(-1, 2, i32::MIN),
        kind: ChunkKind::Sprite,
        draw_count: None,
        gigabuffer_index: Some(5),
    };
    let packed = ChunkDrawInfo::encode(&fields).unwrap();
    assert_eq!(
        packed,
        ChunkDrawInfo {
            chunk: [-1, 2, i32::MIN],
            kind: 2,
            draw_count: -1,
            gigabuffer_index: 5,
        }
    );
    let words: [u32; 6] = bytemuck::cast(packed);
    assert_eq!(words, [u32::MAX, 2, 0x8000_0000, 2, u32::MAX, 5]);
    assert_eq!(packed.decode(), Ok(fields));
}

#[test]
fn counts_above_i32_max_are_rejected() {
    let mut f = ChunkDrawInfoFields {
        draw_count: Some(I32_MAX),
        gigabuffer_index: Some(I32_MAX),
        ..Default::default()
    };
    assert!(ChunkDrawInfo::encode(&f).is_ok());
    f.draw_count = Some(I32_MAX + 1);
    assert_eq!(
        ChunkDrawInfo::encode(&f),
        Err(FormatError::IntegerOutOfRange {
            field: "ChunkDrawInfo.draw_count",
            value: i64::from(I32_MAX) + 1,
            min: 0,
            max: i32::MAX.into(),
        })
    );
    f.draw_count = None;
    f.gigabuffer_index = Some(u32::MAX);
    assert_eq!(
        ChunkDrawInfo::encode(&f),
        Err(FormatError::IntegerOutOfRange {
            field: "ChunkDrawInfo.gigabuffer_index",
            value: u32::MAX.into(),
            min: 0,
            max: i32::MAX.into(),
        })
    );
}

#[test]
fn invalid_kinds_and_sentinels_are_decode_errors() {
    let valid = ChunkDrawInfo::encode(&ChunkDrawInfoFields::default()).unwrap();
    for kind in ChunkKind::ALL {
        let p = ChunkDrawInfo {
            kind: kind as u32,
            ..valid
        };
        assert_eq!(p.decode().unwrap().kind, kind);
    }
    for kind in [3, u32::MAX] {
        let p = ChunkDrawInfo { kind, ..valid };
        assert_eq!(
            p.decode(),
            Err(FormatError::InvalidChunkKind { value: kind })
        );
    }
    for bad in [-2, i32::MIN] {
        let p = ChunkDrawInfo {
            draw_count: bad,
            ..valid
        };
        assert_eq!(
            p.decode(),
            Err(FormatError::IntegerOutOfRange {
                field: "ChunkDrawInfo.draw_count",
                value: bad.into(),
                min: -1,
                max: i32::MAX.into(),
            })
        );
        let p = ChunkDrawInfo {
            gigabuffer_index: bad,
            ..valid
        };
        assert!(matches!(
            p.decode(),
            Err(FormatError::IntegerOutOfRange {
                field: "ChunkDrawInfo.gigabuffer_index",
                ..
            })
        ));
    }
}

proptest! {
    #[test]
    fn encode_then_decode_is_identity(fields in fields()) {
        prop_assert_eq!(ChunkDrawInfo::encode(&fields).unwrap().decode(), Ok(fields));
    }

    #[test]
    fn decodable_bits_re_encode_to_themselves(
        bytes in any::<[u8; 24]>(),
        kind in prop_oneof![0u32..3, any::<u32>()],
        draw_count in prop_oneof![-1i32..=1, any::<i32>()],
        gigabuffer_index in prop_oneof![-1i32..=1, any::<i32>()],
        use_raw_bytes: bool,
    ) {
        let mut packed: ChunkDrawInfo = bytemuck::pod_read_unaligned(&bytes);
        if !use_raw_bytes {
            packed.kind = kind;
            packed.draw_count = draw_count;
            packed.gigabuffer_index = gigabuffer_index;
        }
        match packed.decode() {
            Ok(fields) => prop_assert_eq!(ChunkDrawInfo::encode(&fields), Ok(packed)),
            Err(FormatError::InvalidChunkKind { value }) => prop_assert!(value >= 3),
            Err(FormatError::IntegerOutOfRange { value, .. }) => prop_assert!(value < -1),
            Err(other) => prop_assert!(false, "unexpected error {other:?}"),
        }
    }
}
