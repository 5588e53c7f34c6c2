//! Section 3: diagnostics of a fit: what the data determine and how firmly.
//!
//! [`diagnose`] takes a layout, a data set and a solution `x` (internal coordinates) and
//! reports the singular values and condition number of the column-scaled Jacobian, standard
//! errors and correlations from `s^2 (J^T J)^+`, the combinations of parameters the data do
//! not determine, plain-language warnings, seeded bootstrap intervals (parallel with rayon) and
//! the movement of the fit when the data are perturbed by 1e-12, 1e-8 and 1e-4 relative. It
//! also checks that `x` is a local minimum (a Gauss-Newton step and a full-data refit from it),
//! since everything else describes the point it is given.

mod checks;
mod markdown;

use crate::svd::svd;
use crate::{StressError, derive_seed, percentile};
use bounded_lm::{Options, Problem, Report, SolveError, Solver};
use brdf_model::{DataSet, Evaluator, Layout, Samples};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// What [`diagnose`] computes beyond the local analysis.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct DiagnoseOptions {
    /// Bootstrap resamples (0 skips the bootstrap).
    pub bootstrap: usize,
    /// Seed of the bootstrap draws and of the perturbations.
    pub seed: u64,
    /// Relative perturbations of the data values for the sensitivity refits.
    pub perturbations: Vec<f64>,
    /// A singular value below `null_tol` times the largest marks a direction the data do not
    /// determine: 1e-8 because a relative data change of 1e-8 (well above f64 rounding of the
    /// residuals, ~1e-16 times the condition of the sums) then moves the fit by order one
    /// along it.
    pub null_tol: f64,
}

impl Default for DiagnoseOptions {
    fn default() -> Self {
        DiagnoseOptions {
            bootstrap: 200,
            seed: 1,
            perturbations: vec![1e-12, 1e-8, 1e-4],
            null_tol: 1e-8,
        }
    }
}

/// Bootstrap results (percentile intervals, 95%).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Bootstrap {
    /// Resamples drawn.
    pub resamples: usize,
    /// Refits that could not start or returned a non-finite result (excluded).
    pub failed: usize,
    /// 2.5% quantile of each free parameter (internal coordinates).
    pub lower: Vec<f64>,
    /// 97.5% quantile of each free parameter (internal coordinates).
    pub upper: Vec<f64>,
    /// 95% interval of the RMSE of the refits on their resamples.
    pub rmse: (f64, f64),
}

/// One sensitivity refit.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Sensitivity {
    /// Relative size of the perturbation of every data value (uniform in `[-e, e]`).
    pub relative_perturbation: f64,
    /// Per free parameter: `|x' - x|` divided by the width of its box.
    pub shift: Vec<f64>,
    /// Largest entry of `shift`.
    pub max_shift: f64,
    /// `max_shift / relative_perturbation`: how much the fit amplifies data changes.
    pub amplification: f64,
    /// RMSE of the refit on the perturbed data minus the RMSE of `x` on the original data.
    pub rmse_change: f64,
    /// N2FB code of the refit (`None`: the refit could not start).
    pub code: Option<u8>,
}

/// Diagnostics of a fit.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Diagnosis {
    /// Free parameter names.
    pub names: Vec<String>,
    /// The solution (internal coordinates).
    pub x: Vec<f64>,
    /// Physical values of the free parameters (exponent `n`, pan in degrees).
    pub physical: Vec<f64>,
    /// Samples.
    pub samples: usize,
    /// RMSE at `x`.
    pub rmse: f64,
    /// Singular values of the Jacobian with unit-norm columns, largest first.
    pub singular_values: Vec<f64>,
    /// Largest over smallest singular value (`inf` when a column is zero or dependent).
    pub condition_number: f64,
    /// Standard errors in internal coordinates (`inf`: not determined by the data).
    pub standard_errors: Vec<f64>,
    /// Standard errors of the physical values (delta method: times `dn/dx` for exponents).
    pub physical_standard_errors: Vec<f64>,
    /// Correlation matrix (row-major `p x p`; NaN, written as null, for undetermined ones).
    pub correlation: Vec<Vec<f64>>,
    /// Directions the data do not determine: `(singular value / largest, [(name, weight)])`
    /// with the weights of magnitude above 0.1.
    pub undetermined: Vec<(f64, Vec<(String, f64)>)>,
    /// Plain-language warnings.
    pub warnings: Vec<String>,
    /// Bootstrap intervals (when requested).
    pub bootstrap: Option<Bootstrap>,
    /// Sensitivity refits.
    pub sensitivity: Vec<Sensitivity>,
    /// Stationarity of `x`: the relative reduction of the sum of squares a Gauss-Newton step
    /// from `x` predicts (over the parameters not held at a bound; 0 at a stationary point).
    #[serde(default)]
    pub predicted_reduction: f64,
    /// RMSE after a full-data refit from `x` on the original data (`None`: it could not
    /// start); below [`Diagnosis::rmse`] when `x` is not a local minimum.
    #[serde(default)]
    pub refit_rmse: Option<f64>,
}

