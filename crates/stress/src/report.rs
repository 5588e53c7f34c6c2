//! The stress report: every figure measured, the checks with their tolerances and reasons,
//! and Markdown / JSON output.

use crate::diagnose::{DiagnoseOptions, Diagnosis, diagnose, refit};
use crate::families::{self, FamilySection};
use crate::kernels::{self, KernelSection};
use crate::suite::{self, SuiteSection};
use crate::{NamedData, StressError, StressOptions, derive_seed};
use bounded_lm::Solver;
use brdf_model::{DataSet, Evaluator, Kernel, Layout, LobeKind, Samples, named_params, synthetic};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// One pass/fail check with its tolerance and the reason for that tolerance.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Check {
    /// What is checked.
    pub name: String,
    /// Whether it held.
    pub passed: bool,
    /// The measured value.
    pub measured: String,
    /// The tolerance.
    pub tolerance: String,
    /// Why the tolerance has this value.
    pub reason: String,
}

/// Diagnostics of one fitted data set.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct NamedDiagnosis {
    /// Data set name.
    pub name: String,
    /// Layout description.
    pub layout: String,
    /// The diagnosis.
    pub diagnosis: Diagnosis,
}

/// Everything a stress run measured.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct StressReport {
    /// Quick mode.
    pub quick: bool,
    /// Master seed.
    pub seed: u64,
    /// Worker threads.
    pub threads: usize,
    /// Kernels this CPU runs.
    pub simd_levels: Vec<String>,
    /// Wall seconds of each section (kernels, suite, diagnostics) and in total.
    pub seconds: [f64; 4],
    /// Section 1.
    pub kernels: KernelSection,
    /// Section 1b: the other model families against their double-double references.
    #[serde(default)]
    pub families: FamilySection,
    /// Section 2.
    pub suite: SuiteSection,
    /// Section 3.
    pub diagnostics: Vec<NamedDiagnosis>,
    /// All checks.
    pub checks: Vec<Check>,
}

impl StressReport {
    /// True when every check passed.
    pub fn passed(&self) -> bool {
        self.checks.iter().all(|c| c.passed)
    }

    /// The checks that failed.
    pub fn failures(&self) -> Vec<&Check> {
        self.checks.iter().filter(|c| !c.passed).collect()
    }

    /// The report as pretty-printed JSON (NaN written as null).
    pub fn to_json(&self) -> serde_json::Result<String> {
        serde_json::to_string_pretty(self)
    }

    /// Writes `stress.md` and `stress.json` into `dir` (created if missing), each through
    /// `write(path, bytes)`: the command line passes its atomic writer (temporary file, fsync,
    /// rename), so a failed write never leaves half a report.
    pub fn write_to(
        &self,
        dir: &Path,
        write: impl Fn(&Path, &[u8]) -> std::io::Result<()>,
    ) -> Result<(), StressError> {
        let io = |path: &Path, source| StressError::Io {
            path: path.display().to_string(),
            source,
        };
        std::fs::create_dir_all(dir).map_err(|e| io(dir, e))?;
        let md = dir.join("stress.md");
        write(&md, self.to_markdown().as_bytes()).map_err(|e| io(&md, e))?;
        let js = dir.join("stress.json");
        let text = self
            .to_json()
            .map_err(|e| io(&js, std::io::Error::other(e)))?;
        write(&js, text.as_bytes()).map_err(|e| io(&js, e))?;
        Ok(())
    }

