//! SA, the paper's basic simulated annealing (section 2.3, Figures 4 and 5), used by SALS and
//! AVG and available on its own (`kind = "sa"`: anneal from a random pick, repeat).
//!
//! ```text
//! SA(s, T_start, T_stop, N_t, N_i):
//!   s' := s; T := T_start; c := (T_stop / T_start)^(1 / (N_t - 1))
//!   for t in 1..=N_t:
//!     for i in 1..=N_i:
//!       s* := perturb(s', T)         s*_p := clamp(s'_p + (ub_p - lb_p) T N(0,1), lb_p, ub_p)
//!       s' := accept(s*, s', T)      P = 1 if f(s*) < f(s'), else exp((f(s') - f(s*)) / (r T))
//!     T := c T
//!   return s'
//! ```
//!
//! Choices where the paper is ambiguous:
//! - The objective `f` is the full-data RMSE ([`Search::evaluate`], `n` RMSE rows per step) by
//!   default; the paper does not say whether SA saw a subsample. With
//!   [`SaConfig::sample_size`] `k > 0` each proposal is judged by its RMSE over a fresh random
//!   subsample of `k` samples (`k` RMSE rows), compared with the value the current candidate had
//!   when it was accepted (not re-estimated, so the comparison is noisy); the candidate SA
//!   returns is evaluated on the full data set, which is the only point where such an SA can
//!   improve the trial's best or reach the target.
//! - `r` is not given in the paper; the default 1 makes a worsening of `T` RMSE units as likely
//!   as `1/e` at temperature `T`.
//! - `N_t = 1` (Table 4's lowest value) anneals at `T_start` only.
//! - SA returns the last accepted candidate `s'`, as Figure 4 does, not the best one seen (the
//!   trial context keeps that anyway).
//! - A candidate whose RMSE cannot be computed (`+inf`) is never accepted (its Metropolis
//!   probability is 0; with a constant acceptance `A` it is rejected too).
//! - Constant acceptance (section 3.1.4: "the Metropolis acceptance criterion was replaced by a
//!   constant acceptance ratio A, ranging between 0.05 and 0.2"): a worsening step is accepted
//!   with probability `A` whatever its size ([`SaConfig::constant_acceptance`]).
//! - The standalone SA (`kind = "sa"`) restarts from a new random pick after each schedule.
//!
//! Beyond the paper ([`Perturbation`]): the paper scales every parameter's noise by its range in
//! the problem's natural units ([`Perturbation::Paper`]): for the exponent that is `n` in
//! `[0, 10000]`, so even `T = 0.005` moves `n` by about 50, which the paper's conclusion blames
//! for SA's failure. [`Perturbation::Optimiser`] instead perturbs every coordinate the optimiser
//! sees by its own range there (`ln(1 + n)` in `[0, ln 10001]` for the exponent), so that the
//! same `T` is a relative change of `n`. Measured against each other in
//! results/sls-anneal-bench.md.

use crate::registry::Algorithm;
use crate::search::{Search, Stop};
use crate::validate::{ConfigError, check_at_least, check_count};
use rand::RngExt;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

/// How SA scales its Gaussian perturbation.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Perturbation {
    /// Figure 5: each parameter moves by `(ub - lb) T N(0,1)` in its natural units (the
    /// exponent as `n`), clamped to the box.
    #[default]
    Paper,
    /// Each coordinate moves by `(ub - lb) T N(0,1)` in the optimiser's coordinates (the
    /// exponent as `ln(1 + n)` with brdf-model's default layout), clamped to the box.
    Optimiser,
}

/// One SA schedule (the parameters of Figure 4 and Table 4). The standalone algorithm
/// (`kind = "sa"`) uses it as is; SALS and AVG hold one or two of them.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct SaConfig {
    /// Start temperature `T_start` (Table 4: 0.01 to 1.0; default 1.0, Table 4's highest value,
    /// which AVG used).
    pub t_start: f64,
    /// Stop temperature `T_stop <= T_start` (Table 4: 0.005 to 0.3; default 0.3).
    pub t_stop: f64,
    /// Number of temperatures `N_t` (Table 4: 1 to 50; default 50).
    pub temperatures: usize,
    /// Iterations per temperature `N_i` (Table 4: 40 to 200; default 200).
    pub iterations: usize,
    /// Metropolis constant `r` (> 0; not given in the paper; default 1).
    pub r: f64,
    /// Accept every worsening step with this constant probability `A` in `[0, 1]` instead of
    /// the Metropolis rule (section 3.1.4 tried 0.05 to 0.2); absent (`None`, the default):
    /// Metropolis.
    pub constant_acceptance: Option<f64>,
    /// How the perturbation is scaled (default: the paper's).
    pub perturbation: Perturbation,
    /// 0 (the default): every step's RMSE is over the full data set. Otherwise each proposal's
    /// RMSE is taken over a fresh random subsample of this many samples
    /// ([`Search::evaluate_subsample`]), and the final candidate is evaluated on the full data.
    pub sample_size: usize,
}

