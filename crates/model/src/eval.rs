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

/// Samples per pass of the generic lobe loops. Each loop over a chunk does one stage (the
/// direction products, the logarithm, the exponential): a whole `d^n` is a dependency chain
/// of about 150 cycles and 100 vector instructions, more than a small out-of-order window
/// (Zen 1's 192 micro-ops hold less than one 256-bit iteration) can overlap, while each stage
/// alone is short enough for several iterations to be in flight. The arithmetic is the same
/// as computing `d^n` sample by sample, so the results are bit-identical. On Zen 5 too an
/// AVX2 kernel written with intrinsics in one pass (as `crate::avx512`) was slower than these
/// staged loops in every run (docs/performance.md).
const CHUNK: usize = 64;

/// Adds lobe values to `out`; with `keep = Some((f, l))` also stores each sample's `d^n` in
/// `f` and `ln d` in `l` (both `out.len()` long) for a later Jacobian at the same point.
#[inline(always)]
fn lobe_values<A: MulAdd, const R: bool>(
    c: &Coef,
    d: &View<'_>,
    out: &mut [f64],
    keep: Option<(&mut [f64], &mut [f64])>,
) {
    let m = out.len();
    let mut dd = [0.0f64; CHUNK];
    // Where `ln d` and `d^n` go when they are not kept.
    let (mut stack_l, mut stack_f) = ([0.0f64; CHUNK], [0.0f64; CHUNK]);
    let (mut kf, mut kl) = match keep {
        Some((f, l)) => (Some(f), Some(l)),
        None => (None, None),
    };
    for lo in (0..m).step_by(CHUNK) {
        let hi = (lo + CHUNK).min(m);
        let k = hi - lo;
        let pqrs = [
            &d.pxx[lo..hi],
            &d.pyy[lo..hi],
            &d.pxy[lo..hi],
            &d.pzz[lo..hi],
        ];
        let (dd, out) = (&mut dd[..k], &mut out[lo..hi]);
        direction_products::<A, R>(c, pqrs, dd);
        let ll = match kl.as_deref_mut() {
            Some(l) => &mut l[lo..hi],
            None => &mut stack_l[..k],
        };
        ln_stage::<A>(dd, ll);
        let ff = match kf.as_deref_mut() {
            Some(f) => &mut f[lo..hi],
            None => &mut stack_f[..k],
        };
        if all_exp_normal(c.n, ll) {
            add_powers::<A, true>(c.n, dd, ll, ff, out);
        } else {
            add_powers::<A, false>(c.n, dd, ll, ff, out);
        }
    }
}

/// `f = max(0, d)^n` from `l = ln d` and `out += f`, the exponential in its shorter form when
/// `NORMAL` (the caller checked [`all_exp_normal`]; the same bits).
#[inline(always)]
fn add_powers<A: MulAdd, const NORMAL: bool>(
    n: f64,
    ds: &[f64],
    ls: &[f64],
    fs: &mut [f64],
    out: &mut [f64],
) {
    for (((o, f), &l), &x) in out.iter_mut().zip(fs).zip(ls).zip(ds) {
        *f = pow_from_ln_any::<A, NORMAL>(x, n, l);
        *o += *f;
    }
}

/// [`pow_from_ln_normal`] when `NORMAL`, else [`pow_from_ln`].
#[inline(always)]
fn pow_from_ln_any<A: MulAdd, const NORMAL: bool>(d: f64, n: f64, l: f64) -> f64 {
    if NORMAL {
        pow_from_ln_normal::<A>(d, n, l)
    } else {
        pow_from_ln::<A>(d, n, l)
    }
}

/// `ls = ln_clamped(ds)`, through the shorter [`ln_clamped_normal`] when no `d` is subnormal
/// (the same bits).
#[inline(always)]
fn ln_stage<A: MulAdd>(ds: &[f64], ls: &mut [f64]) {
    if no_subnormal(ds) {
        ln_loop::<A, true>(ds, ls);
    } else {
        ln_loop::<A, false>(ds, ls);
    }
}

