//! Section 2: the solver on problems with known answers.
//!
//! - NIST StRD nonlinear regression, 27 problems from both starts, unbounded, default options:
//!   right when every parameter agrees with the certified value to LRE >= 4 (four significant
//!   digits, the usual pass mark for StRD and the one bounded-lm's own test uses; exchangeable
//!   terms may come in either order).
//! - Moré-Garbow-Hillstrom (`bounded_lm::problems::mgh`): 39 problem sizes from `x0` and
//!   `10 x0`, unbounded and in a box that cuts off the minimiser (see [`mgh_cases`]).
//! - Hostile BRDF fits built from brdf-model: two identical lobes (rank-deficient Jacobian),
//!   exponents at both bounds, 25-sample subsamples from mid-box starts, values spanning
//!   1e-6..1e3, all-zero data, data in a single incidence plane.
//!
//! Every case records the N2FB code, right/wrong against its stated criterion, and the
//! evaluations. A success code (3..=6) on a wrong answer fails the suite, as does a NaN in the
//! solution or a point outside the box.

use crate::derive_seed;
use crate::diagnose::{BrdfFit, refit};
use crate::nist::{self, NAMES, NistProblem};
use bounded_lm::problems::mgh::{self, Mgh};
use bounded_lm::{Options, Problem, Solver};
use brdf_model::{
    BrdfParams, DataSet, Evaluator, Layout, Lobe, LobeKind, Samples, named_params, synthetic,
};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// One solve and its grade.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CaseResult {
    /// `nist`, `mgh` or `brdf`.
    pub group: String,
    /// Case name (with the start for NIST).
    pub name: String,
    /// N2FB code (`None`: the solve could not start).
    pub code: Option<u8>,
    /// The outcome in words, or the error.
    pub outcome: String,
    /// The answer meets the criterion.
    pub right: bool,
    /// What "right" means for this case, with the tolerance and why.
    pub criterion: String,
    /// The measured quantity the criterion judges.
    pub measured: String,
    /// Per-parameter LRE (NIST only; in certified order, before reordering exchangeable terms).
    pub lre: Vec<f64>,
    /// Iterations.
    pub iterations: usize,
    /// Residual evaluations.
    pub residual_evaluations: usize,
    /// Jacobian evaluations.
    pub jacobian_evaluations: usize,
    /// The start (a reproducer together with the seed; empty for NIST, whose starts are
    /// certified).
    pub start: Vec<f64>,
    /// The returned solution.
    pub x: Vec<f64>,
    /// Why this case fails the suite (success code on a wrong answer, NaN, outside the box).
    pub failure: Option<String>,
}

/// Result of section 2.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SuiteSection {
    /// Every case.
    pub cases: Vec<CaseResult>,
    /// NIST runs right.
    pub nist_right: usize,
    /// NIST runs.
    pub nist_total: usize,
    /// Status of the Moré-Garbow-Hillstrom set.
    pub mgh_status: String,
    /// BRDF cases right.
    pub brdf_right: usize,
    /// BRDF cases.
    pub brdf_total: usize,
}

impl SuiteSection {
    /// Cases that fail the suite.
    pub fn failures(&self) -> impl Iterator<Item = &CaseResult> {
        self.cases.iter().filter(|c| c.failure.is_some())
    }
}

/// Runs section 2; `subsamples` 25-row subsample cases.
pub fn run(seed: u64, subsamples: usize) -> SuiteSection {
    run_with(seed, subsamples, &|_| {})
}

/// [`run`], calling `done` with a description of each group (NIST, MGH, BRDF hostile) when
/// that group is done.
pub fn run_with(seed: u64, subsamples: usize, done: &dyn Fn(&str)) -> SuiteSection {
    let mut cases: Vec<CaseResult> = NAMES
        .par_iter()
        .flat_map_iter(|name| {
            let data = nist::load(name).expect("embedded NIST file");
            (0..2).map(move |s| nist_case(&data, s)).collect::<Vec<_>>()
        })
        .collect();
    let nist_total = cases.len();
    let nist_right = cases.iter().filter(|c| c.right).count();
    done("NIST solver cases");
    let (mgh, mgh_status) = mgh_cases();
    cases.extend(mgh);
    done("MGH solver cases");
    let brdf: Vec<CaseResult> = brdf_cases(seed, subsamples)
        .into_par_iter()
        .map(|c| c.solve())
        .collect();
    let brdf_total = brdf.len();
    let brdf_right = brdf.iter().filter(|c| c.right).count();
    cases.extend(brdf);
    done("BRDF hostile solver cases");
    SuiteSection {
        cases,
        nist_right,
        nist_total,
        mgh_status,
        brdf_right,
        brdf_total,
    }
}

