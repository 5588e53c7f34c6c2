//! The search algorithms, one file each, written against [`crate::Search`].
//!
//! Each algorithm is a `run(config, search) -> Result<(), Stop>` function that loops until a
//! [`crate::Search`] method reports a [`crate::Stop`] (target reached or budget spent), which it
//! propagates with `?`; `Ok(())` means the algorithm ended by itself.

pub mod aed;
pub mod aers;
pub mod asa;
pub mod avg;
pub mod ds;
pub mod rpls;
pub mod sa;
pub mod sals;

pub use aed::AedConfig;
pub use aers::AersConfig;
pub use asa::AsaConfig;
pub use avg::AvgConfig;
pub use ds::DsConfig;
pub use rpls::RplsConfig;
pub use sa::{Perturbation, SaConfig};
pub use sals::SalsConfig;

#[cfg(test)]
pub(crate) mod script {
    //! A scripted fake [`Search`] for testing control logic without a solver.

    use crate::search::{Descent, DescentEnd, DescentLimits, Search, Stop};
    use crate::{Rows, SearchRng};
    use bounded_lm::Outcome;
    use rand::SeedableRng;

    /// A fake search: descents return scripted outcomes and record their row counts; random
    /// picks and accepted candidates are tracked through x[0].
    pub(crate) struct Script {
        pub n: usize,
        pub outcomes: Vec<Outcome>,
        pub next: usize,
        pub rows: Vec<Rows>,
        pub picks: usize,
        pub evaluated: Vec<f64>,
        rng: SearchRng,
    }

    impl Script {
        pub fn new(n: usize, outcomes: Vec<Outcome>) -> Self {
            Self {
                n,
                outcomes,
                next: 0,
                rows: Vec::new(),
                picks: 0,
                evaluated: Vec::new(),
                rng: SearchRng::seed_from_u64(1),
            }
        }
    }

    impl Search for Script {
        fn dim(&self) -> usize {
            1
        }
        fn lower(&self) -> &[f64] {
            &[0.0]
        }
        fn upper(&self) -> &[f64] {
            &[1.0]
        }
        fn sample_count(&self) -> usize {
            self.n
        }
        fn rng(&mut self) -> &mut SearchRng {
            &mut self.rng
        }
        fn random_pick(&mut self, x: &mut [f64]) {
            self.picks += 1;
            x[0] = 1000.0 * self.picks as f64;
        }
        fn evaluate(&mut self, x: &[f64]) -> Result<f64, Stop> {
            self.evaluated.push(x[0]);
            Ok(1.0)
        }
        fn descend(
            &mut self,
            x: &mut [f64],
            rows: Rows,
            _limits: DescentLimits,
        ) -> Result<Descent, Stop> {
            let Some(&outcome) = self.outcomes.get(self.next) else {
                return Err(Stop::EvaluationBudget);
            };
            self.next += 1;
            self.rows.push(rows);
            x[0] += 1.0; // every descent moves the candidate
            Ok(Descent {
                end: DescentEnd::Solver(outcome),
                iterations: 1,
            })
        }
        fn count(&mut self, _name: &'static str) {}
    }
}
