//! Stage 4: the trial plan and the fingerprint that guards a results file.

use super::{PlannedTrial, Spec};
use crate::seed::{fingerprint, trial_seed};

impl Spec {
    /// The canonical form of everything that determines trial results (see the module docs).
    pub fn canonical(&self) -> serde_json::Value {
        let instances: Vec<serde_json::Value> = self
            .instances
            .iter()
            .map(|i| {
                serde_json::json!({
                    "name": i.name,
                    "run_target": i.canonical_run_target(),
                    "source": i.source,
                    "model": i.model,
                })
            })
            .collect();
        let configs: Vec<serde_json::Value> = self
            .configurations
            .iter()
            .map(|c| {
                let mut v = serde_json::json!({"label": c.label, "algorithm": c.algorithm});
                // Only a non-default descent enters, so the fingerprints of specs written
                // before the key existed stay the same.
                if c.descent != sls::DescentModel::Default {
                    v["descent"] = serde_json::json!(c.descent);
                }
                v
            })
            .collect();
        serde_json::json!({
            "seed": self.seed,
            "budget": self.budget,
            "instances": instances,
            "configurations": configs,
        })
    }

    /// Takes the settings of the configurations whose kind this program does not know (kept
    /// as written, `sls::registry::read_unknown_kinds_as_opaque`) from `canonical`, a results
    /// header's canonical spec, which has every field with its default: the fingerprint is then
    /// the one the results were written under.
    pub fn adopt_stored_settings(&mut self, canonical: &serde_json::Value) {
        let known = sls::registry::kinds();
        let Some(stored) = canonical["configurations"].as_array() else {
            return;
        };
        for c in &mut self.configurations {
            let kind = c.algorithm.kind_name();
            if known.contains(&kind) {
                continue;
            }
            let full = stored
                .iter()
                .find(|s| s["label"] == c.label.as_str())
                .and_then(|s| {
                    serde_json::from_value::<sls::AlgorithmConfig>(s["algorithm"].clone()).ok()
                });
            if let Some(full) = full.filter(|f| f.kind_name() == kind) {
                c.algorithm = full;
            }
        }
    }

    /// Fingerprint of [`Spec::canonical`] (serde_json with sorted keys, hashed by
    /// [`crate::seed::fingerprint`]).
    pub fn fingerprint(&self) -> String {
        fingerprint(&self.canonical().to_string())
    }

    /// Every trial of the plan, interleaved (trial index outermost) so that partial results
    /// cover every configuration evenly.
    pub fn trials_plan(&self) -> Vec<PlannedTrial> {
        let mut out = Vec::new();
        for trial in 0..self.trials {
            for (ii, inst) in self.instances.iter().enumerate() {
                for (ci, cfg) in self.configurations.iter().enumerate() {
                    out.push(PlannedTrial {
                        instance: ii,
                        config: ci,
                        trial,
                        seed: trial_seed(self.seed, &inst.name, &cfg.label, trial),
                        key: crate::trial_key::trial_key(&inst.name, &cfg.label, trial),
                    });
                }
            }
        }
        out
    }
}
