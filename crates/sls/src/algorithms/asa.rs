//! ASA, Ingber's Adaptive Simulated Annealing (the paper's baseline, sections 3 and 3.1.3), on
//! the full-data RMSE, restarted from a random pick whenever it exits.
//!
//! References: L. Ingber, "Adaptive simulated annealing (ASA): Lessons learned", Control and
//! Cybernetics 25(1), 33-54, 1996 (the paper's reference 3); ASA-README (sections "Generating
//! Probability Density Function", "Acceptance Probability Density Function", "Reannealing
//! Temperature Schedule", and the OPTIONS `Temperature_Ratio_Scale`,
//! `Temperature_Anneal_Scale`, `Cost_Parameter_Scale_Ratio`, `Acceptance_Frequency_Modulus`,
//! `Generated_Frequency_Modulus`, `Delta_X`, `Reanneal_Cost`); and ASA's `asa.c` (`asa()`,
//! `generate_asa_state`, `accept_new_state`, `cost_derivatives`, `reanneal`), whose default
//! code path this module follows.
//!
//! Formulas (D = number of parameters, `[A_i, B_i]` the box, `eps` = f64::EPSILON):
//! ```text
//! annealing scales  m = -ln(Temperature_Ratio_Scale), n = ln(Temperature_Anneal_Scale)
//!                   c_i = m exp(-n / D)                   (every parameter)
//!                   c_cost = c_i * Cost_Parameter_Scale_Ratio
//! temperatures      T_i = T_0i exp(-c_i k_i^(1/D))        (k_i: generations, from 1)
//!                   T_cost = T_0cost exp(-c_cost k_cost^(1/D))   (k_cost: acceptances, from 0)
//!                   T_0i = Initial_Parameter_Temperature (1); T_0cost = mean |f| over
//!                   Number_Cost_Samples (5) states generated from the start (e if ~0)
//! generating        u ~ U[0,1); y_i = sgn(u - 1/2) T_i [(1 + 1/T_i)^|2u - 1| - 1]
//!                   x_i' = x_i + y_i (B_i - A_i), redrawn until A_i + eps <= x_i' <= B_i - eps
//! acceptance        accept if min(1, exp(-(f' - f) / (T_cost + eps))) >= u', u' ~ U[0,1)
//!                   (every generation: k_i += 1; every acceptance: k_cost += 1)
//! re-annealing      after an acceptance that makes the number of acceptances a multiple of
//!                   Acceptance_Frequency_Modulus, after every Generated_Frequency_Modulus
//!                   generations, or when (recent acceptances + 1) / (recent generations + 1)
//!                   falls below Accepted_To_Generated_Ratio:
//!   tangents        s_i = (f(x_best with x_i -> (1 + d) x_i) - f_best) / (d x_i + eps),
//!                   d = Delta_X, or -Delta_X when (1 + d) x_i leaves the box
//!   parameters      for |s_i| >= eps: T_i' = T_i max_j|s_j| / |s_i|;
//!                   k_i = eps + (ln((T_0i + eps) / (T_i' + eps)) / c_i)^D  if T_i' < T_0i,
//!                   else 1; truncated to an integer
//!   cost            (Reanneal_Cost = 1) T_0cost = min(T_0cost, max(|f_last|, |f_best|,
//!                   |f_best - f_last|, eps)); T' = min(max(|f_last - f_best|, T_cost, eps),
//!                   T_0cost); k_cost = eps + (ln((T_0cost + eps) / T') / c_cost)^D
//!                   if T_cost > T' else eps + (ln((T_0cost + eps) / (T_cost + eps)) / c_cost)^D
//!   both            while k > 50000 (MAXIMUM_REANNEAL_INDEX): T_new = T_0 exp(-c k^(1/D)),
//!                   k /= 10 (REANNEAL_SCALE), T_0 = T_new (T_0 / T_new)^(10^(-1/D))
//! exits             T_i or T_cost below eps, acceptances > Limit_Acceptances, generations >
//!                   Limit_Generated, Maximum_Cost_Repeat (5) re-annealings in a row with
//!                   |f_last - f_best| < Cost_Precision (1e-18), or
//!                   Limit_Invalid_Generated_States (1000) unevaluable states in a row
//! ```
//!
//! Simplifications and choices (everything else follows `asa.c`'s default compile options):
//! - The cost is the full-data RMSE ([`Search::evaluate`]); the paper does not say whether it
//!   gave ASA the RMSE or the sum of squares. An unevaluable candidate (`+inf`) is ASA's
//!   "invalid state" and is regenerated (it still costs its RMSE rows).
//! - ASA works in the optimiser's coordinates (the box [`Search`] gives: with brdf-model's
//!   default layout the exponent is `ln(1 + n)`), so its generating ranges and relative
//!   tangent steps apply to `ln(1 + n)`; the paper's ASA presumably saw `n` itself.
//! - The start is a random pick (ASA would generate its first state from the user's initial
//!   parameters at the initial temperature); when ASA exits the trial restarts ASA from a new
//!   random pick (the paper does not say what it did; its cutoff was a CPU time).
//! - Tangents: a coordinate at exactly 0 has a relative step of 0 and, as in ASA, tangent 0,
//!   so it is not re-annealed; an unevaluable offset state (ASA would abort with
//!   INVALID_COST_FUNCTION_DERIV) gives tangent 0 too. Curvatures are never computed (ASA only
//!   computes them on exit, for its report).
//! - A generated coordinate that stays outside the box after 1000 redraws (possible only for
//!   a vanishing temperature at a bound) is clamped inside; counted as `asa_clamped`.
//! - Not implemented (off by default in ASA): quenching, `Sequential_Parameters`, integer
//!   parameters, `ASA_SAMPLE`, `ASA_QUEUE`, multiple-minima reports, user-defined functions.
//!
//! # Checked against Ingber's ASA
//!
//! Item by item against the references above, and against the text of asa.c itself (its
//! ASA-distribution generator, `reanneal` for parameters and for the cost with
//! `Reanneal_Cost = 1`, `cost_derivatives` for the tangents, and the temperature scales set at
//! the start of `asa`): the formulas below are those of that code, constant for constant.
//! - **Generating distribution**: the same function of one uniform draw per parameter, at that
//!   parameter's own temperature, scaled by that parameter's range, redrawn (not clamped) until
//!   inside the box ([`generating_step`], `State::generate`). Same.
//! - **Per-parameter temperatures and schedule**: one temperature and one generation index per
//!   parameter, `T_i = T_0i exp(-c_i k_i^(1/D))` with ASA's `c_i`; the cost temperature has its
//!   own index, counting acceptances, and `c_cost = c_i Cost_Parameter_Scale_Ratio`. Same.
//! - **Re-annealing**: triggered by the same three conditions; tangents by ASA's relative
//!   finite differences at the best state; each parameter's temperature rescaled by
//!   `max_j |s_j| / |s_i|` and its index recomputed from it, with ASA's index cap and rescaling;
//!   the cost temperature re-annealed by ASA's `Reanneal_Cost = 1` rule. Same (unit tests
//!   below cover these functions).
//! - **Quenching**: not implemented. ASA's quenching replaces `k^(1/D)` by `k^(Q/D)` (and `c_i`
//!   by `m exp(-n Q / D)`) with user factors `Q`; ASA compiles it out by default
//!   (`QUENCH_PARAMETERS` and `QUENCH_COST` FALSE, so `Q = 1`), the paper tuned no quenching
//!   option, and with `Q = 1` our schedule is ASA's. A quenched ASA would no longer be the
//!   simulated annealing whose convergence ASA's schedule guarantees; adding it is a choice of
//!   a different algorithm, not a fix.
//! - **What differs, on purpose** (listed above): the cost is the RMSE, the coordinates are the
//!   optimiser's (ln(1 + n) by default), the first state is a random pick, and an exit
//!   restarts ASA. None of these changes ASA's rules; they are the interface to this problem.
//!
//! So nothing was changed, and the "before" and "after" RTDs are the same runs:
//! `results/asa-cornell/` (ASA with its defaults and with the paper's tuned values, and RPLS,
//! on the Krylon and acrylic blue paints with two isotropic lobes).