    /// The report as Markdown.
    pub fn to_markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "# Numerical stress report\n\n{} mode, seed {}, {} threads, kernels {}; \
             {:.1} s (kernels {:.1} s, solver suite {:.1} s, diagnostics {:.1} s).\n",
            if self.quick { "quick" } else { "full" },
            self.seed,
            self.threads,
            self.simd_levels.join(", "),
            self.seconds[3],
            self.seconds[0],
            self.seconds[1],
            self.seconds[2]
        );
        let failed = self.failures();
        let _ = writeln!(
            s,
            "**{}**: {} of {} checks passed.\n",
            if failed.is_empty() {
                "PASSED"
            } else {
                "FAILED"
            },
            self.checks.len() - failed.len(),
            self.checks.len()
        );
        let _ = writeln!(
            s,
            "## Checks\n\n| check | result | measured | tolerance | why this tolerance |\n|---|---|---|---|---|"
        );
        for c in &self.checks {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} |",
                c.name,
                if c.passed { "pass" } else { "**FAIL**" },
                c.measured,
                c.tolerance,
                c.reason
            );
        }
        let k = &self.kernels;
        let _ = writeln!(
            s,
            "\n## 1. Kernel accuracy against double-double\n\n{} batches of {} direction pairs \
             over the layouts {}. Errors in ulps of the reference value; \"normalised\" is the \
             error over its forward-error bound (see the crate docs of `reference`).\n",
            k.batches,
            k.batch_size,
            k.layouts.join("; ")
        );
        let _ = writeln!(
            s,
            "| kernel | values | median ulps | p99.9 ulps | max ulps | max normalised | class mismatches | missed overflow | spurious failures | non-finite J on success |\n|---|---|---|---|---|---|---|---|---|---|"
        );
        for ks in &k.kernels {
            let _ = writeln!(
                s,
                "| {} | {} | {:.2} | {:.1} | {:.3e} | {:.3} | {} | {} | {} | {} |",
                ks.kernel,
                ks.values,
                ks.median_ulps,
                ks.p999_ulps,
                ks.max_ulps,
                ks.max_normalised,
                ks.class_mismatches,
                ks.missed_overflow,
                ks.spurious_failures,
                ks.jacobian_nonfinite_on_success
            );
        }
        for ks in &k.kernels {
            let _ = writeln!(
                s,
                "\n### {}\n\n| regime | values | p99.9 ulps | max ulps | max normalised |\n|---|---|---|---|---|",
                ks.kernel
            );
            for r in &ks.by_regime {
                let _ = writeln!(
                    s,
                    "| {:?} | {} | {:.1} | {:.3e} | {:.3} |",
                    r.regime, r.count, r.p999_ulps, r.max_ulps, r.max_normalised
                );
            }
            if !ks.columns.is_empty() {
                let _ = writeln!(
                    s,
                    "\n| Jacobian column | batch-columns | p99.9 rel. error | max rel. error | max normalised | excluded (at the clamp) |\n|---|---|---|---|---|---|"
                );
                for c in &ks.columns {
                    let _ = writeln!(
                        s,
                        "| {} | {} | {:.2e} | {:.2e} | {:.3} | {} |",
                        c.role,
                        c.columns,
                        c.p999_rel_error,
                        c.max_rel_error,
                        c.max_normalised,
                        c.excluded_near_clamp
                    );
                }
            }
            let _ = writeln!(s, "\nWorst value: {}", ks.worst_value);
            if let Some(m) = &ks.first_mismatch {
                let _ = writeln!(s, "\nFirst mismatch: {m}");
            }
        }
        let _ = writeln!(
            s,
            "\n## 1b. Model families against double-double\n\n{} batches of {} direction \
             pairs per family: one anisotropic lobe, one isotropic lobe or two lobes; points \
             uniform in the box, at the sharpest and widest shape, at the edges of the linear \
             parameters, grazing directions and directions on the horizon (where a family whose \
             value there is +inf, Ward's, must fail). Value errors relative to the reference \
             value, and over their bound (1e-12 of the value plus 8 eps times the lobes' \
             condition, see the checks); Jacobian errors relative to the column's largest \
             entry, against five-point differences of the reference in double-double; both \
             absolute below 1e-250.\n",
            self.families.batches,
            families::BATCH
        );
        let _ = writeln!(
            s,
            "| family | kernel | values | max value error | value error / bound | max Jacobian error | mismatches | NaN |\n|---|---|---|---|---|---|---|---|"
        );
        for f in &self.families.stats {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.2e} | {:.3} | {:.2e} | {} | {} |",
                f.family,
                f.kernel,
                f.values,
                f.max_value_error,
                f.max_value_normalised,
                f.max_jacobian_error,
                f.mismatches,
                f.nans
            );
        }
        let su = &self.suite;
        let _ = writeln!(
            s,
            "\n## 2. Solver suite\n\nNIST StRD: {}/{} right. Moré-Garbow-Hillstrom: {}. BRDF \
             hostile cases: {}/{} right.\n",
            su.nist_right, su.nist_total, su.mgh_status, su.brdf_right, su.brdf_total
        );
        let _ = writeln!(
            s,
            "| group | case | code | outcome | right | measured | iterations | evaluations (r / J) | suite failure |\n|---|---|---|---|---|---|---|---|---|"
        );
        for c in &su.cases {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} | {} / {} | {} |",
                c.group,
                c.name,
                c.code.map_or("-".into(), |v| v.to_string()),
                c.outcome,
                if c.right { "yes" } else { "no" },
                c.measured,
                c.iterations,
                c.residual_evaluations,
                c.jacobian_evaluations,
                c.failure.as_deref().unwrap_or("")
            );
        }
        let mut crit: Vec<&str> = su.cases.iter().map(|c| c.criterion.as_str()).collect();
        crit.sort_unstable();
        crit.dedup();
        let _ = writeln!(s, "\nCriteria:\n");
        for c in crit {
            let _ = writeln!(s, "- {c}");
        }
        let _ = writeln!(s, "\n## 3. Fit diagnostics\n");
        for d in &self.diagnostics {
            let _ = writeln!(
                s,
                "### {} ({})\n\n{}",
                d.name,
                d.layout,
                d.diagnosis.to_markdown()
            );
        }
        s
    }
}

