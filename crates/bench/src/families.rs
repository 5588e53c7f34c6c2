//! The model families' rows of the bench: for every registered family, the evaluation kernel's
//! cost per lobe-sample and what RPLS and AED pay per sample-evaluation, each beside the same
//! measurement of Lafortune, so the ratios compare like with like.
//!
//! Every family is measured at the same kind of point: one lobe of the family's anisotropic
//! kind where it has one (else its first kind), the parameters 0.4 of the way from the lower to
//! the upper bound in the optimiser's coordinates, 10000 noise-free samples (instance seed 1).
//! The searches run to the CPU cutoff (target 0, which no trial reaches): the row is about cost
//! per evaluation, not about time to a target.

use std::hint::black_box;
use std::sync::Arc;

use anyhow::{Context, Result};
use brdf_model::{Evaluator, Layout, LobeKind, family, family_names, synthetic};
use serde::{Deserialize, Serialize};

use crate::{Goal, cpu_ns_per, median_ns_per_computed_evaluation, opt};

/// Samples of a family's instance.
const SAMPLES: usize = 10_000;
/// Where in each bound the measured point lies (in the optimiser's coordinates).
const POINT: f64 = 0.4;
/// Most seeds per family search (the bench's `--seeds` caps it further).
const MAX_SEEDS: u64 = 5;
/// Most CPU seconds per family trial (the bench's `--cutoff` caps it further).
const MAX_CUTOFF: f64 = 0.5;
/// The goal: no family's search costs more than this many times Lafortune's per
/// sample-evaluation.
pub(crate) const SEARCH_RATIO_LIMIT: f64 = 2.0;

/// One family's costs.
#[derive(Serialize, Deserialize)]
pub(crate) struct FamilyRow {
    pub(crate) family: String,
    /// The lobe kind measured.
    pub(crate) kind: String,
    /// Free parameters of the one-lobe layout.
    pub(crate) parameters: usize,
    /// The kernel the fastest evaluator uses.
    pub(crate) kernel: String,
    /// Values, ns per lobe-sample.
    pub(crate) values_ns: f64,
    /// Values and Jacobian from scratch, ns per lobe-sample.
    pub(crate) jacobian_ns: f64,
    /// Median over the trials of CPU ns per computed sample-evaluation, RPLS with its defaults.
    pub(crate) rpls_ns: Option<f64>,
    /// The same for AED with its defaults.
    pub(crate) aed_ns: Option<f64>,
}

/// How the family rows were measured (for the markdown and the page).
pub(crate) fn method(seeds: u64, cutoff: f64) -> String {
    format!(
        "one lobe per family (its anisotropic kind where it has one), parameters {POINT} of the \
         way through each bound in the optimiser's coordinates, {SAMPLES} noise-free samples, \
         the fastest kernel; RPLS and AED with their defaults, {} seed(s) each run to the CPU \
         cutoff of {} s (no target), ns per sample-evaluation is the median over the trials \
         of CPU time over computed sample-evaluations. Ratios are to Lafortune's row, measured \
         the same way.",
        family_seeds(seeds),
        family_cutoff(cutoff)
    )
}

fn family_seeds(seeds: u64) -> u64 {
    seeds.clamp(1, MAX_SEEDS)
}

fn family_cutoff(cutoff: f64) -> f64 {
    cutoff.min(MAX_CUTOFF)
}

/// Measures every registered family.
pub(crate) fn family_rows(seeds: u64, cutoff: f64) -> Result<Vec<FamilyRow>> {
    family_names()
        .into_iter()
        .map(|name| family_row(name, family_seeds(seeds), family_cutoff(cutoff)))
        .collect()
}

fn family_row(name: &str, seeds: u64, cutoff: f64) -> Result<FamilyRow> {
    let f = family(name).with_context(|| format!("family {name}"))?;
    let kind = if f.kinds().contains(&LobeKind::Anisotropic) {
        LobeKind::Anisotropic
    } else {
        f.kinds()[0]
    };
    let layout = Layout::builder_for(&f, &[kind])?.build()?;
    let x: Vec<f64> = layout
        .lower()
        .iter()
        .zip(layout.upper())
        .map(|(&lo, &hi)| lo + POINT * (hi - lo))
        .collect();
    let data = synthetic(&layout.decode(&x), SAMPLES, 0.0, 1);
    let prepared = layout.prepare(&data);
    let mut ev = Evaluator::new(&layout);
    let mut r = vec![0.0; SAMPLES];
    let mut jac = vec![0.0; SAMPLES * layout.dim()];
    let values_ns = cpu_ns_per(SAMPLES as f64, &mut || {
        black_box(ev.residuals(black_box(&x), &prepared, &mut r));
    });
    let jacobian_ns = cpu_ns_per(SAMPLES as f64, &mut || {
        ev.forget_powers();
        black_box(ev.residuals_and_jacobian(black_box(&x), &prepared, &mut r, &mut jac));
    });
    let objective = sls::BrdfObjective::new(Arc::new(data), layout.clone());
    let search_ns = |kind: &str| -> Result<Option<f64>> {
        let config = sls::AlgorithmConfig::default_for(kind).context("algorithm")?;
        let budget = sls::Budget {
            cpu_seconds: Some(cutoff),
            sample_evaluations: None,
        };
        let results: Vec<_> = (0..seeds)
            .map(|s| sls::run_trial(&objective, &config, 1000 + s, budget, 0.0))
            .collect();
        Ok(median_ns_per_computed_evaluation(&results))
    };
    Ok(FamilyRow {
        family: name.to_string(),
        kind: kind.name().to_string(),
        parameters: layout.dim(),
        kernel: ev.kernel().to_string(),
        values_ns,
        jacobian_ns,
        rpls_ns: search_ns("rpls")?,
        aed_ns: search_ns("aed")?,
    })
}

