//! Stage 5: the readable plan that `brdf-sls check` and `run` print.

use sls::Budget;

use crate::duration::human_seconds;

use super::{Source, Spec};

impl Spec {
    /// A readable plan: instances, configurations, trial count and the work at the cutoff
    /// upper bound on `threads` threads.
    pub fn describe(&self, threads: usize) -> String {
        let mut s = String::new();
        s.push_str(&format!("experiment `{}`", self.name));
        if let Some(d) = &self.description {
            s.push_str(&format!(": {d}"));
        }
        s.push('\n');
        s.push_str(&format!(
            "master seed {}, {} trials per (instance, configuration), budget per trial: {}\n",
            self.seed,
            self.trials,
            budget_text(&self.budget)
        ));
        s.push_str(&format!("instances ({}):\n", self.instances.len()));
        for i in &self.instances {
            let src = match &i.source {
                Source::Synthetic {
                    samples,
                    sigma,
                    seed,
                    suite: Some(su),
                    ..
                } => format!(
                    "suite {} material {} ({} channel, {} sampling, {samples} samples, noise {} \
                     relative + {sigma} absolute, seed {seed})",
                    su.suite, su.material, su.channel, su.sampling, su.noise
                ),
                Source::Synthetic {
                    name,
                    samples,
                    sigma,
                    seed,
                    ..
                } => format!(
                    "synthetic {} ({samples} samples, sigma {sigma}, seed {seed})",
                    name.as_deref().unwrap_or("custom params")
                ),
                Source::File { spec, resolved } => format!(
                    "file {} ({})",
                    resolved.display(),
                    spec.format_for(&spec.path)
                        .map_or_else(|e| format!("format unknown: {e}"), |f| f.to_string())
                ),
            };
            let kinds: Vec<String> = i
                .model
                .kinds
                .iter()
                .map(|k| format!("{k:?}").to_lowercase())
                .collect();
            s.push_str(&format!(
                "  {}: {src}; model {} [{}], exponent {:?}, starts {}{}; targets {:?}\n",
                i.name,
                i.model.family.name(),
                kinds.join(", "),
                i.model.exponent,
                i.model.starts.resolve(i.model.exponent).name(),
                if i.model.fixed.is_empty() {
                    String::new()
                } else {
                    format!(", fixed {:?}", i.model.fixed)
                } + &if i.model.bounds.is_empty() {
                    String::new()
                } else {
                    format!(", bounds {:?}", i.model.bounds)
                },
                i.targets
            ));
            if !i.relative_targets.is_empty() {
                let rel: Vec<String> = i
                    .relative_targets
                    .iter()
                    .map(|r| format!("best-known x {}", 1.0 + r))
                    .collect();
                s.push_str(&format!("    relative targets: {}\n", rel.join(", ")));
            }
        }
        s.push_str(&format!(
            "configurations ({}):\n",
            self.configurations.len()
        ));
        for c in &self.configurations {
            let params = serde_json::to_value(&c.algorithm)
                .map(|v| v.to_string())
                .unwrap_or_default();
            let descent = match c.descent {
                sls::DescentModel::Default => String::new(),
                other => format!(" descent={other}"),
            };
            s.push_str(&format!("  {:<24} {params}{descent}\n", c.label));
        }
        let n = self.trials as u64 * self.instances.len() as u64 * self.configurations.len() as u64;
        s.push_str(&format!(
            "plan: {} instance(s) x {} configuration(s) x {} trials = {n} trials\n",
            self.instances.len(),
            self.configurations.len(),
            self.trials
        ));
        if let Some(c) = self.budget.cpu_seconds {
            let total = n as f64 * c;
            s.push_str(&format!(
                "work at the cutoff upper bound: {} CPU ({} wall on {threads} thread(s)); successful trials stop earlier\n",
                human_seconds(total),
                human_seconds(total / threads.max(1) as f64)
            ));
        }
        if let Some(e) = self.budget.sample_evaluations {
            s.push_str(&format!(
                "evaluation upper bound: {:.3e} sample-evaluations\n",
                n as f64 * e as f64
            ));
        }
        s
    }
}

/// Text of a budget, e.g. "10 CPU s".
pub fn budget_text(b: &Budget) -> String {
    let mut parts = Vec::new();
    if let Some(c) = b.cpu_seconds {
        parts.push(format!("{c} CPU s"));
    }
    if let Some(e) = b.sample_evaluations {
        parts.push(format!("{e} sample-evaluations"));
    }
    parts.join(", ")
}
