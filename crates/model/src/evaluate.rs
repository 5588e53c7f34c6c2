//! The [`Evaluate`] trait a family's evaluator implements, and the helpers every evaluator
//! shares.

use crate::samples::Samples;
use brdf_simd::Kernel;

/// A family's evaluator of one layout: the per-thread state (scratch, per-lobe coefficients,
/// caches) behind [`crate::Evaluator`]. Implementations may assume the calls come from
/// [`crate::Evaluator`], which checks the lengths first: `x` has the layout's dimension, `r` and the
/// Jacobian fit `data`.
pub trait Evaluate: Send {
    /// The concrete kernel in use (never [`Kernel::Auto`]).
    fn kernel(&self) -> Kernel;

    /// Decodes the point `x` (internal coordinates) for the [`Evaluate::values`] calls that
    /// follow.
    fn set_point(&mut self, x: &[f64]);

    /// Residuals `r_i = f(u_i, v_i) - y_i` at the point of the last [`Evaluate::set_point`]
    /// (which was `x`) for samples `lo..lo + r.len()` of `data`; false when a value is not
    /// finite. `keep` says that a Jacobian at the same point on the same samples may follow
    /// (and `lo == 0`, `r` covering every sample), so an implementation may keep what it can
    /// reuse for it.
    fn values(&mut self, x: &[f64], data: &Samples, lo: usize, r: &mut [f64], keep: bool) -> bool;

    /// Residuals and the column-major Jacobian `jac[j * m + i] = d r_i / d x_j` over every
    /// sample of `data` at `x`; false when a value or derivative is not finite.
    fn residuals_and_jacobian(
        &mut self,
        x: &[f64],
        data: &Samples,
        r: &mut [f64],
        jac: &mut [f64],
    ) -> bool;

    /// Drops whatever was kept for a Jacobian (a benchmark of the Jacobian alone wants it).
    fn forget(&mut self) {}
}

/// The first `len` entries of a reused buffer, grown (never shrunk) to hold them. Resizing a
/// buffer down and up again between evaluations of different sizes filled it with zeros each
/// time (2% of an AED profile); every entry is written before it is read.
pub fn grown(v: &mut Vec<f64>, len: usize) -> &mut [f64] {
    if v.len() < len {
        v.resize(len, 0.0);
    }
    &mut v[..len]
}

/// True when every element is finite; an integer OR-reduction so it vectorises.
#[inline(always)]
pub fn all_finite(v: &[f64]) -> bool {
    const EXP: u64 = 0x7FF0_0000_0000_0000;
    let mut bad = 0u64;
    for &x in v {
        // An all-ones exponent field (inf/NaN) carries into bit 63.
        bad |= ((x.to_bits() & EXP) + (1u64 << 52)) & (1u64 << 63);
    }
    bad == 0
}
