//! Problem traits and the forward-difference adapter.

/// A nonlinear least-squares problem: minimise `0.5 * sum_i r_i(x)^2` over a box.
///
/// The Jacobian is column-major: `jac[j * m + i] = d r_i / d x_j`.
pub trait Problem {
    /// Number of residuals `m`.
    fn residual_count(&self) -> usize;
    /// Number of parameters `p`.
    fn parameter_count(&self) -> usize;
    /// Residuals at `x` into `r` (length `m`). Return `false` when the residuals cannot be
    /// computed (overflow, NaN, out of domain): a failed evaluation, not a panic.
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool;
    /// Column-major Jacobian at `x` into `jac` (length `m * p`). Return `false` on failure.
    fn jacobian(&mut self, x: &[f64], jac: &mut [f64]) -> bool;
    /// Asked once per iteration, before the Jacobian is evaluated, after a failed evaluation,
    /// and during a step's computation once per million flops of factorizations (models of
    /// more than about 100 free variables): return `true` to end the solve with
    /// [`crate::Outcome::Interrupted`] (code 11, NL2SOL's STOPX), `x` holding the last accepted
    /// point. The hook for a caller's clock (a CPU-time cutoff inside a long descent); keep it
    /// cheap. The default never stops.
    fn should_stop(&mut self) -> bool {
        false
    }
}

impl<P: Problem + ?Sized> Problem for &mut P {
    fn residual_count(&self) -> usize {
        (**self).residual_count()
    }
    fn parameter_count(&self) -> usize {
        (**self).parameter_count()
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        (**self).residuals(x, r)
    }
    fn jacobian(&mut self, x: &[f64], jac: &mut [f64]) -> bool {
        (**self).jacobian(x, jac)
    }
    fn should_stop(&mut self) -> bool {
        (**self).should_stop()
    }
}

/// A least-squares problem that can only compute residuals; wrap it in [`ForwardDifference`]
/// to obtain a [`Problem`].
pub trait ResidualsOnly {
    /// Number of residuals `m`.
    fn residual_count(&self) -> usize;
    /// Number of parameters `p`.
    fn parameter_count(&self) -> usize;
    /// Residuals at `x` into `r` (length `m`); `false` when they cannot be computed.
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool;
    /// As [`Problem::should_stop`] (forwarded by [`ForwardDifference`]).
    fn should_stop(&mut self) -> bool {
        false
    }
}

impl<P: ResidualsOnly + ?Sized> ResidualsOnly for &mut P {
    fn residual_count(&self) -> usize {
        (**self).residual_count()
    }
    fn parameter_count(&self) -> usize {
        (**self).parameter_count()
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        (**self).residuals(x, r)
    }
    fn should_stop(&mut self) -> bool {
        (**self).should_stop()
    }
}

/// Adapter that turns a [`ResidualsOnly`] problem into a [`Problem`] with a forward-difference
/// Jacobian, as N2FB does.
///
/// Column `j` uses the step `h_j = sqrt(eps) * max(|x_j|, typical_j)` (typical size 1 unless set
/// with [`ForwardDifference::with_typical_sizes`]); when bounds are given with
/// [`ForwardDifference::with_bounds`] the step is flipped (backward difference) when `x + h` would
/// leave the box, and halved if neither direction fits. Residual evaluations made for the Jacobian
/// are counted apart ([`ForwardDifference::difference_evaluations`]), as N2FB counts them apart
/// from its evaluation limit. The residuals at the base point are reused from the last
/// [`Problem::residuals`] call when it was made at the same `x` (the solver always evaluates the
/// Jacobian at the point it evaluated last), so a Jacobian costs `p` extra evaluations.
///
/// All scratch space is allocated in the constructor: Jacobians allocate nothing.
#[derive(Clone, Debug)]
pub struct ForwardDifference<P> {
    inner: P,
    m: usize,
    p: usize,
    last_x: Vec<f64>,
    last_r: Vec<f64>,
    last_valid: bool,
    x_work: Vec<f64>,
    r_work: Vec<f64>,
    lower: Vec<f64>,
    upper: Vec<f64>,
    typical: Vec<f64>,
    difference_evaluations: usize,
}

