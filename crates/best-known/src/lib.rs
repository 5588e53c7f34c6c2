//! The best-known RMSE of an instance: the reference that relative targets
//! (`targets = [{ relative = 0.01 }]`) and the closeness warnings are measured against.
//!
//! # Procedure (deterministic)
//!
//! Full-data bounded Levenberg-Marquardt descents with PORT's limits (150 iterations, 200
//! evaluations) and the searches' solver settings with scaled Givens rotations, each repeated
//! from its own result until it improves the RMSE by less than 1e-12 relative or
//! [`POLISH_ROUNDS`] descents were made:
//! - for a synthetic instance whose model is of the generating parameters' family, one from
//!   the generating parameters (the truth, projected into the model's box: lobes beyond the
//!   model's count are dropped);
//! - [`STARTS`] from random picks drawn from the fixed seed [`SEED`], with exponents
//!   log-uniform in n whatever the instance's own start distribution: the best-known RMSE is a
//!   property of the data and the model, not of the search setting, and uniform draws of n in
//!   [0, 10000] mostly start dead or overflowing lobes (`results/ablation-coords-starts`): with
//!   them, 32 starts on the Krylon blue paint found 0.059997 instead of 0.036886;
//! - one from the optimum of each nested layout (all lobes isotropic; the last lobe removed,
//!   i.e. dead), found the same way, at most [`MAX_NESTED`] of them: a layout's best-known
//!   RMSE is then never above that of a layout nested in it (random starts alone left two
//!   anisotropic lobes on the acrylic paint at 500 nm at 0.060916, above the 0.049528 of two
//!   isotropic lobes, and three isotropic lobes at 450 nm at 0.006958, above two lobes'
//!   0.006618);
//! - then starts aimed at the data's [`AIMED_SAMPLES`] brightest samples (Lafortune models):
//!   the best point so far with its weakest lobe replaced by one peaking on the sample, with
//!   each exponent of [`AIMED_EXPONENTS`] below the lobe's upper bound and that bound. A narrow
//!   lobe on a few samples of many (a metal sampled uniformly: the lobe of Ngan et al.'s
//!   tungsten-carbide fit, n = 16,600, on 2 of 3,000 samples) is often out of reach of the
//!   random starts. On that fit's noiseless data (seed 5) they ended at RMSE 3.2e-6 and an
//!   aimed start reached the truth, 2.7e-15; of seeds 1-8 with and without 1% noise, the aimed
//!   starts lowered the best-known RMSE in 4 of 16 cases. A lobe whose peak falls between
//!   its samples is missed by a lobe peaking on either: with noise, seed 2 stayed at 2.97e-3
//!   against the 5.58e-5 of a descent from the truth. So starts are also aimed through two of
//!   the brightest samples at once (the isotropic lobe of each exponent that takes both
//!   samples' values), and those reach it.
//!
//! The best of all is polished with the solver's robust preset until the solver says it is at
//! rest ([`crate::polish`]), and the record says which start
//! led to it and what was tried ([`BestKnown::provenance`]). The best-known RMSE is the lowest
//! full-data RMSE seen. A trial that goes lower is reported by `run` and `stats`
//! ([`below_best_known`]). Everything is seeded and nothing
//! reads a clock, so the number is the same on every run with the same evaluation kernel
//! (kernels agree to rounding). Runs record it in their session line of `trials.jsonl`, and
//! `stats` reports it beside every result.

use std::borrow::Cow;
use std::collections::BTreeMap;

use sls::{DescentLimits, Rows, Search, TrialContext};

pub mod lobe_use;
mod nested;
pub mod polish;
pub mod prepare;

use crate::lobe_use::LobeUse;
use brdf_experiment::instance::{BuiltInstance, InstanceError};
use brdf_experiment::spec::{InstanceSpec, Source, Spec};
use brdf_experiment::store::Contents;

