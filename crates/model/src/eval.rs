//! Residuals, Jacobians and RMSEs of a [`Layout`] over prepared [`Samples`], whatever the
//! family: the [`Evaluator`] every caller uses, over the family's [`Evaluate`].
//!
//! Safety over the box, for every family: a value that overflows makes the evaluation fail
//! ([`Evaluator::residuals`] and [`Evaluator::jacobian`] return false, [`Evaluator::sum_squares`]
//! returns `+inf`), never a NaN value.

use crate::evaluate::{Evaluate, grown};
use crate::family::FamilyRef;
use crate::layout::Layout;
use crate::samples::Samples;
pub use brdf_simd::{Kernel, KernelError};

/// Result of [`Evaluator::sum_squares_below`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SumBelow {
    /// The sum of squared residuals when it is at most the bound (`+inf` for a failed
    /// evaluation only when the bound is `+inf`); `None` when it exceeds the bound.
    pub sum_squares: Option<f64>,
    /// Samples actually evaluated (the data size unless the sum was cut short).
    pub samples: usize,
}

/// Block length of [`Evaluator::sum_squares_below`] (a multiple of 8): the overhead of a
/// block is one check of the partial sum.
pub const SUM_BLOCK: usize = 1024;

/// Per-thread evaluator of one [`Layout`] (any family): residuals, Jacobian, sums of squares
/// and RMSE over the family's prepared [`Samples`] ([`Layout::prepare`]). Owns all scratch
/// space, so repeated calls do not allocate once the buffers have grown to the largest sample
/// set seen.
pub struct Evaluator {
    layout: Layout,
    inner: Box<dyn Evaluate>,
    rbuf: Vec<f64>,
    sub: Samples,
}

impl std::fmt::Debug for Evaluator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Evaluator")
            .field("family", &self.layout.family().name())
            .field("kernel", &self.inner.kernel())
            .finish()
    }
}

impl Evaluator {
    /// The evaluator of `layout` with the fastest kernel the CPU has ([`Kernel::best`]).
    pub fn new(layout: &Layout) -> Self {
        Self::with_kernel(layout, Kernel::Auto).expect("the fastest available kernel is available")
    }

    /// [`Evaluator::new`] with the kernel `kernel` ([`Kernel::Auto`]: the fastest the CPU has).
    ///
    /// # Errors
    /// [`KernelError::Unavailable`] when the running CPU lacks the kernel's instructions.
    pub fn with_kernel(layout: &Layout, kernel: Kernel) -> Result<Self, KernelError> {
        let inner = build(layout, kernel)?;
        Ok(Evaluator {
            layout: layout.clone(),
            inner,
            rbuf: Vec::new(),
            sub: Samples::empty(layout.family().name(), 0),
        })
    }

    /// Selects the evaluation kernel ([`Kernel::Auto`] resolves to the fastest available) and
    /// returns the concrete kernel now in use; on error nothing changes.
    ///
    /// # Errors
    /// [`KernelError::Unavailable`] when the running CPU lacks the kernel's instructions.
    pub fn set_kernel(&mut self, kernel: Kernel) -> Result<Kernel, KernelError> {
        self.inner = build(&self.layout, kernel)?;
        Ok(self.inner.kernel())
    }

    /// The concrete kernel in use (never [`Kernel::Auto`]); its [`Kernel::name`] is what to
    /// record next to results.
    pub fn kernel(&self) -> Kernel {
        self.inner.kernel()
    }

    /// The layout this evaluator was built for.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The family.
    pub fn family(&self) -> &FamilyRef {
        self.layout.family()
    }

    fn fits(&self, x: &[f64], data: &Samples, len: usize) -> bool {
        x.len() == self.layout.dim() && len == data.len()
    }

    /// Residuals `r_i = f(u_i, v_i) - y_i` at internal vector `x`. Returns false (a failed
    /// evaluation) when a value is not finite (overflow) or the lengths do not match.
    pub fn residuals(&mut self, x: &[f64], data: &Samples, r: &mut [f64]) -> bool {
        self.values(x, data, r, true)
    }

    /// [`Evaluator::residuals`]; with `may_keep` false nothing is kept for a Jacobian (an RMSE
    /// is not followed by a Jacobian at the same point on the same samples).
    fn values(&mut self, x: &[f64], data: &Samples, r: &mut [f64], may_keep: bool) -> bool {
        if !self.fits(x, data, r.len()) {
            return false;
        }
        self.inner.set_point(x);
        self.inner.values(x, data, 0, r, may_keep)
    }

    /// Drops what the last [`Evaluator::residuals`] kept, so that the next Jacobian computes
    /// everything itself (what a benchmark of the Jacobian alone wants).
    pub fn forget_powers(&mut self) {
        self.inner.forget();
    }

    /// Column-major Jacobian `jac[j * m + i] = d r_i / d x_j` (length `m * dim`). Returns false
    /// when a value or derivative is not finite or the lengths do not match.
    pub fn jacobian(&mut self, x: &[f64], data: &Samples, jac: &mut [f64]) -> bool {
        let mut r = std::mem::take(&mut self.rbuf);
        let ok = self.residuals_and_jacobian(x, data, grown(&mut r, data.len()), jac);
        self.rbuf = r;
        ok
    }

