//! `ShellRun`: one vertical run of exposed voxels of one block id (SBgl's shell extraction), or
//! a row of such runs side by side along x, in 8 bytes, drawn as an elongated box synthesised
//! in the vertex shader.

use core::mem::{offset_of, size_of};

use bytemuck::{Pod, Zeroable};

use super::error::{check_max, check_range};
use super::wgsl::{WgslStruct, WgslType, member};
use super::{FaceDirection, FormatError};
use crate::BlockId;

/// One vertical run of exposed voxels of one block id: a box of `width x height x 1` voxels
/// whose visible sides the GPU draws. Vertical shells are one voxel wide; heightmap boxes
/// (`mesher::heightmap`) merge equal neighbouring columns along x.
///
/// ```text
/// byte 0     1     2     3      4           6              7                  8
///      +-----+-----+-----+------+-----------+-------+------+-----------+------+
///      |  x  |  z  |  y  |height|  block id | sides | feet | width - 1 | feet |
///      +-----+-----+-----+------+-----------+-------+------+-----------+------+
///                                            bits 0..6 6..8  bits 0..6   6..8
/// ```
///
/// | byte | field      | range            | meaning                                              |
/// | ---- | ---------- | ---------------- | ---------------------------------------------------- |
/// | 0    | `x`        | `0..64`          | chunk-local x of the run's first column              |
/// | 1    | `z`        | `0..64`          | chunk-local column z                                 |
/// | 2    | `y`        | `0..64`          | chunk-local y of the run's lowest voxel              |
/// | 3    | `height`   | `1..=64 - y`     | voxels in the run, stored as is (never 0)            |
/// | 4..6 | `block`    | any `u16`        | the [`BlockId`] of every voxel of the run            |
/// | 6    | `sides`    | `1..64`, bits 0..6 | bit `d`: box face `d` is visible somewhere on the run |
/// | 6    | feet +x -x | bits 6, 7        | the +x / -x side's foot (below)                      |
/// | 7    | `wide`     | `0..64 - x`, bits 0..6 | columns in the box less one (0 for a vertical shell) |
/// | 7    | feet +z -z | bits 6, 7        | the +z / -z side's foot                              |
///
/// `sides` uses the [`FaceDirection::index`] order: bit 0 +x, 1 -x, 2 +y (top of the highest
/// voxel), 3 -y (bottom of the lowest voxel), 4 +z, 5 -z. The faces between the run's own
/// voxels are never visible (they touch an equal id), so the box's six faces are the only ones.
/// Every bit pattern of byte 7's low six bits is a width; only a box that leaves the chunk
/// (`x + width > 64`) is invalid.
///
/// A side's *foot* (heightmap boxes; vertical shells leave them clear) says that the side
/// becomes visible at the box's lowest voxel, above a solid voxel in front of it: the GPU
/// shades that voxel's side with the meshers' ambient occlusion of such a step (darkest at
/// the bottom), where a vertical shell reads its node's hiding mask instead. Feet are bits
/// `[+x, -x, +z, -z]` of [`ShellRunFields::feet`].
///
/// WGSL reads the 8 bytes as two `u32` words ([`ShellRun::WGSL_LAYOUT`]):
/// `xzyh = x | z << 8 | y << 16 | height << 24` and
/// `block_sides = block | sides << 16 | (width - 1) << 24`.
///
/// # Drawing
///
/// One draw of 18 vertices per run (3 faces x 2 triangles), no vertex data. The vertex shader
/// picks axis `vertex_index / 6` and on it the face toward the eye (a box is convex: the
/// face away from the eye is a back face); if that face's `sides` bit is clear it emits a
/// degenerate triangle, otherwise corner `shell_run_corner` of that face of the box
/// `[x, x + width] x [y, y + height] x [z, z + 1]` (chunk-local). A side bit stands for the whole
/// side of the box: the parts of that side whose voxels' faces are hidden are drawn too. They
/// lie against a hiding neighbour, so for opaque runs the depth test removes them.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Pod, Zeroable)]
pub struct ShellRun {
    /// Chunk-local x of the first column.
    pub x: u8,
    /// Chunk-local z of the column.
    pub z: u8,
    /// Chunk-local y of the lowest voxel of the run.
    pub y: u8,
    /// Voxels in the run, `1..=64 - y`, stored as is.
    pub height: u8,
    /// Block id of every voxel of the run.
    pub block: u16,
    /// Visible box faces, bit [`FaceDirection::index`] (bits 0..6), and the feet of the +x
    /// and -x sides (bits 6 and 7).
    pub sides: u8,
    /// Columns in the box less one, `0..64 - x` (bits 0..6), and the feet of the +z and -z
    /// sides (bits 6 and 7).
    pub wide: u8,
}

