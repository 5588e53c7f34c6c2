//! Which configuration of the bounded Levenberg-Marquardt descent a trial uses.

use bounded_lm::Options;
use serde::{Deserialize, Serialize};

/// The descent's solver configuration, chosen per configuration of an experiment so that
/// comparisons can put the paper's solver (PORT's N2FB) beside ours. Each maps onto a preset of
/// bounded-lm with the searches' safeguards ([`Options::for_search`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DescentModel {
    /// [`Options::search`]: bounded-lm's default (NL2SOL's adaptive model choice switching
    /// after 2 secant updates per parameter, the secant term in the scaling after as many)
    /// with the searches' safeguards.
    #[default]
    Default,
    /// [`Options::gauss_newton`] with the searches' safeguards: the Gauss-Newton model only,
    /// with which the figures under `results/` were made.
    GaussNewton,
    /// [`Options::n2fb`] with the searches' safeguards: the adaptive choice and the secant
    /// scaling from the first update, as in the paper's solver.
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

    /// The solver options of this choice (budgets are set per descent by the searches). Every
    /// choice runs without bounded-lm's safeguards ([`bounded_lm::Safeguards::SEARCH`]): inside
    /// a search a descent that ends early only moves the search on, and each safeguard
    /// measured slower there (the numbers are in `docs/solver.md`, "Presets").
    pub fn options(self) -> Options {
        match self {
            DescentModel::Default => Options::search(),
            DescentModel::GaussNewton => Options::gauss_newton().for_search(),
            DescentModel::N2fb => Options::n2fb().for_search(),
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
    use bounded_lm::StepModel;

    #[test]
    fn names_round_trip_and_select_distinct_options() {
        for m in DescentModel::ALL {
            assert_eq!(DescentModel::from_name(m.name()), Some(m));
        }
        assert_eq!(DescentModel::from_name("N2FB"), None);
        let e = "port".parse::<DescentModel>().unwrap_err();
        assert!(e.contains("`port`") && e.contains("gauss-newton"), "{e}");
        assert_eq!("n2fb".parse::<DescentModel>(), Ok(DescentModel::N2fb));
        assert_eq!(DescentModel::Default.options(), Options::search());
        let mut n2fb = Options::n2fb();
        n2fb.safeguards = bounded_lm::Safeguards::SEARCH;
        assert_eq!(DescentModel::N2fb.options(), n2fb);
        assert!(
            DescentModel::ALL
                .iter()
                .all(|m| m.options().safeguards == bounded_lm::Safeguards::SEARCH)
        );
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
