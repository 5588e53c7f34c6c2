//! DS, the downhill simplex method of Nelder and Mead as in Numerical Recipes' `amoeba`
//! (section 2.5), on the full-data RMSE, with restarts.
//!
//! ```text
//! simplex := {x0} + N vertices perturbed from x0,  x0 := RandomPick
//! loop
//!   order vertices: lo (best), nhi (second worst), hi (worst)
//!   if 2|f_hi - f_lo| / (|f_hi| + |f_lo|) < RTOL: restart with x_lo kept as a vertex
//!   reflect hi through the opposite face
//!   if better than lo: expand (twice as far)
//!   else if not better than nhi: contract towards the face;
//!        if still not better than the old hi: shrink every vertex towards lo
//! ```
//!
//! Choices where the paper is ambiguous:
//! - The box: trial points (reflection, expansion, contraction) are clamped into the box
//!   coordinate-wise; initial perturbations that leave the box go the other way instead.
//! - The initial simplex: vertex `i` moves coordinate `i` of the random vertex by
//!   `initial_step` times the box width, in a random direction.
//! - A restart keeps the best vertex and perturbs the others from it afresh (section 2.5: against
//!   false convergence). When such a restart improves the best value by less than a relative
//!   [`MIN_RESTART_GAIN`], the convergence was genuine and the search restarts from a new random
//!   pick instead (otherwise DS would re-converge on the same point forever). A run whose
//!   vertices are all unevaluable (`+inf`), or that exceeds `max_steps` evaluations (Numerical
//!   Recipes' NMAX), also restarts from a new random pick.
//! - Every vertex evaluation is a full-data RMSE (counted as RMSE rows).

use crate::registry::Algorithm;
use crate::search::{Search, Stop};
use crate::validate::{ConfigError, check_at_least, check_count};
use rand::RngExt;
use serde::{Deserialize, Serialize};

/// A restart that keeps the best vertex must improve the best value by at least this relative
/// amount to be followed by another such restart.
pub const MIN_RESTART_GAIN: f64 = 1e-3;

/// DS's parameters.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct DsConfig {
    /// Fractional-range termination tolerance RTOL (section 3.1.6 sweeps 0.07 to 0.10; all
    /// 1000 runs on the tuning instance ended within 12 s at 0.08).
    pub rtol: f64,
    /// Initial perturbation of each vertex, as a fraction of the box width (0 < step <= 1).
    pub initial_step: f64,
    /// Restart after termination, keeping the best vertex (otherwise the trial finishes).
    pub restart: bool,
    /// Function evaluations allowed per simplex run before a fresh restart (NR's NMAX).
    pub max_steps: usize,
}

impl Default for DsConfig {
    fn default() -> Self {
        Self {
            rtol: 0.08,
            initial_step: 0.1,
            restart: true,
            max_steps: 5000,
        }
    }
}

impl DsConfig {
    /// Checks the parameters; the error names the field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        check_at_least("ds", "rtol", self.rtol, 0.0)?;
        if !(self.initial_step > 0.0 && self.initial_step <= 1.0) {
            return Err(ConfigError::new(
                "ds",
                "initial_step",
                format!("must be in (0, 1], found {}", self.initial_step),
            ));
        }
        check_count("ds", "max_steps", self.max_steps, 1)
    }
}

/// The simplex: `N + 1` vertices of dimension `N` and their objective values.
struct Simplex {
    n: usize,
    p: Vec<f64>,
    y: Vec<f64>,
    psum: Vec<f64>,
    trial: Vec<f64>,
    lower: Vec<f64>,
    upper: Vec<f64>,
}

impl Simplex {
    fn vertex(&self, i: usize) -> &[f64] {
        &self.p[i * self.n..(i + 1) * self.n]
    }

    fn vertex_mut(&mut self, i: usize) -> &mut [f64] {
        &mut self.p[i * self.n..(i + 1) * self.n]
    }

    fn update_psum(&mut self) {
        self.psum.fill(0.0);
        for i in 0..=self.n {
            for j in 0..self.n {
                self.psum[j] += self.p[i * self.n + j];
            }
        }
    }

    /// Places vertices 1..=N by perturbing vertex 0 along each axis, and evaluates them.
    fn perturb_from_vertex0<S: Search + ?Sized>(
        &mut self,
        search: &mut S,
        step: f64,
    ) -> Result<(), Stop> {
        let n = self.n;
        for i in 1..=n {
            let j = i - 1;
            let (x0, lo, hi) = (self.p[j], self.lower[j], self.upper[j]);
            let delta = step * (hi - lo);
            let mut xj = if search.rng().random_bool(0.5) {
                x0 + delta
            } else {
                x0 - delta
            };
            if xj > hi || xj < lo {
                xj = 2.0 * x0 - xj; // the other way
            }
            self.p.copy_within(0..n, i * n);
            self.p[i * n + j] = xj.clamp(lo, hi);
            self.y[i] = search.evaluate(self.vertex(i))?;
        }
        self.update_psum();
        Ok(())
    }

