//! [`Kernel`]: which compiled copy of the SIMD loops runs.

use crate::cpu::cpu;

/// The kernel: which implementation of the per-sample (model) and per-row (solver) loops runs.
/// A user-facing choice (`auto|avx512|avx2|portable|scalar`, the
/// [`FromStr`](std::str::FromStr), [`Display`](std::fmt::Display) and serde spelling);
/// [`Kernel::resolve`] turns it into the concrete kernel the running CPU executes.
///
/// What each kernel computes, and how closely the kernels agree, is the using crate's to
/// document: the model's kernels agree to rounding, the solver's bit for bit.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum Kernel {
    /// The fastest kernel the CPU has (AVX-512, else AVX2, else portable).
    #[default]
    Auto,
    /// AVX-512F kernels (8 lanes); needs AVX-512F, AVX2 and FMA.
    Avx512,
    /// Loops compiled with AVX2 and FMA (4 lanes); needs AVX2 and FMA.
    Avx2,
    /// Loops compiled for the baseline target (SSE2 on x86-64), any CPU.
    Portable,
    /// A plain, non-vectorised reference: one sample at a time. Slow; the yardstick the other
    /// kernels are tested against.
    Scalar,
}

/// A kernel name that is not known, or a kernel the running CPU cannot execute.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum KernelError {
    /// Not one of `auto`, `avx512`, `avx2`, `portable`, `scalar`.
    #[error("unknown kernel `{0}`: expected one of auto, avx512, avx2, portable, scalar")]
    Unknown(String),
    /// The CPU lacks the instructions the kernel needs.
    #[error(
        "the {kernel} kernel needs {needs}, which this CPU does not have (available: {available})"
    )]
    Unavailable {
        /// The requested kernel.
        kernel: Kernel,
        /// The CPU features it needs.
        needs: &'static str,
        /// The kernels this CPU can run, comma-separated.
        available: String,
    },
}

impl Kernel {
    /// Every choice, in the order `auto, avx512, avx2, portable, scalar`.
    pub const ALL: [Kernel; 5] = [
        Kernel::Auto,
        Kernel::Avx512,
        Kernel::Avx2,
        Kernel::Portable,
        Kernel::Scalar,
    ];

    /// The lowercase name: `"auto"`, `"avx512"`, `"avx2"`, `"portable"`, `"scalar"`.
    pub fn name(self) -> &'static str {
        match self {
            Kernel::Auto => "auto",
            Kernel::Avx512 => "avx512",
            Kernel::Avx2 => "avx2",
            Kernel::Portable => "portable",
            Kernel::Scalar => "scalar",
        }
    }

    /// True when the running CPU can execute this kernel (always for `auto`, `portable` and
    /// `scalar`); from the cached [`cpu`] detection.
    pub fn is_available(self) -> bool {
        match self {
            Kernel::Auto | Kernel::Portable | Kernel::Scalar => true,
            Kernel::Avx2 => cpu().avx2_fma,
            Kernel::Avx512 => cpu().avx512,
        }
    }

    /// The concrete kernels the running CPU can execute, fastest first (never `auto`).
    pub fn available() -> Vec<Kernel> {
        Kernel::ALL[1..]
            .iter()
            .copied()
            .filter(|k| k.is_available())
            .collect()
    }

    /// The fastest kernel the running CPU has: what `auto` resolves to.
    pub fn best() -> Kernel {
        let c = cpu();
        if c.avx512 {
            Kernel::Avx512
        } else if c.avx2_fma {
            Kernel::Avx2
        } else {
            Kernel::Portable
        }
    }

    /// The concrete kernel this choice runs on this CPU: `auto` becomes [`Kernel::best`], the
    /// others themselves.
    ///
    /// # Errors
    /// [`KernelError::Unavailable`] when the CPU lacks the requested kernel's instructions.
    pub fn resolve(self) -> Result<Kernel, KernelError> {
        match self {
            Kernel::Auto => Ok(Kernel::best()),
            k if k.is_available() => Ok(k),
            k => Err(KernelError::Unavailable {
                kernel: k,
                needs: k.needs(),
                available: Kernel::available()
                    .iter()
                    .map(|k| k.name())
                    .collect::<Vec<_>>()
                    .join(", "),
            }),
        }
    }

    /// The CPU features a kernel needs, for error messages.
    fn needs(self) -> &'static str {
        match self {
            Kernel::Avx512 => "AVX-512F, AVX2 and FMA",
            Kernel::Avx2 => "AVX2 and FMA",
            Kernel::Auto | Kernel::Portable | Kernel::Scalar => "nothing beyond the baseline",
        }
    }

    /// The position in [`Kernel::ALL`], for compact storage (see [`crate::KernelCell`]).
    pub(crate) const fn index(self) -> u8 {
        match self {
            Kernel::Auto => 0,
            Kernel::Avx512 => 1,
            Kernel::Avx2 => 2,
            Kernel::Portable => 3,
            Kernel::Scalar => 4,
        }
    }
}

impl std::fmt::Display for Kernel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Kernel {
    type Err = KernelError;
    /// Parses the lowercase names of [`Kernel::name`] (surrounding spaces and case ignored).
    fn from_str(s: &str) -> Result<Self, KernelError> {
        let t = s.trim().to_ascii_lowercase();
        Kernel::ALL
            .into_iter()
            .find(|k| k.name() == t)
            .ok_or_else(|| KernelError::Unknown(s.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back_and_index_is_the_position_in_all() {
        for (i, k) in Kernel::ALL.into_iter().enumerate() {
            assert_eq!(k.name().parse::<Kernel>(), Ok(k));
            assert_eq!(
                format!(" {} ", k.name().to_uppercase()).parse::<Kernel>(),
                Ok(k)
            );
            assert_eq!(usize::from(k.index()), i);
        }
    }

    #[test]
    fn an_unknown_name_lists_the_choices() {
        let e = "avx3".parse::<Kernel>().unwrap_err();
        assert_eq!(e, KernelError::Unknown("avx3".into()));
        let msg = e.to_string();
        for k in Kernel::ALL {
            assert!(msg.contains(k.name()), "{msg}");
        }
    }

    /// `auto` resolves to the first (fastest) available kernel; available kernels resolve to
    /// themselves, unavailable ones to an error naming what they need and what is available.
    #[test]
    fn resolve_follows_the_detection() {
        let available = Kernel::available();
        assert_eq!(Kernel::Auto.resolve(), Ok(available[0]));
        assert_eq!(Kernel::best(), available[0]);
        assert!(available.ends_with(&[Kernel::Portable, Kernel::Scalar]));
        for k in Kernel::ALL[1..].iter().copied() {
            match k.resolve() {
                Ok(c) => assert!(c == k && available.contains(&k)),
                Err(e) => {
                    assert!(!available.contains(&k));
                    let msg = e.to_string();
                    assert!(msg.contains("AVX2") && msg.contains("portable"), "{msg}");
                }
            }
        }
    }
}