fn nist_case(data: &nist::NistData, start: usize) -> CaseResult {
    let mut x = data.starts[start].clone();
    let p = x.len();
    let (lower, upper) = (vec![f64::NEG_INFINITY; p], vec![f64::INFINITY; p]);
    let mut prob = NistProblem::new(data);
    let res = Solver::new().solve(&mut prob, &mut x, &lower, &upper, &Options::default());
    let min_lre = nist::min_lre(&data.name, &x, &data.certified);
    let lre: Vec<f64> = x
        .iter()
        .zip(&data.certified)
        .map(|(&e, &c)| nist::lre(e, c))
        .collect();
    let right = min_lre >= 4.0;
    let mut c = graded(
        "nist",
        format!("{} start {}", data.name, start + 1),
        res,
        right,
        "every parameter within LRE >= 4 of the certified value (4 significant digits: the \
         StRD pass mark; exchangeable terms in any order)"
            .into(),
        format!("min LRE {min_lre:.1}"),
        &x,
        &lower,
        &upper,
    );
    c.lre = lre;
    c
}

/// Relative projected-gradient tolerance for the boxed MGH cases: right when the projected
/// gradient at the end is at most this fraction of the gradient at the (projected) start, or
/// below [`MGH_KKT_ABS`]. The same criterion as bounded-lm's own MGH table (`results/lm/mgh-default.md`).
const MGH_KKT_REL: f64 = 1e-6;
/// Absolute projected-gradient tolerance for the boxed MGH cases (zero-residual minima).
const MGH_KKT_ABS: f64 = 1e-10;

/// Moré-Garbow-Hillstrom problems ([`bounded_lm::problems::mgh`], the 39 problem sizes of
/// [`mgh::all`]) from `x0` and `10 x0`, unbounded and in the box of [`Mgh::cutting_box`] (one
/// bound halfway between `x0` and the unbounded minimiser reached from `x0` with a budget of
/// 5000, so the bounded minimum has that bound active), default options: 156 runs, all of them
/// in quick mode too (the problems are tiny; the whole set takes well under a second in
/// release).
///
/// - Unbounded: right when `f` reaches one of the minima MGH list for the size (global or a
///   listed local one), within `1e-5` relative (MGH print six digits) or `1e-12` absolute
///   ([`Mgh::reaches_minimum`]); where MGH list none, as the boxed cases.
/// - Boxed: the bounded minimum is not tabulated, so the known answer is first-order (KKT)
///   stationarity: the projected gradient at the end is at most `1e-6` of the gradient at the
///   projected start, or at most `1e-10`.
///
/// A success code on a wrong answer fails the suite, as for every case.
pub fn mgh_cases() -> (Vec<CaseResult>, String) {
    let cases: Vec<CaseResult> = mgh::all()
        .into_par_iter()
        .flat_map_iter(|mut prob| {
            let n = prob.parameter_count();
            let free = (vec![f64::NEG_INFINITY; n], vec![f64::INFINITY; n]);
            let big = mgh::box_reference_options();
            let mut solver = Solver::new();
            let mut x_star = prob.start(1.0);
            let _ = solver.solve(&mut prob, &mut x_star, &free.0, &free.1, &big);
            let bounds = prob.cutting_box(&x_star);
            let mut out = Vec::with_capacity(4);
            for factor in [1.0, 10.0] {
                for boxed in [false, true] {
                    let (lower, upper) = if boxed {
                        (bounds.lower.clone(), bounds.upper.clone())
                    } else {
                        free.clone()
                    };
                    out.push(mgh_case(
                        &mut prob,
                        &mut solver,
                        factor,
                        &lower,
                        &upper,
                        boxed.then(|| bounds.describe()),
                    ));
                }
            }
            out
        })
        .collect();
    let right = cases.iter().filter(|c| c.right).count();
    let status = format!(
        "{right}/{} runs right (39 problem sizes from x0 and 10 x0, unbounded: a listed minimum \
         within 1e-5 relative; in a box cutting off the minimiser: projected gradient <= 1e-6 of \
         the start's or <= 1e-10)",
        cases.len()
    );
    (cases, status)
}