use crate::registry::Algorithm;
use crate::search::{Search, Stop};
use crate::validate::{ConfigError, check_at_least, check_count};
use rand::RngExt;
use serde::{Deserialize, Serialize};

/// ASA's `EPS_DOUBLE`.
const EPS: f64 = f64::EPSILON;
/// ASA's `MAXIMUM_REANNEAL_INDEX`.
const MAXIMUM_REANNEAL_INDEX: f64 = 50000.0;
/// ASA's `REANNEAL_SCALE`.
const REANNEAL_SCALE: f64 = 10.0;
/// ASA's `Limit_Invalid_Generated_States`.
const LIMIT_INVALID_STATES: usize = 1000;
/// ASA's `Maximum_Cost_Repeat` and `Cost_Precision`.
const MAXIMUM_COST_REPEAT: usize = 5;
const COST_PRECISION: f64 = 1e-18;
/// Redraws of one coordinate before it is clamped into the box.
const MAX_REDRAWS: usize = 1000;

/// ASA's OPTIONS (defaults: ASA's own; the paper tuned the first four to 5e-5, 0.9, 25, 5000).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct AsaConfig {
    /// `Temperature_Ratio_Scale` (default 1e-5; the paper's tuned value 5e-5): `m = -ln` of it
    /// sets how fast the temperatures fall.
    pub temperature_ratio_scale: f64,
    /// `Cost_Parameter_Scale_Ratio` (default 1.0; the paper's tuned value 0.9): `c_cost / c_i`.
    pub cost_parameter_scale_ratio: f64,
    /// `Acceptance_Frequency_Modulus` (default 100; the paper's tuned value 25): re-anneal
    /// every this many acceptances (0: never).
    pub acceptance_frequency_modulus: usize,
    /// `Generated_Frequency_Modulus` (default 10000; the paper's tuned value 5000): re-anneal
    /// every this many generated states (0: never).
    pub generated_frequency_modulus: usize,
    /// `Temperature_Anneal_Scale` (default 100): `n = ln` of it.
    pub temperature_anneal_scale: f64,
    /// `Initial_Parameter_Temperature` (default 1.0).
    pub initial_parameter_temperature: f64,
    /// `Number_Cost_Samples` (default 5): states averaged for the initial cost temperature.
    pub number_cost_samples: usize,
    /// `Accepted_To_Generated_Ratio` (default 1e-6): re-anneal when the recent acceptance
    /// ratio falls below it.
    pub accepted_to_generated_ratio: f64,
    /// `Delta_X` (default 0.001): relative step of the finite-difference tangents.
    pub delta_x: f64,
    /// `Limit_Acceptances` (default 10000; 0: no limit): ASA exits (and the trial restarts it)
    /// after this many acceptances.
    pub limit_acceptances: usize,
    /// `Limit_Generated` (default 99999; 0: no limit): ASA exits after this many generated
    /// states.
    pub limit_generated: usize,
}

