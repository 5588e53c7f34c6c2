//! `brdf-sls trial`: one trial of one configuration on one instance with one seed, printing
//! one number (the cost) on standard output: irace's target-runner convention.

use anyhow::{Context, Result};
use brdf_experiment::spec::tune::{CostKind, CostRule, with_values};
use brdf_tune::irace::parse_switches;

use super::shared::load_spec;
use super::{bail_input, flush_stdout, input_error, say};
use crate::cli::TrialArgs;

/// `brdf-sls trial`.
pub fn trial(a: TrialArgs) -> Result<()> {
    let spec = load_spec(&a.spec)?;
    let tune = spec.tune.as_ref();
    // Before anything else: a configuration this program cannot run is refused up front.
    let named = a.config.as_ref().or(tune.map(|t| &t.algorithm));
    if let Some(c) = spec
        .configurations
        .iter()
        .find(|c| named.is_none_or(|l| &c.label == l))
    {
        super::shared::refuse_unrunnable(c, "brdf-sls trial")?;
    }
    let kind = a
        .cost
        .or(tune.map(|t| t.cost.kind))
        .unwrap_or(CostKind::Time);
    let cutoff = match a
        .cutoff
        .or(tune.filter(|t| t.cost.kind == kind).map(|t| t.cost.cutoff))
        .or_else(|| kind.default_cutoff(&spec.budget))
    {
        Some(c) => c,
        None => bail_input!(
            "--cutoff is needed: cost `{}` counts {} and the spec sets no such limit",
            kind.name(),
            kind.cutoff_unit()
        ),
    };
    let rule = CostRule {
        kind,
        cutoff,
        penalty: a.penalty.or(tune.map(|t| t.cost.penalty)).unwrap_or(10.0),
    };
    rule.validate().map_err(input_error)?;
    let label = a
        .config
        .clone()
        .or(tune.map(|t| t.algorithm.clone()))
        .or_else(|| spec.configurations.first().map(|c| c.label.clone()));
    let Some(base) = label
        .as_ref()
        .and_then(|l| spec.configurations.iter().find(|c| &c.label == l))
    else {
        bail_input!(
            "no configuration labelled `{}` (labels: {})",
            label.unwrap_or_default(),
            spec.config_labels().join(", ")
        );
    };
    let Some(instance) = spec.instances.iter().find(|i| i.name == a.instance) else {
        bail_input!(
            "no instance named `{}` in {} (instances: {})",
            a.instance,
            a.spec.display(),
            spec.instance_names().join(", ")
        );
    };
    let values = parse_switches(&a.switches)
        .map_err(|e| input_error(format!("configuration {}: {e}", a.config_id)))?;
    let config = with_values(&base.algorithm, &values)
        .map_err(|e| input_error(format!("configuration {}: {e}", a.config_id)))?;
    let built = brdf_experiment::instance::build(instance)
        .with_context(|| format!("building instance `{}`", instance.name))?;
    bounded_lm::set_kernel(spec.kernel)?;
    let objective = sls::BrdfObjective::with_kernel(
        built.data.clone(),
        built.layout.clone(),
        spec.kernel.resolve()?,
    )?
    .with_starts(instance.model.starts);
    let settings = sls::TrialSettings {
        descent: base.descent,
        ..sls::TrialSettings::default()
    };
    let r = sls::run_trial_with(
        &objective,
        &config,
        a.seed,
        kind.budget(cutoff),
        kind.run_target(instance.run_target()),
        &settings,
    );
    let cost = rule.cost(&r);
    if !cost.is_finite() {
        anyhow::bail!(
            "configuration {} on `{}` (seed {}): the cost is {cost} (no candidate evaluated?)",
            a.config_id,
            instance.name,
            a.seed
        );
    }
    say!("{cost}");
    flush_stdout()
}
