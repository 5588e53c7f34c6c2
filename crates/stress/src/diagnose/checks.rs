//! The plain-language warnings of a diagnosis: identifiability, conditioning, correlations,
//! bounds, stationarity of the point, and bootstrap intervals that disagree with the standard
//! errors.

use brdf_model::{DataSet, Layout, LobeKind, Params};

use super::Bootstrap;
use crate::svd::svd;

/// A full-data refit that lowers the RMSE by more than this (relative) shows that the point is
/// not a local minimum: well above the 1e-12 at which repeated descents stop gaining.
pub const REFIT_GAIN_TOL: f64 = 1e-9;
/// A Gauss-Newton step predicting a relative reduction of the sum of squares above this shows
/// a gradient that is not zero: a converged descent leaves about 1e-10 (PORT's relative
/// function convergence tolerance) or less.
pub const GAUSS_NEWTON_TOL: f64 = 1e-8;
/// An RMSE at most this fraction of the data values' RMS fits the data to round-off: the
/// relative gains and reductions of the stationarity checks are then ratios of round-off and
/// say nothing (noise-free synthetic data fitted exactly gave "6e-1 relative reduction").
pub const EXACT_FIT: f64 = 1e-9;
/// Bootstrap intervals more than this many times wider than the standard-error intervals
/// (+-1.96 standard errors) are flagged.
pub const WIDE_BOOTSTRAP: f64 = 5.0;

/// The reduction of the sum of squares a Gauss-Newton step from `x` predicts, `|P r|^2` with
/// `P` the projection onto the span of the columns of `jac` (column-major, `m` rows) whose
/// parameter is not held at a bound by the gradient; directions with a singular value below
/// `null_tol` times the largest are left out, as for the standard errors.
pub(super) fn gauss_newton_reduction(
    jac: &[f64],
    m: usize,
    r: &[f64],
    x: &[f64],
    lo: &[f64],
    hi: &[f64],
    null_tol: f64,
) -> f64 {
    let p = x.len();
    let g: Vec<f64> = (0..p)
        .map(|j| {
            jac[j * m..(j + 1) * m]
                .iter()
                .zip(r)
                .map(|(a, b)| a * b)
                .sum()
        })
        .collect();
    let free: Vec<usize> = (0..p)
        .filter(|&j| {
            let tol = 1e-9 * (hi[j] - lo[j]).max(1.0);
            // The step is -g (times a positive matrix): blocked when it leaves the box.
            let at_lo = x[j] <= lo[j] + tol && g[j] > 0.0;
            let at_hi = x[j] >= hi[j] - tol && g[j] < 0.0;
            !(at_lo || at_hi)
        })
        .collect();
    let q = free.len();
    if q == 0 || m < q {
        return 0.0;
    }
    let sub: Vec<f64> = free
        .iter()
        .flat_map(|&j| jac[j * m..(j + 1) * m].iter().copied())
        .collect();
    let dec = svd(&sub, m, q);
    let smax = dec.s.first().copied().unwrap_or(0.0);
    dec.s
        .iter()
        .enumerate()
        .filter(|&(_, &s)| s > null_tol * smax && s > 0.0)
        .map(|(k, &s)| {
            let vk = &dec.v[k * q..(k + 1) * q];
            let along: f64 = free.iter().zip(vk).map(|(&j, v)| g[j] * v).sum();
            along * along / (s * s)
        })
        .sum()
}

/// A warning when the point is not a local minimum: a refit from it went lower, or a
/// Gauss-Newton step predicts a reduction. None where the point fits data of RMS `data_rms`
/// exactly (RMSE at most [`EXACT_FIT`] of it).
pub(super) fn stationarity(
    rmse: f64,
    data_rms: f64,
    refit_rmse: Option<f64>,
    predicted_reduction: f64,
) -> Option<String> {
    if rmse <= EXACT_FIT * data_rms {
        return None;
    }
    let gain = refit_rmse.map_or(0.0, |r| (rmse - r) / rmse);
    if !(gain > REFIT_GAIN_TOL || predicted_reduction > GAUSS_NEWTON_TOL) {
        return None;
    }
    let mut why = Vec::new();
    if let Some(r) = refit_rmse.filter(|_| gain > REFIT_GAIN_TOL) {
        why.push(format!(
            "a full-data refit from it lowered the RMSE from {rmse:.9e} to {r:.9e} ({gain:.1e} \
             relative)"
        ));
    }
    if predicted_reduction > GAUSS_NEWTON_TOL {
        why.push(format!(
            "a Gauss-Newton step from it predicts a {predicted_reduction:.1e} relative \
             reduction of the sum of squares (a converged fit leaves below \
             {GAUSS_NEWTON_TOL:.0e})"
        ));
    }
    Some(format!(
        "The point is not a local minimum: {}. The standard errors, correlations and \
         sensitivities describe a point the data do not favour; polish the fit first (`fit` \
         does unless --no-polish).",
        why.join(", and ")
    ))
}

