//! Residuals, analytic Jacobian and RMSE of a [`Layout`] over a [`DataSet`].
//!
//! The rotation by pan is folded into per-lobe coefficients once per evaluation:
//! with `P = ux vx`, `Q = uy vy`, `R = ux vy + uy vx`, `S = uz vz` and `c = cos pan`,
//! `s = sin pan`,
//! `d = (Cx c² + Cy s²) P + (Cx s² + Cy c²) Q + (Cx − Cy) c s R + Cz S`,
//! so no sample is ever rotated; isotropic lobes (and lobes whose pan is fixed at 0) use a
//! loop without the `R` term. `d^n = exp(n ln d)` is computed once per sample and lobe and
//! reused: `∂f/∂C = n d^n / d · ∂d/∂C`, `∂f/∂n = d^n ln d`, times `1 + n` in the
//! [`crate::ExponentCoord::Log1p`] coordinate.
//! Pan columns are derivatives **per degree** (the internal pan coordinate is degrees):
//! `∂d/∂pan = π/180 · (Cx − Cy)(sin 2p (Q − P) + cos 2p R)`.
//!
//! [`Evaluator::residuals`] on [`POWERS_MIN_ROWS`] or more samples (every kernel but the scalar
//! reference) keeps each
//! lobe's `d^n` and `ln d`; a Jacobian at the same point (bit for bit), on the same samples
//! (the data set's stamp) and with the same kernel reuses them instead of recomputing the
//! logarithm and exponential, which are most of its cost. That is what a descent does after
//! every accepted step.
//!
//! Safety over the box: `d <= 0` gives 0 with zero derivatives (also for `n = 0`);
//! `n = 0`, `d > 0` gives 1 with zero C-derivatives; when `d > 1` and `n` is large the value
//! overflows to `+inf`, and then [`Evaluator::residuals`] / [`Evaluator::jacobian`] return
//! false and [`Evaluator::sum_squares`] returns `+inf` (never NaN).
//!
//! Kernels ([`Kernel`], from `brdf-simd`, chosen per [`Evaluator`]: `auto` by default, or by
//! name with [`Evaluator::with_kernel`] / [`Evaluator::set_kernel`]): [`Kernel::Scalar`] is the
//! plain libm reference (one sample at a time, `powf` and `ln`); the fast per-sample loops call
//! branch-free `exp`/`ln` (no libm calls) and exist in three compiled copies, `auto` picking
//! the best the running CPU has (detected once per process), so one portable x86-64 binary
//! uses what the machine has:
//! - [`Kernel::Avx512`]: hand-written AVX-512F kernels, 8 lanes, `getexp`/`getmant` for the
//!   logarithm and `scalef` for the exponential; the Jacobian is written in the same pass as
//!   the values (the data loaded once per lobe);
//! - [`Kernel::Avx2`]: the generic loops compiled with AVX2+FMA (auto-vectorised, 4 lanes);
//! - [`Kernel::Portable`]: the generic loops for the baseline target (SSE2).
//!
//! All agree with the scalar `powf` reference ([`BrdfParams::value`](crate::BrdfParams::value))
//! to about 3e-13 relative (test `evaluator_agrees_with_scalar_libm_reference`), and with
//! [`Kernel::Scalar`] to about 1e-12 relative over the whole Table 1 box; they report overflow
//! (`d^n = +inf`) the same way and never produce NaN values (test
//! `every_kernel_agrees_with_scalar_over_the_box`).

use crate::data::{DataSet, View};
use crate::fastmath::{
    MulAdd, Plain, all_exp_normal, ln_clamped, ln_clamped_normal, no_subnormal, pow_from_ln,
    pow_from_ln_normal,
};
use crate::layout::{ExponentCoord, Field, Layout, LobeKind};
pub use brdf_simd::{Kernel, KernelError};

mod columns;
mod lobe;
mod scalar;
#[cfg(target_arch = "x86_64")]
mod simd;

use columns::{column, four_columns, lobe_columns};
pub(crate) use lobe::g_factors;
use lobe::{lobe_full, lobe_values};

/// Where a model quantity comes from: a free-vector entry or a fixed value.
#[derive(Clone, Copy, Debug)]
enum Src {
    Free(usize),
    Fixed(f64),
}