#[inline(always)]
fn ln_loop<A: MulAdd, const NORMAL: bool>(ds: &[f64], ls: &mut [f64]) {
    for (l, &x) in ls.iter_mut().zip(ds) {
        *l = if NORMAL {
            ln_clamped_normal::<A>(x)
        } else {
            ln_clamped::<A>(x)
        };
    }
}

/// `d = ap P + aq Q + cz S (+ ar R)` for each sample of the chunk's products `[P, Q, R, S]`.
#[inline(always)]
fn direction_products<A: MulAdd, const R: bool>(c: &Coef, pqrs: [&[f64]; 4], dd: &mut [f64]) {
    let k = dd.len();
    let [p, q, r, s] = pqrs;
    let (p, q, r, s) = (&p[..k], &q[..k], &r[..k], &s[..k]);
    let (ap, aq, ar, cz) = (c.ap, c.aq, c.ar, c.cz);
    for i in 0..k {
        let mut x = A::mad(ap, p[i], A::mad(aq, q[i], cz * s[i]));
        if R {
            x = A::mad(ar, r[i], x);
        }
        dd[i] = x;
    }
}

/// Adds lobe values to `out` and stores `g = n d^n / d` and `h = d^n ln d` (0 where `d <= 0`).
/// With `cached = Some((f, l))` (this block's `d^n` and `ln d` from [`lobe_values`] at the same
/// point) the logarithm and exponential are not recomputed; the results are the same bits.
#[inline(always)]
fn lobe_full<A: MulAdd, const R: bool>(
    c: &Coef,
    d: &DataSet,
    lo: usize,
    out: &mut [f64],
    g: &mut [f64],
    h: &mut [f64],
    cached: Option<(&[f64], &[f64])>,
) {
    let m = out.len();
    let hi = lo + m;
    let pqrs = [
        &d.pxx[lo..hi],
        &d.pyy[lo..hi],
        &d.pxy[lo..hi],
        &d.pzz[lo..hi],
    ];
    let (g, h) = (&mut g[..m], &mut h[..m]);
    let n = c.n;
    let (ga, gb) = g_factors(n);
    // Stages as in `lobe_values`, with `g` holding `d` and `h` holding `ln d` in between.
    direction_products::<A, R>(c, pqrs, g);
    let finish = |o: &mut f64, gi: &mut f64, hi: &mut f64, f: f64, l: f64| {
        let x = *gi;
        *o += f;
        // n = 0 must give 0 even when d^n / d overflows.
        let gv = f * ga / if x > 0.0 { x } else { 1.0 } * gb;
        *gi = if n == 0.0 { 0.0 } else { gv };
        *hi = f * l;
    };
    match cached {
        Some((cf, cl)) => {
            let (cf, cl) = (&cf[..m], &cl[..m]);
            for ((((o, gi), hi), &f), &l) in out
                .iter_mut()
                .zip(g.iter_mut())
                .zip(h.iter_mut())
                .zip(cf)
                .zip(cl)
            {
                finish(o, gi, hi, f, l);
            }
        }
        None => {
            ln_stage::<A>(g, h);
            if all_exp_normal(n, h) {
                finish_powers::<A, true>(n, out, g, h, finish);
            } else {
                finish_powers::<A, false>(n, out, g, h, finish);
            }
        }
    }
}

/// The last stage of [`lobe_full`]: `finish(out, g, h, d^n, ln d)` per sample, with `g`
/// holding `d` and `h` holding `ln d` on entry (the exponential's shorter form when `NORMAL`).
#[inline(always)]
fn finish_powers<A: MulAdd, const NORMAL: bool>(
    n: f64,
    out: &mut [f64],
    g: &mut [f64],
    h: &mut [f64],
    finish: impl Fn(&mut f64, &mut f64, &mut f64, f64, f64),
) {
    for ((o, gi), hi) in out.iter_mut().zip(g.iter_mut()).zip(h.iter_mut()) {
        let (x, l) = (*gi, *hi);
        finish(o, gi, hi, pow_from_ln_any::<A, NORMAL>(x, n, l), l);
    }
}