/// The BRDF fit as a bounded-lm problem (as sls drives it: residuals and Jacobian from the
/// evaluator on one data set).
pub struct BrdfFit<'a> {
    /// The evaluator of the layout being fitted.
    pub ev: &'a mut Evaluator,
    /// The prepared samples fitted.
    pub data: &'a Samples,
}

impl Problem for BrdfFit<'_> {
    fn residual_count(&self) -> usize {
        self.data.len()
    }
    fn parameter_count(&self) -> usize {
        self.ev.layout().dim()
    }
    fn residuals(&mut self, x: &[f64], r: &mut [f64]) -> bool {
        self.ev.residuals(x, self.data, r)
    }
    fn jacobian(&mut self, x: &[f64], jac: &mut [f64]) -> bool {
        self.ev.jacobian(x, self.data, jac)
    }
}

/// Solves from `x` (overwritten) with the default options inside the layout's box.
pub(crate) fn refit(
    ev: &mut Evaluator,
    solver: &mut Solver,
    data: &Samples,
    x: &mut [f64],
) -> Result<Report, SolveError> {
    let layout = ev.layout().clone();
    let mut fit = BrdfFit { ev, data };
    solver.solve(
        &mut fit,
        x,
        layout.lower(),
        layout.upper(),
        &Options::default(),
    )
}

