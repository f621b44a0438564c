//! [`InstructionSet`]: which compiled copy of the blocky mesher's loops runs.
//!
//! The blocky mesher is bit twiddling in tight loops (bit scans, variable shifts, popcounts,
//! 64-line mask operations). The portable x86-64 target has none of BMI1 / BMI2 / POPCNT and
//! only 128-bit vectors, so its loops spend two instructions where one would do; yet the
//! library cannot be built for a newer CPU level without excluding older machines. So the
//! mesher is compiled twice and picks a copy at run time, once per mesher, with `std`'s CPU
//! feature detection. Without the `std` feature there is no detection: the portable copy runs,
//! compiled for whatever target features the build enables.
//!
//! **No AVX-512 copy.** Writing lines of single faces 8 quads per 512-bit register gains only
//! on inputs made of single faces (a checkerboard), not on real models, whose lines hold few
//! faces; and it would be unsafe code that the tests cannot run on the many machines without
//! AVX-512 (BENCHMARKS.md, the blocky mesher's "tried and not kept").

/// The instruction set a [`GreedyMesher`](crate::blocky::GreedyMesher) runs on. Every set
/// gives the same quads, bit for bit; only the speed differs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum InstructionSet {
    /// The compilation target's own features (on x86-64 without `-C target-cpu`: SSE2).
    Baseline,
    /// x86-64 with AVX2, BMI1, BMI2, LZCNT and POPCNT: the integer and vector features of the
    /// x86-64-v3 level (Intel Core since Haswell, 2013; AMD since Excavator, 2015, and every
    /// Zen). Not every later x86-64 CPU has it: Intel's Pentium, Celeron and Atom lines lacked
    /// AVX2 for years after, hence the run-time check.
    X86V3,
}

impl InstructionSet {
    /// Every instruction set, the portable one first.
    pub const ALL: [InstructionSet; 2] = [InstructionSet::Baseline, InstructionSet::X86V3];

    /// The fastest instruction set this CPU runs.
    pub fn detect() -> InstructionSet {
        if InstructionSet::X86V3.is_supported() {
            InstructionSet::X86V3
        } else {
            InstructionSet::Baseline
        }
    }

    /// Whether this CPU runs `self` (always true for [`Baseline`](Self::Baseline)).
    pub fn is_supported(self) -> bool {
        match self {
            InstructionSet::Baseline => true,
            InstructionSet::X86V3 => x86_v3_supported(),
        }
    }
}

/// The features of [`InstructionSet::X86V3`], asked of the CPU.
#[cfg(all(feature = "std", target_arch = "x86_64"))]
fn x86_v3_supported() -> bool {
    std::is_x86_feature_detected!("avx2")
        && std::is_x86_feature_detected!("bmi1")
        && std::is_x86_feature_detected!("bmi2")
        && std::is_x86_feature_detected!("lzcnt")
        && std::is_x86_feature_detected!("popcnt")
}

/// Without `std` nothing asks the CPU: only a build for these features has them.
#[cfg(not(all(feature = "std", target_arch = "x86_64")))]
fn x86_v3_supported() -> bool {
    cfg!(all(
        target_arch = "x86_64",
        target_feature = "avx2",
        target_feature = "bmi1",
        target_feature = "bmi2",
        target_feature = "lzcnt",
        target_feature = "popcnt"
    ))
}

/// For the tests of the x86-64-v3 code: true when this CPU runs it; otherwise prints
/// `skipped: <test>: ...` (the workspace's loud skip) and returns false, and under `CI=true`
/// fails instead, so the library's only unsafe SIMD path cannot go untested on an x86-64 CI
/// machine without a visible failure. Planted (`X86V3.is_supported()` made to answer false),
/// under `CI=true` the seven unit tests that use it failed with "would skip".
#[cfg(all(test, feature = "std", target_arch = "x86_64"))]
pub(crate) fn x86_v3_or_skip(what: &str) -> bool {
    if InstructionSet::X86V3.is_supported() {
        return true;
    }
    let current = std::thread::current();
    let test = current.name().unwrap_or("(unnamed test)");
    let reason = std::format!("no AVX2, BMI2 and LZCNT on this CPU, so no test here runs {what}");
    assert!(
        std::env::var("CI").as_deref() != Ok("true"),
        "{test} would skip ({reason}), and a test must not skip under CI=true on x86-64"
    );
    std::eprintln!("skipped: {test}: {reason}");
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_detected_set_is_supported_and_baseline_always_is() {
        assert!(InstructionSet::detect().is_supported());
        assert!(InstructionSet::Baseline.is_supported());
    }
}
