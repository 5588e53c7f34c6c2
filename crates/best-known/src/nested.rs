//! The fit behind [`super::compute`]: seeded random starts, the truth, and the optima of nested
//! layouts, each descended to rest, then the best polished once more.
//!
//! A nested layout is a special case of the instance's: an isotropic lobe is an anisotropic
//! one with `cx = cy` (any pan), and `k` lobes are `k + 1` lobes with the last one dead
//! (`C = 0`). The optimum of a nested layout is therefore a feasible start of the instance's
//! fit with the same RMSE, and the instance's best-known RMSE can never end above it: without
//! this bound the random starts alone once left a one-lobe anisotropic fit of a Cornell
//! material 2.5% above its optimum and above the isotropic optimum. A nested layout is used
//! only when every fixed parameter and bound override of the instance's model names one of
//! its parameters too (otherwise it is not nested).

use std::sync::Arc;

use brdf_model::{DataSet, Layout, LobeKind, Params, Samples};
use sls::{Budget, Search, TrialContext};

use super::{AIMED_EXPONENTS, AIMED_SAMPLES, SEED, STARTS, polish};
use brdf_experiment::spec::ModelSpec;

/// The lowest RMSE found for one layout, the parameters reaching it and how.
#[derive(Clone, Debug)]
pub(super) struct Found {
    /// The lowest full-data RMSE.
    pub rmse: f64,
    /// The parameters reaching it.
    pub params: Params,
    /// The RMSE reached from the generating parameters, when given.
    pub from_truth: Option<f64>,
    /// The start that led to it.
    pub origin: String,
    /// The origin, the final polish and everything that was tried, in one sentence.
    pub provenance: String,
}

/// Fits layouts and their nested layouts, each at most once, at most `left` nested ones.
pub(super) struct Nested {
    data: Arc<DataSet>,
    samples: Arc<Samples>,
    left: usize,
    memo: Vec<(Vec<LobeKind>, Found)>,
}

impl Nested {
    /// Fits on `data` (whose samples for the model's family are `samples`: nested layouts
    /// share the family), with at most `max_nested` nested layouts in all.
    pub fn new(data: Arc<DataSet>, samples: Arc<Samples>, max_nested: usize) -> Self {
        Nested {
            data,
            samples,
            left: max_nested,
            memo: Vec::new(),
        }
    }

    /// The best of `model` (whose layout is `layout`) from the truth, the random starts and
    /// the optima of its nested layouts.
    pub fn optimum(&mut self, model: &ModelSpec, layout: &Layout, truth: Option<&Params>) -> Found {
        let mut seeds = Vec::new();
        for child in nested_models(model) {
            if let Some((child_layout, found)) = self.child(&child) {
                let how = format!(
                    "the optimum of the nested layout with {} (itself from {})",
                    kinds_text(child_layout.kinds()),
                    found.origin
                );
                seeds.push((how, found.params));
            }
        }
        fit_layout(&self.data, &self.samples, layout, truth, &seeds, true)
    }

    /// The optimum of the nested `model`, computed once; `None` once the budget of nested
    /// layouts is spent.
    fn child(&mut self, model: &ModelSpec) -> Option<(Layout, Found)> {
        let layout = model.layout().ok()?;
        if let Some((_, f)) = self.memo.iter().find(|(k, _)| *k == model.kinds) {
            return Some((layout, f.clone()));
        }
        if self.left == 0 {
            return None;
        }
        self.left -= 1;
        let found = self.optimum(model, &layout, None);
        self.memo.push((model.kinds.clone(), found.clone()));
        Some((layout, found))
    }
}

/// The layouts nested in `model`: all lobes isotropic (when one is anisotropic), and the last
/// lobe removed (when there are several); those whose layout cannot be built (a fixed
/// parameter or bound naming a parameter they lack) are not nested and left out.
fn nested_models(model: &ModelSpec) -> Vec<ModelSpec> {
    let mut out = Vec::new();
    if model.kinds.contains(&LobeKind::Anisotropic) {
        let mut iso = model.clone();
        iso.kinds = vec![LobeKind::Isotropic; model.kinds.len()];
        out.push(iso);
    }
    if model.kinds.len() > 1 {
        let mut fewer = model.clone();
        fewer.kinds.pop();
        out.push(fewer);
    }
    out.retain(|m| m.layout().is_ok());
    out
}

