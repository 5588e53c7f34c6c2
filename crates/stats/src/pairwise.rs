//! The pairwise tests of two configurations' RTDs as a list: each [`Test`] is one entry of
//! [`TESTS`], with its name, its columns in `tests.csv` and `stats.json` and how it is run,
//! and its outcome on one pair is a [`TestResult`] (statistic, p-value, Holm-adjusted p-value,
//! effect, direction). The files, the text table, the pages and `compare` render these lists;
//! adding a test adds an entry here and a column set in the files, not an edit in each writer.
//!
//! The order of [`TESTS`] is the order of the columns in `tests.csv` and `stats.json`.

use serde::ser::SerializeMap;

use super::{
    Cell, CellKind, Outcome, domination, kaplan_meier, kolmogorov_smirnov, log_rank, mann_whitney,
};

/// Which configuration of a pair a test finds reaching the target sooner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// The first configuration (`a`).
    A,
    /// The second configuration (`b`).
    B,
    /// Neither, or the test has no direction (Kolmogorov-Smirnov's D).
    Neither,
}

/// An effect size a test reports beside its p-value.
#[derive(Debug)]
pub struct Effect {
    /// Its column in `tests.csv` and `stats.json`.
    pub column: &'static str,
    /// Its short name in the text table (`HR`).
    pub short: &'static str,
    /// Its name in table headings.
    pub name: &'static str,
}