/// A warning when bootstrap intervals are many times wider than the standard-error
/// intervals (determined parameters only): the fit then hangs on a few samples, which the
/// local analysis cannot see. Names the lobe carried by the fewest samples when it is few.
pub(super) fn bootstrap_width(
    layout: &Layout,
    data: &DataSet,
    x: &[f64],
    names: &[String],
    standard_errors: &[f64],
    b: &Bootstrap,
) -> Option<String> {
    let wide: Vec<String> = (0..names.len())
        .filter_map(|j| {
            let se = standard_errors[j];
            let ratio = (b.upper[j] - b.lower[j]) / (2.0 * 1.96 * se);
            (se.is_finite() && se > 0.0 && ratio > WIDE_BOOTSTRAP)
                .then(|| format!("`{}` {ratio:.0}x", names[j]))
        })
        .collect();
    if wide.is_empty() {
        return None;
    }
    let carriers = fewest_carriers(layout, data, x)
        .filter(|&(_, count)| count * 20 < data.len())
        .map(|(lobe, count)| {
            format!(
                " Lobe {} is more than half of the model's value on only {count} of {} samples.",
                lobe + 1,
                data.len()
            )
        })
        .unwrap_or_default();
    Some(format!(
        "Bootstrap intervals are many times wider than the standard-error intervals ({}): the \
         fit hangs on a few samples, and the standard errors, which assume that every sample \
         pulls a little, understate the uncertainty; trust the bootstrap intervals.{carriers}",
        wide.join(", ")
    ))
}

/// The lobe that is more than half of the model's value on the fewest samples, and how many.
fn fewest_carriers(layout: &Layout, data: &DataSet, x: &[f64]) -> Option<(usize, usize)> {
    let params = layout.decode(x);
    let dir = |c: [&[f64]; 3], i: usize| [c[0][i], c[1][i], c[2][i]];
    let (us, vs) = (
        [data.u_x(), data.u_y(), data.u_z()],
        [data.v_x(), data.v_y(), data.v_z()],
    );
    (0..params.lobe_count())
        .map(|k| {
            // The lobe alone: no shared (diffuse) term, every other lobe left out.
            let mut alone = Params::defaults(params.family().clone(), 0);
            alone.shared_mut().fill(0.0);
            alone
                .push_lobe(params.lobe(k).to_vec())
                .expect("a lobe of the same family");
            let count = (0..data.len())
                .filter(|&i| {
                    let (u, v) = (dir(us, i), dir(vs, i));
                    let total = params.value(u, v);
                    total > 0.0 && alone.value(u, v) > 0.5 * total
                })
                .count();
            (k, count)
        })
        .min_by_key(|&(_, count)| count)
}