/// Random starts per instance.
pub const STARTS: usize = 32;
/// The seed of the random starts.
pub const SEED: u64 = 0x6265_7374_6b6e_6f77; // "bestknow"
/// Most descents per start (the first included).
pub const POLISH_ROUNDS: usize = 8;
/// An absolute target at most this fraction above the best-known RMSE is flagged.
pub const CLOSE_FRACTION: f64 = 0.01;
/// `check` computes the best-known RMSE of instances of at most this many samples unless told
/// otherwise: about a second of CPU for one anisotropic lobe (30 s were measured at 1,000,000
/// samples before the nested layouts, which add about as much again).
pub const CHECK_MAX_SAMPLES: usize = 20_000;
/// The brightest samples that the aimed starts point a lobe at (see the module docs).
pub const AIMED_SAMPLES: usize = 3;
/// The exponents of the aimed starts' lobe (those below the lobe's upper bound, and that bound).
pub const AIMED_EXPONENTS: [f64; 2] = [1000.0, 10000.0];
/// Nested layouts (fewer lobes, isotropic for anisotropic) fitted at most per instance, their
/// optima seeding the instance's own fit.
pub const MAX_NESTED: usize = 4;

pub use brdf_experiment::best_known_record::BestKnown;

/// Computes the best-known RMSE of one built instance (see the module docs).
pub fn compute(spec: &InstanceSpec, built: &BuiltInstance) -> Result<BestKnown, InstanceError> {
    Ok(compute_nested(spec, built, MAX_NESTED).0)
}

/// [`compute`] with at most `max_nested` nested layouts (0: random starts and truth only);
/// also returns the parameters reaching the best-known RMSE.
fn compute_nested(
    spec: &InstanceSpec,
    built: &BuiltInstance,
    max_nested: usize,
) -> (BestKnown, brdf_model::Params) {
    // The generating parameters start a descent only when the model is of their family
    // (another family's fields mean something else).
    let truth = match &spec.source {
        Source::Synthetic { params, .. } if *params.family() == spec.model.family => {
            Some(params.clone())
        }
        Source::Synthetic { .. } | Source::File { .. } => None,
    };
    let mut nested = nested::Nested::new(built.data.clone(), built.samples.clone(), max_nested);
    let found = nested.optimum(&spec.model, &built.layout, truth.as_ref());
    let bk = BestKnown {
        rmse: found.rmse,
        from_truth: found.from_truth,
        starts: STARTS,
        seed: SEED,
        provenance: Some(found.provenance),
    };
    (bk, found.params)
}

/// Descends from `x` until a descent gains less than 1e-12 relative, at most
/// [`POLISH_ROUNDS`] times; returns the RMSE.
pub(crate) fn polish<O: sls::Objective>(cx: &mut TrialContext<'_, O>, x: &mut [f64]) -> f64 {
    let mut last = f64::INFINITY;
    for _ in 0..POLISH_ROUNDS {
        // Neither call can stop: there is no target, no clock and no real evaluation limit.
        if cx.descend(x, Rows::Full, DescentLimits::default()).is_err() {
            break;
        }
        let rmse = cx.evaluate(x).unwrap_or(f64::INFINITY);
        // NaN (both infinite) counts as no gain.
        let improving = last - rmse > 1e-12 * rmse;
        last = last.min(rmse);
        if !improving {
            break;
        }
    }
    last
}

/// Resolves every instance's best-known RMSE (from `known` when recorded there, else computed)
/// and with it the relative targets; returns what was used, by instance name.
///
/// An instance whose data cannot be built (e.g. `stats` on a results folder whose data file is
/// not beside it) is an error only when it has relative targets, which cannot be resolved
/// without it; otherwise it is left without a best-known RMSE and named in the returned notes.
pub fn resolve(
    spec: &mut Spec,
    known: &BTreeMap<String, BestKnown>,
) -> Result<Resolved, InstanceError> {
    resolve_with(spec, known, None, |_, inst| {
        brdf_experiment::instance::build(inst).map(Cow::Owned)
    })
}