fn mgh_case(
    prob: &mut Mgh,
    solver: &mut Solver,
    factor: f64,
    lower: &[f64],
    upper: &[f64],
    bound: Option<String>,
) -> CaseResult {
    let start: Vec<f64> = prob
        .start(factor)
        .iter()
        .zip(lower.iter().zip(upper))
        .map(|(&v, (&l, &h))| v.clamp(l, h))
        .collect();
    let mut x = start.clone();
    let res = solver.solve(prob, &mut x, lower, upper, &Options::default());
    let f = res.as_ref().map_or(f64::NAN, |r| r.f);
    let kkt = |prob: &mut Mgh, x: &[f64]| projected_gradient(prob, x, lower, upper);
    let (pg0, g0) = (kkt(prob, &start), full_gradient_norm(prob, &start));
    let pg = kkt(prob, &x);
    let listed = !prob.minima().is_empty();
    let (right, criterion, measured) = if bound.is_none() && listed {
        (
            prob.reaches_minimum(f),
            format!(
                "a minimum listed by MGH (0.5 F: {:?}) within 1e-5 relative or 1e-12 absolute",
                prob.f_minima()
            ),
            format!("f {f:.6e}"),
        )
    } else {
        let scale = pg0.max(g0);
        (
            pg <= MGH_KKT_REL * scale || pg <= MGH_KKT_ABS,
            format!(
                "first-order stationary (KKT): projected gradient <= {MGH_KKT_REL:e} x start \
                 gradient ({scale:.3e}) or <= {MGH_KKT_ABS:e}"
            ),
            format!("projected gradient {pg:.3e}, f {f:.6e}"),
        )
    };
    let name = format!(
        "{} from {}x0, {}",
        prob.label(),
        factor,
        bound.map_or("unbounded".into(), |b| format!("box {b}"))
    );
    let mut c = graded(
        "mgh", name, res, right, criterion, measured, &x, lower, upper,
    );
    c.start = start;
    c
}

/// `J^T r` at `x` (empty when the problem cannot be evaluated there).
fn gradient(prob: &mut Mgh, x: &[f64]) -> Vec<f64> {
    let (m, n) = (prob.residual_count(), prob.parameter_count());
    let mut r = vec![0.0; m];
    let mut jac = vec![0.0; m * n];
    if !(prob.residuals(x, &mut r) && prob.jacobian(x, &mut jac)) {
        return vec![f64::INFINITY; n];
    }
    (0..n)
        .map(|k| {
            jac[k * m..(k + 1) * m]
                .iter()
                .zip(&r)
                .map(|(a, b)| a * b)
                .sum()
        })
        .collect()
}

fn full_gradient_norm(prob: &mut Mgh, x: &[f64]) -> f64 {
    gradient(prob, x).iter().map(|g| g * g).sum::<f64>().sqrt()
}

/// Norm of the projected gradient: components pushing out of the box at an active bound
/// dropped.
fn projected_gradient(prob: &mut Mgh, x: &[f64], lower: &[f64], upper: &[f64]) -> f64 {
    let g = gradient(prob, x);
    let mut s = 0.0;
    for k in 0..x.len() {
        let held = (x[k] <= lower[k] && g[k] > 0.0) || (x[k] >= upper[k] && g[k] < 0.0);
        if !held {
            s += g[k] * g[k];
        }
    }
    s.sqrt()
}

#[allow(clippy::too_many_arguments)]
fn graded(
    group: &str,
    name: String,
    res: Result<bounded_lm::Report, bounded_lm::SolveError>,
    right: bool,
    criterion: String,
    measured: String,
    x: &[f64],
    lower: &[f64],
    upper: &[f64],
) -> CaseResult {
    let mut c = CaseResult {
        group: group.into(),
        name,
        code: None,
        outcome: String::new(),
        right,
        criterion,
        measured,
        lre: Vec::new(),
        start: Vec::new(),
        x: x.to_vec(),
        iterations: 0,
        residual_evaluations: 0,
        jacobian_evaluations: 0,
        failure: None,
    };
    match res {
        Ok(rep) => {
            c.code = Some(rep.outcome.code());
            c.outcome = rep.outcome.to_string();
            c.iterations = rep.iterations;
            c.residual_evaluations = rep.residual_evaluations;
            c.jacobian_evaluations = rep.jacobian_evaluations;
            if rep.outcome.is_success() && !right {
                c.failure = Some(format!("success code {} on a wrong answer", rep.outcome));
            }
            if rep.f.is_nan() {
                c.failure = Some("NaN objective".into());
            }
        }
        Err(e) => c.outcome = format!("error: {e}"),
    }
    if x.iter().any(|v| v.is_nan()) {
        c.failure = Some("NaN in the solution".into());
    } else if x
        .iter()
        .zip(lower.iter().zip(upper))
        .any(|(&v, (&l, &h))| v < l || v > h)
    {
        c.failure = Some("solution outside the box".into());
    }
    c
}