impl Default for SaConfig {
    fn default() -> Self {
        Self {
            t_start: 1.0,
            t_stop: 0.3,
            temperatures: 50,
            iterations: 200,
            r: 1.0,
            constant_acceptance: None,
            perturbation: Perturbation::Paper,
            sample_size: 0,
        }
    }
}

impl SaConfig {
    /// Checks the parameters; the error names the field (as `kind` for SALS's and AVG's
    /// nested schedules).
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.validate_as("sa")
    }

    /// [`SaConfig::validate`] reporting errors under algorithm `kind`.
    pub(crate) fn validate_as(&self, kind: &'static str) -> Result<(), ConfigError> {
        if !(self.t_start.is_finite() && self.t_start > 0.0) {
            return Err(ConfigError::new(
                kind,
                "t_start",
                format!("must be a finite number > 0, found {}", self.t_start),
            ));
        }
        if !(self.t_stop > 0.0 && self.t_stop <= self.t_start) {
            return Err(ConfigError::new(
                kind,
                "t_stop",
                format!(
                    "must be in (0, t_start = {}], found {}",
                    self.t_start, self.t_stop
                ),
            ));
        }
        check_count(kind, "temperatures", self.temperatures, 1)?;
        check_count(kind, "iterations", self.iterations, 1)?;
        if !(self.r.is_finite() && self.r > 0.0) {
            return Err(ConfigError::new(
                kind,
                "r",
                format!("must be a finite number > 0, found {}", self.r),
            ));
        }
        if let Some(a) = self.constant_acceptance {
            check_at_least(kind, "constant_acceptance", a, 0.0)?;
            if a > 1.0 {
                return Err(ConfigError::new(
                    kind,
                    "constant_acceptance",
                    format!("must be a probability in [0, 1], found {a}"),
                ));
            }
        }
        Ok(())
    }

    /// The cooling factor `c = (T_stop / T_start)^(1 / (N_t - 1))` (1 when `N_t = 1`).
    pub fn cooling_factor(&self) -> f64 {
        if self.temperatures <= 1 {
            1.0
        } else {
            (self.t_stop / self.t_start).powf(1.0 / (self.temperatures - 1) as f64)
        }
    }

    /// Temperature number `t` (0-based) of the schedule: `T_start c^t`, so that the last one is
    /// `T_stop` up to rounding.
    pub fn temperature(&self, t: usize) -> f64 {
        self.t_start * self.cooling_factor().powi(t as i32)
    }
}

/// Probability of accepting a move from RMSE `current` to `proposed` at temperature `t`:
/// 1 for an improvement, else `exp((current - proposed) / (r t))` (Metropolis) or the constant
/// `A`. An unevaluable proposal (`+inf`, NaN) has probability 0.
pub fn acceptance_probability(
    current: f64,
    proposed: f64,
    t: f64,
    r: f64,
    constant: Option<f64>,
) -> f64 {
    if proposed.is_nan() || proposed == f64::INFINITY {
        return 0.0;
    }
    if proposed < current {
        return 1.0;
    }
    match constant {
        Some(a) => a,
        None => ((current - proposed) / (r * t)).exp(),
    }
}