/// Factors `(a, b)` with `g = n d^n / d = (d^n a / d) b` computed without a spurious overflow:
/// `(1, n)` for `n >= 1` (then `d^n / d = d^(n-1)` is at most `max(1, d^n)`, so `n (d^n / d)`
/// overflows only when `g` does) and `(n, 1)` for `n < 1` (then `n d^n <= d^n`). Multiplying by
/// 1 is exact, so each case rounds exactly as `n (d^n / d)` or `(n d^n) / d`. Computing
/// `n d^n / d` left to right overflowed for large `n` with `d > 1` (e.g. `d = 1.5`,
/// `n = 1732.55`: `d^n = 1.2e305` but `n d^n = 2.1e308`, while `g = 1.41e308`).
#[inline(always)]
pub(crate) fn g_factors(n: f64) -> (f64, f64) {
    if n >= 1.0 { (1.0, n) } else { (n, 1.0) }
}

/// `col_i = g_i (a P + b Q + c R + e S)` for samples `lo..lo + col.len()`, `w = [a, b, c, e]`.
/// Every direction column but Cz's has `e = 0` and Cz's is `[0, 0, 0, 1]`; those weights are
/// left out of the sums ([`Weights`]), which (the products being finite) changes nothing but
/// the sign of a zero entry and took 9 to 15% off the AVX2 and portable Jacobians
/// (docs/performance.md).
#[inline(always)]
fn column<A: MulAdd>(d: &DataSet, lo: usize, g: &[f64], col: &mut [f64], w: [f64; 4]) {
    match Weights::of(w) {
        Weights::Pqr(w) => column_with::<A>(d, lo, g, col, |p, q, r, _| pqr::<A>(&w, p, q, r)),
        Weights::S => column_with::<A>(d, lo, g, col, |_, _, _, s| s),
        Weights::All(w) => {
            column_with::<A>(d, lo, g, col, |p, q, r, s| weighted::<A>(&w, p, q, r, s))
        }
    }
}

/// `col_i = g_i t(P_i, Q_i, R_i, S_i)` for samples `lo..lo + col.len()`.
#[inline(always)]
fn column_with<A: MulAdd>(
    d: &DataSet,
    lo: usize,
    g: &[f64],
    col: &mut [f64],
    t: impl Fn(f64, f64, f64, f64) -> f64,
) {
    let m = col.len();
    let hi = lo + m;
    let (p, q) = (&d.pxx[lo..hi], &d.pyy[lo..hi]);
    let (r, s) = (&d.pxy[lo..hi], &d.pzz[lo..hi]);
    let g = &g[..m];
    for i in 0..m {
        col[i] = g[i] * t(p[i], q[i], r[i], s[i]);
    }
}

/// The weights of `P, Q, R, S` in a direction column, by which of them can be left out.
#[derive(Clone, Copy)]
enum Weights {
    /// `[a, b, c, 0]` (Cx, Cy, Cxy and pan).
    Pqr([f64; 3]),
    /// `[0, 0, 0, 1]` (Cz).
    S,
    /// Any other weights.
    All([f64; 4]),
}

impl Weights {
    fn of(w: [f64; 4]) -> Self {
        if w == [0.0, 0.0, 0.0, 1.0] {
            Weights::S
        } else if w[3] == 0.0 {
            Weights::Pqr([w[0], w[1], w[2]])
        } else {
            Weights::All(w)
        }
    }
}

/// `a P + b Q + c R + e S` for `w = [a, b, c, e]`, in the order every column uses.
#[inline(always)]
fn weighted<A: MulAdd>(w: &[f64; 4], p: f64, q: f64, r: f64, s: f64) -> f64 {
    A::mad(w[0], p, A::mad(w[1], q, A::mad(w[2], r, w[3] * s)))
}

/// [`weighted`] with `e = 0`: the same value, but for the sign of a zero result.
#[inline(always)]
fn pqr<A: MulAdd>(w: &[f64; 3], p: f64, q: f64, r: f64) -> f64 {
    A::mad(w[0], p, A::mad(w[1], q, w[2] * r))
}