/// What a BRDF case must reach.
#[derive(Clone, Copy, Debug)]
enum Expect {
    /// The global minimum RMSE 0 (noise-free data the layout can represent): right when the
    /// final RMSE is at most this fraction of the data's RMS value (of the start's RMSE for
    /// all-zero data).
    Global(f64),
    /// A first-order stationary point on the box: right when every free column's cosine with
    /// the residual vector (zero for a variable held at a bound by its gradient) is at most
    /// this, or the residual vanishes.
    Stationary(f64),
}

/// Global-minimum tolerance: noise-free data are matched by the model to ~1e-13 relative, a
/// converged Levenberg-Marquardt run gets far below 1e-6, while a local minimum of these
/// problems leaves an RMSE of 1e-3 or more of the data scale.
const GLOBAL_TOL: f64 = 1e-6;
/// Stationarity tolerance: relative function convergence (code 4) guarantees the Gauss-Newton
/// reduction is at most 1e-10 f, i.e. the residual's component in the range of J is below
/// 1.4e-5 of its norm; x-convergence on badly scaled columns is looser, hence 1e-3.
const STATIONARY_TOL: f64 = 1e-3;

/// First-order change of f over a whole box width, relative to f, below which a column counts
/// as numerically flat (a plateau) in the stationarity test: 1e-8 is far below any decrease a
/// fit could use and far above the rounding of `J^T r` (about 1e-16 relative).
const PLATEAU: f64 = 1e-8;

struct BrdfCase {
    name: String,
    layout: Layout,
    data: DataSet,
    start: Vec<f64>,
    expect: Expect,
}

impl BrdfCase {
    fn solve(self) -> CaseResult {
        let mut ev = Evaluator::new(&self.layout);
        let mut solver = Solver::new();
        let m = self.data.len();
        let samples = self.layout.prepare(&self.data);
        let start_rmse = ev.rmse(&self.start, &samples);
        let rms_y = (self.data.values().iter().map(|v| v * v).sum::<f64>() / m as f64).sqrt();
        let mut x = self.start.clone();
        let res = refit(&mut ev, &mut solver, &samples, &mut x);
        let rmse = ev.rmse(&x, &samples);
        let (right, criterion, measured) = match self.expect {
            Expect::Global(tol) => {
                let scale = if rms_y > 0.0 { rms_y } else { start_rmse };
                (
                    rmse <= tol * scale,
                    format!(
                        "global minimum RMSE 0: RMSE <= {tol:e} x {} ({scale:.3e})",
                        if rms_y > 0.0 {
                            "RMS of the data"
                        } else {
                            "start RMSE"
                        }
                    ),
                    format!("RMSE {rmse:.3e}"),
                )
            }
            Expect::Stationary(tol) => {
                let cos = stationarity(&mut ev, &samples, &x);
                (
                    cos <= tol || rmse <= GLOBAL_TOL * rms_y.max(f64::MIN_POSITIVE),
                    format!(
                        "first-order stationary on the box: max column cosine <= {tol:e} (columns flat to 1e-8 of f over the box width ignored)"
                    ),
                    format!("max cosine {cos:.2e}, RMSE {rmse:.3e}"),
                )
            }
        };
        let mut c = graded(
            "brdf",
            self.name,
            res,
            right,
            criterion,
            measured,
            &x,
            self.layout.lower(),
            self.layout.upper(),
        );
        c.start = self.start;
        c
    }
}