#[allow(clippy::too_many_arguments)]
pub(super) fn warnings(
    layout: &Layout,
    data: &DataSet,
    x: &[f64],
    names: &[String],
    undetermined: &[(f64, Vec<(String, f64)>)],
    correlation: &[Vec<f64>],
    condition_number: f64,
    norms: &[f64],
) -> Vec<String> {
    let mut w = Vec::new();
    // In-plane incidence: with u_y = 0 on every sample only Cx cos^2 p + Cy sin^2 p and
    // (Cx - Cy) cos p sin p reach the data, so Cx, Cy and pan cannot all be determined.
    let in_plane = data.u_y().iter().all(|v| v.abs() <= 1e-9);
    let exit_in_plane = data.v_y().iter().all(|v| v.abs() <= 1e-9);
    if in_plane {
        for (k, kind) in layout.kinds().iter().enumerate() {
            let free = |f: &str| layout.free_index(&format!("lobe{}.{f}", k + 1)).is_some();
            if *kind == LobeKind::Anisotropic && (free("cx") || free("cy") || free("pan")) {
                w.push(format!(
                    "All incident directions lie in one plane (incident azimuth always 0{}): \
                     the split between Cx and Cy and the pan angle of lobe {} cannot be \
                     determined from these data. Fit the isotropic layout (--kind isotropic) \
                     instead.",
                    if exit_in_plane {
                        ", and every exitant direction too"
                    } else {
                        ""
                    },
                    k + 1
                ));
            }
        }
    }
    for (j, &n) in norms.iter().enumerate() {
        if n == 0.0 {
            w.push(format!(
                "`{}` has no effect on any sample at this solution (its Jacobian column is \
                 zero; for a lobe this means d <= 0 everywhere or n = 0): the data say nothing \
                 about it.",
                names[j]
            ));
        }
    }
    for (ratio, combo) in undetermined {
        let list: Vec<String> = combo
            .iter()
            .map(|(n, v)| format!("{n} ({v:+.2})"))
            .collect();
        w.push(format!(
            "The data do not determine the combination {} (singular value {ratio:.1e} of the \
             largest): the parameters can move together along it without changing the fit, \
             so their standard errors are reported as infinite.",
            list.join(", ")
        ));
    }
    if condition_number.is_finite() && condition_number > 1e6 {
        w.push(format!(
            "The scaled Jacobian is ill-conditioned (condition number {condition_number:.1e}): \
             small changes in the data can move the parameters a lot."
        ));
    }
    let p = names.len();
    for a in 0..p {
        for b in a + 1..p {
            let c = correlation[a][b];
            if c.is_finite() && c.abs() > 0.99 {
                w.push(format!(
                    "`{}` and `{}` are correlated at {c:+.3}: the data mostly determine a \
                     combination of them.",
                    names[a], names[b]
                ));
            }
        }
    }
    let (lo, hi) = (layout.lower(), layout.upper());
    for j in 0..p {
        let tol = 1e-9 * (hi[j] - lo[j]).max(1.0);
        if x[j] <= lo[j] + tol || x[j] >= hi[j] - tol {
            w.push(format!(
                "`{}` is at its bound: the optimum may lie outside the box, and the standard \
                 error does not describe a one-sided uncertainty.",
                names[j]
            ));
        }
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;
    use brdf_model::{BrdfParams, Lobe};

    /// An exact fit's relative measures are round-off ratios: no warning; the same ratios at
    /// an RMSE above round-off warn.
    #[test]
    fn an_exact_fit_is_not_called_a_non_minimum() {
        assert_eq!(stationarity(3e-15, 0.3, Some(2e-15), 0.6), None);
        let w = stationarity(3e-3, 0.3, Some(2e-3), 0.6).unwrap();
        assert!(
            w.contains("not a local minimum") && w.contains("6.0e-1"),
            "{w}"
        );
        assert_eq!(stationarity(3e-3, 0.3, Some(3e-3), 0.0), None);
    }

    /// A narrow second lobe carries few samples; intervals 10 times the standard-error ones
    /// are flagged and that lobe is named, intervals of 2 times are not.
    #[test]
    fn wide_bootstrap_intervals_are_flagged_with_the_lobe_on_few_samples() {
        let params = BrdfParams {
            kd: 0.1,
            lobes: vec![
                Lobe::isotropic(-0.5, 0.5, 2.0),
                Lobe::isotropic(-1.0, 1.0, 5000.0),
            ],
        };
        let data = brdf_model::synthetic(&params, 400, 0.0, 9);
        let layout = Layout::builder(&[LobeKind::Isotropic, LobeKind::Isotropic])
            .build()
            .unwrap();
        let x = layout.encode(&params);
        let names = layout.free_names().to_vec();
        let se = vec![0.01; x.len()];
        let interval = |half: f64| Bootstrap {
            resamples: 10,
            failed: 0,
            lower: x.iter().map(|v| v - half).collect(),
            upper: x.iter().map(|v| v + half).collect(),
            rmse: (0.0, 0.0),
        };
        let narrow = interval(2.0 * 1.96 * 0.01);
        assert_eq!(
            bootstrap_width(&layout, &data, &x, &names, &se, &narrow),
            None
        );
        let wide = interval(10.0 * 1.96 * 0.01);
        let w = bootstrap_width(&layout, &data, &x, &names, &se, &wide).unwrap();
        assert!(w.contains("`kd` 10x"), "{w}");
        assert!(w.contains("Lobe 2 is more than half"), "{w}");
    }
}
