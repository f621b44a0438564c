//! A smooth mesh's quads in one of three forms ([`SmoothQuads`]): what the mesher writes and
//! what the GPU reads, byte for byte.

use super::compact_quad::compact_quad_decode;

/// Which form a buffer of smooth quads has; the value is the tag a GPU draw record carries
/// (`SMOOTH_QUADS_COMPACT`, `SMOOTH_QUADS_U16`, `SMOOTH_QUADS_U32` in WGSL).
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum SmoothQuadForm {
    /// Compact records, 6 bytes per quad ([`super::compact_quad`]).
    #[default]
    Compact = 0,
    /// 4 `u16` vertex indices, 8 bytes per quad.
    U16 = 1,
    /// 4 `u32` vertex indices, 16 bytes per quad.
    U32 = 2,
}

impl SmoothQuadForm {
    /// Bytes per quad: 6, 8 or 16.
    pub const fn quad_bytes(self) -> usize {
        match self {
            SmoothQuadForm::Compact => 6,
            SmoothQuadForm::U16 => 8,
            SmoothQuadForm::U32 => 16,
        }
    }
}

/// The quads of a smooth mesh (the mesher's `SmoothMesh::quads`), in the form the mesh uses:
/// each quad is 4 vertex indices, counter-clockwise from outside, for the triangles
/// `(0, 1, 2)` and `(0, 2, 3)` of its corners.
///
/// On the GPU a chunk's quads are its [`bytes`](Self::bytes) padded with zeros to a multiple of
/// 4, read as `array<u32>` together with the [`form`](Self::form) tag; FORMATS_WGSL's
/// `smooth_quad_word` and `smooth_quad_corner` read corner `c` of quad `q` from the words, as
/// [`get`](Self::get) does here:
///
/// | form | quad `q`, corner `c` |
/// | --- | --- |
/// | compact | record = `u16`s `3q`, `3q + 1`, `3q + 2` (in words `3q / 2` and the next), decoded by [`compact_quad_decode`] |
/// | u16 | `u16` number `4q + c` (word `2q + c / 2`, low half for even `c`) |
/// | u32 | word `4q + c` |
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SmoothQuads<'a> {
    /// 6 bytes per quad: compact records, decoded by [`compact_quad_decode`].
    Compact(&'a [[u16; 3]]),
    /// 8 bytes per quad: 4 `u16` indices.
    U16(&'a [[u16; 4]]),
    /// 16 bytes per quad: 4 `u32` indices.
    U32(&'a [[u32; 4]]),
}

impl Default for SmoothQuads<'_> {
    /// No quads (compact).
    fn default() -> Self {
        SmoothQuads::Compact(&[])
    }
}

impl SmoothQuads<'_> {
    /// Number of quads.
    pub fn len(&self) -> usize {
        match self {
            SmoothQuads::Compact(q) => q.len(),
            SmoothQuads::U16(q) => q.len(),
            SmoothQuads::U32(q) => q.len(),
        }
    }

    /// True when there are no quads.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The form, as its GPU tag.
    pub fn form(&self) -> SmoothQuadForm {
        match self {
            SmoothQuads::Compact(_) => SmoothQuadForm::Compact,
            SmoothQuads::U16(_) => SmoothQuadForm::U16,
            SmoothQuads::U32(_) => SmoothQuadForm::U32,
        }
    }

    /// Bytes per quad of this form: 6, 8 or 16.
    pub fn quad_bytes(&self) -> usize {
        self.form().quad_bytes()
    }

    /// Quad `i`'s 4 corners as `u32`, or `None` past the end (and for a compact record that
    /// does not decode, which a mesher's output never holds).
    #[inline]
    pub fn get(&self, i: usize) -> Option<[u32; 4]> {
        match self {
            SmoothQuads::Compact(q) => q.get(i).and_then(|&r| compact_quad_decode(r).ok()),
            SmoothQuads::U16(q) => q.get(i).map(|q| q.map(u32::from)),
            SmoothQuads::U32(q) => q.get(i).copied(),
        }
    }

    /// Every quad's 4 corners as `u32` (records that do not decode are skipped).
    pub fn iter(&self) -> impl Iterator<Item = [u32; 4]> + '_ {
        (0..self.len()).filter_map(|i| self.get(i))
    }

    /// The quad buffer's bytes, little-endian: 3 `u16` per compact record (6 bytes, so a
    /// buffer of an odd count is not a multiple of 4), or 4 indices per quad.
    pub fn bytes(&self) -> &[u8] {
        match self {
            SmoothQuads::Compact(q) => bytemuck::cast_slice(q),
            SmoothQuads::U16(q) => bytemuck::cast_slice(q),
            SmoothQuads::U32(q) => bytemuck::cast_slice(q),
        }
    }

    /// `u32` words the GPU copy takes: [`bytes`](Self::bytes) rounded up to a multiple of 4.
    pub fn word_len(&self) -> usize {
        self.bytes().len().div_ceil(4)
    }
}
