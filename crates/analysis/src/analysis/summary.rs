//! The answer first: per instance and target, which configuration has the lowest ERT, every
//! other configuration's ERT as a ratio to it and whether the difference is significant (the
//! primary test, Holm-adjusted); per configuration, aggregates over all (instance, target)
//! pairs (pairs solved, best on, geometric-mean ERT ratio, mean rank) and a matrix of
//! significant pairwise outcomes. Computed from the statistics of one [`super::Analysis`].

use crate::stats::{ConfigStats, Direction, Measure, MeasureSummary, StatsReport, pairwise};

/// The significance level of the summary's marks and matrix (Holm-adjusted p-values).
pub const ALPHA: f64 = 0.05;

/// One configuration at one (instance, target) in the summary's measure.
#[derive(Clone, Debug, PartialEq)]
pub struct SummaryCell {
    /// Its ERT (`None`: no trial reached the target).
    pub ert: Option<f64>,
    /// Trials that reached the target.
    pub successes: usize,
    /// Trials.
    pub trials: usize,
    /// Its ERT over the best configuration's (1 for the best; `None` without success).
    pub ratio: Option<f64>,
    /// The best configuration reaches the target significantly sooner (primary test, Holm,
    /// [`ALPHA`]); false for the best itself.
    pub significant: bool,
    /// The Holm-adjusted p-value of the primary test against the best.
    pub p_holm: Option<f64>,
}

/// One (instance, target) of the summary.
#[derive(Clone, Debug, PartialEq)]
pub struct SummaryRow {
    /// Instance name.
    pub instance: String,
    /// Target RMSE.
    pub target: f64,
    /// The configuration with the lowest ERT (index into [`Summary::configs`]), if any reached
    /// the target.
    pub best: Option<usize>,
    /// One cell per configuration (`None`: it has no trials there).
    pub cells: Vec<Option<SummaryCell>>,
}

/// One configuration over all (instance, target) pairs.
#[derive(Clone, Debug, PartialEq)]
pub struct Aggregate {
    /// Pairs it ran.
    pub pairs: usize,
    /// Pairs where at least one of its trials reached the target.
    pub solved: usize,
    /// Pairs where it has the lowest ERT.
    pub best: usize,
    /// Geometric mean of its ERT ratio to the best over the pairs it solved.
    pub geo_mean_ratio: Option<f64>,
    /// Mean rank by ERT (1 the lowest; no success ranks last; ties share their mean rank).
    pub mean_rank: f64,
    /// (pair, other configuration) where it is significantly sooner.
    pub wins: usize,
    /// (pair, other configuration) where it is significantly later.
    pub losses: usize,
}

/// The summary of a run in one measure.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// The measure of ERTs and tests.
    pub measure: Measure,
    /// The configurations, in the spec's order.
    pub configs: Vec<String>,
    /// One row per (instance, target), in the spec's order.
    pub rows: Vec<SummaryRow>,
    /// One per configuration, in [`Summary::configs`]' order.
    pub aggregates: Vec<Aggregate>,
    /// `matrix[i][j]`: pairs where configuration `i` reaches the target significantly sooner
    /// than `j` (primary test, Holm, [`ALPHA`]).
    pub matrix: Vec<Vec<usize>>,
    /// Pairs where both `i` and `j` ran (the matrix's denominators).
    pub compared: Vec<Vec<usize>>,
}

impl Summary {
    /// The configurations' indices from the best mean rank to the worst (ties: the lower
    /// geometric-mean ratio, then the spec's order).
    pub fn ranking(&self) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.configs.len()).collect();
        let key = |i: usize| {
            let a = &self.aggregates[i];
            (a.mean_rank, a.geo_mean_ratio.unwrap_or(f64::INFINITY))
        };
        order.sort_by(|&x, &y| {
            let (a, b) = (key(x), key(y));
            a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1))
        });
        order
    }

    /// The rows of `instance`.
    pub fn instance_rows<'s>(&'s self, instance: &'s str) -> impl Iterator<Item = &'s SummaryRow> {
        self.rows.iter().filter(move |r| r.instance == instance)
    }
}

fn measure_of(c: &ConfigStats, m: Measure) -> &MeasureSummary {
    match m {
        Measure::CpuSeconds => &c.cpu,
        Measure::Evaluations => &c.evaluations,
    }
}

/// The primary test's verdict between `x` and `y` at (instance, target) in `m`: `Some(true)`
/// when `x` is significantly sooner, `Some(false)` when `y` is, `None` otherwise; with the
/// Holm-adjusted p-value.
fn significant(
    stats: &StatsReport,
    (instance, target, m): (&str, f64, Measure),
    x: &str,
    y: &str,
) -> (Option<bool>, Option<f64>) {
    let primary = pairwise::primary();
    let Some(t) = stats.tests.iter().find(|t| {
        t.instance == instance
            && t.target == target
            && t.measure == m
            && ((t.a == x && t.b == y) || (t.a == y && t.b == x))
    }) else {
        return (None, None);
    };
    let Some(r) = t.result(primary) else {
        return (None, None);
    };
    let sooner = match r.direction {
        Direction::A => Some(t.a == x),
        Direction::B => Some(t.b == x),
        Direction::Neither => None,
    };
    (sooner.filter(|_| r.significant(ALPHA)), r.p_holm)
}