/// Sizes of a run ([`Sizes::quick`], [`Sizes::full`], or smaller for tests).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Sizes {
    /// Kernel batches (each [`kernels::BATCH`] direction pairs).
    pub batches: usize,
    /// 25-sample subsample cases in the solver suite.
    pub subsamples: usize,
    /// Bootstrap resamples per diagnosed fit.
    pub bootstrap: usize,
    /// Seeded starts when fitting a supplied data set.
    pub starts: usize,
    /// Samples of the synthetic diagnostics instance.
    pub synthetic_samples: usize,
}

impl Sizes {
    /// Quick mode: under a minute on 2 cores in release mode.
    pub fn quick() -> Sizes {
        Sizes {
            batches: 6000,
            subsamples: 40,
            bootstrap: 200,
            starts: 8,
            synthetic_samples: 2000,
        }
    }
    /// Full mode.
    pub fn full() -> Sizes {
        Sizes {
            batches: 60000,
            subsamples: 200,
            bootstrap: 1000,
            starts: 32,
            synthetic_samples: 10000,
        }
    }
}

pub(crate) fn run_all(o: &StressOptions) -> Result<StressReport, StressError> {
    let plan = o.sizes.unwrap_or(if o.quick {
        Sizes::quick()
    } else {
        Sizes::full()
    });
    let t0 = Instant::now();
    let last = std::cell::Cell::new(0.0);
    let done = |group: &str| {
        let now = t0.elapsed().as_secs_f64();
        if let Some(progress) = o.progress {
            progress(&format!(
                "stress: {group} done in {:.1} s ({:.1} s elapsed)",
                now - last.get(),
                now
            ));
        }
        last.set(now);
    };
    let sets: Vec<&DataSet> = o.data.iter().map(|d| &d.data).collect();
    let kernels = kernels::run(plan.batches, derive_seed(o.seed, 1, 0), &sets);
    let families = families::run((plan.batches / 20).max(15), derive_seed(o.seed, 4, 0));
    done("kernels");
    let t1 = t0.elapsed().as_secs_f64();
    let suite = suite::run_with(derive_seed(o.seed, 2, 0), plan.subsamples, &done);
    let t2 = t0.elapsed().as_secs_f64();
    let diagnostics = diagnostics(o, &plan)?;
    done("diagnostics");
    let t3 = t0.elapsed().as_secs_f64();
    let mut checks = checks(&kernels, &suite, &diagnostics);
    checks.extend(family_checks(&families));
    Ok(StressReport {
        quick: o.quick,
        seed: o.seed,
        threads: rayon::current_num_threads(),
        simd_levels: Kernel::available()
            .iter()
            .map(|l| l.name().to_string())
            .collect(),
        seconds: [t1, t2 - t1, t3 - t2, t3],
        kernels,
        families,
        suite,
        diagnostics,
        checks,
    })
}