/// Lafortune's row, the reference of the ratios.
fn reference(rows: &[FamilyRow]) -> Option<&FamilyRow> {
    rows.iter().find(|r| r.family == brdf_model::DEFAULT_FAMILY)
}

/// `a / b` where both are known.
fn ratio(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    Some(a? / b?)
}

/// The goal per family and search: ns per sample-evaluation at most [`SEARCH_RATIO_LIMIT`]
/// times Lafortune's.
pub(crate) fn family_goals(rows: &[FamilyRow]) -> Vec<Goal> {
    let Some(lafortune) = reference(rows) else {
        return Vec::new();
    };
    rows.iter()
        .filter(|r| r.family != lafortune.family)
        .flat_map(|r| {
            [
                ("RPLS", r.rpls_ns, lafortune.rpls_ns),
                ("AED", r.aed_ns, lafortune.aed_ns),
            ]
            .map(|(alg, own, reference)| {
                let measured = ratio(own, reference);
                Goal {
                    goal: format!(
                        "{alg} on {}: ns per sample-evaluation over Lafortune's",
                        r.family
                    ),
                    met: measured.is_some_and(|m| m <= SEARCH_RATIO_LIMIT),
                    measured,
                    limit: SEARCH_RATIO_LIMIT,
                    unit: "x".into(),
                }
            })
        })
        .collect()
}

/// The columns of the family table.
pub(crate) const HEADER: [&str; 10] = [
    "family",
    "kind",
    "parameters",
    "kernel",
    "values ns/lobe-sample",
    "values + Jacobian ns/lobe-sample",
    "Jacobian / Lafortune's",
    "RPLS ns/sample-evaluation",
    "AED ns/sample-evaluation",
    "RPLS / Lafortune's",
];

/// The family table's cells, row by row (numbers as text; `-` where not measured).
pub(crate) fn cells(rows: &[FamilyRow]) -> Vec<Vec<String>> {
    let lafortune = reference(rows);
    rows.iter()
        .map(|r| {
            vec![
                r.family.clone(),
                r.kind.clone(),
                r.parameters.to_string(),
                r.kernel.clone(),
                format!("{:.2}", r.values_ns),
                format!("{:.2}", r.jacobian_ns),
                opt(
                    ratio(Some(r.jacobian_ns), lafortune.map(|l| l.jacobian_ns)),
                    2,
                ),
                opt(r.rpls_ns, 2),
                opt(r.aed_ns, 2),
                opt(ratio(r.rpls_ns, lafortune.and_then(|l| l.rpls_ns)), 2),
            ]
        })
        .collect()
}

/// The family table in markdown.
pub(crate) fn markdown(rows: &[FamilyRow], seeds: u64, cutoff: f64) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let mut s = format!(
        "\nModel families: {}\n\n| {} |\n|{}\n",
        method(seeds, cutoff),
        HEADER.join(" | "),
        "---|".repeat(HEADER.len())
    );
    for row in cells(rows) {
        s.push_str(&format!("| {} |\n", row.join(" | ")));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(family: &str, rpls: Option<f64>, aed: Option<f64>) -> FamilyRow {
        FamilyRow {
            family: family.into(),
            kind: "isotropic".into(),
            parameters: 4,
            kernel: "portable".into(),
            values_ns: 1.0,
            jacobian_ns: 2.0,
            rpls_ns: rpls,
            aed_ns: aed,
        }
    }

    #[test]
    fn goals_compare_each_family_with_lafortune() {
        let rows = [
            row("lafortune", Some(3.0), Some(6.0)),
            row("ggx", Some(5.9), Some(12.1)),
            row("ward", None, Some(1.0)),
        ];
        let goals = family_goals(&rows);
        let met: Vec<(String, bool)> = goals.iter().map(|g| (g.goal.clone(), g.met)).collect();
        assert_eq!(goals.len(), 4, "{met:?}");
        // 5.9 / 3 is within 2x; 12.1 / 6 is not; an unmeasured row is a missed goal.
        assert!(
            goals[0].met && !goals[1].met && !goals[2].met && goals[3].met,
            "{met:?}"
        );
        assert_eq!(cells(&rows)[1][9], "1.97");
        assert!(family_goals(&rows[1..]).is_empty());
    }

    #[test]
    fn a_family_and_lafortune_are_measured() {
        // Two families, not all: the timings take about a second each in a debug build.
        let rows: Vec<FamilyRow> = ["lafortune", "ggx"]
            .iter()
            .map(|f| family_row(f, 1, 0.02).unwrap())
            .collect();
        for r in &rows {
            assert!(
                r.values_ns > 0.0 && r.jacobian_ns >= r.values_ns * 0.5,
                "{}",
                r.family
            );
            assert!(r.rpls_ns.is_some() && r.aed_ns.is_some(), "{}", r.family);
        }
        assert_eq!(
            (rows[1].kind.as_str(), rows[1].parameters),
            ("anisotropic", 6)
        );
        let md = markdown(&rows, 1, 0.02);
        assert!(
            md.contains("| ggx |") && md.contains("| lafortune |"),
            "{md}"
        );
    }
}
