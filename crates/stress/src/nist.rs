//! NIST StRD nonlinear regression problems for the solver suite: the problems, their data and
//! the LRE scoring are `bounded_lm::problems::nist`; this adds the lookup the suite uses.

pub use bounded_lm::problems::nist::{NAMES, NistData, NistProblem, lre, min_lre, model};

/// The embedded problem `name` with its data and certified values, `None` for an unknown name.
pub fn load(name: &str) -> Option<NistData> {
    NAMES
        .contains(&name)
        .then(|| bounded_lm::problems::nist::load(name))
}