fn family_checks(f: &FamilySection) -> Vec<Check> {
    let mut c = Vec::new();
    for s in &f.stats {
        let who = format!("{} ({})", s.family, s.kernel);
        c.push(check(
            &format!("{who}: value error against double-double"),
            s.max_value_normalised <= 1.0,
            format!(
                "{:.2e} relative, {:.3} of the bound",
                s.max_value_error, s.max_value_normalised
            ),
            &format!(
                "<= {:e} relative + {} eps sum_k |lobe_k| kappa_k",
                families::VALUE_TOLERANCE,
                families::CONDITION_FACTOR
            ),
            "the formulas round a fixed number of times (the fast exp and ln within a few \
             ulps): 1e-12 is a wide margin, which a cancellation or a wrong formula leaves; \
             kappa_k is the condition of lobe k's logarithm (its exponent's, 2 sum |x'| A / a^2 \
             for a quadratic form of rotated slopes x' = c x + s y, A = |c x| + |s y|): where \
             a sharp axis crosses a half vector far from the normal, the rounding of the \
             prepared slopes and of the pan's cosine moves the value by up to 3e-10 in any \
             f64 evaluation, and 8 covers the roundings per unit of kappa (about 5.5)",
        ));
        c.push(check(
            &format!("{who}: Jacobian error against double-double differences"),
            s.max_jacobian_error <= families::JACOBIAN_TOLERANCE,
            format!("{:.2e}", s.max_jacobian_error),
            "<= 1e-8 of the column's scale",
            "an analytic derivative is exact to rounding; a missing or wrong term of the chain \
             rule shows at 1e-3 or worse",
        ));
        c.push(check(
            &format!("{who}: NaN and success mismatches"),
            s.nans == 0 && s.mismatches == 0,
            format!("{} NaN, {} mismatches", s.nans, s.mismatches),
            "0",
            "inside the box every value is finite: an evaluation must neither fail nor give NaN",
        ));
    }
    c
}