impl Default for AsaConfig {
    fn default() -> Self {
        Self {
            temperature_ratio_scale: 1e-5,
            cost_parameter_scale_ratio: 1.0,
            acceptance_frequency_modulus: 100,
            generated_frequency_modulus: 10000,
            temperature_anneal_scale: 100.0,
            initial_parameter_temperature: 1.0,
            number_cost_samples: 5,
            accepted_to_generated_ratio: 1e-6,
            delta_x: 0.001,
            limit_acceptances: 10000,
            limit_generated: 99999,
        }
    }
}

impl AsaConfig {
    /// The paper's tuned values (section 3.1.3): 5e-5, 0.9, 25, 5000; ASA's defaults otherwise.
    pub fn paper_tuned() -> Self {
        Self {
            temperature_ratio_scale: 5e-5,
            cost_parameter_scale_ratio: 0.9,
            acceptance_frequency_modulus: 25,
            generated_frequency_modulus: 5000,
            ..Self::default()
        }
    }

    /// Checks the parameters; the error names the field.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let open_unit = |field, v: f64| {
            if v > 0.0 && v < 1.0 {
                Ok(())
            } else {
                Err(ConfigError::new(
                    "asa",
                    field,
                    format!("must be in (0, 1), found {v}"),
                ))
            }
        };
        open_unit("temperature_ratio_scale", self.temperature_ratio_scale)?;
        let positive = |field, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(ConfigError::new(
                    "asa",
                    field,
                    format!("must be a finite number > 0, found {v}"),
                ))
            }
        };
        positive(
            "cost_parameter_scale_ratio",
            self.cost_parameter_scale_ratio,
        )?;
        check_at_least(
            "asa",
            "temperature_anneal_scale",
            self.temperature_anneal_scale,
            1.0,
        )?;
        positive(
            "initial_parameter_temperature",
            self.initial_parameter_temperature,
        )?;
        check_count("asa", "number_cost_samples", self.number_cost_samples, 1)?;
        check_at_least(
            "asa",
            "accepted_to_generated_ratio",
            self.accepted_to_generated_ratio,
            0.0,
        )?;
        positive("delta_x", self.delta_x)
    }

    /// `c_i = -ln(Temperature_Ratio_Scale) exp(-ln(Temperature_Anneal_Scale) / D)`.
    pub fn parameter_scale(&self, d: usize) -> f64 {
        -self.temperature_ratio_scale.ln() * (-self.temperature_anneal_scale.ln() / d as f64).exp()
    }
}