/// [`column`] for the four direction columns of a lobe with every direction parameter free
/// (slots 0, 1, 2 and 4: Cx, Cy, Cz and pan): one pass, the products and `g` loaded once for
/// all four, each entry computed as [`column`] computes it.
#[inline(always)]
fn four_columns<A: MulAdd>(
    d: &DataSet,
    lo: usize,
    g: &[f64],
    cols: [&mut [f64]; 4],
    w: [[f64; 4]; 4],
) {
    let m = g.len();
    let hi = lo + m;
    let (p, q) = (&d.pxx[lo..hi], &d.pyy[lo..hi]);
    let (r, s) = (&d.pxy[lo..hi], &d.pzz[lo..hi]);
    let [c0, c1, c2, c3] = cols;
    let (c0, c1, c2, c3) = (&mut c0[..m], &mut c1[..m], &mut c2[..m], &mut c3[..m]);
    if let [
        Weights::Pqr(w0),
        Weights::Pqr(w1),
        Weights::S,
        Weights::Pqr(w3),
    ] = w.map(Weights::of)
    {
        for i in 0..m {
            c0[i] = g[i] * pqr::<A>(&w0, p[i], q[i], r[i]);
            c1[i] = g[i] * pqr::<A>(&w1, p[i], q[i], r[i]);
            c2[i] = g[i] * s[i];
            c3[i] = g[i] * pqr::<A>(&w3, p[i], q[i], r[i]);
        }
        return;
    }
    let entry = |w: &[f64; 4], i: usize| g[i] * weighted::<A>(w, p[i], q[i], r[i], s[i]);
    for i in 0..m {
        c0[i] = entry(&w[0], i);
        c1[i] = entry(&w[1], i);
        c2[i] = entry(&w[2], i);
        c3[i] = entry(&w[3], i);
    }
}

/// Samples per block in the generic Jacobian: the block's directions, `g` and `h` stay in L1
/// while the lobe's columns are written.
pub(crate) const BLOCK: usize = 512;