/// Section 3 on a synthetic tuning instance (noise 0.01, the truth known), the same
/// directions restricted to the plane of incidence (the identifiability warning must
/// appear), and every supplied data set (fitted with one isotropic lobe from the best of a
/// few seeded starts).
fn diagnostics(o: &StressOptions, plan: &Sizes) -> Result<Vec<NamedDiagnosis>, StressError> {
    let dopt = |k: u64| DiagnoseOptions {
        bootstrap: plan.bootstrap,
        seed: derive_seed(o.seed, 3, k),
        ..DiagnoseOptions::default()
    };
    let tuning = named_params("tuning").expect("tuning");
    let aniso = Layout::builder(&[LobeKind::Anisotropic]).build()?;
    let mut out = Vec::new();
    let data = synthetic(
        &tuning,
        plan.synthetic_samples,
        0.01,
        derive_seed(o.seed, 4, 0),
    );
    let x = fit_from(&aniso, &aniso.prepare(&data), aniso.encode(&tuning));
    out.push(NamedDiagnosis {
        name: format!(
            "synthetic tuning, {} samples, sigma 0.01",
            plan.synthetic_samples
        ),
        layout: "1 anisotropic lobe".into(),
        diagnosis: diagnose(&aniso, &data, &x, &dopt(0))?,
    });
    let mut rng = Pcg64::seed_from_u64(derive_seed(o.seed, 4, 1));
    let mut plane = DataSet::new();
    for _ in 0..plan.synthetic_samples / 2 {
        let ti = 1.45 * rng.random::<f64>();
        let to = 2.9 * rng.random::<f64>() - 1.45;
        let (u, v) = ([ti.sin(), 0.0, ti.cos()], [to.sin(), 0.0, to.cos()]);
        plane.push(u, v, tuning.value(u, v));
    }
    let x = fit_from(&aniso, &aniso.prepare(&plane), aniso.encode(&tuning));
    out.push(NamedDiagnosis {
        name: "in-plane tuning (incident azimuth 0)".into(),
        layout: "1 anisotropic lobe".into(),
        diagnosis: diagnose(&aniso, &plane, &x, &dopt(1))?,
    });
    let iso = Layout::builder(&[LobeKind::Isotropic]).build()?;
    for (k, NamedData { name, data }) in o.data.iter().enumerate() {
        if data.is_empty() {
            continue;
        }
        let mut rng = Pcg64::seed_from_u64(derive_seed(o.seed, 5, k as u64));
        let mut best: Option<(f64, Vec<f64>)> = None;
        let mut ev = Evaluator::new(&iso);
        let samples = iso.prepare(data);
        for _ in 0..plan.starts {
            let start: Vec<f64> = iso
                .lower()
                .iter()
                .zip(iso.upper())
                .map(|(&l, &h)| l + (h - l) * rng.random::<f64>())
                .collect();
            let x = fit_from(&iso, &samples, start);
            let e = ev.rmse(&x, &samples);
            if best.as_ref().is_none_or(|b| e < b.0) {
                best = Some((e, x));
            }
        }
        let Some((_, x)) = best else { continue };
        match diagnose(&iso, data, &x, &dopt(10 + k as u64)) {
            Ok(d) => out.push(NamedDiagnosis {
                name: name.clone(),
                layout: "1 isotropic lobe (best of seeded starts)".into(),
                diagnosis: d,
            }),
            Err(StressError::Invalid(_)) => continue,
            Err(e) => return Err(e),
        }
    }
    Ok(out)
}

fn fit_from(layout: &Layout, data: &Samples, mut x: Vec<f64>) -> Vec<f64> {
    let mut ev = Evaluator::new(layout);
    let mut solver = Solver::new();
    // A start that cannot be evaluated keeps x as given; diagnose reports on it.
    let _ = refit(&mut ev, &mut solver, data, &mut x);
    x
}

fn check(name: &str, passed: bool, measured: String, tolerance: &str, reason: &str) -> Check {
    Check {
        name: name.into(),
        passed,
        measured,
        tolerance: tolerance.into(),
        reason: reason.into(),
    }
}