/// The summary of `stats` in `m`; `instances` and `configs` give the order.
pub fn summarise(
    stats: &StatsReport,
    instances: &[String],
    configs: &[String],
    m: Measure,
) -> Summary {
    let configs: Vec<String> = configs
        .iter()
        .filter(|c| stats.configs.iter().any(|s| &s.config == *c))
        .cloned()
        .collect();
    let n = configs.len();
    let mut rows = Vec::new();
    for inst in instances {
        let mut targets: Vec<f64> = Vec::new();
        for s in stats.configs.iter().filter(|s| &s.instance == inst) {
            if !targets.contains(&s.target) {
                targets.push(s.target);
            }
        }
        for t in targets {
            let found: Vec<Option<&MeasureSummary>> = configs
                .iter()
                .map(|c| {
                    stats
                        .configs
                        .iter()
                        .find(|s| &s.instance == inst && s.target == t && &s.config == c)
                        .map(|s| measure_of(s, m))
                })
                .collect();
            let best = (0..n)
                .filter_map(|i| found[i].and_then(|s| s.ert).map(|e| (i, e)))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(i, _)| i);
            let best_ert = best.and_then(|b| found[b].and_then(|s| s.ert));
            let cells = (0..n)
                .map(|i| {
                    let s = found[i]?;
                    let (sig, p_holm) = match best {
                        Some(b) if b != i => {
                            significant(stats, (inst, t, m), &configs[b], &configs[i])
                        }
                        _ => (None, None),
                    };
                    Some(SummaryCell {
                        ert: s.ert,
                        successes: s.successes,
                        trials: s.trials,
                        ratio: s
                            .ert
                            .zip(best_ert)
                            .map(|(e, b)| if b > 0.0 { e / b } else { 1.0 }),
                        significant: sig == Some(true),
                        p_holm,
                    })
                })
                .collect();
            rows.push(SummaryRow {
                instance: inst.clone(),
                target: t,
                best,
                cells,
            });
        }
    }
    let mut matrix = vec![vec![0; n]; n];
    let mut compared = vec![vec![0; n]; n];
    for r in &rows {
        for i in 0..n {
            for j in 0..n {
                if i == j || r.cells[i].is_none() || r.cells[j].is_none() {
                    continue;
                }
                compared[i][j] += 1;
                let (sig, _) =
                    significant(stats, (&r.instance, r.target, m), &configs[i], &configs[j]);
                if sig == Some(true) {
                    matrix[i][j] += 1;
                }
            }
        }
    }
    let aggregates = (0..n).map(|i| aggregate(&rows, i, n, &matrix)).collect();
    Summary {
        measure: m,
        configs,
        rows,
        aggregates,
        matrix,
        compared,
    }
}

/// Configuration `i`'s aggregate over `rows`.
fn aggregate(rows: &[SummaryRow], i: usize, n: usize, matrix: &[Vec<usize>]) -> Aggregate {
    let mut a = Aggregate {
        pairs: 0,
        solved: 0,
        best: 0,
        geo_mean_ratio: None,
        mean_rank: 0.0,
        wins: matrix[i].iter().sum(),
        losses: (0..n).map(|j| matrix[j][i]).sum(),
    };
    let (mut log_sum, mut ranks) = (0.0, 0.0);
    for r in rows {
        let Some(cell) = &r.cells[i] else { continue };
        a.pairs += 1;
        if r.best == Some(i) {
            a.best += 1;
        }
        if let Some(ratio) = cell.ratio {
            a.solved += 1;
            log_sum += ratio.ln();
        }
        ranks += rank(r, i);
    }
    if a.solved > 0 {
        a.geo_mean_ratio = Some((log_sum / a.solved as f64).exp());
    }
    if a.pairs > 0 {
        a.mean_rank = ranks / a.pairs as f64;
    }
    a
}

/// The rank of configuration `i` in row `r` by ERT (no success: after every success; ties
/// share the mean of their ranks).
fn rank(r: &SummaryRow, i: usize) -> f64 {
    let key = |c: &SummaryCell| c.ert.unwrap_or(f64::INFINITY);
    let mine = r.cells[i].as_ref().map_or(f64::INFINITY, key);
    let others: Vec<f64> = r.cells.iter().flatten().map(key).collect();
    let below = others.iter().filter(|&&e| e < mine).count() as f64;
    let equal = others.iter().filter(|&&e| e == mine).count() as f64;
    below + (equal + 1.0) / 2.0
}
