//! Which configuration of the bounded Levenberg-Marquardt descent a trial uses.

use bounded_lm::{Options, StepModel};
use serde::{Deserialize, Serialize};

/// The descent's solver configuration, chosen per configuration of an experiment so that
/// comparisons can put the paper's solver (PORT's N2FB) beside ours.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DescentModel {
    /// bounded-lm's defaults ([`Options::default`]): NL2SOL's adaptive model choice allowed to
    /// switch after 2 secant updates per parameter, the secant term in the scaling after as
    /// many (dead columns left free, see [`DescentModel::options`]).
    #[default]
    Default,
    /// The Gauss-Newton model only, with the other defaults (the default before 2026-12-02,
    /// with which the figures under `results/` were made).
    GaussNewton,
    /// N2FB's configuration ([`Options::n2fb`]): the adaptive choice and the secant scaling
    /// from the first update, as in the paper's solver (and, as in every choice here and in
    /// N2FB, numerically dead columns left free).
    N2fb,
}

impl DescentModel {
    /// Every choice, in the order of the docs.
    pub const ALL: [DescentModel; 3] = [
        DescentModel::Default,
        DescentModel::GaussNewton,
        DescentModel::N2fb,
    ];

    /// The spelling in spec files (`default`, `gauss-newton`, `n2fb`).
    pub fn name(self) -> &'static str {
        match self {
            DescentModel::Default => "default",
            DescentModel::GaussNewton => "gauss-newton",
            DescentModel::N2fb => "n2fb",
        }
    }

    /// The choice spelled `name`, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }

    /// The solver options of this choice (budgets are set per descent by the searches).
    ///
    /// Every choice leaves numerically dead columns free
    /// ([`Options::hold_dead_columns`] off, as N2FB does): a descent on a subsample where a lobe
    /// is dead then moves that lobe's parameters, which seems to be how a two-lobe search
    /// revives it (the effect below is measured, the mechanism inferred).
    /// With the library's default hold AED needed 3.6 times the sample-evaluations to RMSE 0.02
    /// on the cross brushed metal instance (median 10.7e6 against 3.0e6; RPLS 2.28e6 against
    /// 1.92e6; 100 seeds), while on the one-lobe tuning instance the hold saves AED 6% in the
    /// median (105,095 against 111,464; 90th percentile 640,557 against 1,144,807) and RPLS 3%
    /// (710,000 against 730,000; 1000 seeds; `cargo run --release -p sls --example
    /// tuning_bench -- [--hold-dead-columns]`). These were measured with the library's
    /// singular-convergence test step, before the searches took N2FB's (below).
    ///
    /// For the same reason every choice keeps searching for the Levenberg parameter when a
    /// singular model's minimum-norm step lies inside the region
    /// ([`Options::stop_at_minimum_norm_step`] off). In one build and run, stopping there cut
    /// AED's median CPU to target on the tuning instance in the raw exponent coordinate from
    /// 3.64 to 2.40 ms and its median sample-evaluations from 196,147 to 169,768 (300 seeds),
    /// and in log1p coordinates the medians of AED (108,292 -> 104,258), AERS (805,750 ->
    /// 788,075) and RPLS (700,000 -> 680,000; 1000 seeds); but on the noiseless cross instance
    /// AED's median rose from 886,319 to 1,574,817, AERS's from 1,143,400 to 1,287,625 and
    /// RPLS's from 1,710,000 to 1,860,000 (300 seeds), and RPLS's in raw coordinates from
    /// 4,770,000 to 5,230,000 (1000 seeds; `tuning_bench -- [--stop-at-minimum-norm-step]`,
    /// 2026-12-02).
    ///
    /// Every choice also runs N2FB's singular-convergence test, a test step of scaled length
    /// LMAXS alone ([`Options::singular_radius_at_least_x`] off): it can end a descent from a
    /// hopeless start at once with code 7, which in a search only shrinks the subsample or
    /// moves on. Against the library's longer test step, in one build: AED's median on the
    /// tuning instance 111,464 -> 108,292 (90th percentile 1,144,807 -> 437,236; RPLS 730,000
    /// -> 700,000; 1000 seeds), on the noiseless cross instance 2,007,622 -> 1,250,764 (RPLS
    /// 1,940,000 -> 1,800,000; 100 seeds); on the noisy cross instance AED reached its target
    /// within 2 s in 162 of 300 trials instead of 175 (`tuning_bench --
    /// [--singular-radius-at-least-x]`; bounded-lm's crate docs, "Robustness").
    ///
    /// No choice corrects a rejected step for the residuals' curvature
    /// ([`Options::second_order_correction`] off): with it AED's median sample-evaluations on
    /// the tuning instance rose from 104,333 to 113,480 and its 90th percentile from 441,796 to
    /// 743,212, RPLS's median from 710,000 to 720,000 (200 seeds, `tuning_bench --
    /// [--second-order-correction]`, 2026-12-03). The figures were made without it.
    pub fn options(self) -> Options {
        let options = match self {
            DescentModel::Default => Options::default(),
            DescentModel::GaussNewton => Options {
                model: StepModel::GaussNewton,
                ..Options::default()
            },
            DescentModel::N2fb => Options::n2fb(),
        };
        Options {
            hold_dead_columns: false,
            singular_radius_at_least_x: false,
            stop_at_minimum_norm_step: false,
            second_order_correction: false,
            ..options
        }
    }
}

impl std::str::FromStr for DescentModel {
    type Err = String;

    /// Parses the spec spelling; the error lists the choices.
    fn from_str(name: &str) -> Result<Self, String> {
        Self::from_name(name).ok_or_else(|| {
            let names: Vec<&str> = Self::ALL.iter().map(|m| m.name()).collect();
            format!(
                "unknown descent `{name}` (expected one of {})",
                names.join(", ")
            )
        })
    }
}

impl std::fmt::Display for DescentModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_select_distinct_options() {
        for m in DescentModel::ALL {
            assert_eq!(DescentModel::from_name(m.name()), Some(m));
        }
        assert_eq!(DescentModel::from_name("N2FB"), None);
        let e = "port".parse::<DescentModel>().unwrap_err();
        assert!(e.contains("`port`") && e.contains("gauss-newton"), "{e}");
        assert_eq!("n2fb".parse::<DescentModel>(), Ok(DescentModel::N2fb));
        let searches = Options {
            hold_dead_columns: false,
            singular_radius_at_least_x: false,
            stop_at_minimum_norm_step: false,
            second_order_correction: false,
            ..Options::default()
        };
        assert_eq!(DescentModel::Default.options(), searches);
        assert_eq!(
            DescentModel::N2fb.options(),
            Options {
                hold_dead_columns: false,
                singular_radius_at_least_x: false,
                stop_at_minimum_norm_step: false,
                second_order_correction: false,
                ..Options::n2fb()
            }
        );
        assert!(DescentModel::ALL.iter().all(|m| {
            let o = m.options();
            !o.hold_dead_columns
                && !o.singular_radius_at_least_x
                && !o.stop_at_minimum_norm_step
                && !o.second_order_correction
        }));
        assert_eq!(
            DescentModel::GaussNewton.options().model,
            StepModel::GaussNewton
        );
        assert_ne!(
            DescentModel::GaussNewton.options(),
            DescentModel::Default.options()
        );
    }
}
