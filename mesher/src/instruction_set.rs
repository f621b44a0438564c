//! [`InstructionSet`]: which compiled copy of the blocky mesher's loops runs.
//!
//! The blocky mesher is bit twiddling in tight loops (bit scans, variable shifts, popcounts,
//! 64-line mask operations). The portable x86-64 target has none of BMI1 / BMI2 / POPCNT and
//! only 128-bit vectors, so its loops spend two instructions where one would do; yet the
//! library cannot be built for a newer CPU level without excluding older machines. So the
//! mesher is compiled twice and picks a copy at run time, once per mesher, with `std`'s CPU
//! feature detection. On CPUs with AVX-512 the AVX2 copy also writes its lines of single
//! faces 8 quads per vector instruction ([`InstructionSet::X86V4`]). Without the `std` feature there is no detection: the portable copy runs,
//! compiled for whatever target features the build enables.

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
    /// [`X86V3`](Self::X86V3) plus AVX-512 F, BW, CD, DQ and VL, the x86-64-v4 level (Intel
    /// server CPUs since Skylake-SP, AMD Zen 4 and later): the lines of faces that become
    /// single quads are built 8 quads per 512-bit register, and a compress instruction keeps
    /// those of faces.
    X86V4,
}

impl InstructionSet {
    /// Every instruction set, the portable one first.
    pub const ALL: [InstructionSet; 3] = [
        InstructionSet::Baseline,
        InstructionSet::X86V3,
        InstructionSet::X86V4,
    ];

    /// The fastest instruction set this CPU runs.
    pub fn detect() -> InstructionSet {
        [InstructionSet::X86V4, InstructionSet::X86V3]
            .into_iter()
            .find(|set| set.is_supported())
            .unwrap_or(InstructionSet::Baseline)
    }

    /// Whether this CPU runs `self` (always true for [`Baseline`](Self::Baseline)).
    pub fn is_supported(self) -> bool {
        match self {
            InstructionSet::Baseline => true,
            InstructionSet::X86V3 => x86_v3_supported(),
            InstructionSet::X86V4 => x86_v3_supported() && x86_v4_supported(),
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

/// The AVX-512 features [`InstructionSet::X86V4`] adds, asked of the CPU.
#[cfg(all(feature = "std", target_arch = "x86_64"))]
fn x86_v4_supported() -> bool {
    std::is_x86_feature_detected!("avx512f")
        && std::is_x86_feature_detected!("avx512bw")
        && std::is_x86_feature_detected!("avx512cd")
        && std::is_x86_feature_detected!("avx512dq")
        && std::is_x86_feature_detected!("avx512vl")
}

/// Without `std` nothing asks the CPU: only a build for these features has them.
#[cfg(not(all(feature = "std", target_arch = "x86_64")))]
fn x86_v4_supported() -> bool {
    cfg!(all(
        target_arch = "x86_64",
        target_feature = "avx512f",
        target_feature = "avx512bw",
        target_feature = "avx512cd",
        target_feature = "avx512dq",
        target_feature = "avx512vl"
    ))
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