/// "1 anisotropic lobe", "2 isotropic lobes", or "lobes anisotropic, isotropic".
fn kinds_text(kinds: &[LobeKind]) -> String {
    let name = |k: &LobeKind| match k {
        LobeKind::Anisotropic => "anisotropic",
        LobeKind::Isotropic => "isotropic",
    };
    match kinds.first() {
        Some(k0) if kinds.iter().all(|k| k == k0) => {
            let s = if kinds.len() == 1 { "" } else { "s" };
            format!("{} {} lobe{s}", kinds.len(), name(k0))
        }
        _ => format!(
            "lobes {}",
            kinds.iter().map(name).collect::<Vec<_>>().join(", ")
        ),
    }
}

/// `p` as a start of `layout`: encoded (lobes `p` lacks are dead: zeros) and clamped into the box.
fn start_in(layout: &Layout, p: &Params) -> Vec<f64> {
    let mut x = layout.encode(p);
    for ((v, &lo), &hi) in x.iter_mut().zip(layout.lower()).zip(layout.upper()) {
        *v = v.clamp(lo, hi);
    }
    x
}

/// Descends to rest from `x`; names `how` in `origin` when that lowered the best RMSE.
fn descend_from<O: sls::Objective>(
    cx: &mut TrialContext<'_, O>,
    x: &mut [f64],
    how: String,
    origin: &mut String,
) -> f64 {
    let before = cx.best_rmse();
    let rmse = polish(cx, x);
    if cx.best_rmse() < before {
        *origin = how;
    }
    rmse
}

/// Seeded full-data descents of `layout` on `data`: from the truth, from [`STARTS`] random
/// picks (in this order, the random stream of earlier versions), then from `seeds`; the best
/// is polished once more.
fn fit_layout(
    data: &Arc<DataSet>,
    samples: &Arc<Samples>,
    layout: &Layout,
    truth: Option<&Params>,
    seeds: &[(String, Params)],
    aim: bool,
) -> Found {
    let objective = sls::BrdfObjective::with_samples(data.clone(), samples.clone(), layout.clone())
        .with_starts(sls::StartDist::LogUniform);
    // No clock and no target: only the evaluation count could stop it, and it is unlimited.
    let budget = Budget {
        cpu_seconds: None,
        sample_evaluations: Some(u64::MAX),
    };
    let mut cx = TrialContext::new(&objective, SEED, budget, f64::NEG_INFINITY);
    // The searches' solver settings, whose moves of dead lobes revive some of them, but with
    // scaled Givens rotations: with the plain ones every Levenberg parameter of a step with a
    // dead lobe looked "not positive definite" until its 60 trials ran out, which took 94% of
    // `check`'s 12 CPU s on 64 anisotropic lobes and 500 samples (3.1 s with them, the same
    // best-known RMSE; docs/performance.md).
    cx.set_scale_tiny_rotations(true);
    let mut origin = String::from("no evaluable start");
    let from_truth = truth.map(|t| {
        let mut x = start_in(layout, t);
        descend_from(
            &mut cx,
            &mut x,
            "the generating parameters".into(),
            &mut origin,
        )
    });
    // The best point of the starts so far, for the aimed starts below.
    let mut best = (f64::INFINITY, Vec::new());
    let mut keep = |rmse: f64, x: &[f64]| {
        if rmse < best.0 {
            best = (rmse, x.to_vec());
        }
    };
    let mut x = vec![0.0; layout.dim()];
    for k in 0..STARTS {
        cx.random_pick(&mut x);
        let how = format!("random start {} of {STARTS}", k + 1);
        let rmse = descend_from(&mut cx, &mut x, how, &mut origin);
        keep(rmse, &x);
    }
    for (how, p) in seeds {
        let mut x = start_in(layout, p);
        let rmse = descend_from(&mut cx, &mut x, how.clone(), &mut origin);
        keep(rmse, &x);
    }
    let aimed = if best.1.is_empty() || !aim {
        Vec::new()
    } else {
        aimed_starts(layout, data, &layout.decode(&best.1))
    };
    for (how, p) in &aimed {
        let mut x = start_in(layout, p);
        descend_from(&mut cx, &mut x, how.clone(), &mut origin);
    }
    let searched = cx.finish(Ok(()));
    let (rmse, best_x, polish_note) = polish_best(&objective, searched.best_x, searched.best_rmse);
    let mut tried = Vec::new();
    if truth.is_some() {
        tried.push("the generating parameters".to_string());
    }
    tried.push(format!(
        "{STARTS} random starts (log-uniform exponents, seed {SEED:#x})"
    ));
    tried.extend(seeds.iter().map(|(how, _)| how.clone()));
    if !aimed.is_empty() {
        tried.push(format!(
            "{} starts with the weakest lobe aimed at the {AIMED_SAMPLES} brightest samples, one or two at a time",
            aimed.len()
        ));
    }
    Found {
        rmse,
        params: layout.decode(&best_x),
        from_truth,
        provenance: format!(
            "lowest from {origin}, {polish_note}; full-data descents from {}",
            tried.join("; ")
        ),
        origin,
    }
}