/// One pairwise test: what it is called, which columns it fills, and how it runs.
#[derive(Debug)]
pub struct Test {
    /// A short key (`mw`, `ks`, `dom`, `lr`).
    pub key: &'static str,
    /// Its name in tables (`Mann-Whitney`).
    pub name: &'static str,
    /// The column of its statistic, if it has one (`mw_u`).
    pub statistic: Option<&'static str>,
    /// The columns of its p-value and Holm-adjusted p-value, if it has a p-value.
    pub p: Option<[&'static str; 2]>,
    /// Its effect size, if it reports one.
    pub effect: Option<Effect>,
    /// Columns of its direction as two flags (`a` sooner, `b` sooner), for a test whose whole
    /// outcome is a direction (RTD domination).
    pub flags: Option<[&'static str; 2]>,
    /// Words for a direction-only outcome: what the sooner side does, and neither.
    pub direction_words: [&'static str; 2],
    /// One sentence on what it tests and how to read it.
    pub about: &'static str,
    run: fn(&[Outcome], &[Outcome]) -> Option<Raw>,
}

impl PartialEq for Test {
    fn eq(&self, other: &Test) -> bool {
        self.key == other.key
    }
}

/// What a test's run returns before Holm's adjustment.
struct Raw {
    statistic: Option<f64>,
    p: Option<f64>,
    effect: Option<f64>,
    direction: Direction,
}

/// Mann-Whitney U of `a` with censored runs as `+inf`: below `m n / 2`, `a`'s times are
/// smaller.
fn run_mann_whitney(a: &[Outcome], b: &[Outcome]) -> Option<Raw> {
    let (ta, tb) = (times(a), times(b));
    let (u, p) = mann_whitney(&ta, &tb)?;
    let half = (ta.len() * tb.len()) as f64 / 2.0;
    Some(Raw {
        statistic: Some(u),
        p: Some(p),
        effect: None,
        direction: sign(half - u),
    })
}

fn run_kolmogorov_smirnov(a: &[Outcome], b: &[Outcome]) -> Option<Raw> {
    let (d, p) = kolmogorov_smirnov(&times(a), &times(b))?;
    Some(Raw {
        statistic: Some(d),
        p: Some(p),
        effect: None,
        direction: Direction::Neither,
    })
}

fn run_domination(a: &[Outcome], b: &[Outcome]) -> Option<Raw> {
    let direction = match domination(&kaplan_meier(a), &kaplan_meier(b)) {
        (true, _) => Direction::A,
        (_, true) => Direction::B,
        _ => Direction::Neither,
    };
    Some(Raw {
        statistic: None,
        p: None,
        effect: None,
        direction,
    })
}

fn run_log_rank(a: &[Outcome], b: &[Outcome]) -> Option<Raw> {
    let lr = log_rank(a, b)?;
    Some(Raw {
        statistic: Some(lr.chi2),
        p: Some(lr.p),
        effect: Some(lr.hazard_ratio),
        direction: sign(lr.hazard_ratio - 1.0),
    })
}

fn times(o: &[Outcome]) -> Vec<f64> {
    o.iter().map(Outcome::time_or_inf).collect()
}

/// A positive value favours `a`, a negative one `b`.
fn sign(x: f64) -> Direction {
    if x > 0.0 {
        Direction::A
    } else if x < 0.0 {
        Direction::B
    } else {
        Direction::Neither
    }
}

/// Mann-Whitney U (censored runs as `+inf`).
pub static MANN_WHITNEY: Test = Test {
    key: "mw",
    name: "Mann-Whitney",
    statistic: Some("mw_u"),
    p: Some(["mw_p", "mw_p_holm"]),
    effect: None,
    flags: None,
    direction_words: ["", ""],
    about: "Mann-Whitney U on the run times with censored runs as +inf: are one \
            configuration's times to target generally smaller?",
    run: run_mann_whitney,
};

/// Two-sample Kolmogorov-Smirnov.
pub static KOLMOGOROV_SMIRNOV: Test = Test {
    key: "ks",
    name: "KS",
    statistic: Some("ks_d"),
    p: Some(["ks_p", "ks_p_holm"]),
    effect: None,
    flags: None,
    direction_words: ["", ""],
    about: "two-sample Kolmogorov-Smirnov D: do the two RTDs differ anywhere (no direction)?",
    run: run_kolmogorov_smirnov,
};

/// Probabilistic domination of the RTDs.
pub static DOMINATION: Test = Test {
    key: "dom",
    name: "RTD domination",
    statistic: None,
    p: None,
    effect: None,
    flags: Some(["a_dominates", "b_dominates"]),
    direction_words: ["dominates", "curves cross"],
    about: "one RTD at or above the other everywhere and above somewhere (no p-value)",
    run: run_domination,
};

/// The log-rank test with its hazard ratio: the primary test (censoring-aware).
pub static LOG_RANK: Test = Test {
    key: "lr",
    name: "log-rank",
    statistic: Some("lr_chi2"),
    p: Some(["lr_p", "lr_p_holm"]),
    effect: Some(Effect {
        column: "lr_hazard_ratio",
        short: "HR",
        name: "hazard ratio A/B",
    }),
    flags: None,
    direction_words: ["", ""],
    about: "log-rank test with each censored run at its own censoring time; the hazard \
            ratio (O_a/E_a)/(O_b/E_b) above 1 means A reaches the target sooner",
    run: run_log_rank,
};

/// Every pairwise test, in the order of their columns in the files.
pub static TESTS: [&Test; 4] = [&MANN_WHITNEY, &KOLMOGOROV_SMIRNOV, &DOMINATION, &LOG_RANK];

/// The test significance marks and `compare`'s verdicts use: the log-rank test, which takes
/// each censored run at its own censoring time.
pub fn primary() -> &'static Test {
    &LOG_RANK
}

/// A test's outcome on one pair.
#[derive(Clone, Debug, PartialEq)]
pub struct TestResult {
    /// The test.
    pub test: &'static Test,
    /// Its statistic (`None`: no statistic, or the test could not be run).
    pub statistic: Option<f64>,
    /// Its p-value.
    pub p: Option<f64>,
    /// Its p-value Holm-adjusted over the family (see [`adjust`]).
    pub p_holm: Option<f64>,
    /// Its effect size ([`Test::effect`]).
    pub effect: Option<f64>,
    /// Which side it finds sooner.
    pub direction: Direction,
}

impl TestResult {
    /// Runs `test` on `a` against `b` (not yet Holm-adjusted).
    pub fn run(test: &'static Test, a: &[Outcome], b: &[Outcome]) -> TestResult {
        let raw = (test.run)(a, b).unwrap_or(Raw {
            statistic: None,
            p: None,
            effect: None,
            direction: Direction::Neither,
        });
        TestResult {
            test,
            statistic: raw.statistic,
            p: raw.p,
            p_holm: None,
            effect: raw.effect,
            direction: raw.direction,
        }
    }

    /// An empty result of `test` (not run), to be filled from columns.
    pub fn empty(test: &'static Test) -> TestResult {
        TestResult {
            test,
            statistic: None,
            p: None,
            p_holm: None,
            effect: None,
            direction: Direction::Neither,
        }
    }

    /// Whether the Holm-adjusted p-value is below `alpha`.
    pub fn significant(&self, alpha: f64) -> bool {
        self.p_holm.is_some_and(|p| p < alpha)
    }

    /// The test's columns with their values, in file order.
    pub fn cells(&self) -> Vec<(&'static str, Cell)> {
        let t = self.test;
        let mut out = Vec::new();
        if let Some(c) = t.statistic {
            out.push((c, Cell::Number(self.statistic)));
        }
        if let Some([p, holm]) = t.p {
            out.push((p, Cell::Number(self.p)));
            out.push((holm, Cell::Number(self.p_holm)));
        }
        if let Some([a, b]) = t.flags {
            out.push((a, Cell::Flag(self.direction == Direction::A)));
            out.push((b, Cell::Flag(self.direction == Direction::B)));
        }
        if let Some(e) = &t.effect {
            out.push((e.column, Cell::Effect(self.effect)));
        }
        out
    }

    /// Fills the result from its columns (`get` returns a column's value); `Err` names the
    /// column that does not read.
    pub fn from_cells(
        test: &'static Test,
        mut get: impl FnMut(&'static str, CellKind) -> Result<Cell, String>,
    ) -> Result<TestResult, String> {
        let mut r = TestResult::empty(test);
        let number = |c: Cell| match c {
            Cell::Number(x) | Cell::Effect(x) | Cell::Time(x) => x,
            Cell::Count(n) => Some(n as f64),
            Cell::Flag(_) => None,
        };
        if let Some(c) = test.statistic {
            r.statistic = number(get(c, CellKind::Number)?);
        }
        if let Some([p, holm]) = test.p {
            r.p = number(get(p, CellKind::Number)?);
            r.p_holm = number(get(holm, CellKind::Number)?);
        }
        if let Some([a, b]) = test.flags {
            let flag = |c: Cell| matches!(c, Cell::Flag(true));
            let (fa, fb) = (flag(get(a, CellKind::Flag)?), flag(get(b, CellKind::Flag)?));
            r.direction = match (fa, fb) {
                (true, _) => Direction::A,
                (_, true) => Direction::B,
                _ => Direction::Neither,
            };
        }
        if let Some(e) = &test.effect {
            r.effect = number(get(e.column, CellKind::Effect)?);
            if test.p.is_some() {
                r.direction = r.effect.map_or(Direction::Neither, |h| sign(h - 1.0));
            }
        }
        Ok(r)
    }
}

impl serde::Serialize for TestResult {
    /// The test's key and its columns, as in `tests.csv`.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(None)?;
        map.serialize_entry("test", self.test.key)?;
        serialize_cells(std::slice::from_ref(self), &mut map)?;
        map.end()
    }
}

/// Holm's adjustment of each p-value test over a family of pairs (`results` of every pair of
/// one instance, target and measure, each in [`TESTS`] order).
pub fn adjust<'r>(family: impl Iterator<Item = &'r mut Vec<TestResult>>) {
    let mut family: Vec<&mut Vec<TestResult>> = family.collect();
    for (k, test) in TESTS.iter().enumerate() {
        if test.p.is_none() {
            continue;
        }
        let mut slots: Vec<&mut TestResult> = family
            .iter_mut()
            .filter_map(|r| r.get_mut(k))
            .filter(|r| r.p.is_some())
            .collect();
        let p: Vec<f64> = slots.iter().filter_map(|r| r.p).collect();
        for (slot, adj) in slots.iter_mut().zip(super::holm(&p)) {
            slot.p_holm = Some(adj);
        }
    }
}

/// Every test of [`TESTS`] on `a` against `b` (not yet Holm-adjusted).
pub fn run_all(a: &[Outcome], b: &[Outcome]) -> Vec<TestResult> {
    TESTS.iter().map(|t| TestResult::run(t, a, b)).collect()
}

/// Serialises `results`' columns into an open JSON map (after the pair's own fields).
pub fn serialize_cells<M: SerializeMap>(
    results: &[TestResult],
    map: &mut M,
) -> Result<(), M::Error> {
    for r in results {
        for (column, cell) in r.cells() {
            map.serialize_entry(column, &cell)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn succ(t: f64) -> Outcome {
        Outcome {
            success: Some(t),
            spent: t,
        }
    }

    #[test]
    fn directions_point_to_the_sooner_side() {
        let fast: Vec<Outcome> = (1..=8).map(|i| succ(f64::from(i))).collect();
        let slow: Vec<Outcome> = (1..=8).map(|i| succ(f64::from(i) * 100.0)).collect();
        for test in TESTS {
            let r = TestResult::run(test, &fast, &slow);
            let back = TestResult::run(test, &slow, &fast);
            let (want, other) = if test.key == "ks" {
                (Direction::Neither, Direction::Neither)
            } else {
                (Direction::A, Direction::B)
            };
            assert_eq!(
                (r.direction, back.direction),
                (want, other),
                "{}",
                test.name
            );
        }
    }

    #[test]
    fn columns_read_back() {
        let a: Vec<Outcome> = (1..=5).map(|i| succ(f64::from(i))).collect();
        let b: Vec<Outcome> = (3..=9).map(|i| succ(f64::from(i))).collect();
        for mut r in run_all(&a, &b) {
            r.p_holm = r.p.map(|p| (p * 2.0).min(1.0));
            let cells = r.cells();
            let back = TestResult::from_cells(r.test, |c, _| {
                Ok(cells.iter().find(|x| x.0 == c).unwrap().1)
            })
            .unwrap();
            // Mann-Whitney's direction needs the sample sizes, which no column holds.
            if r.test.key == "mw" {
                r.direction = Direction::Neither;
            }
            assert_eq!(back, r, "{}", r.test.name);
        }
    }
}