/// ASA's generating function (`generate_asa_state`): a step, as a fraction of the range, drawn
/// from `u` in `[0, 1)` at temperature `t`. `|y| <= 1`; `P(|y| <= a) = ln(1 + a/t) / ln(1 + 1/t)`.
pub fn generating_step(u: f64, t: f64) -> f64 {
    let sign = if u < 0.5 { -1.0 } else { 1.0 };
    sign * t * ((1.0 + 1.0 / t).powf((2.0 * u - 1.0).abs()) - 1.0)
}

/// `T = T_0 exp(-c k^(1/D))`.
pub fn temperature(t0: f64, c: f64, k: f64, d: usize) -> f64 {
    t0 * (-c * k.powf(1.0 / d as f64)).exp()
}

/// The annealing index that gives temperature `t` from `t0` (`t < t0`):
/// `eps + (ln((t0 + eps) / (t + eps)) / c)^D`, rescaled (with `t0`) while above
/// `MAXIMUM_REANNEAL_INDEX` as ASA does; returns `(k, t0)`, `k` truncated to an integer.
fn reanneal_index(t0: f64, t: f64, c: f64, d: usize) -> (f64, f64) {
    let mut t0 = t0;
    let mut k = EPS + (((t0 + EPS) / (t + EPS)).ln().abs() / c).powi(d as i32);
    while k > MAXIMUM_REANNEAL_INDEX {
        let t_new = temperature(t0, c, k, d);
        k /= REANNEAL_SCALE;
        t0 = t_new * (t0 / t_new).powf(1.0 / REANNEAL_SCALE.powf(1.0 / d as f64));
    }
    (k.trunc(), t0)
}

/// Re-annealing of one parameter (`reanneal` in asa.c): from its current temperature
/// `t_current`, initial temperature `t0`, scale `c`, tangent and the largest |tangent|, the new
/// generation index and initial temperature `(k, t0)`; `None` when the tangent is too small to
/// use (the parameter keeps its schedule).
pub fn reanneal_parameter(
    t_current: f64,
    t0: f64,
    c: f64,
    d: usize,
    tangent: f64,
    max_tangent: f64,
) -> Option<(f64, f64)> {
    if tangent.abs() < EPS {
        return None;
    }
    let t_new = (t_current * (max_tangent / tangent)).abs();
    if t_new < t0 {
        Some(reanneal_index(t0, t_new, c, d))
    } else {
        Some((1.0, t0))
    }
}