/// Largest `|J_j^T r| / (||J_j|| ||r||)` over free columns not held at a bound by the sign
/// of the gradient and not numerically flat ([`PLATEAU`]); 0 when the residual vanishes;
/// `inf` when the model cannot be evaluated.
fn stationarity(ev: &mut Evaluator, data: &Samples, x: &[f64]) -> f64 {
    let layout = ev.layout().clone();
    let (m, p) = (data.len(), layout.dim());
    let mut fit = BrdfFit { ev, data };
    let mut r = vec![0.0; m];
    let mut jac = vec![0.0; m * p];
    if !(fit.residuals(x, &mut r) && fit.jacobian(x, &mut jac)) {
        return f64::INFINITY;
    }
    let rn = r.iter().map(|v| v * v).sum::<f64>().sqrt();
    if rn == 0.0 {
        return 0.0;
    }
    let (lo, hi) = (layout.lower(), layout.upper());
    let mut worst: f64 = 0.0;
    for j in 0..p {
        let col = &jac[j * m..(j + 1) * m];
        let g: f64 = col.iter().zip(&r).map(|(a, b)| a * b).sum();
        let cn = col.iter().map(|v| v * v).sum::<f64>().sqrt();
        if cn == 0.0 {
            continue;
        }
        let tol = 1e-12 * (hi[j] - lo[j]).max(1.0);
        // A descent direction that leaves the box does not count.
        if (x[j] <= lo[j] + tol && g > 0.0) || (x[j] >= hi[j] - tol && g < 0.0) {
            continue;
        }
        // A numerically dead column (a lobe whose d^n is ~1e-30 everywhere): even a move
        // across the whole box would change f by a negligible amount to first order, so its
        // cosine says nothing; this is a plateau, which no local method can leave.
        if g.abs() * (hi[j] - lo[j]) <= PLATEAU * 0.5 * rn * rn {
            continue;
        }
        worst = worst.max(g.abs() / (cn * rn));
    }
    worst
}

fn values_of(p: &BrdfParams, dirs: &[([f64; 3], [f64; 3])]) -> DataSet {
    let mut d = DataSet::with_capacity(dirs.len());
    for &(u, v) in dirs {
        d.push(u, v, p.value(u, v));
    }
    d
}

fn uniform_dirs(rng: &mut Pcg64, n: usize) -> Vec<([f64; 3], [f64; 3])> {
    (0..n)
        .map(|_| {
            (
                brdf_model::uniform_hemisphere(rng),
                brdf_model::uniform_hemisphere(rng),
            )
        })
        .collect()
}

fn layout(kinds: &[LobeKind]) -> Layout {
    Layout::builder(kinds).build().expect("default layout")
}