impl Src {
    #[inline]
    fn get(self, x: &[f64]) -> f64 {
        match self {
            Src::Free(j) => x[j],
            Src::Fixed(v) => v,
        }
    }
}

#[derive(Clone, Copy, Debug)]
struct LobePlan {
    kind: LobeKind,
    /// For isotropic lobes `cx` holds cxy and `cy`, `pan` are unused.
    cx: Src,
    cy: Src,
    cz: Src,
    n: Src,
    pan: Src,
    /// The `R` term can be skipped (isotropic, or pan fixed at 0).
    no_r: bool,
}

/// Per-lobe coefficients for one parameter vector.
#[derive(Clone, Copy, Debug, Default)]
struct Coef {
    ap: f64,
    aq: f64,
    ar: f64,
    cz: f64,
    n: f64,
    c2: f64,
    s2: f64,
    cs: f64,
    cx: f64,
    cy: f64,
    sin2: f64,
    cos2: f64,
    no_r: bool,
}

/// What one Jacobian column differentiates.
#[derive(Clone, Copy, Debug)]
enum Col {
    Kd,
    Lobe(usize, Field),
}

/// Per-thread evaluator for one [`Layout`]: owns all scratch space, so repeated calls do not
/// allocate once the buffers have grown to the largest data set seen.
#[derive(Clone, Debug)]
pub struct Evaluator {
    layout: Layout,
    kd: Src,
    plans: Vec<LobePlan>,
    coefs: Vec<Coef>,
    cols: Vec<Col>,
    g: Vec<f64>,
    h: Vec<f64>,
    rbuf: Vec<f64>,
    sub: DataSet,
    /// The concrete kernel in use (never [`Kernel::Auto`]).
    kernel: Kernel,
    /// `d^n` and `ln d` of every lobe and sample from the last [`Evaluator::residuals`] on a
    /// data set of at least [`POWERS_MIN_ROWS`] samples, and where they were computed.
    powers: Vec<f64>,
    powers_at: PowersKey,
}

/// Residual evaluations on this many samples or more keep their powers for the Jacobian: a
/// descent asks for the Jacobian at each accepted point, where the residuals were just
/// computed, and the logarithm and exponential are most of the Jacobian's cost.
pub const POWERS_MIN_ROWS: usize = 256;

/// Where [`Evaluator::powers`](Evaluator) were computed: the point (bit for bit), the data set
/// (its stamp, which changes with every change of its samples), the rows and the kernel.
#[derive(Clone, Debug, Default)]
struct PowersKey {
    valid: bool,
    x: Vec<f64>,
    stamp: u64,
    rows: usize,
    kernel: Option<Kernel>,
}

impl PowersKey {
    fn matches(&self, x: &[f64], data: &DataSet, rows: usize, kernel: Kernel) -> bool {
        self.valid
            && self.stamp == data.stamp
            && self.rows == rows
            && self.kernel == Some(kernel)
            && self.x.len() == x.len()
            && self
                .x
                .iter()
                .zip(x)
                .all(|(a, b)| a.to_bits() == b.to_bits())
    }
}

impl Evaluator {
    /// Builds the evaluation plan for `layout`, evaluated with the fastest kernel the CPU has
    /// ([`Kernel::best`]).
    pub fn new(layout: &Layout) -> Self {
        let mut kd = Src::Fixed(0.0);
        let mut plans: Vec<LobePlan> = layout
            .kinds()
            .iter()
            .map(|&kind| LobePlan {
                kind,
                cx: Src::Fixed(0.0),
                cy: Src::Fixed(0.0),
                cz: Src::Fixed(0.0),
                n: Src::Fixed(0.0),
                pan: Src::Fixed(0.0),
                no_r: false,
            })
            .collect();
        let mut cols = Vec::new();
        let mut next = 0;
        for p in &layout.params {
            let src = match p.fixed {
                Some(v) => Src::Fixed(v),
                None => {
                    cols.push(if p.field == Field::Kd {
                        Col::Kd
                    } else {
                        Col::Lobe(p.lobe, p.field)
                    });
                    next += 1;
                    Src::Free(next - 1)
                }
            };
            match p.field {
                Field::Kd => kd = src,
                Field::Cx | Field::Cxy => plans[p.lobe].cx = src,
                Field::Cy => plans[p.lobe].cy = src,
                Field::Cz => plans[p.lobe].cz = src,
                Field::N => plans[p.lobe].n = src,
                Field::Pan => plans[p.lobe].pan = src,
            }
        }
        for pl in &mut plans {
            pl.no_r = pl.kind == LobeKind::Isotropic || matches!(pl.pan, Src::Fixed(v) if v == 0.0);
        }
        Evaluator {
            layout: layout.clone(),
            kd,
            coefs: vec![Coef::default(); plans.len()],
            plans,
            cols,
            g: Vec::new(),
            h: Vec::new(),
            rbuf: Vec::new(),
            sub: DataSet::new(),
            kernel: Kernel::best(),
            powers: Vec::new(),
            powers_at: PowersKey::default(),
        }
    }