/// Starts aimed at the data's brightest samples (Lafortune layouts only; none otherwise):
/// `best` with its weakest lobe (the smallest largest contribution,
/// [`crate::lobe_use::lobe_use`]) replaced by one peaking on one of the [`AIMED_SAMPLES`]
/// brightest samples, for each exponent of [`AIMED_EXPONENTS`] within the lobe's bounds and the
/// upper bound itself. A narrow lobe on a few samples of many is out of reach of random
/// starts: log-uniform exponents rarely draw one that sharp pointing there, and a descent from
/// a broad lobe stays broad.
///
/// The aimed lobe peaks, for the sample's incoming direction `u`, on its outgoing `v`
/// (`cj = vj / uj` up to scale; isotropic lobes the least-squares `cxy`), scaled so that
/// `d^n` is the sample's value less the rest of the model there.
pub(super) fn aimed_starts(
    layout: &Layout,
    data: &DataSet,
    best: &Params,
) -> Vec<(String, Params)> {
    let m = data.len();
    if !layout.family().is_lafortune() || best.lobe_count() == 0 || m == 0 {
        return Vec::new();
    }
    let used = crate::lobe_use::lobe_use(best, data);
    let weakest = (0..used.len())
        .min_by(|&a, &b| used[a].largest.total_cmp(&used[b].largest))
        .unwrap_or(0);
    let mut without = best.clone();
    without.lobe_mut(weakest).iter_mut().for_each(|v| *v = 0.0);
    let mut order: Vec<usize> = (0..m).filter(|&i| data.value(i).is_finite()).collect();
    order.sort_by(|&a, &b| data.value(b).total_cmp(&data.value(a)));
    let name = format!("lobe{}.n", weakest + 1);
    let hi = layout.physical_bounds(&name).map_or(10000.0, |b| b.1);
    let mut exponents: Vec<f64> = AIMED_EXPONENTS
        .iter()
        .copied()
        .filter(|&n| n < hi)
        .collect();
    exponents.push(hi);
    let isotropic = layout.kinds().get(weakest) == Some(&LobeKind::Isotropic);
    let mut out = Vec::new();
    // The brightest samples with their values less the rest of the model there.
    let top: Vec<(usize, f64)> = order
        .iter()
        .take(AIMED_SAMPLES)
        .map(|&i| (i, data.value(i) - without.value(data.u(i), data.v(i))))
        .collect();
    for (rank, &(i, rest)) in top.iter().enumerate() {
        let (u, v) = (data.u(i), data.v(i));
        let peak = if rest > 0.0 { rest } else { data.value(i) };
        if peak.is_nan() || peak <= 0.0 {
            continue;
        }
        // The lobe's peak for the incoming `u` lies along `(cx ux, cy uy, cz uz)`: `C` with
        // `cj = vj / uj` puts it on the sample's `v` (isotropic: the least-squares `cxy`; a
        // component of `u` near 0 leaves its `c` at 0).
        let ratio = |num: f64, den: f64| if den.abs() > 1e-6 { num / den } else { 0.0 };
        let c = if isotropic {
            let xy = ratio(u[0] * v[0] + u[1] * v[1], u[0] * u[0] + u[1] * u[1]);
            [xy, xy, ratio(v[2], u[2])]
        } else {
            [ratio(v[0], u[0]), ratio(v[1], u[1]), ratio(v[2], u[2])]
        };
        let d0: f64 = (0..3).map(|j| c[j] * u[j] * v[j]).sum();
        if d0.is_nan() || d0 <= 0.0 {
            continue;
        }
        for &n in &exponents {
            let t = peak.powf(1.0 / n.max(1.0));
            let mut p = best.clone();
            let lobe = p.lobe_mut(weakest);
            for j in 0..3 {
                lobe[j] = t * c[j] / d0;
            }
            lobe[3] = n;
            if let Some(pan) = lobe.get_mut(4) {
                *pan = 0.0;
            }
            let how = format!(
                "lobe{} aimed at the brightest sample {} (n = {n})",
                weakest + 1,
                rank + 1
            );
            out.push((how, p));
        }
    }
    out.extend(pair_aimed_starts(data, best, weakest, &top, &exponents));
    out
}