fn checks(k: &KernelSection, s: &SuiteSection, d: &[NamedDiagnosis]) -> Vec<Check> {
    let mut c = Vec::new();
    for ks in &k.kernels {
        let name = &ks.kernel;
        c.push(check(
            &format!("{name}: NaN/inf class mismatches of values"),
            ks.class_mismatches == 0,
            ks.class_mismatches.to_string(),
            "0",
            "a value must be +inf exactly when d^n overflows and never NaN (crate contract); \
             only values within 1e-9 (log scale) of the threshold may go either way",
        ));
        c.push(check(
            &format!("{name}: value error over forward-error bound"),
            ks.max_normalised <= 1.0,
            format!("{:.3}", ks.max_normalised),
            "<= 1",
            "bound = eps (64 + 8 n A/|d| + 4 |n ln d|) f: the kernel exp truncates at ~32 eps, \
             d carries <= 8 eps A from rounded products and rotation, n ln d is rounded; a \
             wrong formula exceeds it by orders of magnitude",
        ));
        if ks.kernel != "scalar-libm" {
            c.push(check(
                &format!("{name}: overflow reported by residuals/jacobian"),
                ks.missed_overflow == 0,
                ks.missed_overflow.to_string(),
                "0",
                "the evaluator must report a failed evaluation whenever a value (or, for the \
                 Jacobian, a derivative) overflows, so the solver rejects the step",
            ));
            c.push(check(
                &format!("{name}: no spurious failed evaluation"),
                ks.spurious_failures == 0,
                ks.spurious_failures.to_string(),
                "0",
                "a failure without an overflow in exact arithmetic (outside the 1e-9 rounding \
                 band of the threshold) makes the solver reject a valid step",
            ));
            c.push(check(
                &format!("{name}: non-finite Jacobian entries on success"),
                ks.jacobian_nonfinite_on_success == 0,
                ks.jacobian_nonfinite_on_success.to_string(),
                "0",
                "a Jacobian reported as successful must be finite everywhere",
            ));
            let worst = ks
                .columns
                .iter()
                .map(|c| c.max_normalised)
                .fold(0.0, f64::max);
            c.push(check(
                &format!("{name}: Jacobian error over forward-error bound"),
                worst <= 1.0,
                format!("{worst:.3}"),
                "<= 1",
                "per entry: the value bound for n d^n / d (with one more d rounding) times \
                 |dd/dtheta| plus 8 eps for the rounded weights; entries within 8 eps A of the \
                 clamp d = 0 are excluded (the derivative jumps there); where d^n is below \
                 1.4e-304, which the vector kernels flush to 0, a zero entry passes",
            ));
        }
        if ks.overflow_batches == 0 {
            c.push(check(
                &format!("{name}: overflow path exercised"),
                false,
                "0 batches".into(),
                ">= 1",
                "the sweep must reach the overflow of d^n to test it",
            ));
        }
    }
    let wrong: Vec<String> = s
        .failures()
        .map(|c| format!("{}: {}", c.name, c.failure.as_deref().unwrap_or("")))
        .collect();
    c.push(check(
        "solver suite: no success code on a wrong answer, no NaN, no point outside the box",
        wrong.is_empty(),
        if wrong.is_empty() {
            "none".into()
        } else {
            wrong.join("; ")
        },
        "none",
        "a success code (3..=6) is a promise the search algorithms act on",
    ));
    c.push(check(
        "NIST StRD right (LRE >= 4)",
        s.nist_right >= 52,
        format!("{}/{}", s.nist_right, s.nist_total),
        ">= 52/54",
        "bounded-lm's documented result (the misses are MGH17 start 1 and MGH10 start 1, both \
         with failure codes); fewer is a regression",
    ));
    let plane = d.iter().find(|n| n.name.starts_with("in-plane"));
    let warned = plane.is_some_and(|n| {
        n.diagnosis
            .warnings
            .iter()
            .any(|w| w.contains("isotropic layout"))
    });
    c.push(check(
        "diagnostics: in-plane data produce the identifiability warning",
        warned,
        warned.to_string(),
        "true",
        "with incident azimuth 0 only Cx cos^2 p + Cy sin^2 p and (Cx - Cy) cos p sin p reach \
         the data",
    ));
    let nan = d.iter().any(|n| {
        let g = &n.diagnosis;
        g.x.iter()
            .chain(&g.singular_values)
            .chain(&g.standard_errors)
            .any(|v| v.is_nan())
            || g.rmse.is_nan()
    });
    c.push(check(
        "diagnostics: no NaN in parameters, singular values, standard errors",
        !nan,
        (!nan).to_string(),
        "true",
        "undetermined quantities are reported as inf with a warning, never NaN",
    ));
    c
}