/// Diagnoses the fit `x` of `layout` to `data`.
pub fn diagnose(
    layout: &Layout,
    data: &DataSet,
    x: &[f64],
    options: &DiagnoseOptions,
) -> Result<Diagnosis, StressError> {
    let (m, p) = (data.len(), layout.dim());
    if x.len() != p {
        return Err(StressError::Invalid(format!(
            "x has {} entries, the layout {p}",
            x.len()
        )));
    }
    if m == 0 {
        return Err(StressError::Invalid("empty data set".into()));
    }
    let samples = layout.prepare(data);
    let mut ev = Evaluator::new(layout);
    let mut r = vec![0.0; m];
    let mut jac = vec![0.0; m * p];
    if !ev.residuals_and_jacobian(x, &samples, &mut r, &mut jac) {
        return Err(StressError::Invalid(
            "the model cannot be evaluated at x (overflow)".into(),
        ));
    }
    let ssr: f64 = r.iter().map(|v| v * v).sum();
    let rmse = (ssr / m as f64).sqrt();
    // Scale columns to unit norm so that the condition number is not an artefact of units.
    let norms: Vec<f64> = (0..p)
        .map(|j| {
            jac[j * m..(j + 1) * m]
                .iter()
                .map(|v| v * v)
                .sum::<f64>()
                .sqrt()
        })
        .collect();
    for (j, &nj) in norms.iter().enumerate() {
        if nj > 0.0 {
            jac[j * m..(j + 1) * m].iter_mut().for_each(|v| *v /= nj);
        }
    }
    let dec = svd(&jac, m, p);
    let smax = dec.s.first().copied().unwrap_or(0.0);
    let smin = dec.s.last().copied().unwrap_or(0.0);
    let condition_number = if smin > 0.0 {
        smax / smin
    } else {
        f64::INFINITY
    };
    let names = layout.free_names().to_vec();
    let mut undetermined = Vec::new();
    let mut undet = vec![false; p];
    for (k, &s) in dec.s.iter().enumerate() {
        if s > options.null_tol * smax {
            continue;
        }
        let vk = &dec.v[k * p..(k + 1) * p];
        let mut combo = Vec::new();
        for j in 0..p {
            if vk[j].abs() > 0.1 {
                undet[j] = true;
                combo.push((names[j].clone(), vk[j]));
            }
        }
        undetermined.push((if smax > 0.0 { s / smax } else { 0.0 }, combo));
    }
    // Covariance s^2 D^-1 V S^-2 V^T D^-1 over the determined directions.
    let dof = (m.saturating_sub(p)).max(1) as f64;
    let s2 = ssr / dof;
    let mut cov = vec![0.0; p * p];
    for (k, &s) in dec.s.iter().enumerate() {
        if s <= options.null_tol * smax || s == 0.0 {
            continue;
        }
        let vk = &dec.v[k * p..(k + 1) * p];
        for a in 0..p {
            for b in 0..p {
                cov[a * p + b] += vk[a] * vk[b] / (s * s);
            }
        }
    }
    for a in 0..p {
        for b in 0..p {
            let d = norms[a] * norms[b];
            cov[a * p + b] = if d > 0.0 {
                s2 * cov[a * p + b] / d
            } else {
                0.0
            };
        }
    }
    let standard_errors: Vec<f64> = (0..p)
        .map(|j| {
            if undet[j] || norms[j] == 0.0 {
                f64::INFINITY
            } else {
                cov[j * p + j].sqrt()
            }
        })
        .collect();
    let correlation = (0..p)
        .map(|a| {
            (0..p)
                .map(|b| {
                    if !standard_errors[a].is_finite() || !standard_errors[b].is_finite() {
                        f64::NAN
                    } else {
                        let d = (cov[a * p + a] * cov[b * p + b]).sqrt();
                        if d > 0.0 { cov[a * p + b] / d } else { 0.0 }
                    }
                })
                .collect()
        })
        .collect::<Vec<Vec<f64>>>();
    let coord = layout.exponent_coord();
    let physical: Vec<f64> = (0..p)
        .map(|j| {
            if layout.is_exponent(j) {
                coord.to_physical(x[j])
            } else {
                x[j]
            }
        })
        .collect();
    let physical_standard_errors = (0..p)
        .map(|j| {
            if layout.is_exponent(j) {
                standard_errors[j] * coord.dn_dx(physical[j])
            } else {
                standard_errors[j]
            }
        })
        .collect();
    let (lo, hi) = (layout.lower(), layout.upper());
    let predicted_reduction = if ssr > 0.0 {
        checks::gauss_newton_reduction(&jac, m, &r, x, lo, hi, options.null_tol) / ssr
    } else {
        0.0
    };
    let refit_rmse = refit_from(layout, &samples, x);
    let mut warnings = checks::warnings(
        layout,
        data,
        x,
        &names,
        &undetermined,
        &correlation,
        condition_number,
        &norms,
    );
    let data_rms = (data.values().iter().map(|y| y * y).sum::<f64>() / m.max(1) as f64).sqrt();
    warnings.extend(checks::stationarity(
        rmse,
        data_rms,
        refit_rmse,
        predicted_reduction,
    ));
    let bootstrap = (options.bootstrap > 0).then(|| bootstrap(layout, &samples, x, options));
    if let Some(b) = &bootstrap {
        warnings.extend(checks::bootstrap_width(
            layout,
            data,
            x,
            &names,
            &standard_errors,
            b,
        ));
    }
    let sensitivity = options
        .perturbations
        .iter()
        .enumerate()
        .map(|(k, &e)| {
            sensitivity(
                layout,
                data,
                x,
                e,
                derive_seed(options.seed, 31, k as u64),
                rmse,
            )
        })
        .collect();
    Ok(Diagnosis {
        names,
        x: x.to_vec(),
        physical,
        samples: m,
        rmse,
        singular_values: dec.s,
        condition_number,
        standard_errors,
        physical_standard_errors,
        correlation,
        undetermined,
        warnings,
        bootstrap,
        sensitivity,
        predicted_reduction,
        refit_rmse,
    })
}