/// [`resolve`] with the instances already built (`built[i]` is instance `i`, as
/// [`brdf_experiment::instance::build_all`] returns them): those are not built again.
pub fn resolve_built(
    spec: &mut Spec,
    known: &BTreeMap<String, BestKnown>,
    built: &[BuiltInstance],
) -> Result<Resolved, InstanceError> {
    resolve_with(spec, known, None, |i, inst| match built.get(i) {
        Some(b) => Ok(Cow::Borrowed(b)),
        None => brdf_experiment::instance::build(inst).map(Cow::Owned),
    })
}

/// [`resolve`], computing no best-known RMSE of an instance with more than `max_samples`
/// samples (when given): such instances are left without one and named in the notes, with the
/// reason. `check` uses it to stay fast; `run` computes every one.
pub fn resolve_within(
    spec: &mut Spec,
    known: &BTreeMap<String, BestKnown>,
    max_samples: Option<usize>,
) -> Result<Resolved, InstanceError> {
    resolve_with(spec, known, max_samples, |_, inst| {
        brdf_experiment::instance::build(inst).map(Cow::Owned)
    })
}

/// [`resolve`] with `build(i, instance)` giving each instance's data when no value is known,
/// skipping instances of more than `max_samples` samples (when given).
fn resolve_with<'b>(
    spec: &mut Spec,
    known: &BTreeMap<String, BestKnown>,
    max_samples: Option<usize>,
    mut build: impl FnMut(usize, &InstanceSpec) -> Result<Cow<'b, BuiltInstance>, InstanceError>,
) -> Result<Resolved, InstanceError> {
    let mut out = Resolved::default();
    for (i, inst) in spec.instances.iter_mut().enumerate() {
        let bk = match known.get(&inst.name) {
            Some(bk) => bk.clone(),
            None => match compute_within(inst, max_samples, |inst| build(i, inst)) {
                Ok(Ok((bk, lobes))) => {
                    out.lobes.insert(inst.name.clone(), lobes);
                    bk
                }
                Ok(Err(skipped)) => {
                    out.notes.push(skipped);
                    out.skipped += 1;
                    continue;
                }
                Err(e) if inst.relative_targets.is_empty() => {
                    out.notes.push(format!(
                        "no best-known RMSE for instance `{}`: {e}",
                        inst.name
                    ));
                    continue;
                }
                Err(e) => return Err(e),
            },
        };
        inst.resolve_targets(bk.clone());
        out.known.insert(inst.name.clone(), bk);
    }
    Ok(out)
}

/// Builds `inst` (with `build`) and computes its best-known RMSE, or says why it was skipped (more samples
/// than `max_samples`). A generated instance is not even generated then.
fn compute_within<'b>(
    inst: &InstanceSpec,
    max_samples: Option<usize>,
    build: impl FnOnce(&InstanceSpec) -> Result<Cow<'b, BuiltInstance>, InstanceError>,
) -> Result<Result<(BestKnown, LobesOnData), String>, InstanceError> {
    let skip = |n: usize| {
        max_samples.filter(|&limit| n > limit).map(|limit| {
            format!(
                "best-known RMSE of instance `{}` not computed here: {n} samples, above the \
                 limit of {limit} for computing it while checking (`run` computes it before \
                 the first trial; `check --best-known` computes it here)",
                inst.name
            )
        })
    };
    if let Source::Synthetic { samples, .. } = &inst.source
        && let Some(note) = skip(*samples)
    {
        return Ok(Err(note));
    }
    let built = build(inst)?;
    if let Some(note) = skip(built.data.len()) {
        return Ok(Err(note));
    }
    let (bk, params) = compute_nested(inst, &built, MAX_NESTED);
    let lobes = crate::lobe_use::lobe_use(&params, &built.data);
    Ok(Ok((bk, (built.data.len(), lobes))))
}

