//! Which traversal kernel runs, and the run-time CPU feature detection that picks it.

use core::fmt;

/// Which traversal code runs: the widest the CPU supports, found at run time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    /// Two four-lane halves through glam (SSE2 on x86-64, NEON on AArch64, scalar elsewhere).
    Portable,
    /// AVX2 (x86-64).
    Avx2,
    /// AVX-512 F/VL on eight lanes (x86-64).
    Avx512,
}

impl Kernel {
    /// The widest kernel this CPU runs.
    #[must_use]
    pub fn detect() -> Self {
        [Kernel::Avx512, Kernel::Avx2].into_iter().find(|k| k.is_available()).unwrap_or(Kernel::Portable)
    }

    /// Whether this CPU runs the kernel.
    #[must_use]
    pub fn is_available(self) -> bool {
        match self {
            Kernel::Portable => true,
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx2 => has_avx2(),
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx512 => has_avx512(),
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }
}

impl fmt::Display for Kernel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Kernel::Portable if cfg!(target_arch = "x86_64") => "sse2 (2×4 lanes)",
            Kernel::Portable if cfg!(target_arch = "aarch64") => "neon (2×4 lanes)",
            Kernel::Portable => "scalar (2×4 lanes)",
            Kernel::Avx2 => "avx2 (8 lanes)",
            Kernel::Avx512 => "avx512 (8 lanes)",
        })
    }
}

/// AVX2 with FMA, POPCNT and BMI1 (every AVX2 CPU has them).
#[cfg(target_arch = "x86_64")]
pub(super) fn has_avx2() -> bool {
    is_x86_feature_detected!("avx2")
        && is_x86_feature_detected!("fma")
        && is_x86_feature_detected!("popcnt")
        && is_x86_feature_detected!("bmi1")
}

/// AVX-512 F and VL besides AVX2.
#[cfg(target_arch = "x86_64")]
pub(super) fn has_avx512() -> bool {
    has_avx2() && is_x86_feature_detected!("avx512f") && is_x86_feature_detected!("avx512vl")
}
