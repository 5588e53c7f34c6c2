//! The same loops compiled with AVX2 and FMA (and, for the `*512` entry points, AVX-512F
//! with the hand-written lobe kernels of `super::avx512`).

use super::impls::{jacobian_impl, residuals_impl};
use crate::fastmath::Fused;
use crate::lafortune::coef::{AVX512, Coef, GENERIC, JacWork};
use crate::lafortune::samples::View;

/// # Safety
/// The CPU must support AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn residuals(
    coefs: &[Coef],
    kd: f64,
    data: &View<'_>,
    r: &mut [f64],
    keep: Option<&mut [f64]>,
) -> bool {
    residuals_impl::<Fused, GENERIC>(coefs, kd, data, r, keep)
}

/// # Safety
/// The CPU must support AVX-512F, AVX2 and FMA.
#[target_feature(enable = "avx512f,avx2,fma")]
pub(super) unsafe fn residuals512(
    coefs: &[Coef],
    kd: f64,
    data: &View<'_>,
    r: &mut [f64],
    keep: Option<&mut [f64]>,
) -> bool {
    residuals_impl::<Fused, AVX512>(coefs, kd, data, r, keep)
}

/// # Safety
/// The CPU must support AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn jacobian(
    w: &JacWork<'_>,
    r: &mut [f64],
    jac: &mut [f64],
    g: &mut [f64],
    h: &mut [f64],
) -> bool {
    jacobian_impl::<Fused, GENERIC>(w, r, jac, g, h)
}

/// # Safety
/// The CPU must support AVX-512F, AVX2 and FMA.
#[target_feature(enable = "avx512f,avx2,fma")]
pub(super) unsafe fn jacobian512(
    w: &JacWork<'_>,
    r: &mut [f64],
    jac: &mut [f64],
    g: &mut [f64],
    h: &mut [f64],
) -> bool {
    jacobian_impl::<Fused, AVX512>(w, r, jac, g, h)
}