/// The RMSE after a full-data refit from `x` (`None` when it cannot start or ends non-finite).
fn refit_from(layout: &Layout, data: &Samples, x: &[f64]) -> Option<f64> {
    let mut ev = Evaluator::new(layout);
    let mut solver = Solver::new();
    let mut x1 = x.to_vec();
    refit(&mut ev, &mut solver, data, &mut x1).ok()?;
    let rmse = ev.rmse(&x1, data);
    rmse.is_finite().then_some(rmse)
}

fn bootstrap(layout: &Layout, data: &Samples, x: &[f64], o: &DiagnoseOptions) -> Bootstrap {
    let m = data.len();
    let fits: Vec<Option<(Vec<f64>, f64)>> = (0..o.bootstrap)
        .into_par_iter()
        .map_init(
            || {
                (
                    Evaluator::new(layout),
                    Solver::new(),
                    Samples::empty(data.family(), data.column_count()),
                    Vec::new(),
                )
            },
            |(ev, solver, sub, rows), b| {
                let mut rng = Pcg64::seed_from_u64(derive_seed(o.seed, 30, b as u64));
                rows.clear();
                rows.extend((0..m).map(|_| rng.random_range(0..m as u32)));
                data.gather_into(rows, sub);
                let mut xb = x.to_vec();
                let rep = refit(ev, solver, sub, &mut xb).ok()?;
                let rmse = (2.0 * rep.f / m as f64).sqrt();
                (xb.iter().all(|v| v.is_finite()) && rmse.is_finite()).then_some((xb, rmse))
            },
        )
        .collect();
    let ok: Vec<&(Vec<f64>, f64)> = fits.iter().flatten().collect();
    let p = x.len();
    let q = |j: Option<usize>, at: f64| {
        let mut v: Vec<f64> = ok.iter().map(|(xb, e)| j.map_or(*e, |j| xb[j])).collect();
        percentile(&mut v, at)
    };
    Bootstrap {
        resamples: o.bootstrap,
        failed: o.bootstrap - ok.len(),
        lower: (0..p).map(|j| q(Some(j), 0.025)).collect(),
        upper: (0..p).map(|j| q(Some(j), 0.975)).collect(),
        rmse: (q(None, 0.025), q(None, 0.975)),
    }
}