/// Figure 5: perturbs `from` at temperature `t` into `to`, clamped to the box. `natural_lo` and
/// `natural_hi` are the box in natural units (only read by [`Perturbation::Paper`]).
pub(crate) fn perturb<S: Search + ?Sized>(
    search: &mut S,
    kind: Perturbation,
    natural_lo: &[f64],
    natural_hi: &[f64],
    t: f64,
    from: &[f64],
    to: &mut [f64],
) {
    for i in 0..from.len() {
        let z: f64 = search.rng().sample(StandardNormal);
        let (lo, hi) = (search.lower()[i], search.upper()[i]);
        to[i] = match kind {
            Perturbation::Optimiser => (from[i] + (hi - lo) * t * z).clamp(lo, hi),
            Perturbation::Paper => {
                let (nlo, nhi) = (natural_lo[i], natural_hi[i]);
                let v = search.natural_value(i, from[i]);
                let v = (v + (nhi - nlo) * t * z).clamp(nlo, nhi);
                // The round trip may leave the box by an ulp.
                search.optimiser_value(i, v).clamp(lo, hi)
            }
        };
    }
}

/// Buffers and the natural box, allocated once per trial and shared by SALS and AVG.
pub(crate) struct Annealer {
    natural_lo: Vec<f64>,
    natural_hi: Vec<f64>,
    proposal: Vec<f64>,
}

impl Annealer {
    /// Buffers for `search`'s dimension.
    pub(crate) fn new<S: Search + ?Sized>(search: &S) -> Self {
        let n = search.dim();
        let natural_lo = (0..n)
            .map(|i| search.natural_value(i, search.lower()[i]))
            .collect();
        let natural_hi = (0..n)
            .map(|i| search.natural_value(i, search.upper()[i]))
            .collect();
        Self {
            natural_lo,
            natural_hi,
            proposal: vec![0.0; n],
        }
    }

    /// Figure 4 from `s` (RMSE `f`, `+inf` if unknown): `s` receives the last accepted candidate
    /// and its RMSE is returned.
    pub(crate) fn anneal<S: Search + ?Sized>(
        &mut self,
        config: &SaConfig,
        search: &mut S,
        s: &mut [f64],
        mut f: f64,
    ) -> Result<f64, Stop> {
        search.count("sa_runs");
        for t in 0..config.temperatures {
            let temperature = config.temperature(t);
            for _ in 0..config.iterations {
                perturb(
                    search,
                    config.perturbation,
                    &self.natural_lo,
                    &self.natural_hi,
                    temperature,
                    s,
                    &mut self.proposal,
                );
                let f_new = if config.sample_size == 0 {
                    search.evaluate(&self.proposal)?
                } else {
                    search.evaluate_subsample(&self.proposal, config.sample_size)?
                };
                let p = acceptance_probability(
                    f,
                    f_new,
                    temperature,
                    config.r,
                    config.constant_acceptance,
                );
                // Draw only when needed so that improvements cost no random number.
                if p >= 1.0 || (p > 0.0 && search.rng().random::<f64>() < p) {
                    if f_new >= f {
                        search.count("sa_worsening_accepted");
                    }
                    s.copy_from_slice(&self.proposal);
                    f = f_new;
                }
            }
        }
        if config.sample_size > 0 {
            f = search.evaluate(s)?;
        }
        Ok(f)
    }
}

impl Algorithm for SaConfig {
    const KIND: &'static str = "sa";

    fn validate(&self) -> Result<(), ConfigError> {
        SaConfig::validate(self)
    }

    fn run(&self, search: &mut dyn Search) -> Result<(), Stop> {
        run(self, search)
    }
}

