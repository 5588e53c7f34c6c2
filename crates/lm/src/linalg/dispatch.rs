//! Which build of the long loops (the column survey, `J^T v` and the tall QR's block fold)
//! runs: one process-wide [`Kernel`] choice, resolved once when set and read with one atomic
//! load per call; the CPU's features come from `brdf-simd`'s detection, cached per process.
//!
//! Every build gives the portable build's bits (the lanes are summed in [`super::dot`]'s order
//! and no multiply-add is fused), so the choice changes speed only, never a result: unit tests
//! in `linalg` and `qr` compare the builds bit for bit, and `tests/kernels.rs` whole solves.

use brdf_simd::{Kernel, KernelCell, KernelError};

static KERNEL: KernelCell = KernelCell::new();

/// Selects the kernel of the solver's long loops for the whole process and returns the
/// concrete kernel now in use: [`Kernel::Auto`] (the default) becomes the fastest the CPU has,
/// and [`Kernel::Scalar`] the portable build (the solver has no separate scalar reference: its
/// portable loops are the reference). On error nothing changes.
///
/// # Errors
/// [`KernelError::Unavailable`] when the running CPU lacks the kernel's instructions.
pub fn set_kernel(kernel: Kernel) -> Result<Kernel, KernelError> {
    let concrete = match kernel.resolve()? {
        Kernel::Scalar => Kernel::Portable,
        k => k,
    };
    KERNEL.set(concrete)
}

/// The concrete kernel the solver's long loops use: `avx512`, `avx2` or `portable` (never
/// `auto` or `scalar`); its [`Kernel::name`] is what to record next to results.
pub fn kernel() -> Kernel {
    KERNEL.get()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `scalar` runs the portable build; `auto` the fastest; unavailable kernels are refused.
    /// (The only test in this crate's unit tests that sets the process-wide choice; every
    /// choice gives the same bits, so other tests running meanwhile are unaffected.)
    #[test]
    fn set_kernel_resolves_and_maps_scalar_to_portable() {
        assert_eq!(set_kernel(Kernel::Scalar), Ok(Kernel::Portable));
        assert_eq!(kernel(), Kernel::Portable);
        for k in Kernel::ALL {
            match k.resolve() {
                Ok(Kernel::Scalar) => {}
                Ok(c) => {
                    assert_eq!(set_kernel(k), Ok(c));
                    assert_eq!(kernel(), c);
                }
                Err(e) => assert_eq!(set_kernel(k), Err(e)),
            }
        }
        assert_eq!(set_kernel(Kernel::Auto), Ok(Kernel::best()));
    }
}