/// Starts whose aimed lobe passes through two of the [`AIMED_SAMPLES`] brightest samples at
/// once: an isotropic lobe `(Cxy (ux vx + uy vy) + Cz uz vz)^n` takes both samples' values
/// (less the rest of the model) for each exponent of `exponents` when `(Cxy, Cz)` solve the
/// 2 x 2 linear system of the `n`-th roots. A lobe narrower than the sampling's spacing whose
/// peak falls between samples is missed by a lobe peaking on either one: on Ngan et al.'s
/// tungsten-carbide fit (n = 16,600; 3,000 uniform pairs, 1% noise, seed 2) every start aimed
/// at one sample ended at RMSE 2.97e-3 and the pair start reaches the truth's descent.
fn pair_aimed_starts(
    data: &DataSet,
    best: &Params,
    weakest: usize,
    top: &[(usize, f64)],
    exponents: &[f64],
) -> Vec<(String, Params)> {
    let mut out = Vec::new();
    for (r1, &s1) in top.iter().enumerate() {
        for (r2, &s2) in top.iter().enumerate().skip(r1 + 1) {
            for &n in exponents {
                let Some((cxy, cz)) = lobe_through(data, [s1, s2], n) else {
                    continue;
                };
                let mut p = best.clone();
                let lobe = p.lobe_mut(weakest);
                lobe[..4].copy_from_slice(&[cxy, cxy, cz, n]);
                if let Some(pan) = lobe.get_mut(4) {
                    *pan = 0.0;
                }
                let how = format!(
                    "lobe{} through the brightest samples {} and {} (n = {n})",
                    weakest + 1,
                    r1 + 1,
                    r2 + 1
                );
                out.push((how, p));
            }
        }
    }
    out
}

/// `(Cxy, Cz)` of the isotropic lobe of exponent `n` that takes the value `rest` at each of
/// the two samples `(row, rest)`; `None` when a `rest` is not positive or the system is
/// singular.
fn lobe_through(data: &DataSet, samples: [(usize, f64); 2], n: f64) -> Option<(f64, f64)> {
    let mut a = [0.0; 2];
    let mut b = [0.0; 2];
    let mut t = [0.0; 2];
    for (k, &(i, rest)) in samples.iter().enumerate() {
        let (u, v) = (data.u(i), data.v(i));
        if rest.is_nan() || rest <= 0.0 {
            return None;
        }
        a[k] = u[0] * v[0] + u[1] * v[1];
        b[k] = u[2] * v[2];
        t[k] = rest.powf(1.0 / n.max(1.0));
    }
    let det = a[0] * b[1] - a[1] * b[0];
    let scale = (a[0].abs() + b[0].abs()) * (a[1].abs() + b[1].abs());
    if det.is_nan() || det.abs() <= 1e-12 * scale {
        return None;
    }
    let cxy = (t[0] * b[1] - t[1] * b[0]) / det;
    let cz = (a[0] * t[1] - a[1] * t[0]) / det;
    (cxy.is_finite() && cz.is_finite()).then_some((cxy, cz))
}