/// The best-known RMSEs recorded in `contents` when it was written by `spec` (same
/// fingerprint), else none.
pub fn recorded_for(spec: &Spec, contents: Option<&Contents>) -> BTreeMap<String, BestKnown> {
    let fingerprint = spec.fingerprint();
    contents
        .filter(|c| c.header.fingerprint == fingerprint)
        .map(|c| c.best_known().clone())
        .unwrap_or_default()
}

/// [`resolve`] before a run into `dir` (what the Python package's `run` uses; `brdf-sls run`
/// does the same inside [`crate::prepare`]): the best-known RMSEs recorded in `dir`'s results
/// when that folder was written by this spec, else computed. Returns [`run_lines`].
pub fn resolve_for_run(
    spec: &mut Spec,
    dir: Option<&std::path::Path>,
) -> Result<Vec<String>, InstanceError> {
    let contents = dir.and_then(|d| brdf_experiment::store::read_results(d).ok());
    let known = recorded_for(spec, contents.as_ref());
    let resolved = resolve(spec, &known)?;
    Ok(run_lines(spec, &resolved))
}

/// What a run prints after resolving: the notes on instances left without a best-known RMSE,
/// then the closeness [`warnings`], one line each.
pub fn run_lines(spec: &Spec, resolved: &Resolved) -> Vec<String> {
    let mut lines: Vec<String> = resolved
        .notes
        .iter()
        .map(|n| format!("note: {n}"))
        .collect();
    lines.extend(warnings(spec));
    lines
}

/// What [`resolve`] used and what it could not do.
#[derive(Clone, Debug, Default)]
pub struct Resolved {
    /// Best-known RMSE by instance name.
    pub known: BTreeMap<String, BestKnown>,
    /// Instances left without one (their data could not be built, or they were skipped), with
    /// the reason.
    pub notes: Vec<String>,
    /// Instances skipped for their size ([`resolve_within`]).
    pub skipped: usize,
    /// The samples of the data and what each lobe of the best-known fit does on them (samples
    /// covered, dead), by instance name: for the best-known RMSEs computed here, not those
    /// read from results.
    pub lobes: BTreeMap<String, LobesOnData>,
}

/// The number of samples of an instance's data and what each lobe of its best-known fit does
/// on them.
pub type LobesOnData = (usize, Vec<LobeUse>);

/// Warnings for absolute targets within [`CLOSE_FRACTION`] of (or below) the best-known RMSE:
/// such targets measure luck in hitting a near-optimum, or cannot be reached at all.
pub fn warnings(spec: &Spec) -> Vec<String> {
    let mut out = Vec::new();
    for inst in &spec.instances {
        let Some(bk) = inst.best_known.as_ref().map(|b| b.rmse) else {
            continue;
        };
        for &t in &inst.absolute_targets {
            if t < bk {
                out.push(format!(
                    "warning: instance `{}`: target {t} is below the best-known RMSE {} \
                     (it may never be reached)",
                    inst.name,
                    rmse_text(bk)
                ));
            } else if t <= bk * (1.0 + CLOSE_FRACTION) {
                out.push(format!(
                    "warning: instance `{}`: target {t} is within {}% of the best-known RMSE \
                     {} ({:.3}% above it)",
                    inst.name,
                    CLOSE_FRACTION * 100.0,
                    rmse_text(bk),
                    (t / bk - 1.0) * 100.0
                ));
            }
        }
    }
    out
}