const _: () = assert!(size_of::<ShellRun>() == 8, "ShellRun must be 8 bytes");

/// The unpacked, checked fields of a [`ShellRun`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ShellRunFields {
    /// Chunk-local `[x, y, z]` of the run's lowest voxel, each `0..64`.
    pub position: [u32; 3],
    /// Voxels in the run, `1..=64 - y`.
    pub height: u32,
    /// Columns in the box along x, `1..=64 - x` (1 for a vertical shell).
    pub width: u32,
    /// Block id of every voxel of the run.
    pub block: BlockId,
    /// Visible box faces, bit [`FaceDirection::index`], `1..64`.
    pub sides: u8,
    /// Sides whose foot is at the box's lowest voxel (see [`ShellRun`]): bits `[+x, -x, +z,
    /// -z]`, `0..16`; 0 for a vertical shell.
    pub feet: u8,
}

impl ShellRun {
    /// Largest valid position axis.
    pub const MAX_POSITION: u32 = 63;
    /// Largest valid `y + height`: a run ends inside a chunk of at most 64 voxels.
    pub const MAX_TOP: u32 = 64;
    /// Largest valid side mask (all six faces).
    pub const ALL_SIDES: u8 = 0b11_1111;
    /// Vertices drawn per run: the 3 faces toward the eye, of 2 triangles each.
    pub const VERTICES: u32 = 18;
    /// The low six bits of bytes 6 and 7 (the side mask and the width), under the feet.
    const FIELD_MASK: u8 = 0b11_1111;
    /// Largest valid foot mask (all four sides).
    pub const ALL_FEET: u8 = 0b1111;

    /// The WGSL struct `ShellRun { xzyh: u32, block_sides: u32 }` (layout in the type docs).
    pub const WGSL_LAYOUT: WgslStruct = WgslStruct {
        name: "ShellRun",
        size: size_of::<ShellRun>(),
        members: &[
            member("xzyh", offset_of!(ShellRun, x), WgslType::U32),
            member("block_sides", offset_of!(ShellRun, block), WgslType::U32),
        ],
    };

    /// A run one column wide with these fields, unchecked (the extractor's fast path; it
    /// only makes runs that [`decode`](Self::decode) accepts). Use [`encode`](Self::encode) for
    /// values from elsewhere.
    #[inline]
    pub fn new(x: u8, z: u8, y: u8, height: u8, block: u16, sides: u8) -> ShellRun {
        #[cfg(target_endian = "little")]
        {
            // Built as one word: writing the 8 fields to memory one by one and reading them
            // back as a word to push it stalls store forwarding, once per run, which on chunks
            // of many short runs (random fills) costs more than the extraction itself.
            let word = u64::from(x)
                | u64::from(z) << 8
                | u64::from(y) << 16
                | u64::from(height) << 24
                | u64::from(block) << 32
                | u64::from(sides) << 48;
            bytemuck::cast(word.to_le_bytes())
        }
        #[cfg(not(target_endian = "little"))]
        {
            ShellRun {
                x,
                z,
                y,
                height,
                block,
                sides,
                wide: 0,
            }
        }
    }

    /// This run widened to `width` columns along x (`1..=64 - x`), unchecked like
    /// [`new`](Self::new); the feet are kept.
    #[inline]
    pub fn with_width(self, width: u8) -> ShellRun {
        ShellRun {
            wide: (self.wide & !Self::FIELD_MASK) | (width.wrapping_sub(1) & Self::FIELD_MASK),
            ..self
        }
    }

    /// This run with feet `feet` (bits `[+x, -x, +z, -z]`, see [`ShellRun`]), unchecked like
    /// [`new`](Self::new).
    #[inline]
    pub fn with_feet(self, feet: u8) -> ShellRun {
        ShellRun {
            sides: (self.sides & Self::FIELD_MASK) | (feet & 3) << 6,
            wide: (self.wide & Self::FIELD_MASK) | (feet >> 2 & 3) << 6,
            ..self
        }
    }

    /// The visible box faces, bit [`FaceDirection::index`].
    #[inline]
    pub fn side_mask(self) -> u8 {
        self.sides & Self::FIELD_MASK
    }

