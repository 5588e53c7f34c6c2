//! The Lafortune evaluator: residuals and analytic Jacobian of a Lafortune layout over
//! the family's [`Samples`].
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
//! [`crate::Evaluator::residuals`] on [`POWERS_MIN_ROWS`] or more samples (every kernel but the scalar
//! reference) keeps each
//! lobe's `d^n` and `ln d`; a Jacobian at the same point (bit for bit), on the same samples
//! (the samples' stamp) and with the same kernel reuses them instead of recomputing the
//! logarithm and exponential, which are most of its cost. That is what a descent does after
//! every accepted step.
//!
//! Safety over the box: `d <= 0` gives 0 with zero derivatives (also for `n = 0`);
//! `n = 0`, `d > 0` gives 1 with zero C-derivatives; when `d > 1` and `n` is large the value
//! overflows to `+inf`, and then the evaluation fails (never NaN).
//!
//! Kernels ([`Kernel`], from `brdf-simd`, chosen per [`Evaluator`]: `auto` by default, or by
//! name with [`crate::Evaluator::with_kernel`] / [`crate::Evaluator::set_kernel`]): [`Kernel::Scalar`] is the
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
//! [`Kernel::Scalar`] to about 1e-12 relative over the whole Table 1 box and for exponents up
//! to [`MAX_EXPONENT`](crate::MAX_EXPONENT) (beyond the rounding of `d`, which `n` amplifies);
//! they report overflow
//! (`d^n = +inf`) the same way and never produce NaN values (test
//! `every_kernel_agrees_with_scalar_over_the_box`).

use super::coef::{BLOCK, Coef, Col, Field, GENERIC, JacWork};
use super::samples::{NAME, View, view};
use crate::evaluate::{Evaluate, grown};
use crate::family::{Coord, LayoutParam, LobeKind};
use crate::fastmath::Plain;
use crate::samples::Samples;
use brdf_simd::Kernel;

mod columns;
mod impls;
mod lobe;
mod scalar;
#[cfg(target_arch = "x86_64")]
mod simd;

use impls::{jacobian_impl, residuals_impl};

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
    /// The exponent's coordinate.
    n_coord: Coord,
    /// The `R` term can be skipped (isotropic, or pan fixed at 0).
    no_r: bool,
}

/// The Lafortune family's [`Evaluate`]: the evaluation plan of one layout and all its
/// scratch space.
#[derive(Clone, Debug)]
pub(crate) struct LafortuneEval {
    dim: usize,
    kd: Src,
    plans: Vec<LobePlan>,
    coefs: Vec<Coef>,
    cols: Vec<Col>,
    g: Vec<f64>,
    h: Vec<f64>,
    /// The decoded `kd` of the last [`Evaluate::set_point`].
    kd_value: f64,
    /// The concrete kernel in use (never [`Kernel::Auto`]).
    kernel: Kernel,
    /// `d^n` and `ln d` of every lobe and sample from the last residual evaluation that may
    /// keep them, on at least [`POWERS_MIN_ROWS`] samples, and where they were computed.
    powers: Vec<f64>,
    powers_at: PowersKey,
}

/// Residual evaluations on this many samples or more keep their powers for the Jacobian: a
/// descent asks for the Jacobian at each accepted point, where the residuals were just
/// computed, and the logarithm and exponential are most of the Jacobian's cost.
pub const POWERS_MIN_ROWS: usize = 256;

/// Where [`LafortuneEval::powers`](LafortuneEval) were computed: the point (bit for bit), the
/// samples (their stamp, which changes with every change of them), the rows and the kernel.
#[derive(Clone, Debug, Default)]
struct PowersKey {
    valid: bool,
    x: Vec<f64>,
    stamp: u64,
    rows: usize,
    kernel: Option<Kernel>,
}