/// Warnings for instances where a trial reached a lower full-data RMSE than the recorded
/// best-known one (by more than 1e-9 relative, above rounding): the relative targets and the
/// closeness warnings were then measured against a reference that is too high.
pub fn below_best_known(
    spec: &Spec,
    records: &[brdf_experiment::store::TrialRecord],
) -> Vec<String> {
    let mut out = Vec::new();
    for inst in &spec.instances {
        let Some(bk) = inst.best_known.as_ref().map(|b| b.rmse) else {
            continue;
        };
        let lowest = records
            .iter()
            .filter(|r| r.instance == inst.name && r.result.best_rmse.is_finite())
            .min_by(|a, b| a.result.best_rmse.total_cmp(&b.result.best_rmse));
        if let Some(r) = lowest.filter(|r| r.result.best_rmse < bk * (1.0 - 1e-9)) {
            out.push(format!(
                "warning: instance `{}`: trial {} reached RMSE {}, {:.3}% below the recorded \
                 best-known RMSE {}: targets relative to it are easier than intended, and it \
                 is not the optimum",
                inst.name,
                r.key,
                rmse_text(r.result.best_rmse),
                (1.0 - r.result.best_rmse / bk) * 100.0,
                rmse_text(bk)
            ));
        }
    }
    out
}

/// An RMSE with 6 significant digits, in scientific notation when small.
fn rmse_text(x: f64) -> String {
    if x != 0.0 && x.abs() < 1e-3 {
        format!("{x:.5e}")
    } else {
        format!("{x:.6}")
    }
}

/// How far `t` lies above `bk`: a percentage, or a ratio when `bk` is (near) zero.
fn above_text(t: f64, bk: f64) -> String {
    let ratio = t / bk;
    if ratio.is_finite() && ratio < 100.0 {
        format!("{:+.2}%", (ratio - 1.0) * 100.0)
    } else {
        "far above".into()
    }
}