    /// The feet, bits `[+x, -x, +z, -z]` (see [`ShellRun`]).
    #[inline]
    pub fn feet(self) -> u8 {
        self.sides >> 6 | (self.wide >> 6) << 2
    }

    /// Packs `fields`, rejecting a position axis above 63, a height of 0 or past the chunk
    /// (`y + height > 64`), a width of 0 or past the chunk (`x + width > 64`), a side mask of 0
    /// or above 63 and a foot mask above 15 with [`FormatError::IntegerOutOfRange`] naming the
    /// field.
    pub fn encode(fields: &ShellRunFields) -> Result<ShellRun, FormatError> {
        let [x, y, z] = fields.position;
        let x = check_max("ShellRun.x", x, Self::MAX_POSITION)?;
        let y = check_max("ShellRun.y", y, Self::MAX_POSITION)?;
        let z = check_max("ShellRun.z", z, Self::MAX_POSITION)?;
        let height = check_range("ShellRun.height", fields.height, 1, Self::MAX_TOP - y)?;
        let width = check_range("ShellRun.width", fields.width, 1, Self::MAX_TOP - x)?;
        let feet = check_max("ShellRun.feet", fields.feet.into(), Self::ALL_FEET.into())?;
        let sides = check_range(
            "ShellRun.sides",
            fields.sides.into(),
            1,
            Self::ALL_SIDES.into(),
        )?;
        Ok(ShellRun::new(
            x as u8,
            z as u8,
            y as u8,
            height as u8,
            fields.block.0,
            sides as u8,
        )
        .with_width(width as u8)
        .with_feet(feet as u8))
    }

    /// Unpacks and checks the fields: a position axis above 63, a height of 0 or past the
    /// chunk (`y + height > 64`), a width past the chunk (`x + width > 64`) or a side mask of
    /// 0 or above 63 is [`FormatError::IntegerOutOfRange`] naming the field. Never panics.
    pub fn decode(self) -> Result<ShellRunFields, FormatError> {
        ShellRun::encode(&self.fields_unchecked()).map(|run| run.fields_unchecked())
    }

    fn fields_unchecked(self) -> ShellRunFields {
        ShellRunFields {
            position: [self.x, self.y, self.z].map(u32::from),
            height: self.height.into(),
            width: u32::from(self.wide & Self::FIELD_MASK) + 1,
            block: BlockId(self.block),
            sides: self.side_mask(),
            feet: self.feet(),
        }
    }

    /// The block id.
    #[inline]
    pub fn block_id(self) -> BlockId {
        BlockId(self.block)
    }

    /// True if the box's `face` is visible somewhere along the run.
    #[inline]
    pub fn has_side(self, face: FaceDirection) -> bool {
        (self.sides >> face.index()) & 1 != 0
    }

    /// Columns in the box along x (1 for a vertical shell).
    #[inline]
    pub fn width(self) -> u32 {
        u32::from(self.wide & Self::FIELD_MASK) + 1
    }

    /// Chunk-local positions of the box's voxels, bottom to top, then along x.
    pub fn voxels(self) -> impl Iterator<Item = [u32; 3]> {
        let (x, y, z) = (u32::from(self.x), u32::from(self.y), u32::from(self.z));
        let width = self.width();
        (x..x + width).flat_map(move |x| (y..y + u32::from(self.height)).map(move |y| [x, y, z]))
    }
}

impl ShellRunFields {
    /// The 4 corners of the box's `face` in chunk-local voxel units, counter-clockwise seen
    /// from outside (draw `(0, 1, 2)` and `(0, 2, 3)`): the corners of the greedy quad that
    /// covers the same side, in the same order (`PackedQuadFields::corners`). The twin of WGSL
    /// `shell_run_corner`.
    pub fn corners(&self, face: FaceDirection) -> [[u32; 3]; 4] {
        let extent = [self.width, self.height, 1];
        let (n, w, h) = (face.normal_axis(), face.width_axis(), face.height_axis());
        let swap = matches!(
            face,
            FaceDirection::PosX | FaceDirection::PosY | FaceDirection::NegZ
        );
        [(0, 0), (1, 0), (1, 1), (0, 1)].map(|(a, b)| {
            let (du, dv) = if swap { (b, a) } else { (a, b) };
            let mut p = self.position;
            p[n] += u32::from(face.is_positive()) * extent[n];
            p[w] += du * extent[w];
            p[h] += dv * extent[h];
            p
        })
    }
}