/// Runs the standalone SA: anneal from a random pick, then again from a new one.
pub fn run<S: Search + ?Sized>(config: &SaConfig, search: &mut S) -> Result<(), Stop> {
    let mut annealer = Annealer::new(search);
    let mut s = vec![0.0; search.dim()];
    loop {
        search.count("random_picks");
        search.random_pick(&mut s);
        let f = search.evaluate(&s)?;
        annealer.anneal(config, search, &mut s, f)?;
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::SearchRng;
    use crate::search::{Descent, DescentLimits};
    use crate::{Rows, Stop};
    use rand::SeedableRng;

    /// A quadratic bowl in a box, with an exponent-like coordinate 1 held as `ln(1 + n)`,
    /// `n` in `[0, 10000]`; records every evaluated candidate.
    pub(crate) struct Bowl {
        pub lower: Vec<f64>,
        pub upper: Vec<f64>,
        pub evaluated: Vec<Vec<f64>>,
        pub budget: usize,
        rng: SearchRng,
    }

    impl Bowl {
        pub(crate) fn new(budget: usize) -> Self {
            Self {
                lower: vec![-1.0, 0.0],
                upper: vec![1.0, 10000f64.ln_1p()],
                evaluated: Vec::new(),
                budget,
                rng: SearchRng::seed_from_u64(3),
            }
        }
    }

    impl Search for Bowl {
        fn dim(&self) -> usize {
            2
        }
        fn lower(&self) -> &[f64] {
            &self.lower
        }
        fn upper(&self) -> &[f64] {
            &self.upper
        }
        fn sample_count(&self) -> usize {
            10
        }
        fn rng(&mut self) -> &mut SearchRng {
            &mut self.rng
        }
        fn random_pick(&mut self, x: &mut [f64]) {
            x[0] = 0.9;
            x[1] = 1.0;
        }
        fn evaluate(&mut self, x: &[f64]) -> Result<f64, Stop> {
            if self.evaluated.len() >= self.budget {
                return Err(Stop::EvaluationBudget);
            }
            self.evaluated.push(x.to_vec());
            Ok(x[0] * x[0] + (x[1] - 3.0).powi(2))
        }
        fn descend(&mut self, x: &mut [f64], _: Rows, _: DescentLimits) -> Result<Descent, Stop> {
            x[0] = 0.0;
            x[1] = 3.0;
            Ok(Descent {
                end: crate::DescentEnd::Solver(bounded_lm::Outcome::RelativeFunctionConvergence),
                iterations: 1,
            })
        }
        fn count(&mut self, _: &'static str) {}
        fn natural_value(&self, i: usize, x: f64) -> f64 {
            if i == 1 { x.exp_m1() } else { x }
        }
        fn optimiser_value(&self, i: usize, v: f64) -> f64 {
            if i == 1 { v.ln_1p() } else { v }
        }
    }

    #[test]
    fn schedule_is_geometric_from_t_start_to_t_stop() {
        let c = SaConfig {
            t_start: 0.8,
            t_stop: 0.01,
            temperatures: 7,
            ..SaConfig::default()
        };
        assert_eq!(c.temperature(0), 0.8);
        assert!((c.temperature(6) - 0.01).abs() < 1e-12);
        let k = c.cooling_factor();
        for t in 1..7 {
            assert!((c.temperature(t) / c.temperature(t - 1) - k).abs() < 1e-12);
        }
        assert!((k - (0.01f64 / 0.8).powf(1.0 / 6.0)).abs() < 1e-15);
        let one = SaConfig {
            temperatures: 1,
            ..c.clone()
        };
        assert_eq!(one.cooling_factor(), 1.0);
        assert_eq!(one.temperature(0), 0.8);
    }

    #[test]
    fn metropolis_and_constant_acceptance() {
        assert_eq!(acceptance_probability(1.0, 0.5, 0.1, 1.0, None), 1.0);
        let p = acceptance_probability(1.0, 1.2, 0.1, 2.0, None);
        assert!((p - (-0.2f64 / 0.2).exp()).abs() < 1e-15);
        // Equal values are "otherwise": exp(0) = 1.
        assert_eq!(acceptance_probability(1.0, 1.0, 0.1, 1.0, None), 1.0);
        assert_eq!(acceptance_probability(1.0, 5.0, 0.1, 1.0, Some(0.1)), 0.1);
        assert_eq!(acceptance_probability(1.0, 0.9, 0.1, 1.0, Some(0.1)), 1.0);
        assert_eq!(
            acceptance_probability(1.0, f64::INFINITY, 1e9, 1.0, Some(0.5)),
            0.0
        );
        assert_eq!(
            acceptance_probability(f64::INFINITY, 3.0, 0.1, 1.0, None),
            1.0
        );
    }

    #[test]
    fn perturbation_is_clamped_and_scaled_as_configured() {
        let mut b = Bowl::new(0);
        let a = Annealer::new(&b);
        assert!((a.natural_hi[1] - 10000.0).abs() < 1e-6);
        let mut to = [0.0; 2];
        // Hot: many coordinates end on the bounds, none outside.
        let mut on_bound = 0;
        for _ in 0..1000 {
            perturb(
                &mut b,
                Perturbation::Paper,
                &a.natural_lo,
                &a.natural_hi,
                1.0,
                &[0.9, 1.0],
                &mut to,
            );
            assert!((-1.0..=1.0).contains(&to[0]));
            assert!((0.0..=b.upper[1]).contains(&to[1]));
            on_bound += usize::from(to[0] == 1.0 || to[0] == -1.0);
        }
        assert!(on_bound > 300, "{on_bound}");
        // Cool: the exponent moves by about 10000 T in n (paper) vs ln(10001) T in ln(1 + n).
        let mut spread = |b: &mut Bowl, kind| {
            let mut s = 0.0;
            for _ in 0..2000 {
                perturb(
                    b,
                    kind,
                    &a.natural_lo,
                    &a.natural_hi,
                    0.001,
                    &[0.0, 5000f64.ln_1p()],
                    &mut to,
                );
                s += (to[1].exp_m1() - 5000.0).powi(2);
            }
            (s / 2000.0).sqrt()
        };
        let paper = spread(&mut b, Perturbation::Paper);
        let optimiser = spread(&mut b, Perturbation::Optimiser);
        assert!((paper / 10.0 - 1.0).abs() < 0.1, "{paper}");
        // d n = (1 + n) d u with sd(u) = ln(10001) * 0.001: about 46 at n = 5000.
        let expected = 5001.0 * 10001f64.ln() * 0.001;
        assert!((optimiser / expected - 1.0).abs() < 0.1, "{optimiser}");
    }

    #[test]
    fn anneal_makes_exactly_nt_times_ni_steps_and_cold_sa_improves() {
        let mut b = Bowl::new(usize::MAX);
        let mut a = Annealer::new(&b);
        let c = SaConfig {
            t_start: 0.05,
            t_stop: 0.001,
            temperatures: 10,
            iterations: 40,
            perturbation: Perturbation::Optimiser,
            r: 0.01,
            ..SaConfig::default()
        };
        let mut s = [0.9, 1.0];
        let f0 = b.evaluate(&s).unwrap();
        let f = a.anneal(&c, &mut b, &mut s, f0).unwrap();
        assert_eq!(b.evaluated.len(), 1 + 400);
        assert!(f < 0.05 * f0, "{f} vs {f0}");
        assert_eq!(f, s[0] * s[0] + (s[1] - 3.0).powi(2));
    }

    #[test]
    fn subsampled_sa_ends_with_a_full_data_evaluation() {
        // The bowl's subsample RMSE is its full RMSE (the trait's default); one extra
        // evaluation of the final candidate.
        let mut b = Bowl::new(usize::MAX);
        let mut a = Annealer::new(&b);
        let c = SaConfig {
            temperatures: 2,
            iterations: 5,
            sample_size: 3,
            ..SaConfig::default()
        };
        let mut s = [0.9, 1.0];
        let f = a.anneal(&c, &mut b, &mut s, f64::INFINITY).unwrap();
        assert_eq!(b.evaluated.len(), 11);
        assert_eq!(b.evaluated[10], s.to_vec());
        assert_eq!(f, s[0] * s[0] + (s[1] - 3.0).powi(2));
    }

    #[test]
    fn standalone_sa_stops_on_the_budget() {
        let mut b = Bowl::new(1000);
        let c = SaConfig {
            temperatures: 3,
            iterations: 7,
            ..SaConfig::default()
        };
        assert_eq!(run(&c, &mut b), Err(Stop::EvaluationBudget));
        assert_eq!(b.evaluated.len(), 1000);
        // A restart every 1 + 21 evaluations: the pick (0.9, 1.0) recurs.
        assert_eq!(b.evaluated[22], vec![0.9, 1.0]);
    }

    #[test]
    fn validation_names_the_field() {
        let bad = |c: SaConfig| c.validate().unwrap_err().field;
        let d = SaConfig::default();
        assert!(d.validate().is_ok());
        assert_eq!(
            bad(SaConfig {
                t_stop: 2.0,
                ..d.clone()
            }),
            "t_stop"
        );
        assert_eq!(
            bad(SaConfig {
                t_start: 0.0,
                ..d.clone()
            }),
            "t_start"
        );
        assert_eq!(
            bad(SaConfig {
                temperatures: 0,
                ..d.clone()
            }),
            "temperatures"
        );
        assert_eq!(
            bad(SaConfig {
                iterations: 0,
                ..d.clone()
            }),
            "iterations"
        );
        assert_eq!(
            bad(SaConfig {
                r: -1.0,
                ..d.clone()
            }),
            "r"
        );
        assert_eq!(
            bad(SaConfig {
                constant_acceptance: Some(1.5),
                ..d
            }),
            "constant_acceptance"
        );
    }
}