impl<P: ResidualsOnly> ForwardDifference<P> {
    /// Wraps `inner`; no bounds, typical parameter size 1.
    pub fn new(inner: P) -> Self {
        let m = inner.residual_count();
        let p = inner.parameter_count();
        Self {
            inner,
            m,
            p,
            last_x: vec![0.0; p],
            last_r: vec![0.0; m],
            last_valid: false,
            x_work: vec![0.0; p],
            r_work: vec![0.0; m],
            lower: vec![f64::NEG_INFINITY; p],
            upper: vec![f64::INFINITY; p],
            typical: vec![1.0; p],
            difference_evaluations: 0,
        }
    }

    /// Keeps difference points inside `[lower, upper]` (the same box the solver uses). Slices of
    /// the wrong length are ignored (the box stays unbounded).
    pub fn with_bounds(mut self, lower: &[f64], upper: &[f64]) -> Self {
        if lower.len() == self.p && upper.len() == self.p {
            self.lower.copy_from_slice(lower);
            self.upper.copy_from_slice(upper);
        }
        self
    }

    /// Sets the typical magnitude of each parameter (the floor of the difference step is
    /// `sqrt(eps) * typical_j`). Non-positive or non-finite entries and slices of the wrong
    /// length are ignored.
    pub fn with_typical_sizes(mut self, typical: &[f64]) -> Self {
        if typical.len() == self.p {
            for (t, &v) in self.typical.iter_mut().zip(typical) {
                if v.is_finite() && v > 0.0 {
                    *t = v;
                }
            }
        }
        self
    }

    /// Residual evaluations spent on difference Jacobians so far.
    pub fn difference_evaluations(&self) -> usize {
        self.difference_evaluations
    }

    /// Resets the difference-evaluation counter.
    pub fn reset_count(&mut self) {
        self.difference_evaluations = 0;
    }

    /// The wrapped problem.
    pub fn inner(&self) -> &P {
        &self.inner
    }

    /// The wrapped problem, mutably. Changing it invalidates the cached base residuals.
    pub fn inner_mut(&mut self) -> &mut P {
        self.last_valid = false;
        &mut self.inner
    }

    /// Unwraps the adapter.
    pub fn into_inner(self) -> P {
        self.inner
    }
}

impl<P: ResidualsOnly> Problem for ForwardDifference<P> {
    fn residual_count(&self) -> usize {
        self.m
    }
    fn should_stop(&mut self) -> bool {
        self.inner.should_stop()
    }
    fn parameter_count(&self) -> usize {
        self.p
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        let ok = self.inner.residuals(x, r);
        if ok && x.len() == self.p && r.len() == self.m {
            self.last_x.copy_from_slice(x);
            self.last_r.copy_from_slice(r);
            self.last_valid = true;
        } else {
            self.last_valid = false;
        }
        ok
    }
    fn jacobian(&mut self, x: &[f64], jac: &mut [f64]) -> bool {
        let (m, p) = (self.m, self.p);
        if x.len() != p || jac.len() != m * p {
            return false;
        }
        if !(self.last_valid && self.last_x == x) {
            self.difference_evaluations += 1;
            if !self.inner.residuals(x, &mut self.last_r) {
                self.last_valid = false;
                return false;
            }
            self.last_x.copy_from_slice(x);
            self.last_valid = true;
        }
        let sqrt_eps = f64::EPSILON.sqrt();
        self.x_work.copy_from_slice(x);
        for j in 0..p {
            let mut h = sqrt_eps * x[j].abs().max(self.typical[j]);
            // Keep the difference point inside the box: flip to a backward difference, and halve
            // the step when neither side has room (a box narrower than the step).
            let mut tries = 0;
            loop {
                if x[j] + h <= self.upper[j] && x[j] + h >= self.lower[j] {
                    break;
                }
                if x[j] - h >= self.lower[j] && x[j] - h <= self.upper[j] {
                    h = -h;
                    break;
                }
                h *= 0.5;
                tries += 1;
                if tries > 60 {
                    return false;
                }
            }
            self.x_work[j] = x[j] + h;
            let h_actual = self.x_work[j] - x[j];
            self.difference_evaluations += 1;
            let ok = self.inner.residuals(&self.x_work, &mut self.r_work);
            self.x_work[j] = x[j];
            if !ok || h_actual == 0.0 {
                return false;
            }
            let col = &mut jac[j * m..(j + 1) * m];
            for ((c, &r1), &r0) in col.iter_mut().zip(&self.r_work).zip(&self.last_r) {
                *c = (r1 - r0) / h_actual;
            }
        }
        true
    }
}