fn sensitivity(
    layout: &Layout,
    data: &DataSet,
    x: &[f64],
    e: f64,
    seed: u64,
    rmse0: f64,
) -> Sensitivity {
    let mut rng = Pcg64::seed_from_u64(seed);
    let cols = [
        data.u_x().to_vec(),
        data.u_y().to_vec(),
        data.u_z().to_vec(),
        data.v_x().to_vec(),
        data.v_y().to_vec(),
        data.v_z().to_vec(),
        data.values()
            .iter()
            .map(|&y| y * (1.0 + e * (2.0 * rng.random::<f64>() - 1.0)))
            .collect(),
    ];
    let perturbed = layout.prepare(&DataSet::from_columns(cols).unwrap_or_default());
    let mut ev = Evaluator::new(layout);
    let mut solver = Solver::new();
    let mut x1 = x.to_vec();
    let rep = refit(&mut ev, &mut solver, &perturbed, &mut x1).ok();
    let (lo, hi) = (layout.lower(), layout.upper());
    let shift: Vec<f64> = (0..x.len())
        .map(|j| (x1[j] - x[j]).abs() / (hi[j] - lo[j]).max(f64::MIN_POSITIVE))
        .collect();
    let max_shift = shift.iter().copied().fold(0.0, f64::max);
    let rmse1 = ev.rmse(&x1, &perturbed);
    Sensitivity {
        relative_perturbation: e,
        max_shift,
        amplification: max_shift / e,
        shift,
        rmse_change: rmse1 - rmse0,
        code: rep.map(|r| r.outcome.code()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use brdf_model::{LobeKind, named_params};

    /// In-plane data (u_y = v_y = 0): the Cx/Cy split and pan are flagged, and a standard error
    /// is infinite; the isotropic layout on the same data has neither problem.
    #[test]
    fn in_plane_data_produce_the_identifiability_warning() {
        let p = named_params("tuning").unwrap();
        let mut data = DataSet::new();
        for i in 0..60 {
            for k in 0..5 {
                let ti = 0.1 + 1.3 * i as f64 / 60.0;
                let to = -1.4 + 2.8 * k as f64 / 5.0;
                let u = [ti.sin(), 0.0, ti.cos()];
                let v = [to.sin(), 0.0, to.cos()];
                data.push(u, v, p.value(u, v));
            }
        }
        let layout = Layout::builder(&[LobeKind::Anisotropic]).build().unwrap();
        let x = layout.encode(&p);
        let o = DiagnoseOptions {
            bootstrap: 0,
            perturbations: vec![],
            ..DiagnoseOptions::default()
        };
        let d = diagnose(&layout, &data, &x, &o).unwrap();
        assert!(
            d.warnings.iter().any(|w| w.contains("isotropic layout")),
            "{:?}",
            d.warnings
        );
        assert!(d.standard_errors.iter().any(|s| s.is_infinite()));
        assert!(!d.undetermined.is_empty());
        let iso = Layout::builder(&[LobeKind::Isotropic]).build().unwrap();
        let xi = iso.encode(&brdf_model::BrdfParams {
            kd: 0.15,
            lobes: vec![brdf_model::Lobe::isotropic(-0.5, 0.9, 20.0)],
        });
        let d = diagnose(&iso, &data, &xi, &o).unwrap();
        assert!(d.warnings.iter().all(|w| !w.contains("isotropic layout")));
        assert!(d.standard_errors.iter().all(|s| s.is_finite()));
    }

    /// The generating parameters of noisy data are not the least-squares optimum: diagnosing
    /// them warns that the point is not a local minimum; diagnosing the refit does not.
    #[test]
    fn a_point_that_is_not_a_minimum_is_flagged() {
        let p = named_params("tuning").unwrap();
        let data = brdf_model::synthetic(&p, 400, 0.05, 5);
        let layout = Layout::builder(&[LobeKind::Anisotropic]).build().unwrap();
        let o = DiagnoseOptions {
            bootstrap: 0,
            perturbations: vec![],
            ..DiagnoseOptions::default()
        };
        let truth = layout.encode(&p);
        let d = diagnose(&layout, &data, &truth, &o).unwrap();
        let flagged = |d: &Diagnosis| d.warnings.iter().any(|w| w.contains("not a local minimum"));
        assert!(flagged(&d), "{:?}", d.warnings);
        assert!(d.refit_rmse.unwrap() < d.rmse);
        let mut x = truth.clone();
        let (mut ev, mut solver) = (Evaluator::new(&layout), Solver::new());
        for _ in 0..3 {
            refit(&mut ev, &mut solver, &layout.prepare(&data), &mut x).unwrap();
        }
        let d = diagnose(&layout, &data, &x, &o).unwrap();
        assert!(!flagged(&d), "{:?} {}", d.warnings, d.predicted_reduction);
    }

    /// In-plane data leave the pan angle undetermined: its bootstrap interval is marked.
    #[test]
    fn bootstrap_intervals_of_undetermined_parameters_are_marked() {
        let p = named_params("tuning").unwrap();
        let mut data = DataSet::new();
        for i in 0..40 {
            for k in 0..5 {
                let ti = 0.1 + 1.3 * i as f64 / 40.0;
                let to = -1.4 + 2.8 * k as f64 / 5.0;
                let u = [ti.sin(), 0.0, ti.cos()];
                let v = [to.sin(), 0.0, to.cos()];
                data.push(u, v, p.value(u, v));
            }
        }
        let layout = Layout::builder(&[LobeKind::Anisotropic]).build().unwrap();
        let o = DiagnoseOptions {
            bootstrap: 8,
            perturbations: vec![],
            ..DiagnoseOptions::default()
        };
        let d = diagnose(&layout, &data, &layout.encode(&p), &o).unwrap();
        let md = d.to_markdown();
        let pan = md.lines().find(|l| l.starts_with("| lobe1.pan ")).unwrap();
        assert!(pan.ends_with("(undetermined) |"), "{pan}");
        let kd = md.lines().find(|l| l.starts_with("| kd ")).unwrap();
        assert!(!kd.contains("undetermined"), "{kd}");
    }
}