/// Descends to rest once more from the best point; returns its RMSE, the point and a note.
fn polish_best(
    objective: &sls::BrdfObjective,
    mut x: Vec<f64>,
    rmse: f64,
) -> (f64, Vec<f64>, String) {
    if x.is_empty() {
        return (rmse, x, "nothing to polish".into());
    }
    let budget = Budget {
        cpu_seconds: None,
        sample_evaluations: Some(u64::MAX),
    };
    let mut cx = TrialContext::new(objective, SEED, budget, f64::NEG_INFINITY);
    crate::polish::use_robust_solver(&mut cx);
    // Cannot stop: no target, no clock, no real evaluation limit.
    let _ = cx.evaluate(&x);
    let rest = crate::polish::to_rest(&mut cx, &mut x, rmse);
    let polished = cx.finish(Ok(()));
    let gain = (rmse - polished.best_rmse) / rmse;
    let note = format!(
        "then polished by {} full-data descent(s) with the solver's robust preset, the last \
         ending with {} (RMSE lower by {:.1e} relative)",
        rest.descents,
        rest.end_text(),
        gain.max(0.0)
    );
    // The first evaluation was the start itself, so the best is never above it.
    (polished.best_rmse, polished.best_x, note)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The nested layouts docs/experiment-format.md lists: all lobes isotropic, the last lobe
    /// removed, and neither when a fixed value names a parameter it lacks.
    #[test]
    fn nested_layouts_are_the_isotropic_and_the_shorter_model() {
        use LobeKind::{Anisotropic as A, Isotropic as I};
        let kinds = |m: &ModelSpec| -> Vec<Vec<LobeKind>> {
            nested_models(m).into_iter().map(|n| n.kinds).collect()
        };
        let two = ModelSpec::simple(2, A);
        assert_eq!(kinds(&two), vec![vec![I, I], vec![A]]);
        assert_eq!(kinds(&ModelSpec::simple(2, I)), vec![vec![I]]);
        assert_eq!(kinds(&ModelSpec::simple(1, A)), vec![vec![I]]);
        assert!(kinds(&ModelSpec::simple(1, I)).is_empty());
        // `lobe2.n` fixed: the one-lobe model lacks it; `lobe1.pan` fixed: the isotropic one.
        let mut fixed = two.clone();
        fixed.fixed.insert("lobe2.n".into(), 10.0);
        assert_eq!(kinds(&fixed), vec![vec![I, I]]);
        let mut fixed = two;
        fixed.fixed.insert("lobe1.pan".into(), 10.0);
        assert_eq!(kinds(&fixed), vec![vec![A]]);
    }

    /// Ngan et al.'s Lafortune fit of tungsten-carbide (green: one lobe of n = 16,600) on 3,000
    /// direction pairs uniform by solid angle with `relative` noise (instance `seed`), where
    /// its lobe covers 2 samples: the parameters, the data, a layout whose exponent reaches
    /// 20,000, and the prepared samples.
    fn tungsten_carbide(relative: f64, seed: u64) -> (Params, Arc<DataSet>, Layout, Arc<Samples>) {
        use brdf_published::suite::{Noise, Sampling, generate, suite};
        let m = suite("ngan-lafortune")
            .unwrap()
            .material("tungsten-carbide", brdf_io::Channel::Green)
            .unwrap();
        let noise = Noise {
            relative,
            absolute: 0.0,
        };
        let data = Arc::new(generate(&m.params, Sampling::Uniform, 3000, noise, seed).unwrap());
        let layout = Layout::builder(&[LobeKind::Isotropic])
            .bounds("lobe1.n", 0.0, 20000.0)
            .unwrap()
            .build()
            .unwrap();
        let samples = Arc::new(layout.prepare(&data));
        assert_eq!(crate::lobe_use::lobe_use(&m.params, &data)[0].covered, 2);
        (m.params, data, layout, samples)
    }

    /// Issue 45, item 18, the rest: with 1% noise and instance seed 2 the same fit's lobe lies
    /// between its 2 samples; the starts aimed at one sample ended at RMSE 2.97e-3, 53 times
    /// the 5.58e-5 of the descent from the truth; a start through two samples reaches it.
    #[test]
    fn pair_aimed_starts_find_a_lobe_between_two_samples() {
        let (truth, data, layout, samples) = tungsten_carbide(0.01, 2);
        let truth = fit_layout(&data, &samples, &layout, Some(&truth), &[], false);
        let truth = truth.from_truth.unwrap();
        let found = fit_layout(&data, &samples, &layout, None, &[], true);
        assert!(
            found.rmse <= truth * (1.0 + 1e-6),
            "{} against the truth's descent {truth}: {}",
            found.rmse,
            found.provenance
        );
        assert!(
            found.origin.contains("through the brightest samples"),
            "{}",
            found.origin
        );
    }

    /// Issue 45, item 18: [`tungsten_carbide`] without noise (seed 5). The best of the 32 random starts ends at RMSE 3.2e-6; a start aimed at
    /// the third brightest sample reached the truth (2.7e-15), one through two samples now
    /// reaches it first.
    #[test]
    fn aimed_starts_find_a_lobe_on_a_few_samples() {
        let (_, data, layout, samples) = tungsten_carbide(0.0, 5);
        let random = fit_layout(&data, &samples, &layout, None, &[], false);
        let found = fit_layout(&data, &samples, &layout, None, &[], true);
        assert!(random.rmse > 1e-6, "{}", random.provenance);
        assert!(
            found.rmse < 1e-12 && found.origin.contains("brightest sample"),
            "{}: {}",
            found.rmse,
            found.provenance
        );
    }
}