/// One line per instance: its best-known RMSE and every target relative to it (empty when no
/// instance has one).
pub fn summary(spec: &Spec) -> String {
    if spec.instances.iter().all(|i| i.best_known.is_none()) {
        return String::new();
    }
    let mut s = format!(
        "best-known RMSE (full-data descents from {STARTS} seeded starts, from the truth of \
         generated instances and from the optima of nested layouts, the best polished):\n"
    );
    for inst in &spec.instances {
        let Some(bk) = inst.best_known.as_ref().map(|b| b.rmse) else {
            continue;
        };
        let rel: Vec<String> = inst
            .targets
            .iter()
            .map(|&t| format!("{} ({})", rmse_text(t), above_text(t, bk)))
            .collect();
        s.push_str(&format!(
            "  {}: {}; targets {}\n",
            inst.name,
            rmse_text(bk),
            rel.join(", ")
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn spec(targets: &str, sigma: f64) -> Spec {
        let text = format!(
            "seed = 1\ntrials = 1\n[budget]\ncpu_seconds = 1\n[[instance]]\nname = \"t\"\n\
             targets = {targets}\n[instance.synthetic]\nparams = \"tuning\"\nsamples = 400\n\
             sigma = {sigma}\n[[algorithm]]\nkind = \"rpls\"\n"
        );
        Spec::parse(&text, "t.toml", "t", Path::new(".")).unwrap()
    }

    #[test]
    fn best_known_is_deterministic_and_near_the_noise_level() {
        let s = spec("[0.2]", 0.1);
        let built = brdf_experiment::instance::build(&s.instances[0]).unwrap();
        let a = compute(&s.instances[0], &built).unwrap();
        let b = compute(&s.instances[0], &built).unwrap();
        assert_eq!(a, b);
        // Noise sigma 0.1 on 400 samples with 6 free parameters: the optimum lies a little
        // below 0.1, and the fit from the truth cannot be worse than the truth's own RMSE.
        assert!((0.08..0.11).contains(&a.rmse), "{a:?}");
        assert!(a.rmse <= a.from_truth.unwrap());
    }

    #[test]
    fn missing_data_is_a_note_unless_a_relative_target_needs_it() {
        let missing = |targets: &str| {
            let text = format!(
                "seed = 1\ntrials = 1\n[budget]\ncpu_seconds = 1\n[[instance]]\nname = \"f\"\n\
                 targets = {targets}\n[instance.file]\npath = \"no-such-file.brdf\"\n\
                 [[algorithm]]\nkind = \"rpls\"\n"
            );
            Spec::parse(&text, "t.toml", "t", Path::new(".")).unwrap()
        };
        let mut s = missing("[0.1]");
        let r = resolve(&mut s, &BTreeMap::new()).unwrap();
        assert!(r.known.is_empty());
        assert!(r.notes[0].contains("instance `f`"), "{:?}", r.notes);
        assert_eq!(s.instances[0].run_target(), 0.1);
        assert_eq!(summary(&s), "");
        assert!(resolve(&mut missing("[{ relative = 0.01 }]"), &BTreeMap::new()).is_err());
    }

    /// The best-known RMSE belongs to the data and the model, not to the search setting: with
    /// the paper's uniform starts in raw n, 32 starts once found 0.059997 on the Krylon paint
    /// instead of its optimum 0.036886.
    #[test]
    fn best_known_does_not_depend_on_the_start_distribution() {
        let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../experiments/data");
        let krylon = |model: &str| {
            let text = format!(
                "seed = 1\ntrials = 1\n[budget]\ncpu_seconds = 1\n[[instance]]\nname = \"k\"\n\
                 targets = [0.04]\n[instance.file]\npath = \"krylon_blue.brdf\"\n\
                 format = \"cornell\"\nwavelength = 550\nmax_value = 1.0\n[instance.model]\n\
                 kind = \"isotropic\"\n{model}\n[[algorithm]]\nkind = \"rpls\"\n"
            );
            let s = Spec::parse(&text, "k.toml", "k", &data).unwrap();
            let built = brdf_experiment::instance::build(&s.instances[0]).unwrap();
            compute(&s.instances[0], &built).unwrap().rmse
        };
        let ours = krylon("");
        let paper = krylon("exponent = \"raw\"\nstarts = \"uniform\"");
        assert!((ours - 0.036886).abs() < 5e-7, "{ours}");
        assert!((paper - ours).abs() < 1e-6 * ours, "{paper} vs {ours}");
    }

    /// The acrylic paint: random starts alone (no nested layouts) ended two anisotropic lobes
    /// at 500 nm at 0.060916, above the 0.049528 of two isotropic lobes, and three isotropic
    /// lobes at 450 nm (values up to 1) at 0.006958, above the 0.006618 of two. With the
    /// nested layouts a layout's best-known RMSE is at most those of the layouts nested in it.
    #[test]
    fn nested_layouts_bound_the_best_known() {
        let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../experiments/data");
        let acryl = |wavelength: u32, max_value: &str, kind: &str, lobes: usize| {
            let text = format!(
                "seed = 1\ntrials = 1\n[budget]\ncpu_seconds = 1\n[[instance]]\nname = \"a\"\n\
                 targets = [0.04]\n[instance.file]\npath = \"acryl_blue.brdf\"\n\
                 format = \"cornell\"\nwavelength = {wavelength}\n{max_value}\
                 [instance.model]\nkind = \"{kind}\"\nlobes = {lobes}\n\
                 [[algorithm]]\nkind = \"rpls\"\n"
            );
            let s = Spec::parse(&text, "a.toml", "a", &data).unwrap();
            let built = brdf_experiment::instance::build(&s.instances[0]).unwrap();
            compute(&s.instances[0], &built).unwrap()
        };
        let at_most = |a: &BestKnown, b: &BestKnown| a.rmse <= b.rmse * (1.0 + 1e-12);
        let two = acryl(500, "", "anisotropic", 2);
        let two_iso = acryl(500, "", "isotropic", 2);
        let one = acryl(500, "", "anisotropic", 1);
        assert!(at_most(&two, &two_iso), "{two:?} vs {two_iso:?}");
        assert!(at_most(&two, &one), "{two:?} vs {one:?}");
        // The nested layout's optimum is among the candidates. Which candidate ends lowest is
        // a matter of round-off: it was that optimum until issue 38's round-off changes (`d^n`
        // flushed below 2^-1010, the tall QR's 256-row blocks); since then a random start,
        // polished, ends lower.
        let how = two.provenance.unwrap();
        assert!(
            how.contains("the optimum of the nested layout with 2 isotropic lobes"),
            "{how}"
        );
        let three = acryl(450, "max_value = 1.0\n", "isotropic", 3);
        let two = acryl(450, "max_value = 1.0\n", "isotropic", 2);
        assert!(at_most(&three, &two), "{three:?} vs {two:?}");
    }

    #[test]
    fn a_trial_below_the_best_known_is_reported() {
        let mut s = spec("[0.5]", 0.1);
        let recorded = BestKnown {
            rmse: 0.2,
            from_truth: None,
            starts: STARTS,
            seed: SEED,
            provenance: None,
        };
        resolve(&mut s, &BTreeMap::from([("t".to_string(), recorded)])).unwrap();
        let record = |rmse: f64| brdf_experiment::store::TrialRecord {
            key: "t/RPLS/0".into(),
            instance: "t".into(),
            config: "RPLS".into(),
            trial: 0,
            seed: 1,
            target: 0.5,
            budget: sls::Budget::default(),
            result: sls::TrialResult {
                stop: sls::StopReason::CpuBudget,
                reached_at: None,
                ended_at: sls::Stamp::default(),
                best_rmse: rmse,
                best_x: vec![],
                trace: vec![],
                counters: vec![],
                failure: None,
            },
        };
        assert!(below_best_known(&s, &[record(0.2), record(0.3)]).is_empty());
        let w = below_best_known(&s, &[record(0.3), record(0.19)]).join("\n");
        assert!(
            w.contains("trial t/RPLS/0 reached RMSE 0.190000, 5.000% below the recorded best-known RMSE 0.200000"),
            "{w}"
        );
    }

    #[test]
    fn noiseless_best_known_is_near_zero() {
        let s = spec("[0.01]", 0.0);
        let built = brdf_experiment::instance::build(&s.instances[0]).unwrap();
        let a = compute(&s.instances[0], &built).unwrap();
        assert!(a.rmse < 1e-6, "{a:?}");
    }

    #[test]
    fn relative_targets_resolve_and_close_targets_warn() {
        // Relative targets alone: nothing to run to until resolved.
        assert!(
            spec("[{ relative = 0.05 }]", 0.1).instances[0]
                .run_target()
                .is_nan()
        );
        let mut s = spec("[{ relative = 0.05 }, 0.0999, 0.5]", 0.1);
        assert!(s.has_unresolved_targets());
        assert_eq!(s.instances[0].run_target(), 0.0999);
        let used = resolve(&mut s, &BTreeMap::new()).unwrap().known;
        let bk = used["t"].rmse;
        assert!(!s.has_unresolved_targets());
        assert!(s.instances[0].targets.contains(&(bk * 1.05)));
        // A recorded value is used as it is, not recomputed.
        let mut recorded = used.clone();
        recorded.get_mut("t").unwrap().rmse = 0.1;
        let mut s2 = spec("[{ relative = 0.05 }, 0.0999, 0.5]", 0.1);
        resolve(&mut s2, &recorded).unwrap();
        assert_eq!(s2.instances[0].run_target(), 0.0999);
        let w = warnings(&s2).join("\n");
        assert!(w.contains("target 0.0999 is below"), "{w}");
        assert!(!w.contains("target 0.5"), "{w}");
        let mut closer = recorded["t"].clone();
        closer.rmse = 0.0995;
        s2.instances[0].resolve_targets(closer);
        let w = warnings(&s2).join("\n");
        assert!(w.contains("target 0.0999 is within 1%"), "{w}");
    }
}