impl PowersKey {
    fn matches(&self, x: &[f64], data: &Samples, rows: usize, kernel: Kernel) -> bool {
        self.valid
            && self.stamp == data.stamp()
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

impl LafortuneEval {
    /// The evaluation plan of a Lafortune layout (its lobe kinds and parameters) with the
    /// concrete `kernel`.
    pub(crate) fn new(kinds: &[LobeKind], params: &[LayoutParam], kernel: Kernel) -> Self {
        let mut kd = Src::Fixed(0.0);
        let mut plans: Vec<LobePlan> = kinds
            .iter()
            .map(|&kind| LobePlan {
                kind,
                cx: Src::Fixed(0.0),
                cy: Src::Fixed(0.0),
                cz: Src::Fixed(0.0),
                n: Src::Fixed(0.0),
                pan: Src::Fixed(0.0),
                n_coord: Coord::Identity,
                no_r: false,
            })
            .collect();
        let mut cols = Vec::new();
        let mut next = 0;
        for p in params {
            let field = Field::of(p.def.name);
            let src = match p.fixed {
                Some(v) => Src::Fixed(v),
                None => {
                    cols.push(match p.lobe {
                        None => Col::Kd,
                        Some(k) => Col::Lobe(k, field),
                    });
                    next += 1;
                    Src::Free(next - 1)
                }
            };
            let lobe = p.lobe.unwrap_or(0);
            match field {
                Field::Kd => kd = src,
                Field::Cx | Field::Cxy => plans[lobe].cx = src,
                Field::Cy => plans[lobe].cy = src,
                Field::Cz => plans[lobe].cz = src,
                Field::N => {
                    plans[lobe].n = src;
                    plans[lobe].n_coord = p.coord;
                }
                Field::Pan => plans[lobe].pan = src,
            }
        }
        for pl in &mut plans {
            pl.no_r = pl.kind == LobeKind::Isotropic || matches!(pl.pan, Src::Fixed(v) if v == 0.0);
        }
        LafortuneEval {
            dim: next,
            kd,
            coefs: vec![Coef::default(); plans.len()],
            plans,
            cols,
            g: Vec::new(),
            h: Vec::new(),
            kd_value: 0.0,
            kernel,
            powers: Vec::new(),
            powers_at: PowersKey::default(),
        }
    }

    fn prepare(&mut self, x: &[f64]) -> f64 {
        for (pl, c) in self.plans.iter().zip(self.coefs.iter_mut()) {
            let cx = pl.cx.get(x);
            let cz = pl.cz.get(x);
            let n = match pl.n {
                Src::Free(j) => pl.n_coord.to_physical(x[j]),
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
                n_coord: pl.n_coord,
            };
        }
        self.kd.get(x)
    }
}

impl Evaluate for LafortuneEval {
    fn kernel(&self) -> Kernel {
        self.kernel
    }

    fn set_point(&mut self, x: &[f64]) {
        self.kd_value = self.prepare(x);
    }

    fn values(
        &mut self,
        x: &[f64],
        data: &Samples,
        lo: usize,
        r: &mut [f64],
        may_keep: bool,
    ) -> bool {
        debug_assert_eq!(data.family(), NAME);
        let m = r.len();
        let kd = self.kd_value;
        let keep = may_keep
            && lo == 0
            && m >= POWERS_MIN_ROWS
            && matches!(
                self.kernel,
                Kernel::Avx512 | Kernel::Avx2 | Kernel::Portable
            );
        let v = view(data, lo, lo + m);
        if !keep {
            return residuals_view(self.kernel, &self.coefs, kd, &v, r);
        }
        self.powers_at.valid = false;
        let powers = grown(&mut self.powers, 2 * self.coefs.len() * m);
        let ok = residuals_keeping(self.kernel, &self.coefs, kd, &v, r, Some(powers));
        if ok {
            let key = &mut self.powers_at;
            key.x.clear();
            key.x.extend_from_slice(x);
            (key.stamp, key.rows, key.kernel, key.valid) =
                (data.stamp(), m, Some(self.kernel), true);
        }
        ok
    }

    fn forget(&mut self) {
        self.powers_at.valid = false;
    }

    fn residuals_and_jacobian(
        &mut self,
        x: &[f64],
        data: &Samples,
        r: &mut [f64],
        jac: &mut [f64],
    ) -> bool {
        debug_assert_eq!(data.family(), NAME);
        let m = data.len();
        debug_assert_eq!(x.len(), self.dim);
        let kd = self.prepare(x);
        grown(&mut self.g, m.min(BLOCK));
        grown(&mut self.h, m.min(BLOCK));
        let cached = self.powers_at.matches(x, data, m, self.kernel);
        let w = JacWork {
            coefs: &self.coefs,
            cols: &self.cols,
            kd,
            data: view(data, 0, m),
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