/// The hostile BRDF cases (data, start and expectation all seeded).
fn brdf_cases(seed: u64, subsamples: usize) -> Vec<BrdfCase> {
    let mut rng = Pcg64::seed_from_u64(derive_seed(seed, 20, 0));
    let iso = LobeKind::Isotropic;
    let aniso = LobeKind::Anisotropic;
    let mut cases = Vec::new();

    // Two identical lobes: the two lobes' Jacobian columns are equal at every iterate (the
    // iteration preserves the symmetry), so J has rank 4 of 7 throughout; the truth lies in
    // the symmetric subspace.
    let lobe = Lobe::isotropic(-0.9, 0.9, 15.0);
    let truth = BrdfParams {
        kd: 0.1,
        lobes: vec![lobe, lobe],
    };
    let l2 = layout(&[iso, iso]);
    let start_lobe = Lobe::isotropic(-0.7, 0.8, 10.0);
    cases.push(BrdfCase {
        name: "two identical lobes (rank-deficient J)".into(),
        start: l2.encode(&BrdfParams {
            kd: 0.2,
            lobes: vec![start_lobe, start_lobe],
        }),
        data: values_of(&truth, &uniform_dirs(&mut rng, 500)),
        layout: l2,
        expect: Expect::Global(GLOBAL_TOL),
    });

    // Exponent at the upper bound: a sharp lobe (n = 10000) sampled near the mirror direction.
    let truth = BrdfParams {
        kd: 0.05,
        lobes: vec![Lobe::isotropic(-1.0, 1.0, 10000.0)],
    };
    let l1 = layout(&[iso]);
    let dirs: Vec<_> = (0..400)
        .map(|_| {
            let u = brdf_model::uniform_hemisphere(&mut rng);
            let (a, b) = (0.02 * rng.random::<f64>(), 0.02 * rng.random::<f64>());
            let v = [-u[0] + a, -u[1] + b, u[2]];
            let nv = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            (u, [v[0] / nv, v[1] / nv, v[2] / nv])
        })
        .collect();
    cases.push(BrdfCase {
        name: "exponent at the upper bound (n = 10000)".into(),
        start: l1.encode(&BrdfParams {
            kd: 0.05,
            lobes: vec![Lobe::isotropic(-1.0, 1.0, 3000.0)],
        }),
        data: values_of(&truth, &dirs),
        layout: l1.clone(),
        expect: Expect::Global(GLOBAL_TOL),
    });

    // Exponent at the lower bound: n = 0 makes the lobe the indicator of d > 0 (C's only
    // matter through the sign of d, their columns vanish at the solution).
    let truth = BrdfParams {
        kd: 0.1,
        lobes: vec![Lobe::isotropic(0.3, 0.5, 0.0)],
    };
    cases.push(BrdfCase {
        name: "exponent at the lower bound (n = 0)".into(),
        start: l1.encode(&BrdfParams {
            kd: 0.1,
            lobes: vec![Lobe::isotropic(0.3, 0.5, 2.0)],
        }),
        data: values_of(&truth, &uniform_dirs(&mut rng, 400)),
        layout: l1.clone(),
        expect: Expect::Global(GLOBAL_TOL),
    });

    // Values spanning 1e-6 .. 1e3: a strong forward lobe (1.5^17 = 985 at normal incidence)
    // over kd = 1e-6.
    let truth = BrdfParams {
        kd: 1e-6,
        lobes: vec![Lobe::isotropic(-1.4, 1.5, 17.0)],
    };
    let mut dirs = uniform_dirs(&mut rng, 400);
    dirs.push(([0.0, 0.0, 1.0], [0.0, 0.0, 1.0]));
    cases.push(BrdfCase {
        name: "values spanning 1e-6 to 1e3".into(),
        start: l1.encode(&BrdfParams {
            kd: 1e-3,
            lobes: vec![Lobe::isotropic(-1.0, 1.2, 10.0)],
        }),
        data: values_of(&truth, &dirs),
        layout: l1.clone(),
        expect: Expect::Stationary(STATIONARY_TOL),
    });

    // All-zero data from a mid-box start: the minimum 0 is reached by kd = 0 and a vanishing
    // lobe.
    let la = layout(&[aniso]);
    let zero = BrdfParams {
        kd: 0.0,
        lobes: vec![],
    };
    cases.push(BrdfCase {
        name: "all-zero data, mid-box start".into(),
        start: mid_box(&la, &mut rng),
        data: values_of(&zero, &uniform_dirs(&mut rng, 300)),
        layout: la.clone(),
        expect: Expect::Global(GLOBAL_TOL),
    });

    // A single incidence plane (u_y = v_y = 0): Cy and pan are not determined (two null
    // directions), but the truth is reachable.
    let tuning = named_params("tuning").expect("tuning");
    let dirs: Vec<_> = (0..400)
        .map(|_| {
            let ti = 1.45 * rng.random::<f64>();
            let to = 2.9 * rng.random::<f64>() - 1.45;
            ([ti.sin(), 0.0, ti.cos()], [to.sin(), 0.0, to.cos()])
        })
        .collect();
    let mut start = tuning.clone();
    start.lobes[0].cx += 0.1;
    start.lobes[0].cz -= 0.1;
    start.lobes[0].pan_deg = 30.0;
    cases.push(BrdfCase {
        name: "single incidence plane (Cy, pan undetermined)".into(),
        start: la.encode(&start),
        data: values_of(&tuning, &dirs),
        layout: la.clone(),
        expect: Expect::Global(GLOBAL_TOL),
    });

    // 25-sample subsamples of the tuning instance from mid-box starts: local minima are
    // legitimate, so the known answer is first-order stationarity.
    let full = synthetic(&tuning, 10000, 0.0, derive_seed(seed, 21, 0));
    let mut sub = DataSet::new();
    let mut sampler = brdf_model::Subsampler::new(full.len());
    for k in 0..subsamples {
        let rows = sampler.draw(25, &mut rng).to_vec();
        full.gather_into(&rows, &mut sub);
        cases.push(BrdfCase {
            name: format!("25-sample subsample #{k}, mid-box start"),
            start: mid_box(&la, &mut rng),
            data: sub.clone(),
            layout: la.clone(),
            expect: Expect::Stationary(STATIONARY_TOL),
        });
    }
    cases
}

/// The middle of the internal box, jittered by up to 5% of each width.
fn mid_box(layout: &Layout, rng: &mut Pcg64) -> Vec<f64> {
    layout
        .lower()
        .iter()
        .zip(layout.upper())
        .map(|(&l, &h)| 0.5 * (l + h) + 0.05 * (h - l) * (2.0 * rng.random::<f64>() - 1.0))
        .collect()
}
