//! The speed goals the bench checks: issue 38's (AED's median CPU, RPLS against the kernel)
//! and issue 46's (every search's cost per sample-evaluation against RPLS's).

use crate::{KernelRow, SearchRow};
use brdf_model::Kernel;
use serde::{Deserialize, Serialize};

/// One speed goal with its measured value.
#[derive(Serialize, Deserialize)]
pub(crate) struct Goal {
    pub(crate) goal: String,
    /// The measured value (`None`: the row it needs has no median).
    pub(crate) measured: Option<f64>,
    pub(crate) limit: f64,
    pub(crate) unit: String,
    pub(crate) met: bool,
}

/// The goals of issue 38 against `searches` and the fastest kernel's values + Jacobian cost
/// (one lobe, as the tuning instance has). A goal whose row has no median is missed.
pub(crate) fn goals(kernels: &[KernelRow], searches: &[SearchRow]) -> Vec<Goal> {
    let find = |coord: &str, alg: &str| {
        searches
            .iter()
            .find(|r| r.instance == "tuning" && r.coordinate == coord && r.algorithm == alg)
    };
    let aed = |coord| find(coord, "AED").and_then(|r| r.median_cpu_ms);
    let rpls = |coord| find(coord, "RPLS").and_then(|r| r.ns_per_sample_evaluation);
    let best = Kernel::best().to_string();
    let jacobian = kernels
        .iter()
        .find(|k| k.kernel == best)
        .map_or(f64::NAN, |k| k.jacobian_ns);
    let goal = |goal: String, measured: Option<f64>, limit: f64, unit: &str| Goal {
        met: measured.is_some_and(|m| m <= limit),
        goal,
        measured,
        limit,
        unit: unit.into(),
    };
    let rpls_log = rpls("log1p");
    let mut goals = vec![
        goal(
            "AED on T2, log1p: median CPU to target".into(),
            aed("log1p"),
            0.3,
            "ms",
        ),
        goal(
            "AED on T2, raw n (uniform starts): median CPU to target".into(),
            aed("raw n"),
            2.5,
            "ms",
        ),
        goal(
            "RPLS on T2, log1p: ns per sample-evaluation".into(),
            rpls_log,
            3.0,
            "ns",
        ),
        goal(
            "RPLS on T2, raw n: ns per sample-evaluation, at most log1p's".into(),
            rpls("raw n"),
            rpls_log.unwrap_or(f64::NAN),
            "ns",
        ),
        goal(
            format!(
                "RPLS on T2, log1p: ns per sample-evaluation within 1.5x the {best} kernel's \
                 values + Jacobian"
            ),
            rpls_log,
            1.5 * jacobian,
            "ns",
        ),
        goal(
            format!(
                "RPLS on T2, raw n: ns per sample-evaluation within 1.5x the {best} kernel's \
                 values + Jacobian"
            ),
            rpls("raw n"),
            1.5 * jacobian,
            "ns",
        ),
    ];
    goals.extend(per_evaluation_ratio_goals(searches));
    goals
}

/// Issue 46's goal: on every search row, AED's and AERS's CPU per computed sample-evaluation
/// at most 1.5 times RPLS's on the same instance and coordinate (the kernel is the same, so
/// the rest is the searches' own overhead: subsample descents' linear algebra, gathering,
/// per-call costs). The measured value is the ratio.
fn per_evaluation_ratio_goals(searches: &[SearchRow]) -> Vec<Goal> {
    let mut goals = Vec::new();
    for rpls in searches.iter().filter(|r| r.algorithm == "RPLS") {
        for alg in ["AED", "AERS"] {
            let Some(row) = searches.iter().find(|r| {
                r.algorithm == alg && r.instance == rpls.instance && r.coordinate == rpls.coordinate
            }) else {
                continue;
            };
            let ratio = row
                .ns_per_sample_evaluation
                .zip(rpls.ns_per_sample_evaluation)
                .map(|(a, b)| a / b);
            goals.push(Goal {
                goal: format!(
                    "{alg} / RPLS ns per sample-evaluation, {} {}",
                    rpls.instance, rpls.coordinate
                ),
                met: ratio.is_some_and(|q| q <= 1.5),
                measured: ratio,
                limit: 1.5,
                unit: "x".into(),
            });
        }
    }
    goals
}
