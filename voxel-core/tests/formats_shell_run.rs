//! `ShellRun`: exact byte layout, round trips, named errors for bad runs, and box corners that
//! are the greedy quads' corners of the same sides.

use proptest::prelude::*;
use voxel_core::BlockId;
use voxel_core::formats::{FaceDirection, FormatError, PackedQuadFields, ShellRun, ShellRunFields};

fn fields() -> impl Strategy<Value = ShellRunFields> {
    ([0u32..64, 0..64, 0..64], any::<u16>(), 1u8..64, 0u8..16).prop_flat_map(
        |(position, block, sides, feet)| {
            (1..=64 - position[1], 1..=64 - position[0]).prop_map(move |(height, width)| {
                ShellRunFields {
                    position,
                    height,
                    width,
                    block: BlockId(block),
                    sides,
                    feet,
                }
            })
        },
    )
}

fn sample() -> ShellRunFields {
    ShellRunFields {
        position: [1, 3, 2],
        height: 5,
        width: 1,
        block: BlockId(0xBEEF),
        sides: 0b10_0101,
        feet: 0,
    }
}

proptest! {
    #[test]
    fn valid_fields_round_trip(f in fields()) {
        let run = ShellRun::encode(&f).unwrap();
        prop_assert_eq!(run.decode().unwrap(), f);
        prop_assert_eq!(run.width(), f.width);
        prop_assert_eq!(run.feet(), f.feet);
        prop_assert_eq!(run.side_mask(), f.sides);
    }

    #[test]
    fn any_bytes_decode_without_panicking_and_re_encode_to_themselves(bytes in any::<[u8; 8]>()) {
        let run: ShellRun = bytemuck::cast(bytes);
        if let Ok(f) = run.decode() {
            prop_assert_eq!(ShellRun::encode(&f).unwrap(), run);
        }
    }
}

#[test]
fn the_bytes_are_the_documented_ones() {
    let run = ShellRun::encode(&sample()).unwrap();
    let words: [u32; 2] = bytemuck::cast(run);
    assert_eq!(words[0], 1 | 2 << 8 | 3 << 16 | 5 << 24);
    assert_eq!(words[1], 0xBEEF | 0b10_0101 << 16);
    assert_eq!(run, ShellRun::new(1, 2, 3, 5, 0xBEEF, 0b10_0101));
}

#[test]
fn bad_runs_are_named_errors() {
    let out_of_range = |field, value, min, max| FormatError::IntegerOutOfRange {
        field,
        value,
        min,
        max,
    };
    let with = |edit: fn(&mut ShellRunFields)| {
        let mut f = sample();
        edit(&mut f);
        ShellRun::encode(&f).unwrap_err()
    };
    assert_eq!(
        with(|f| f.height = 0),
        out_of_range("ShellRun.height", 0, 1, 61)
    );
    assert_eq!(
        with(|f| f.position = [0, 60, 0]),
        out_of_range("ShellRun.height", 5, 1, 4)
    );
    assert_eq!(
        with(|f| f.position[0] = 64),
        out_of_range("ShellRun.x", 64, 0, 63)
    );
    assert_eq!(
        with(|f| f.position[2] = 200),
        out_of_range("ShellRun.z", 200, 0, 63)
    );
    assert_eq!(
        with(|f| f.sides = 0),
        out_of_range("ShellRun.sides", 0, 1, 63)
    );
    assert_eq!(
        with(|f| f.sides = 64),
        out_of_range("ShellRun.sides", 64, 1, 63)
    );
    assert_eq!(
        with(|f| f.width = 0),
        out_of_range("ShellRun.width", 0, 1, 63)
    );
    assert_eq!(
        with(|f| f.width = 64),
        out_of_range("ShellRun.width", 64, 1, 63)
    );
    // The same checks on decode.
    let zero_height = ShellRun::new(0, 0, 0, 0, 1, 1);
    assert_eq!(
        zero_height.decode(),
        Err(out_of_range("ShellRun.height", 0, 1, 64))
    );
    let past_the_chunk = ShellRun::new(0, 0, 63, 2, 1, 1);
    assert_eq!(
        past_the_chunk.decode(),
        Err(out_of_range("ShellRun.height", 2, 1, 1))
    );
    let too_far = ShellRun::new(255, 0, 0, 1, 1, 1);
    assert_eq!(
        too_far.decode(),
        Err(out_of_range("ShellRun.x", 255, 0, 63))
    );
    let too_wide = ShellRun::new(60, 0, 0, 1, 1, 1).with_width(5);
    assert_eq!(
        too_wide.decode(),
        Err(out_of_range("ShellRun.width", 5, 1, 4))
    );
    // Byte 7 is the width less one.
    let wide = ShellRun::new(2, 0, 0, 1, 1, 1).with_width(7);
    let words: [u32; 2] = bytemuck::cast(wide);
    assert_eq!(words[1] >> 24, 6);
    assert_eq!(wide.decode().map(|f| f.width), Ok(7));
    // The feet sit above the side mask and the width: +x, -x in byte 6, +z, -z in byte 7.
    let footed = wide.with_feet(0b1101);
    let words: [u32; 2] = bytemuck::cast(footed);
    assert_eq!((words[1] >> 22 & 3, words[1] >> 30), (0b01, 0b11));
    assert_eq!(
        footed.decode().map(|f| (f.width, f.sides, f.feet)),
        Ok((7, 1, 0b1101))
    );
    assert_eq!(
        with(|f| f.feet = 16),
        out_of_range("ShellRun.feet", 16, 0, 15)
    );
}

/// The greedy quad that covers side `face` of the run's box.
fn covering_quad(f: &ShellRunFields, face: FaceDirection) -> PackedQuadFields {
    let mut position = f.position;
    if face == FaceDirection::PosY {
        position[1] += f.height - 1;
    }
    if face == FaceDirection::PosX {
        position[0] += f.width - 1;
    }
    let extent = [f.width, f.height, 1];
    PackedQuadFields {
        position,
        width: extent[face.width_axis()],
        height: extent[face.height_axis()],
        face,
        ao: [3; 4],
        block: f.block,
    }
}

proptest! {
    #[test]
    fn box_corners_are_the_covering_quads_corners(f in fields()) {
        for face in FaceDirection::ALL {
            prop_assert_eq!(f.corners(face), covering_quad(&f, face).corners(), "{:?}", face);
        }
    }
}

#[test]
fn the_box_spans_the_run() {
    let f = sample();
    let corners: Vec<[u32; 3]> = FaceDirection::ALL
        .into_iter()
        .flat_map(|face| f.corners(face))
        .collect();
    let axis = |i: usize| {
        let v = corners.iter().map(|c| c[i]);
        (v.clone().min().unwrap(), v.max().unwrap())
    };
    assert_eq!([axis(0), axis(1), axis(2)], [(1, 2), (3, 8), (2, 3)]);
    assert!(ShellRun::encode(&f).unwrap().has_side(FaceDirection::PosY));
}