    /// [`Evaluator::new`] with the kernel `kernel` ([`Kernel::Auto`]: the fastest the CPU has).
    ///
    /// # Errors
    /// [`KernelError::Unavailable`] when the running CPU lacks the kernel's instructions.
    pub fn with_kernel(layout: &Layout, kernel: Kernel) -> Result<Self, KernelError> {
        let mut ev = Self::new(layout);
        ev.set_kernel(kernel)?;
        Ok(ev)
    }

    /// Selects the evaluation kernel ([`Kernel::Auto`] resolves to the fastest available) and
    /// returns the concrete kernel now in use; on error nothing changes.
    ///
    /// # Errors
    /// [`KernelError::Unavailable`] when the running CPU lacks the kernel's instructions.
    pub fn set_kernel(&mut self, kernel: Kernel) -> Result<Kernel, KernelError> {
        self.kernel = kernel.resolve()?;
        Ok(self.kernel)
    }

    /// The concrete kernel in use (never [`Kernel::Auto`]); its [`Kernel::name`] is what to
    /// record next to results.
    pub fn kernel(&self) -> Kernel {
        self.kernel
    }

    /// The layout this evaluator was built for.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    fn prepare(&mut self, x: &[f64]) -> f64 {
        let coord = self.layout.exponent_coord();
        for (pl, c) in self.plans.iter().zip(self.coefs.iter_mut()) {
            let cx = pl.cx.get(x);
            let cz = pl.cz.get(x);
            let n = match pl.n {
                Src::Free(j) => coord.to_physical(x[j]),
                Src::Fixed(v) => v,
            };
            let (cy, pan) = match pl.kind {
                LobeKind::Isotropic => (cx, 0.0),
                LobeKind::Anisotropic => (pl.cy.get(x), pl.pan.get(x).to_radians()),
            };
            let (s, co) = pan.sin_cos();
            let (sin2, cos2) = (2.0 * pan).sin_cos();
            let (c2, s2, cs) = (co * co, s * s, co * s);
            *c = Coef {
                ap: cx * c2 + cy * s2,
                aq: cx * s2 + cy * c2,
                ar: (cx - cy) * cs,
                cz,
                n,
                c2,
                s2,
                cs,
                cx,
                cy,
                sin2,
                cos2,
                no_r: pl.no_r,
            };
        }
        self.kd.get(x)
    }

    fn check(&self, x: &[f64], data: &DataSet, len: usize) -> bool {
        x.len() == self.layout.dim() && len == data.len()
    }

    /// Residuals `r_i = f(u_i, v_i) - y_i` at internal vector `x`. Returns false (a failed
    /// evaluation) when a value is not finite (overflow) or the lengths do not match.
    pub fn residuals(&mut self, x: &[f64], data: &DataSet, r: &mut [f64]) -> bool {
        self.values(x, data, r, true)
    }

    /// [`Evaluator::residuals`]; with `may_keep` false the powers are never kept (an RMSE is not
    /// followed by a Jacobian at the same point on the same samples, so keeping them would only
    /// cost their stores).
    fn values(&mut self, x: &[f64], data: &DataSet, r: &mut [f64], may_keep: bool) -> bool {
        if !self.check(x, data, r.len()) {
            return false;
        }
        let kd = self.prepare(x);
        let m = r.len();
        let keep = may_keep
            && m >= POWERS_MIN_ROWS
            && matches!(
                self.kernel,
                Kernel::Avx512 | Kernel::Avx2 | Kernel::Portable
            );
        if !keep {
            return residuals_view(self.kernel, &self.coefs, kd, &data.view(0, m), r);
        }
        self.powers_at.valid = false;
        let powers = grown(&mut self.powers, 2 * self.coefs.len() * m);
        let view = data.view(0, m);
        let ok = residuals_keeping(self.kernel, &self.coefs, kd, &view, r, Some(powers));
        if ok {
            let key = &mut self.powers_at;
            key.x.clear();
            key.x.extend_from_slice(x);
            (key.stamp, key.rows, key.kernel, key.valid) = (data.stamp, m, Some(self.kernel), true);
        }
        ok
    }

    /// Drops the powers kept by the last [`Evaluator::residuals`], so that the next Jacobian
    /// computes every `d^n` itself (what a benchmark of the Jacobian alone wants).
    pub fn forget_powers(&mut self) {
        self.powers_at.valid = false;
    }

    /// Column-major Jacobian `jac[j * m + i] = d r_i / d x_j` (length `m * dim`). Returns false
    /// when a value or derivative is not finite or the lengths do not match.
    pub fn jacobian(&mut self, x: &[f64], data: &DataSet, jac: &mut [f64]) -> bool {
        let mut r = std::mem::take(&mut self.rbuf);
        let ok = self.residuals_and_jacobian(x, data, grown(&mut r, data.len()), jac);
        self.rbuf = r;
        ok
    }

    /// Residuals and Jacobian in one pass (each `d^n` computed once for both).
    pub fn residuals_and_jacobian(
        &mut self,
        x: &[f64],
        data: &DataSet,
        r: &mut [f64],
        jac: &mut [f64],
    ) -> bool {
        let m = data.len();
        if !self.check(x, data, r.len()) || jac.len() != m * self.layout.dim() {
            return false;
        }
        let kd = self.prepare(x);
        grown(&mut self.g, m.min(BLOCK));
        grown(&mut self.h, m.min(BLOCK));
        let cached = self.powers_at.matches(x, data, m, self.kernel);
        let w = JacWork {
            coefs: &self.coefs,
            cols: &self.cols,
            coord: self.layout.exponent_coord(),
            kd,
            data,
            powers: cached.then_some(&self.powers[..]),
        };
        match self.kernel {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: a kernel is only selected when the CPU reports its features.
            Kernel::Avx512 => unsafe { simd::jacobian512(&w, r, jac, &mut self.g, &mut self.h) },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: as above.
            Kernel::Avx2 => unsafe { simd::jacobian(&w, r, jac, &mut self.g, &mut self.h) },
            Kernel::Scalar => scalar::jacobian(&w, r, jac),
            _ => jacobian_impl::<Plain, GENERIC>(&w, r, jac, &mut self.g, &mut self.h),
        }
    }

    /// Sum of squared residuals; `+inf` when the evaluation fails (never NaN).
    pub fn sum_squares(&mut self, x: &[f64], data: &DataSet) -> f64 {
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
    pub fn sum_squares_below(&mut self, x: &[f64], data: &DataSet, bound: f64) -> SumBelow {
        let m = data.len();
        let mut r = std::mem::take(&mut self.rbuf);
        let out = self.sum_below_impl(x, data, bound, grown(&mut r, m));
        self.rbuf = r;
        out
    }

    fn sum_below_impl(&mut self, x: &[f64], data: &DataSet, bound: f64, r: &mut [f64]) -> SumBelow {
        let m = data.len();
        let failed = |samples| SumBelow {
            sum_squares: (f64::INFINITY <= bound).then_some(f64::INFINITY),
            samples,
        };
        if x.len() != self.layout.dim() {
            return failed(0);
        }
        let kd = self.prepare(x);
        // The accumulators of `sum_sq`, carried across blocks (whose length is a multiple of 8,
        // so the lanes line up exactly as in one call over all samples).
        let mut acc = [0.0f64; 8];
        let mut tail = 0.0;
        for lo in (0..m).step_by(SUM_BLOCK) {
            let hi = (lo + SUM_BLOCK).min(m);
            let rb = &mut r[lo..hi];
            if !residuals_view(self.kernel, &self.coefs, kd, &data.view(lo, hi), rb) {
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
    pub fn rmse(&mut self, x: &[f64], data: &DataSet) -> f64 {
        if data.is_empty() {
            return 0.0;
        }
        (self.sum_squares(x, data) / data.len() as f64).sqrt()
    }

    /// RMSE over the samples `rows` of `data` (gathered into an internal reused buffer).
    /// Rows out of range are skipped.
    pub fn rmse_rows(&mut self, x: &[f64], data: &DataSet, rows: &[u32]) -> f64 {
        let mut sub = std::mem::take(&mut self.sub);
        data.gather_into(rows, &mut sub);
        let e = self.rmse(x, &sub);
        self.sub = sub;
        e
    }
}

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

/// The first `len` entries of a reused buffer, grown (never shrunk) to hold them. Resizing a
/// buffer down and up again between evaluations of different sizes filled it with zeros each
/// time (2% of an AED profile); every entry is written before it is read.
fn grown(v: &mut Vec<f64>, len: usize) -> &mut [f64] {
    if v.len() < len {
        v.resize(len, 0.0);
    }
    &mut v[..len]
}

/// Residuals of samples `data` into `r` with the kernel `kernel` (concrete).
fn residuals_view(kernel: Kernel, coefs: &[Coef], kd: f64, data: &View<'_>, r: &mut [f64]) -> bool {
    residuals_keeping(kernel, coefs, kd, data, r, None)
}

/// [`residuals_view`] that also stores every lobe's `d^n` and `ln d` in `keep` (ignored by the
/// scalar reference kernel).
fn residuals_keeping(
    kernel: Kernel,
    coefs: &[Coef],
    kd: f64,
    data: &View<'_>,
    r: &mut [f64],
    keep: Option<&mut [f64]>,
) -> bool {
    match kernel {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: a kernel is only selected when the CPU reports its features.
        Kernel::Avx512 => unsafe { simd::residuals512(coefs, kd, data, r, keep) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as above.
        Kernel::Avx2 => unsafe { simd::residuals(coefs, kd, data, r, keep) },
        Kernel::Scalar => scalar::residuals(coefs, kd, data, r),
        _ => residuals_impl::<Plain, GENERIC>(coefs, kd, data, r, keep),
    }
}

const GENERIC: u8 = 0;
const AVX512: u8 = 2;

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

/// True when every element is finite; an integer OR-reduction so it vectorises.
#[inline(always)]
fn all_finite(v: &[f64]) -> bool {
    const EXP: u64 = 0x7FF0_0000_0000_0000;
    let mut bad = 0u64;
    for &x in v {
        // An all-ones exponent field (inf/NaN) carries into bit 63.
        bad |= ((x.to_bits() & EXP) + (1u64 << 52)) & (1u64 << 63);
    }
    bad == 0
}

/// Samples per block in the generic Jacobian: the block's directions, `g` and `h` stay in L1
/// while the lobe's columns are written.
pub(crate) const BLOCK: usize = 512;

#[inline(always)]
fn residuals_impl<A: MulAdd, const K: u8>(
    coefs: &[Coef],
    kd: f64,
    data: &View<'_>,
    r: &mut [f64],
    mut keep: Option<&mut [f64]>,
) -> bool {
    let m = r.len();
    for (ri, &y) in r.iter_mut().zip(&data.value[..m]) {
        *ri = kd - y;
    }
    for (lobe, c) in coefs.iter().enumerate() {
        let keep = keep.as_deref_mut().map(|p| lobe_powers_mut(p, m, lobe));
        if K == AVX512 {
            // SAFETY: K == AVX512 is only instantiated inside AVX-512F functions; the kept
            // columns have m entries.
            #[cfg(target_arch = "x86_64")]
            unsafe {
                crate::avx512::lobe_values(&[c.ap, c.aq, c.ar, c.cz], c.n, !c.no_r, data, r, keep)
            };
        } else if c.no_r {
            lobe_values::<A, false>(c, data, r, keep);
        } else {
            lobe_values::<A, true>(c, data, r, keep);
        }
    }
    all_finite(r)
}

/// Lobe `lobe`'s `(d^n, ln d)` columns in a powers buffer laid out `[f_0, l_0, f_1, l_1, ...]`,
/// each `m` long.
fn lobe_powers_mut(p: &mut [f64], m: usize, lobe: usize) -> (&mut [f64], &mut [f64]) {
    p[2 * lobe * m..(2 * lobe + 2) * m].split_at_mut(m)
}

/// Read-only [`lobe_powers_mut`].
fn lobe_powers(p: &[f64], m: usize, lobe: usize) -> (&[f64], &[f64]) {
    p[2 * lobe * m..(2 * lobe + 2) * m].split_at(m)
}

struct JacWork<'a> {
    coefs: &'a [Coef],
    cols: &'a [Col],
    coord: ExponentCoord,
    kd: f64,
    data: &'a DataSet,
    /// `d^n` and `ln d` of every lobe and sample at this point, when a residual evaluation
    /// at the same point and data left them (every kernel but scalar).
    powers: Option<&'a [f64]>,
}

#[inline(always)]
fn jacobian_impl<A: MulAdd, const K: u8>(
    w: &JacWork<'_>,
    r: &mut [f64],
    jac: &mut [f64],
    g: &mut [f64],
    h: &mut [f64],
) -> bool {
    let m = r.len();
    let data = w.data;
    for (ri, &y) in r.iter_mut().zip(&data.value[..m]) {
        *ri = w.kd - y;
    }
    if m == 0 {
        return true;
    }
    let mut ok = true;
    for (j, col) in jac.chunks_exact_mut(m).enumerate() {
        if let Col::Kd = w.cols[j] {
            col.fill(1.0);
        }
    }
    for (l, c) in w.coefs.iter().enumerate() {
        let (mut cols, rows) = lobe_columns(jac, m, w.cols, l, c);
        let n_scale = w.coord.dn_dx(c.n);
        #[cfg(target_arch = "x86_64")]
        if K == AVX512 {
            // One pass per lobe: value and all its columns, the data loaded once.
            let coef = [c.ap, c.aq, c.ar, c.cz];
            // SAFETY: K == AVX512 is only instantiated inside AVX-512F functions; every
            // column has m entries.
            ok &= unsafe {
                crate::avx512::lobe_jacobian(
                    &coef,
                    c.n,
                    !c.no_r,
                    &data.view(0, m),
                    r,
                    &mut cols,
                    &rows,
                    n_scale,
                    w.powers.map(|p| lobe_powers(p, m, l)),
                )
            };
            continue;
        }
        let powers = w.powers.map(|p| lobe_powers(p, m, l));
        for lo in (0..m).step_by(BLOCK) {
            let hi = (lo + BLOCK).min(m);
            let (gb, hb) = (&mut g[..hi - lo], &mut h[..hi - lo]);
            let cached = powers.map(|(f, lg)| (&f[lo..hi], &lg[lo..hi]));
            if c.no_r {
                lobe_full::<A, false>(c, data, lo, &mut r[lo..hi], gb, hb, cached);
            } else {
                lobe_full::<A, true>(c, data, lo, &mut r[lo..hi], gb, hb, cached);
            }
            ok &= all_finite(gb);
            let [c0, c1, c2, _, c4] = &mut cols;
            if let (Some(c0), Some(c1), Some(c2), Some(c4)) = (c0, c1, c2, c4) {
                let cbs = [
                    &mut c0[lo..hi],
                    &mut c1[lo..hi],
                    &mut c2[lo..hi],
                    &mut c4[lo..hi],
                ];
                four_columns::<A>(data, lo, gb, cbs, [rows[0], rows[1], rows[2], rows[4]]);
            } else {
                for k in [0, 1, 2, 4] {
                    if let Some(col) = &mut cols[k] {
                        column::<A>(data, lo, gb, &mut col[lo..hi], rows[k]);
                    }
                }
            }
            if let Some(col) = &mut cols[3] {
                let cb = &mut col[lo..hi];
                for (o, &hv) in cb.iter_mut().zip(hb.iter()) {
                    *o = hv * n_scale;
                }
                ok &= all_finite(cb);
            }
        }
    }
    ok && all_finite(r)
}
