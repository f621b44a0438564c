//! [`Slices`]: the scratch slices of the masks, each on a 64-byte boundary (a cache line);
//! [`Words`]: a plain array's occupancy columns, from a cache line on.
//!
//! The passes read and write a slice's lines with 32-byte AVX2 loads and stores. In a `Vec` of
//! plain slices, which the allocator aligns to 16 bytes, half of those cross a cache line
//! when the buffer lands 16 or 48 bytes past one, and none when it lands on one: where it
//! lands changes from one mesher, and one process, to the next, and so would the mesher's
//! speed. On cache lines every load is whole, whatever the allocator does.

use alloc::vec::Vec;
use core::ops::{Deref, DerefMut};

/// 64 lines of one slice.
pub(crate) type Slice = [u64; 64];

/// One slice on a cache line.
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(64))]
struct OnCacheLine(Slice);

/// Slices that each start on a cache line, read and written as `[Slice]`. Scratch that keeps
/// its capacity between chunks.
#[derive(Clone, Debug, Default)]
pub(crate) struct Slices(Vec<OnCacheLine>);

impl Slices {
    /// Resizes to `n` slices. Callers overwrite lines `0..n` of every slice; lines `n..64` are
    /// zeroed here when the size changes (nothing to do for 62^3 chunks, where `n` is 64). At
    /// an unchanged size they are still zero: the call that sized the slices zeroed them, and
    /// every chunk since wrote lines `0..n` only.
    pub(crate) fn resize(&mut self, n: usize) {
        if self.0.len() == n {
            return;
        }
        self.0.resize(n, OnCacheLine([0; 64]));
        if n < 64 {
            for s in self.iter_mut() {
                s[n..].fill(0);
            }
        }
    }
}

impl Deref for Slices {
    type Target = [Slice];

    fn deref(&self) -> &[Slice] {
        bytemuck::cast_slice(&self.0)
    }
}

impl DerefMut for Slices {
    fn deref_mut(&mut self) -> &mut [Slice] {
        bytemuck::cast_slice_mut(&mut self.0)
    }
}

/// Eight words on one cache line.
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(64))]
struct WordLine([u64; 8]);

/// Words from a cache line on, read as `[u64]`: the occupancy columns that
/// [`GreedyMesher::mesh_u16`](super::GreedyMesher::mesh_u16) builds, written with 32-byte
/// stores. (A `Vec<u64>` lands 16 bytes past a cache line as often as on one, and then half
/// of those stores split across two lines.) Scratch that keeps its capacity between chunks.
#[derive(Clone, Debug, Default)]
pub(crate) struct Words {
    lines: Vec<WordLine>,
    len: usize,
}

impl Words {
    /// The `n` words, for the caller to overwrite: resized, and zeroed, only when `n` changes.
    pub(crate) fn sized(&mut self, n: usize) -> &mut [u64] {
        if self.len != n {
            self.lines.clear();
            self.lines.resize(n.div_ceil(8), WordLine([0; 8]));
            self.len = n;
        }
        let words: &mut [u64] = bytemuck::cast_slice_mut(&mut self.lines);
        &mut words[..n]
    }
}

impl Deref for Words {
    type Target = [u64];

    fn deref(&self) -> &[u64] {
        let words: &[u64] = bytemuck::cast_slice(&self.lines);
        &words[..self.len]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every slice starts on a cache line, at every size, and resizing zeroes the lines past
    /// the new size but keeps what the callers wrote below it.
    #[test]
    fn slices_start_on_cache_lines_and_resize_zeroes_the_lines_past_the_size() {
        let mut slices = Slices::default();
        for n in [64, 34, 34, 18, 64, 10] {
            slices.resize(n);
            assert_eq!(slices.len(), n);
            for (i, s) in slices.iter().enumerate() {
                assert_eq!(s.as_ptr() as usize % 64, 0, "slice {i} of {n}");
                assert!(s[n..].iter().all(|&line| line == 0), "slice {i} of {n}");
            }
            for s in slices.iter_mut() {
                s[..n].fill(u64::MAX);
            }
        }
        slices.resize(10);
        assert!(
            slices
                .iter()
                .all(|s| s[..10].iter().all(|&l| l == u64::MAX))
        );
    }

    /// The words start on a cache line at every size; a size kept keeps what was written,
    /// and a new one starts from zeros.
    #[test]
    fn words_start_on_a_cache_line_and_keep_their_contents_at_one_size() {
        let mut words = Words::default();
        assert!(words.is_empty());
        for n in [1156, 4096, 4096, 324, 100, 1156] {
            let kept = words.len() == n;
            let fresh = words.sized(n);
            assert_eq!(fresh.len(), n);
            assert_eq!(fresh.as_ptr() as usize % 64, 0, "{n} words");
            if kept {
                assert!(fresh.iter().all(|&w| w == 7), "{n} words kept");
            } else {
                assert!(fresh.iter().all(|&w| w == 0), "{n} words zeroed");
            }
            fresh.fill(7);
            assert_eq!(words.len(), n);
        }
    }
}