/// The free columns of lobe `l` (slots: Cx or Cxy, Cy, Cz, n, pan) and the weights of
/// `P, Q, R, S` in `∂d/∂θ` for each.
#[allow(clippy::type_complexity)]
fn lobe_columns<'j>(
    jac: &'j mut [f64],
    m: usize,
    cols: &[Col],
    l: usize,
    c: &Coef,
) -> ([Option<&'j mut [f64]>; 5], [[f64; 4]; 5]) {
    let mut out: [Option<&mut [f64]>; 5] = [None, None, None, None, None];
    let mut rows = [[0.0; 4]; 5];
    for (j, col) in jac.chunks_exact_mut(m).enumerate() {
        let Col::Lobe(lobe, field) = cols[j] else {
            continue;
        };
        if lobe != l {
            continue;
        }
        let (slot, row) = match field {
            Field::Cx => (0, [c.c2, c.s2, c.cs, 0.0]),
            Field::Cxy => (0, [1.0, 1.0, 0.0, 0.0]),
            Field::Cy => (1, [c.s2, c.c2, -c.cs, 0.0]),
            Field::Cz => (2, [0.0, 0.0, 0.0, 1.0]),
            Field::N => (3, [0.0; 4]),
            Field::Pan => {
                let k = std::f64::consts::PI / 180.0 * (c.cx - c.cy);
                (4, [-k * c.sin2, k * c.sin2, k * c.cos2, 0.0])
            }
            Field::Kd => continue,
        };
        out[slot] = Some(col);
        rows[slot] = row;
    }
    (out, rows)
}

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

#[cfg(target_arch = "x86_64")]
mod simd {
    //! The same loops compiled with AVX2 and FMA (and, for the `*512` entry points, AVX-512F
    //! with the hand-written lobe kernels of `crate::avx512`).
    use super::*;
    use crate::fastmath::Fused;

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
}

mod scalar {
    //! The reference kernel: one sample at a time, std's libm `powf` and `ln`, no FMA, no
    //! blocking. Mirrors the failure rules of the fast kernels: a value, `g = n d^n / d` (computed
    //! as in [`g_factors`], so it fails only when `g` itself overflows) or
    //! (when the exponent is free) `d^n ln d` that is not finite fails the evaluation.
    use super::*;

    /// `(P, Q, R, S)` and `d` of lobe `c` at sample `i`.
    #[inline]
    fn products(c: &Coef, d: &View<'_>, i: usize) -> ([f64; 4], f64) {
        let p = d.ux[i] * d.vx[i];
        let q = d.uy[i] * d.vy[i];
        let r = d.ux[i] * d.vy[i] + d.uy[i] * d.vx[i];
        let s = d.uz[i] * d.vz[i];
        let mut dd = c.ap * p + c.aq * q + c.cz * s;
        if !c.no_r {
            dd += c.ar * r;
        }
        ([p, q, r, s], dd)
    }

    #[inline]
    fn power(dd: f64, n: f64) -> f64 {
        if dd > 0.0 { dd.powf(n) } else { 0.0 }
    }

    pub(super) fn residuals(coefs: &[Coef], kd: f64, d: &View<'_>, r: &mut [f64]) -> bool {
        let mut ok = true;
        for (i, ri) in r.iter_mut().enumerate() {
            let mut f = kd;
            for c in coefs {
                f += power(products(c, d, i).1, c.n);
            }
            *ri = f - d.value[i];
            ok &= ri.is_finite();
        }
        ok
    }

    pub(super) fn jacobian(w: &JacWork<'_>, r: &mut [f64], jac: &mut [f64]) -> bool {
        let m = r.len();
        let d = w.data.view(0, m);
        for (ri, &y) in r.iter_mut().zip(d.value) {
            *ri = w.kd - y;
        }
        if m == 0 {
            return true;
        }
        for (j, col) in jac.chunks_exact_mut(m).enumerate() {
            if let Col::Kd = w.cols[j] {
                col.fill(1.0);
            }
        }
        let mut ok = true;
        for (l, c) in w.coefs.iter().enumerate() {
            let (mut cols, rows) = lobe_columns(jac, m, w.cols, l, c);
            let n_scale = w.coord.dn_dx(c.n);
            for i in 0..m {
                let (pqrs, dd) = products(c, &d, i);
                let f = power(dd, c.n);
                r[i] += f;
                let (g, h) = if dd > 0.0 {
                    let (ga, gb) = g_factors(c.n);
                    let g = if c.n == 0.0 { 0.0 } else { f * ga / dd * gb };
                    (g, f * dd.ln())
                } else {
                    (0.0, 0.0)
                };
                ok &= g.is_finite();
                for (k, col) in cols.iter_mut().enumerate() {
                    let Some(col) = col else { continue };
                    col[i] = if k == 3 {
                        let v = h * n_scale;
                        ok &= v.is_finite();
                        v
                    } else {
                        let wk = &rows[k];
                        g * (wk[0] * pqrs[0] + wk[1] * pqrs[1] + wk[2] * pqrs[2] + wk[3] * pqrs[3])
                    };
                }
            }
        }
        ok && r.iter().all(|v| v.is_finite())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fastmath::Fused;

    fn coef(n: f64) -> Coef {
        Coef {
            ap: 1.0,
            aq: 0.0,
            ar: 0.0,
            cz: 0.0,
            n,
            c2: 0.0,
            s2: 0.0,
            cs: 0.0,
            cx: 0.0,
            cy: 0.0,
            sin2: 0.0,
            cos2: 0.0,
            no_r: true,
        }
    }

    /// `d = P` for `coef`: three chunks of [`CHUNK`] samples, the first all ordinary (both
    /// fast paths), the second with a subnormal `d` (the general logarithm), the third with
    /// `n ln d` out of the fast exponential's range (the general exponential), plus a tail.
    fn directions() -> Vec<f64> {
        let mut p: Vec<f64> = (0..3 * CHUNK + 7)
            .map(|i| 0.05 + 0.9 * ((i * 37) % 101) as f64 / 101.0)
            .collect();
        p[3] = -0.25;
        p[5] = 0.0;
        p[CHUNK + 9] = 3e-310;
        p[2 * CHUNK + 4] = 1e-200;
        p
    }

    fn check<A: MulAdd>(n: f64) {
        let p = directions();
        let m = p.len();
        let zeros = vec![0.0; m];
        let view = View {
            ux: &zeros,
            uy: &zeros,
            uz: &zeros,
            vx: &zeros,
            vy: &zeros,
            vz: &zeros,
            value: &zeros,
            pxx: &p,
            pyy: &zeros,
            pxy: &zeros,
            pzz: &zeros,
        };
        let c = coef(n);
        let mut out = vec![0.0; m];
        lobe_values::<A, false>(&c, &view, &mut out, None);
        let mut ds = vec![0.0; m];
        direction_products::<A, false>(&c, [&p, &zeros, &zeros, &zeros], &mut ds);
        for (i, (&o, &d)) in out.iter().zip(&ds).enumerate() {
            let want = pow_from_ln::<A>(d, n, ln_clamped::<A>(d));
            assert_eq!(o.to_bits(), want.to_bits(), "sample {i}, d {d}, n {n}");
        }
    }

    /// Directions from a small grid with many zero and negative products, and a `g` with
    /// zeros, so that the columns meet zero sums and zero factors of both signs.
    fn column_data() -> (DataSet, Vec<f64>) {
        let axis = [-1.0, -0.6, 0.0, 0.6, 1.0];
        let mut data = DataSet::new();
        for &a in &axis {
            for &b in &axis {
                for &c in &[0.0, 0.5, 1.0] {
                    data.push([a, b, c], [b, -a, 1.0 - c], 0.25);
                }
            }
        }
        let g = (0..data.len())
            .map(|i| {
                if i % 7 == 0 {
                    0.0
                } else {
                    0.5 - (i % 11) as f64 * 0.13
                }
            })
            .collect();
        (data, g)
    }

    /// Every column of [`column`] and [`four_columns`] with the structural zero weights left
    /// out equals the full weighted sum (values compared with `==`: only the sign of a zero may
    /// differ), for the weights of Cx, Cy, Cz, pan, the isotropic Cxy and arbitrary ones.
    fn check_columns<A: MulAdd>() {
        let (data, g) = column_data();
        let m = data.len();
        let (c, s) = (0.3f64.cos(), 0.3f64.sin());
        let rows = [
            [c * c, s * s, c * s, 0.0],
            [s * s, c * c, -c * s, 0.0],
            [0.0, 0.0, 0.0, 1.0],
            [
                -0.4 * (0.6f64).sin(),
                0.4 * (0.6f64).sin(),
                0.4 * (0.6f64).cos(),
                0.0,
            ],
            [1.0, 1.0, 0.0, 0.0],
            [0.3, -0.2, 0.7, 0.4],
        ];
        let full = |w: &[f64; 4]| -> Vec<f64> {
            (0..m)
                .map(|i| {
                    g[i] * weighted::<A>(w, data.pxx[i], data.pyy[i], data.pxy[i], data.pzz[i])
                })
                .collect()
        };
        for w in &rows {
            let mut col = vec![f64::NAN; m];
            column::<A>(&data, 0, &g, &mut col, *w);
            assert_eq!(col, full(w), "weights {w:?}");
        }
        for w4 in [
            [rows[0], rows[1], rows[2], rows[3]],
            [rows[0], rows[5], rows[2], rows[3]],
        ] {
            let mut cols = vec![vec![f64::NAN; m]; 4];
            let [c0, c1, c2, c3] = &mut cols[..] else {
                unreachable!()
            };
            four_columns::<A>(&data, 0, &g, [c0, c1, c2, c3], w4);
            for (col, w) in cols.iter().zip(&w4) {
                assert_eq!(col, &full(w), "weights {w:?}");
            }
        }
    }

    #[test]
    fn columns_without_zero_weights_equal_the_full_sums() {
        check_columns::<Plain>();
        check_columns::<Fused>();
    }

    /// The chunk-wise fast paths of the logarithm and the exponential give the bits of the
    /// general functions sample by sample, whichever chunks take them.
    #[test]
    fn lobe_values_equal_the_general_functions_in_every_chunk() {
        for n in [0.0, 1.0, 7.5, 350.0] {
            check::<Plain>(n);
            check::<Fused>(n);
        }
    }
}