/// Re-annealing of the cost temperature with `Reanneal_Cost = 1`: the new acceptance index and
/// initial cost temperature.
pub fn reanneal_cost(
    t_current: f64,
    t0: f64,
    c_cost: f64,
    d: usize,
    f_best: f64,
    f_last: f64,
) -> (f64, f64) {
    let reset = f_last
        .abs()
        .max(f_best.abs())
        .max((f_best - f_last).abs())
        .max(EPS);
    let t0 = t0.min(reset);
    let target = (f_last - f_best).abs().max(t_current).max(EPS).min(t0);
    if t_current > target {
        // ASA divides by `target` here without the eps of the other branch.
        let mut t0 = t0;
        let mut k = EPS + (((t0 + EPS) / target).ln().abs() / c_cost).powi(d as i32);
        while k > MAXIMUM_REANNEAL_INDEX {
            let t_new = temperature(t0, c_cost, k, d);
            k /= REANNEAL_SCALE;
            t0 = t_new * (t0 / t_new).powf(1.0 / REANNEAL_SCALE.powf(1.0 / d as f64));
        }
        (k.trunc(), t0)
    } else {
        reanneal_index(t0, t_current, c_cost, d)
    }
}

/// One ASA run's state.
struct State {
    d: usize,
    lower: Vec<f64>,
    upper: Vec<f64>,
    t0: Vec<f64>,
    t: Vec<f64>,
    k: Vec<f64>,
    tangents: Vec<f64>,
    last: Vec<f64>,
    best: Vec<f64>,
    trial: Vec<f64>,
}

impl State {
    /// Draws a new state around `last` at the current temperatures into `trial`.
    fn generate<S: Search + ?Sized>(&mut self, search: &mut S) {
        for i in 0..self.d {
            let (lo, hi) = (self.lower[i], self.upper[i]);
            let range = hi - lo;
            if range.abs() < EPS {
                self.trial[i] = self.last[i];
                continue;
            }
            let mut x = f64::NAN;
            for _ in 0..MAX_REDRAWS {
                let u: f64 = search.rng().random();
                x = self.last[i] + generating_step(u, self.t[i]) * range;
                if x <= hi - EPS && x >= lo + EPS {
                    break;
                }
            }
            if !(x <= hi - EPS && x >= lo + EPS) {
                search.count("asa_clamped");
                x = x.clamp(lo, hi);
                if x.is_nan() {
                    x = self.last[i];
                }
            }
            self.trial[i] = x;
        }
    }

    /// Generates states until one is evaluable; `None` after too many unevaluable ones.
    fn generate_valid<S: Search + ?Sized>(&mut self, search: &mut S) -> Result<Option<f64>, Stop> {
        for _ in 0..LIMIT_INVALID_STATES {
            self.generate(search);
            let f = search.evaluate(&self.trial)?;
            if f.is_finite() {
                return Ok(Some(f));
            }
            search.count("asa_invalid_states");
        }
        Ok(None)
    }

    /// `cost_derivatives`: finite-difference tangents at the best state; the largest |tangent|.
    fn tangents<S: Search + ?Sized>(
        &mut self,
        search: &mut S,
        f_best: f64,
        delta_x: f64,
    ) -> Result<f64, Stop> {
        self.trial.copy_from_slice(&self.best);
        let mut max_tangent: f64 = 0.0;
        for i in 0..self.d {
            self.tangents[i] = 0.0;
            if (self.upper[i] - self.lower[i]).abs() < EPS {
                continue;
            }
            let x = self.best[i];
            let mut delta = delta_x;
            let mut offset = (1.0 + delta) * x;
            if offset > self.upper[i] || offset < self.lower[i] {
                delta = -delta;
                offset = (1.0 + delta) * x;
            }
            self.trial[i] = offset;
            let f = search.evaluate(&self.trial)?;
            self.trial[i] = x;
            if f.is_finite() {
                self.tangents[i] = (f - f_best) / (delta * x + EPS);
            }
            max_tangent = max_tangent.max(self.tangents[i].abs());
        }
        Ok(max_tangent)
    }
}

/// Why one ASA run ended (besides a [`Stop`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Exit {
    TemperatureTooSmall,
    Limit,
    CostRepeating,
    InvalidStates,
}

impl Algorithm for AsaConfig {
    const KIND: &'static str = "asa";

    fn validate(&self) -> Result<(), ConfigError> {
        AsaConfig::validate(self)
    }

