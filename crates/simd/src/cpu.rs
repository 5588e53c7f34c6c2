//! The running CPU's SIMD features, detected once per process.

use std::sync::OnceLock;

/// The SIMD features the kernels need, as the running CPU reports them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cpu {
    /// AVX2 and FMA (the [`Kernel::Avx2`](crate::Kernel::Avx2) kernels).
    pub avx2_fma: bool,
    /// AVX-512F besides AVX2 and FMA (the [`Kernel::Avx512`](crate::Kernel::Avx512) kernels).
    pub avx512: bool,
}

/// The running CPU's features, detected on the first call and cached for the process (the
/// answer cannot change while it runs). Every kernel dispatch of the model and the solver
/// reads this, never the CPU itself.
pub fn cpu() -> Cpu {
    static CPU: OnceLock<Cpu> = OnceLock::new();
    *CPU.get_or_init(detect)
}

#[cfg(target_arch = "x86_64")]
fn detect() -> Cpu {
    let avx2_fma = std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma");
    Cpu {
        avx2_fma,
        avx512: avx2_fma && std::is_x86_feature_detected!("avx512f"),
    }
}

#[cfg(not(target_arch = "x86_64"))]
fn detect() -> Cpu {
    Cpu {
        avx2_fma: false,
        avx512: false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// AVX-512 implies AVX2 and FMA (the AVX-512 kernels run AVX2 code for their tails), and
    /// the cached answer is the CPU's.
    #[test]
    fn avx512_implies_avx2_and_the_cache_holds_the_detection() {
        let c = cpu();
        assert!(!c.avx512 || c.avx2_fma);
        assert_eq!(c, detect());
        assert_eq!(cpu(), c);
    }
}