    /// Numerical Recipes' `amotry`: moves the worst vertex by factor `fac` through the face of
    /// the others (clamped into the box); replaces it if the trial point is better.
    fn try_move<S: Search + ?Sized>(
        &mut self,
        search: &mut S,
        hi: usize,
        fac: f64,
    ) -> Result<f64, Stop> {
        let n = self.n;
        let fac1 = (1.0 - fac) / n as f64;
        let fac2 = fac1 - fac;
        for j in 0..n {
            let t = self.psum[j] * fac1 - self.p[hi * n + j] * fac2;
            self.trial[j] = t.clamp(self.lower[j], self.upper[j]);
        }
        let y_try = search.evaluate(&self.trial)?;
        if y_try < self.y[hi] {
            self.y[hi] = y_try;
            for j in 0..n {
                self.psum[j] += self.trial[j] - self.p[hi * n + j];
                self.p[hi * n + j] = self.trial[j];
            }
        }
        Ok(y_try)
    }

    /// Indices of the best, worst and second-worst vertices.
    fn order(&self) -> (usize, usize, usize) {
        let (mut lo, mut hi, mut nhi) = if self.y[0] > self.y[1] {
            (0, 0, 1)
        } else {
            (0, 1, 0)
        };
        for i in 0..=self.n {
            if self.y[i] <= self.y[lo] {
                lo = i;
            }
            if self.y[i] > self.y[hi] {
                nhi = hi;
                hi = i;
            } else if self.y[i] > self.y[nhi] && i != hi {
                nhi = i;
            }
        }
        (lo, hi, nhi)
    }

    /// Moves every vertex but `lo` halfway towards it and re-evaluates them.
    fn shrink_towards<S: Search + ?Sized>(
        &mut self,
        search: &mut S,
        lo: usize,
    ) -> Result<(), Stop> {
        let n = self.n;
        for i in 0..=n {
            if i == lo {
                continue;
            }
            for j in 0..n {
                self.p[i * n + j] = 0.5 * (self.p[i * n + j] + self.p[lo * n + j]);
            }
            self.y[i] = search.evaluate(self.vertex(i))?;
        }
        self.update_psum();
        Ok(())
    }
}

/// Fractional range of the simplex's values; infinite while the worst vertex is unevaluable.
fn fractional_range(f_hi: f64, f_lo: f64) -> f64 {
    if f_hi.is_finite() && f_lo.is_finite() {
        2.0 * (f_hi - f_lo).abs() / (f_hi.abs() + f_lo.abs() + 1e-300)
    } else {
        f64::INFINITY
    }
}

impl Algorithm for DsConfig {
    const KIND: &'static str = "ds";

    fn validate(&self) -> Result<(), ConfigError> {
        DsConfig::validate(self)
    }

    fn run(&self, search: &mut dyn Search) -> Result<(), Stop> {
        run(self, search)
    }
}

/// Runs DS.
pub fn run<S: Search + ?Sized>(config: &DsConfig, search: &mut S) -> Result<(), Stop> {
    let n = search.dim();
    let mut simplex = Simplex {
        n,
        p: vec![0.0; (n + 1) * n],
        y: vec![f64::INFINITY; n + 1],
        psum: vec![0.0; n],
        trial: vec![0.0; n],
        lower: search.lower().to_vec(),
        upper: search.upper().to_vec(),
    };
    let mut fresh = true;
    // Best value at the start of the current run (+inf for a fresh run).
    let mut y_start = f64::INFINITY;
    loop {
        if fresh {
            search.count("random_picks");
            search.random_pick(simplex.vertex_mut(0));
            simplex.y[0] = search.evaluate(simplex.vertex(0))?;
        } else {
            search.count("restarts");
        }
        simplex.perturb_from_vertex0(search, config.initial_step)?;
        let mut steps = 0;
        // One simplex run (amoeba) until the fractional range falls below RTOL.
        let lo = loop {
            let (lo, hi, nhi) = simplex.order();
            if fractional_range(simplex.y[hi], simplex.y[lo]) < config.rtol {
                break Some(lo);
            }
            if steps >= config.max_steps || !simplex.y[lo].is_finite() {
                break None;
            }
            steps += 2;
            let y_try = simplex.try_move(search, hi, -1.0)?; // reflect
            if y_try <= simplex.y[lo] {
                simplex.try_move(search, hi, 2.0)?; // expand
            } else if y_try >= simplex.y[nhi] {
                let y_save = simplex.y[hi];
                let y_try = simplex.try_move(search, hi, 0.5)?; // contract
                if y_try >= y_save {
                    simplex.shrink_towards(search, lo)?;
                    steps += n;
                }
            } else {
                steps -= 1;
            }
        };
        match lo {
            Some(lo) => {
                if !config.restart {
                    return Ok(());
                }
                let y_lo = simplex.y[lo];
                if y_lo < y_start * (1.0 - MIN_RESTART_GAIN) {
                    // Restart with the best vertex kept (as vertex 0).
                    simplex.p.copy_within(lo * n..(lo + 1) * n, 0);
                    simplex.y[0] = y_lo;
                    y_start = y_lo;
                    fresh = false;
                } else {
                    y_start = f64::INFINITY;
                    fresh = true;
                }
            }
            None => {
                y_start = f64::INFINITY;
                fresh = true;
            }
        }
    }
}
