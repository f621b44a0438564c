//! The six face directions as slices of lines of bits, and the walk over them that turns face
//! masks into quads.
//!
//! For a direction, slice `n` is the layer of voxels at padded coordinate `n` along the normal;
//! its faces are `cur[l] & !front[l]`, where `front` is the slice at `n + 1` (positive faces) or
//! `n - 1` (negative faces), restricted to the chunk's interior lines and bits `1..=e`. Which
//! axis the lines and bits run along is the layout's (see [`super::masks`]):
//!
//! | faces | layout | slice `n` | line `l` | bit `b` | width axis | grown first along | quads start at |
//! | ----- | ------ | --------- | -------- | ------- | ---------- | ----------------- | -------------- |
//! | ±X    | C      | x         | y        | z       | bits (z)   | bits (z)          | lowest bit, then line |
//! | ±Y    | B      | y         | z        | x       | bits (x)   | lines (z)         | lowest line, then bit |
//! | ±Z    | A      | z         | y        | x       | bits (x)   | bits (x)          | lowest line, then bit |
//!
//! The merge order is `block-mesh`'s (its `RIGHT_HANDED_Y_UP_CONFIG` grows a quad along its
//! `u` axis first: z for ±X and ±Y faces, x for ±Z faces, and scans x fastest, then y, then
//! z), so with AO off both produce exactly the same quads. The ±X faces have their bits along
//! z, not y, because on terrain their lines then hold more faces each (on the 62^3 bench
//! terrain chunk, little more than half as many lines for the same faces), and the per-line
//! work is a large part of the cost; `block-mesh` scans them z first, so their quads start
//! bit-major.

use alloc::vec::Vec;

use voxel_core::formats::PackedQuad;

use super::bits::{many, masked, ones};
use super::direction::{Axis, Facing};
use super::faces::{Quads, SliceFaces, SliceQuads};
use super::input::Input;
use super::keys::{FROM_IDS, FROM_ONE, FROM_TABLE, Keys};
use super::lone_x::drop_handled;
use super::masks::Slice;
use super::memo::NeighbourhoodMemo;
use super::merge::{greedy, rows_of, unit_quads};
use crate::{BlockClasses, MeshError};

const ZERO: Slice = [0; 64];

/// Slice `n` of a layout (all zero past the end, which never happens for `n <= p - 1`).
#[inline]
fn slice(layout: &[Slice], n: usize) -> &Slice {
    layout.get(n).unwrap_or(&ZERO)
}

/// Meshes the faces along axis `A` that face as `facing` says: every slice, opaque faces into
/// `opaque`, transparent ones into `transparent`. `AO` is the input's AO setting, as a
/// constant, so that each setting's walk is code of its own.
#[inline(always)]
pub(crate) fn mesh_direction<const A: usize, const AO: bool>(
    facing: Facing,
    input: &Input<'_>,
    classes: &BlockClasses,
    keys: &mut Keys,
    buf: &mut SliceQuads,
    opaque: &mut Vec<PackedQuad>,
    transparent: &mut Vec<PackedQuad>,
) -> Result<(), MeshError> {
    debug_assert_eq!(input.ao, AO, "the walk compiled for the input's AO setting");
    let p = input.p;
    let e = p - 2;
    let inner = (u64::MAX >> (64 - e)) << 1;
    let layout = Axis::<A>::LAYOUT;
    let o_layout = input.opaque.by[layout];
    let o_occupied = input.opaque.occupied[layout];
    let t_layout = input.transparent.map(|t| t.by[layout]);
    let t_occupied = input.transparent.map_or(0, |t| t.occupied[layout]);
    let [stride_n, stride_l, stride_b] = Axis::<A>::strides(p);
    keys.memo = NeighbourhoodMemo::new();
    // Lines 0 and p - 1 are the padding; lines past p are zero in every layout.
    let mut faces: Slice = [0; 64];
    // The lines of a slice, padding included; those past them are zero in every layout, and
    // never read (at 32^3, 34 of 64: 5 cache lines of a slice's 8).
    let lines = p.min(64);
    #[expect(
        clippy::range_plus_one,
        reason = "`Range` iterates faster than `RangeInclusive`"
    )]
    for n in 1..e + 1 {
        let front_n = facing.front(n);
        let cur = slice(o_layout, n);
        let front = slice(o_layout, front_n);
        let mut any = 0;
        if (o_occupied >> n) & 1 != 0 {
            for ((f, &c), &fr) in faces[..lines].iter_mut().zip(cur).zip(front) {
                *f = c & !fr & inner;
                any |= *f;
            }
        }
        faces[0] = 0;
        faces[masked::<64>(p - 1)] = 0;
        if Axis::<A>::LAYOUT == 2 && any != 0 && input.lone_x_rows[facing.direction & 1] {
            // Some lone ±X faces of this direction were emitted from the rows.
            drop_handled(&mut faces, &input.handled[facing.direction & 1]);
            any = faces.iter().fold(0, |any, &f| any | f);
        }
        let mut slice_faces = SliceFaces::<A> {
            voxels: input.voxels,
            base: n * stride_n,
            stride_l,
            stride_b,
            front,
            n,
            known_below: classes.known_below(),
            short: p <= 48,
            equal: input.equal,
            facing,
        };
        if any != 0 {
            let one = input.one_id.is_some();
            emit::<A, AO>(input, one, &slice_faces, &mut faces, keys, buf, opaque)?;
        }

        let Some(t_layout) = t_layout else { continue };
        if (t_occupied >> n) & 1 == 0 {
            continue;
        }
        let t_cur = slice(t_layout, n);
        let t_front = slice(t_layout, front_n);
        let mut any = 0;
        let t_lines = faces[..lines].iter_mut().zip(t_cur).zip(front).zip(t_front);
        for (((f, &c), &fr), &tf) in t_lines {
            *f = c & !(fr | tf) & inner;
            any |= c;
        }
        if any == 0 {
            continue;
        }
        faces[0] = 0;
        faces[masked::<64>(p - 1)] = 0;
        if input.mixed_transparent {
            for l in 1..e + 1 {
                let both = t_cur[masked::<64>(l)] & t_front[masked::<64>(l)] & inner;
                if both != 0 {
                    faces[masked::<64>(l)] |= differing_ids(
                        input.voxels,
                        [n, front_n, l],
                        [stride_n, stride_l, stride_b],
                        both,
                    );
                }
            }
        }
        slice_faces.known_below = u32::MAX;
        emit::<A, AO>(
            input,
            false,
            &slice_faces,
            &mut faces,
            keys,
            buf,
            transparent,
        )?;
    }
    Ok(())
}

