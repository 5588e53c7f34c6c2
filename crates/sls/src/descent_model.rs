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
    /// many.
    #[default]
    Default,
    /// The Gauss-Newton model only, with the other defaults (the default before 2026-12-02,
    /// with which the figures under `results/` were made).
    GaussNewton,
    /// N2FB's configuration ([`Options::n2fb`]): the adaptive choice and the secant scaling
    /// from the first update, as in the paper's solver.
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
    pub fn options(self) -> Options {
        match self {
            DescentModel::Default => Options::default(),
            DescentModel::GaussNewton => Options {
                model: StepModel::GaussNewton,
                ..Options::default()
            },
            DescentModel::N2fb => Options::n2fb(),
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
        assert_eq!(DescentModel::Default.options(), Options::default());
        assert_eq!(DescentModel::N2fb.options(), Options::n2fb());
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