    fn run(&self, search: &mut dyn Search) -> Result<(), Stop> {
        run(self, search)
    }
}

/// Runs ASA, restarting it from a random pick whenever it exits.
pub fn run<S: Search + ?Sized>(config: &AsaConfig, search: &mut S) -> Result<(), Stop> {
    let d = search.dim();
    let mut state = State {
        d,
        lower: search.lower().to_vec(),
        upper: search.upper().to_vec(),
        t0: vec![0.0; d],
        t: vec![0.0; d],
        k: vec![0.0; d],
        tangents: vec![0.0; d],
        last: vec![0.0; d],
        best: vec![0.0; d],
        trial: vec![0.0; d],
    };
    loop {
        search.count("restarts");
        let exit = run_once(config, search, &mut state)?;
        search.count(match exit {
            Exit::TemperatureTooSmall => "asa_exit_temperature",
            Exit::Limit => "asa_exit_limit",
            Exit::CostRepeating => "asa_exit_cost_repeating",
            Exit::InvalidStates => "asa_exit_invalid_states",
        });
    }
}

/// One call of `asa()` from a random pick.
fn run_once<S: Search + ?Sized>(
    config: &AsaConfig,
    search: &mut S,
    st: &mut State,
) -> Result<Exit, Stop> {
    let d = st.d;
    let c = config.parameter_scale(d);
    let c_cost = c * config.cost_parameter_scale_ratio;
    st.t0.fill(config.initial_parameter_temperature);
    st.t.copy_from_slice(&st.t0);
    st.k.fill(1.0);

    // The start, and the initial cost temperature from states generated around it.
    search.random_pick(&mut st.last);
    let mut f_last = search.evaluate(&st.last)?;
    let mut sum = 0.0;
    for _ in 0..config.number_cost_samples {
        match st.generate_valid(search)? {
            Some(f) => sum += f.abs(),
            None => return Ok(Exit::InvalidStates),
        }
    }
    let mut t0_cost = sum / config.number_cost_samples as f64;
    if t0_cost.abs() <= 1e-18 {
        // ASA's literal 2.718.
        t0_cost = std::f64::consts::E;
    }
    if !f_last.is_finite() {
        // ASA generates its first state until a valid one: here from the random pick.
        match st.generate_valid(search)? {
            Some(f) => {
                st.last.copy_from_slice(&st.trial);
                f_last = f;
            }
            None => return Ok(Exit::InvalidStates),
        }
    }
    st.best.copy_from_slice(&st.last);
    let mut f_best = f_last;
    let mut k_cost = 0.0;
    let (mut accepted, mut generated) = (0usize, 0usize);
    let (mut recent_accepted, mut recent_generated) = (0usize, 0usize);
    let mut cost_repeat = 0;

    loop {
        if (config.limit_acceptances > 0 && accepted > config.limit_acceptances)
            || (config.limit_generated > 0 && generated > config.limit_generated)
        {
            return Ok(Exit::Limit);
        }
        for i in 0..d {
            st.t[i] = temperature(st.t0[i], c, st.k[i], d);
            if st.t[i] < EPS {
                return Ok(Exit::TemperatureTooSmall);
            }
        }
        let t_cost = temperature(t0_cost, c_cost, k_cost, d);
        if t_cost < EPS {
            return Ok(Exit::TemperatureTooSmall);
        }

        let Some(f_new) = st.generate_valid(search)? else {
            return Ok(Exit::InvalidStates);
        };
        // accept_new_state
        recent_generated += 1;
        generated += 1;
        st.k.iter_mut().for_each(|k| *k += 1.0);
        let p = (-(f_new - f_last) / (t_cost + EPS)).exp().min(1.0);
        let u: f64 = search.rng().random();
        let just_accepted = p >= u;
        if just_accepted {
            st.last.copy_from_slice(&st.trial);
            f_last = f_new;
            recent_accepted += 1;
            accepted += 1;
            k_cost += 1.0;
        }
        let ratio = (recent_accepted + 1) as f64 / (recent_generated + 1) as f64;
        if f_new < f_best {
            st.best.copy_from_slice(&st.trial);
            f_best = f_new;
            recent_accepted = 0;
            recent_generated = 0;
        }

        // Periodic testing and re-annealing.
        let by_acceptances = config.acceptance_frequency_modulus > 0
            && just_accepted
            && accepted % config.acceptance_frequency_modulus == 0;
        let by_generations = config.generated_frequency_modulus > 0
            && generated % config.generated_frequency_modulus == 0;
        let by_ratio = ratio < config.accepted_to_generated_ratio;
        if by_acceptances || by_generations || by_ratio {
            if by_ratio {
                recent_accepted = 0;
                recent_generated = 0;
            }
            if (f_last - f_best).abs() < COST_PRECISION {
                cost_repeat += 1;
                if cost_repeat == MAXIMUM_COST_REPEAT {
                    return Ok(Exit::CostRepeating);
                }
            } else {
                cost_repeat = 0;
            }
            search.count("asa_reannealings");
            let max_tangent = st.tangents(search, f_best, config.delta_x)?;
            for i in 0..d {
                if let Some((k, t0)) =
                    reanneal_parameter(st.t[i], st.t0[i], c, d, st.tangents[i], max_tangent)
                {
                    st.k[i] = k;
                    st.t0[i] = t0;
                }
            }
            let (k, t0) = reanneal_cost(t_cost, t0_cost, c_cost, d, f_best, f_last);
            k_cost = k;
            t0_cost = t0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SearchRng;
    use crate::algorithms::sa::tests::Bowl;
    use rand::SeedableRng;

    #[test]
    fn generating_distribution_has_asa_s_shape() {
        let mut rng = SearchRng::seed_from_u64(5);
        for &t in &[1.0, 1e-2, 1e-5] {
            let n = 20000;
            let mut ys: Vec<f64> = (0..n)
                .map(|_| generating_step(rng.random::<f64>(), t))
                .collect();
            assert!(ys.iter().all(|y| y.abs() <= 1.0));
            let positive = ys.iter().filter(|&&y| y > 0.0).count() as f64 / n as f64;
            assert!((positive - 0.5).abs() < 0.02, "{positive}");
            ys.iter_mut().for_each(|y| *y = y.abs());
            for a in [t / 10.0, t, 10.0 * t, 0.5]
                .into_iter()
                .filter(|&a| a <= 1.0)
            {
                let empirical = ys.iter().filter(|&&y| y <= a).count() as f64 / n as f64;
                let cdf = (1.0 + a / t).ln() / (1.0 + 1.0 / t).ln();
                assert!(
                    (empirical - cdf).abs() < 0.02,
                    "t {t} a {a}: {empirical} vs {cdf}"
                );
            }
        }
        assert_eq!(generating_step(0.5, 0.1), 0.0);
        assert!((generating_step(1.0 - 1e-16, 0.1) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn generated_states_stay_in_the_open_box() {
        let mut b = Bowl::new(0);
        let mut st = State {
            d: 2,
            lower: b.lower.clone(),
            upper: b.upper.clone(),
            t0: vec![1.0; 2],
            t: vec![1.0, 1e-3],
            k: vec![1.0; 2],
            tangents: vec![0.0; 2],
            last: vec![-1.0, b.upper[1]], // on the bounds
            best: vec![0.0; 2],
            trial: vec![0.0; 2],
        };
        for _ in 0..2000 {
            st.generate(&mut b);
            assert!(st.trial[0] > -1.0 && st.trial[0] < 1.0);
            assert!(st.trial[1] > 0.0 && st.trial[1] < b.upper[1]);
        }
    }

    #[test]
    fn schedule_constants_follow_asa() {
        let c = AsaConfig::default();
        let d = 6;
        let ci = c.parameter_scale(d);
        assert!((ci - 1e5f64.ln() * 100f64.powf(-1.0 / 6.0)).abs() < 1e-12);
        // Temperature_Ratio_Scale is T_f / T_0 at k_f = Temperature_Anneal_Scale.
        assert!((temperature(1.0, ci, 100.0, d) / 1e-5 - 1.0).abs() < 1e-12);
        // The index of a temperature inverts the schedule.
        let t = temperature(1.0, ci, 500.0, d);
        let (k, t0) = reanneal_index(1.0, t, ci, d);
        assert_eq!(t0, 1.0);
        assert!((k - 500.0).abs() <= 1.0, "{k}");
    }

    #[test]
    fn reannealing_heats_insensitive_parameters_only() {
        let d = 4;
        let c = AsaConfig::default().parameter_scale(d);
        let k_old = 2000.0;
        let t = temperature(1.0, c, k_old, d);
        // The most sensitive parameter keeps its temperature (and index).
        let (k, _) = reanneal_parameter(t, 1.0, c, d, -8.0, 8.0).unwrap();
        assert!((k - k_old).abs() <= 1.0, "{k}");
        // One 100 times less sensitive is 100 times hotter: a smaller index.
        let (k, t0) = reanneal_parameter(t, 1.0, c, d, 0.08, 8.0).unwrap();
        assert!(k < k_old);
        let t_new = temperature(t0, c, k, d);
        assert!(
            (t_new / (100.0 * t) - 1.0).abs() < 0.05,
            "{t_new} vs {}",
            100.0 * t
        );
        // Hotter than the initial temperature: back to the start of the schedule.
        assert_eq!(
            reanneal_parameter(0.5, 1.0, c, d, 1e-3, 8.0),
            Some((1.0, 1.0))
        );
        assert_eq!(reanneal_parameter(t, 1.0, c, d, 0.0, 8.0), None);
        // A huge index is rescaled with the initial temperature, giving the same temperature.
        // (Only in many dimensions: ASA's eps caps the index near (ln(1/eps)/c)^D.)
        let d = 12;
        let c = AsaConfig::default().parameter_scale(d);
        let t_tiny = temperature(1.0, c, 1e6, d);
        let (k, t0) = reanneal_index(1.0, t_tiny, c, d);
        assert!(k <= MAXIMUM_REANNEAL_INDEX && t0 < 1.0, "{k} {t0}");
        assert!((temperature(t0, c, k, d) / t_tiny - 1.0).abs() < 0.05);
    }

    #[test]
    fn cost_reannealing_caps_the_initial_cost_temperature() {
        let d = 3;
        let c = AsaConfig::default().parameter_scale(d);
        // T_0cost drops to max(|f_last|, |f_best|, |f_best - f_last|) = 0.25; a cool current
        // temperature is kept (its index is recomputed against the new T_0cost) ...
        let (k, t0) = reanneal_cost(1e-4, 10.0, c, d, 0.2, 0.25);
        assert_eq!(t0, 0.25);
        let t = temperature(t0, c, k, d);
        assert!((t / 1e-4 - 1.0).abs() < 0.05, "{t}");
        // ... and a hotter one is capped at the new T_0cost.
        let (k, t0) = reanneal_cost(5.0, 10.0, c, d, 0.2, 0.25);
        assert_eq!((k, t0), (0.0, 0.25));
    }

    #[test]
    fn asa_minimises_the_bowl_and_stops_on_the_budget() {
        let mut b = Bowl::new(4000);
        assert_eq!(
            run(&AsaConfig::default(), &mut b),
            Err(Stop::EvaluationBudget)
        );
        let best = b
            .evaluated
            .iter()
            .map(|x| x[0] * x[0] + (x[1] - 3.0).powi(2))
            .fold(f64::INFINITY, f64::min);
        assert!(best < 1e-3, "{best}");
        for x in &b.evaluated {
            assert!((-1.0..=1.0).contains(&x[0]) && (0.0..=b.upper[1]).contains(&x[1]));
        }
    }

    #[test]
    fn validation_names_the_field() {
        assert!(AsaConfig::default().validate().is_ok());
        assert!(AsaConfig::paper_tuned().validate().is_ok());
        let c = AsaConfig {
            temperature_ratio_scale: 1.0,
            ..AsaConfig::default()
        };
        assert_eq!(c.validate().unwrap_err().field, "temperature_ratio_scale");
        let c = AsaConfig {
            delta_x: 0.0,
            ..AsaConfig::default()
        };
        assert_eq!(c.validate().unwrap_err().field, "delta_x");
    }
}