/// The bits of `both` (transparent voxels with a transparent front voxel) whose two ids
/// differ; `at` holds the slice, front slice and line, `strides` the voxel index strides.
fn differing_ids(voxels: &[u16], at: [usize; 3], strides: [usize; 3], both: u64) -> u64 {
    let [n, front_n, l] = at;
    let [stride_n, stride_l, stride_b] = strides;
    let mut out = 0;
    for b in ones(both) {
        let id = |n: usize| {
            let i = n * stride_n + l * stride_l + b * stride_b;
            voxels.get(i).copied().unwrap_or(0)
        };
        if id(n) != id(front_n) {
            out |= 1 << b;
        }
    }
    out
}

/// Turns the face lines of one slice into quads, leaving `faces` all zero. With `one` (the
/// opaque layer of a one-id chunk, AO off) every face has the key `keys.one`. `AO` is the
/// input's AO setting (see [`mesh_direction`]).
#[inline(always)]
fn emit<const A: usize, const AO: bool>(
    input: &Input<'_>,
    one: bool,
    slice: &SliceFaces<'_, A>,
    faces: &mut Slice,
    keys: &mut Keys,
    buf: &mut SliceQuads,
    out: &mut Vec<PackedQuad>,
) -> Result<(), MeshError> {
    let mut quads = Quads::new(buf, out);
    let rows = rows_of(faces);
    // Faces none of which touches another are their own greedy quads: no merging to do.
    let merge = input.merge && !isolated_faces(faces, rows);
    match (merge, AO, one) {
        (false, true, _) => unit_quads::<A, true, false>(slice, faces, rows, keys, &mut quads)?,
        (false, false, false) => {
            unit_quads::<A, false, false>(slice, faces, rows, keys, &mut quads)?;
        }
        (false, false, true) => unit_quads::<A, false, true>(slice, faces, rows, keys, &mut quads)?,
        (true, true, _) => greedy::<A, true, FROM_TABLE>(slice, faces, rows, keys, &mut quads)?,
        (true, false, false)
            if input
                .equal
                .is_some_and(|e| Axis::<A>::LAYOUT != 2 || e.has_layout_c()) =>
        {
            greedy::<A, false, FROM_IDS>(slice, faces, rows, keys, &mut quads)?;
        }
        (true, false, false) => {
            greedy::<A, false, FROM_TABLE>(slice, faces, rows, keys, &mut quads)?;
        }
        (true, false, true) => greedy::<A, false, FROM_ONE>(slice, faces, rows, keys, &mut quads)?,
    }
    quads.flush();
    Ok(())
}

/// True when no face of the slice (lines `rows`) has a neighbouring face, as on a
/// checkerboard: then every face is a 1 x 1 greedy quad, and the greedy pass's per-line
/// bookkeeping can be skipped. Only slices whose first line with faces has [`many`] such
/// faces are scanned, so that slices of other shapes (terrain) pay a handful of operations.
#[inline(always)]
fn isolated_faces(faces: &Slice, rows: u64) -> bool {
    // Line l - 1 has no face: l is the first line with one. A slice may have none (transparent
    // voxels that face only their own id): then the mask turns l = 64 into line 0, which holds
    // no face (padding), and the answer is false. (A separate early return for such slices
    // only changes the code layout.)
    let l = rows.trailing_zeros() as usize & 63;
    let f = faces[l];
    if !many(f) || f & ((f << 1) | (f >> 1) | faces[masked::<64>(l + 1)]) != 0 {
        return false;
    }
    // Lines 0 and 63 never hold faces (padding).
    let mut touching = 0;
    for l in 1..63 {
        let f = faces[l];
        touching |= f & ((f << 1) | (f >> 1) | faces[l - 1] | faces[l + 1]);
    }
    touching == 0
}
