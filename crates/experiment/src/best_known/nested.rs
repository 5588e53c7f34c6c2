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

use super::{SEED, STARTS, polish};
use crate::spec::ModelSpec;

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
        fit_layout(&self.data, &self.samples, layout, truth, &seeds)
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
    let mut x = vec![0.0; layout.dim()];
    for k in 0..STARTS {
        cx.random_pick(&mut x);
        let how = format!("random start {} of {STARTS}", k + 1);
        descend_from(&mut cx, &mut x, how, &mut origin);
    }
    for (how, p) in seeds {
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
