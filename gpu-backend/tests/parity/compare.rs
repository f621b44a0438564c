//! Word-by-word comparison of GPU output with the CPU's expected words.

use std::fmt::Write;

use super::expected::Word;
use super::harness::UNWRITTEN;

/// How far apart two f32 are in units in the last place (0 for +0 and -0).
pub(crate) fn ulp_distance(a: f32, b: f32) -> u64 {
    fn ordered(x: f32) -> i64 {
        let bits = i64::from(x.to_bits() as i32);
        if bits < 0 {
            i64::from(i32::MIN) - bits
        } else {
            bits
        }
    }
    (ordered(a) - ordered(b)).unsigned_abs()
}

/// What a comparison found.
#[derive(Debug, Default)]
pub(crate) struct Outcome {
    /// Mismatching words, with a description of the first few.
    pub mismatches: usize,
    pub report: String,
    /// Largest ulp distance seen on a normal component.
    pub max_normal_ulps: u64,
}

/// Compares `got` with `expected` (both `stride` words per element). Exact words must be equal
/// bit for bit; normal components within `normal_ulps`. `describe(i)` prints element `i`'s
/// input for the report.
pub(crate) fn compare(
    got: &[u32],
    expected: &[Word],
    stride: usize,
    normal_ulps: u64,
    describe: impl Fn(usize) -> String,
) -> Outcome {
    assert_eq!(got.len(), expected.len(), "output length");
    let mut outcome = Outcome::default();
    for (w, (&g, e)) in got.iter().zip(expected).enumerate() {
        let ok = match *e {
            Word::Exact(bits) => g == bits,
            Word::Normal(value) => {
                let d = ulp_distance(f32::from_bits(g), value);
                outcome.max_normal_ulps = outcome.max_normal_ulps.max(d);
                g != UNWRITTEN && d <= normal_ulps
            }
        };
        if !ok {
            outcome.mismatches += 1;
            if outcome.mismatches <= 8 {
                let (element, word) = (w / stride, w % stride);
                let values = match *e {
                    Word::Exact(bits) => format!("GPU {g:#010x} ({g}), CPU {bits:#010x} ({bits})"),
                    Word::Normal(v) => {
                        format!("GPU {} ({g:#010x}), CPU {v} (normal)", f32::from_bits(g))
                    }
                };
                let _ = writeln!(
                    outcome.report,
                    "  element {element} word {word}: {values}; input {}",
                    describe(element)
                );
            }
        }
    }
    outcome
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ulps() {
        assert_eq!(ulp_distance(1.0, 1.0), 0);
        assert_eq!(ulp_distance(0.0, -0.0), 0);
        assert_eq!(ulp_distance(1.0, f32::from_bits(1.0f32.to_bits() + 3)), 3);
        assert_eq!(ulp_distance(f32::from_bits(1), -f32::from_bits(1)), 2);
    }
}
