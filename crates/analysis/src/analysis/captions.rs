//! Captions of the charts: what each shows and how to read it, with the axes as they are
//! drawn (a log axis spanning less than a decade is drawn linear; the caption says which).

use brdf_graphics::chart::Chart;

use crate::stats::Measure;

/// "log" or "linear": how the drawn chart's axis is scaled.
fn scale(log: bool) -> &'static str {
    if log { "log scale" } else { "linear scale" }
}

/// The axes of the chart as drawn: "x: ... (log scale); y: ... (linear scale)".
fn axes(c: &Chart) -> String {
    let r = c.resolved();
    let strip = |s: &str| s.replace(" (log scale)", "");
    format!(
        "x: {} ({}); y: {} ({}).",
        strip(&r.x_label),
        scale(r.x_log),
        strip(&r.y_label),
        scale(r.y_log)
    )
}

/// How a measure's censoring reads on a Kaplan-Meier curve.
fn censoring(measure: Measure) -> &'static str {
    match measure {
        Measure::CpuSeconds => {
            "A trial that did not reach the target counts as censored where it ended (the \
             cutoff): the curve is the Kaplan-Meier estimate, the plain ECDF when all trials \
             share one cutoff."
        }
        Measure::Evaluations => {
            "A trial that did not reach the target counts as censored at the sample-evaluations \
             it had used when the budget stopped it: the curve is the Kaplan-Meier estimate, \
             which leaves such a trial out from that point on, so it can reach 1 although a \
             trial failed when that trial was stopped early (by the CPU budget) in this measure."
        }
    }
}

/// An RTD's caption.
pub fn rtd(c: &Chart, instance: &str, target: &str, measure: Measure, cutoff: bool) -> String {
    let mut s = format!(
        "Run-time distribution on {instance} for target RMSE {target}: for each configuration, \
         the fraction of its trials that reached the target within a given number of {} \
         (higher and further left is better). {} Shaded: pointwise 95% confidence band \
         (Greenwood). The legend gives trials solved of trials.",
        measure.label(),
        censoring(measure)
    );
    if cutoff {
        s.push_str(" The grey dashed line is the budget per trial.");
    }
    s.push(' ');
    s.push_str(&axes(c));
    s
}

/// A sweep's caption.
pub fn sweep(c: &Chart, param: &str, target: &str) -> String {
    format!(
        "ERT (solid, with its bootstrap [10%, 90%] band) and median run time (dashed) to RMSE \
         {target} against the swept value of {param}; lower is better. A value whose trials \
         never reached the target has no point. {}",
        axes(c)
    )
}

/// A trace chart's caption.
pub fn trace(c: &Chart, per_config: usize) -> String {
    format!(
        "Anytime traces: the best full-data RMSE of the first {per_config} trials of each \
         configuration against CPU time, one line per trial; grey dashed lines are the targets. \
         The range zooms on the targets: a trace that leaves the bottom has reached them all. {}",
        axes(c)
    )
}

/// A scatter's caption.
pub fn scatter(c: &Chart, target: &str) -> String {
    format!(
        "Each trial's final best RMSE against the CPU time at its end: filled points reached \
         RMSE {target} (the grey line), hollow ones were censored. {}",
        axes(c)
    )
}

/// An error-time chart's caption.
pub fn error_time(c: &Chart, measure: Measure) -> String {
    format!(
        "Run time against the target error, read from the anytime traces: for each target RMSE \
         on the grid, each configuration's ERT (solid) and median time to it (dashed), in {}; \
         lower is better, and a line ends where the configuration no longer reaches half its \
         trials (median) or none (ERT). {}",
        measure.label(),
        axes(c)
    )
}

/// An ECDF-over-targets chart's caption.
pub fn ecdf_targets(c: &Chart, targets: usize) -> String {
    format!(
        "COCO-style ECDF: the fraction of (trial, target) pairs solved within a given CPU time, \
         over {targets} targets spaced evenly on a log scale between the lowest target and the \
         typical first RMSE of a trial. {}",
        axes(c)
    )
}

/// A fixed-budget chart's caption.
pub fn fixed_budget(c: &Chart, measure: Measure, run_target: &str) -> String {
    format!(
        "Fixed-budget view: the best full-data RMSE each configuration had reached after a given \
         number of {} (line: median over its trials; band: 25% to 75%), read from the recorded \
         anytime traces; lower is better. Trials stop at the run target {run_target}, so the \
         curves level off at or below it; a trial that ended keeps its last RMSE, and a point is \
         drawn once half the trials have evaluated a candidate. {}",
        measure.label(),
        axes(c)
    )
}

/// An aggregated ECDF's caption.
pub fn aggregate(c: &Chart, measure: Measure) -> String {
    let cost = match measure {
        Measure::CpuSeconds => {
            " Instances differ in cost per evaluation, so CPU seconds mix scales; the \
             sample-evaluation view does not depend on the machine."
        }
        Measure::Evaluations => "",
    };
    format!(
        "Runtime ECDF over every (instance, target) pair of the run: for each configuration, the \
         mean over the pairs of its Kaplan-Meier RTD, i.e. the fraction of (trial, instance, \
         target) triples solved within a given number of {}, each pair weighted equally; higher \
         and further left is better.{cost} {}",
        measure.label(),
        axes(c)
    )
}