    /// Residuals and Jacobian in one pass.
    pub fn residuals_and_jacobian(
        &mut self,
        x: &[f64],
        data: &Samples,
        r: &mut [f64],
        jac: &mut [f64],
    ) -> bool {
        if !self.fits(x, data, r.len()) || jac.len() != data.len() * self.layout.dim() {
            return false;
        }
        self.inner.residuals_and_jacobian(x, data, r, jac)
    }

    /// Sum of squared residuals; `+inf` when the evaluation fails (never NaN).
    pub fn sum_squares(&mut self, x: &[f64], data: &Samples) -> f64 {
        let mut r = std::mem::take(&mut self.rbuf);
        let rm = grown(&mut r, data.len());
        let ok = self.values(x, data, rm, false);
        let ss = if ok { sum_sq(rm) } else { f64::INFINITY };
        self.rbuf = r;
        if ss.is_finite() { ss } else { f64::INFINITY }
    }

    /// [`Evaluator::sum_squares`], stopping early once the partial sum exceeds `bound`.
    ///
    /// The residuals are computed in blocks of [`SUM_BLOCK`] samples; after each block the
    /// partial sum is compared with `bound`. Returns `sum_squares: None` as soon as it exceeds
    /// `bound` (then the full sum does too: every term is non-negative), otherwise the full sum,
    /// **bit for bit equal** to [`Evaluator::sum_squares`] (same kernel, same per-sample
    /// arithmetic, same summation order). A failed evaluation counts as `+inf`, so it gives
    /// `None` for any finite `bound`. `samples` is how many samples were actually evaluated.
    pub fn sum_squares_below(&mut self, x: &[f64], data: &Samples, bound: f64) -> SumBelow {
        let m = data.len();
        let mut r = std::mem::take(&mut self.rbuf);
        let out = self.sum_below_impl(x, data, bound, grown(&mut r, m));
        self.rbuf = r;
        out
    }

    fn sum_below_impl(&mut self, x: &[f64], data: &Samples, bound: f64, r: &mut [f64]) -> SumBelow {
        let m = data.len();
        let failed = |samples| SumBelow {
            sum_squares: (f64::INFINITY <= bound).then_some(f64::INFINITY),
            samples,
        };
        if x.len() != self.layout.dim() {
            return failed(0);
        }
        self.inner.set_point(x);
        // The accumulators of `sum_sq`, carried across blocks (whose length is a multiple of 8,
        // so the lanes line up exactly as in one call over all samples).
        let mut acc = [0.0f64; 8];
        let mut tail = 0.0;
        for lo in (0..m).step_by(SUM_BLOCK) {
            let hi = (lo + SUM_BLOCK).min(m);
            let rb = &mut r[lo..hi];
            if !self.inner.values(x, data, lo, rb, false) {
                return failed(hi);
            }
            let mut chunks = rb.chunks_exact(8);
            for c in &mut chunks {
                for k in 0..8 {
                    acc[k] += c[k] * c[k];
                }
            }
            tail = chunks.remainder().iter().map(|v| v * v).sum();
            if hi < m && acc.iter().sum::<f64>() > bound {
                return SumBelow {
                    sum_squares: None,
                    samples: hi,
                };
            }
        }
        let mut ss = tail;
        ss += acc.iter().sum::<f64>();
        let ss = if ss.is_finite() { ss } else { f64::INFINITY };
        SumBelow {
            sum_squares: (ss <= bound).then_some(ss),
            samples: m,
        }
    }

    /// Root mean square error `sqrt(sum_squares / m)`; `+inf` on failure, 0 for an empty set.
    pub fn rmse(&mut self, x: &[f64], data: &Samples) -> f64 {
        if data.is_empty() {
            return 0.0;
        }
        (self.sum_squares(x, data) / data.len() as f64).sqrt()
    }

    /// RMSE over the samples `rows` of `data` (gathered into an internal reused buffer).
    /// Rows out of range are skipped.
    pub fn rmse_rows(&mut self, x: &[f64], data: &Samples, rows: &[u32]) -> f64 {
        let mut sub = std::mem::take(&mut self.sub);
        data.gather_into(rows, &mut sub);
        let e = self.rmse(x, &sub);
        self.sub = sub;
        e
    }
}

fn build(layout: &Layout, kernel: Kernel) -> Result<Box<dyn Evaluate>, KernelError> {
    let kernel = kernel.resolve()?;
    layout
        .family()
        .evaluator(layout.kinds(), layout.params(), kernel)
}

/// Sum of squares with 8 independent accumulators (a single ordered accumulator would make
/// the loop latency-bound and block vectorisation).
#[inline(always)]
fn sum_sq(r: &[f64]) -> f64 {
    let mut acc = [0.0f64; 8];
    let mut chunks = r.chunks_exact(8);
    for c in &mut chunks {
        for k in 0..8 {
            acc[k] += c[k] * c[k];
        }
    }
    let mut s: f64 = chunks.remainder().iter().map(|v| v * v).sum();
    s += acc.iter().sum::<f64>();
    s
}
