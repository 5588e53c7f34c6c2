//! [`Diagnosis::to_markdown`]: the diagnosis as tables and warnings.

use super::Diagnosis;

impl Diagnosis {
    /// The diagnosis as Markdown (tables of parameters, singular values, warnings,
    /// bootstrap and sensitivity).
    pub fn to_markdown(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "{} samples, RMSE {:.6e}, condition number of the scaled Jacobian {:.3e}\n",
            self.samples, self.rmse, self.condition_number
        );
        let _ = writeln!(
            s,
            "| parameter | internal x | std. error | physical | std. error | bootstrap 95% (internal) |\n|---|---|---|---|---|---|"
        );
        let marked =
            self.bootstrap.is_some() && self.standard_errors.iter().any(|s| s.is_infinite());
        for j in 0..self.names.len() {
            // An undetermined parameter's resamples start at the fit and the data do not pull
            // them away: the interval measures the solver's start, not the data.
            let undetermined = if self.standard_errors[j].is_infinite() {
                " (undetermined)"
            } else {
                ""
            };
            let ci = self
                .bootstrap
                .as_ref()
                .map(|b| format!("[{:.5e}, {:.5e}]{undetermined}", b.lower[j], b.upper[j]))
                .unwrap_or_else(|| "-".into());
            let _ = writeln!(
                s,
                "| {} | {:.6e} | {:.3e} | {:.6e} | {:.3e} | {} |",
                self.names[j],
                self.x[j],
                self.standard_errors[j],
                self.physical[j],
                self.physical_standard_errors[j],
                ci
            );
        }
        if marked {
            let _ = writeln!(
                s,
                "\nIntervals marked (undetermined): the data do not determine the parameter; its \
                 refits start at the fit and stay near it, so the interval shows where they \
                 started, not a range the data allow."
            );
        }
        let _ = writeln!(
            s,
            "\nStationarity: a Gauss-Newton step predicts a {:.1e} relative reduction of the sum \
             of squares; a full-data refit from the point ends at RMSE {}",
            self.predicted_reduction,
            self.refit_rmse
                .map_or("- (could not start)".into(), |r| format!("{r:.9e}"))
        );
        let sv: Vec<String> = self
            .singular_values
            .iter()
            .map(|v| format!("{v:.3e}"))
            .collect();
        let _ = writeln!(
            s,
            "\nSingular values (unit-norm columns): {}\n",
            sv.join(", ")
        );
        if let Some(b) = &self.bootstrap {
            let _ = writeln!(
                s,
                "Bootstrap: {} resamples ({} failed), RMSE 95% [{:.5e}, {:.5e}]\n",
                b.resamples, b.failed, b.rmse.0, b.rmse.1
            );
        }
        if !self.sensitivity.is_empty() {
            let _ = writeln!(
                s,
                "| data perturbation | max parameter shift (box widths) | amplification | RMSE change | code |\n|---|---|---|---|---|"
            );
            for t in &self.sensitivity {
                let _ = writeln!(
                    s,
                    "| {:.0e} | {:.3e} | {:.3e} | {:+.3e} | {} |",
                    t.relative_perturbation,
                    t.max_shift,
                    t.amplification,
                    t.rmse_change,
                    t.code.map_or("-".into(), |c| c.to_string())
                );
            }
        }
        if self.warnings.is_empty() {
            let _ = writeln!(s, "\nNo warnings.");
        } else {
            let _ = writeln!(s, "\nWarnings:\n");
            for w in &self.warnings {
                let _ = writeln!(s, "- {w}");
            }
        }
        s
    }
}
