//! `brdf-sls fit`: one fit of one data set with one algorithm.

use std::sync::Arc;

use anyhow::{Context, Result, bail};
use brdf_model::Evaluator;
use harness::spec::ModelSpec;

use super::shared::load_non_empty;
use super::{input_error, say};
use crate::cli::{FitArgs, ModelArgs};

/// The model the flags describe.
fn model_spec(m: &ModelArgs) -> Result<ModelSpec> {
    if !(1..=harness::spec::limits::MAX_LOBES).contains(&m.lobes) {
        return Err(input_error(format!(
            "--lobes {}: expected 1 to {}",
            m.lobes,
            harness::spec::limits::MAX_LOBES
        )));
    }
    let mut spec = ModelSpec::simple(m.lobes, m.kind);
    spec.exponent = m.exponent;
    spec.fixed.extend(m.fixed.iter().cloned());
    Ok(spec)
}

/// The algorithm configuration `--algorithm` and `--set` describe, validated by sls.
fn algorithm(a: &FitArgs) -> Result<sls::AlgorithmConfig> {
    let mut table = toml::Table::new();
    table.insert("kind".into(), toml::Value::String(a.algorithm.clone()));
    table.extend(a.set.iter().cloned());
    let algorithm: sls::AlgorithmConfig = toml::Value::Table(table)
        .try_into()
        .map_err(|e: toml::de::Error| input_error(format!("--algorithm/--set: {}", e.message())))?;
    algorithm.validate()?;
    Ok(algorithm)
}

/// `brdf-sls fit`.
pub fn fit(a: FitArgs) -> Result<()> {
    // The value parser admits finite numbers only.
    if a.cpu_seconds <= 0.0 {
        return Err(input_error(format!(
            "--cpu-seconds {}: expected a positive number",
            a.cpu_seconds
        )));
    }
    if a.bootstrap > harness::spec::limits::MAX_BOOTSTRAP {
        return Err(input_error(format!(
            "--bootstrap {}: at most {}",
            a.bootstrap,
            harness::spec::limits::MAX_BOOTSTRAP
        )));
    }
    if a.target < 0.0 {
        return Err(input_error(format!("--target {}: expected >= 0", a.target)));
    }
    let algorithm = algorithm(&a)?;
    let layout = model_spec(&a.model)?.layout()?;
    let (data, _) = load_non_empty(&a.data)?;
    let data = Arc::new(data);
    let objective = sls::BrdfObjective::with_kernel(data.clone(), layout.clone(), a.kernel)?;
    let budget = sls::Budget {
        cpu_seconds: Some(a.cpu_seconds),
        sample_evaluations: None,
    };
    let r = sls::run_trial(&objective, &algorithm, a.seed, budget, a.target);
    if r.best_x.is_empty() {
        bail!("the run evaluated no candidate (stop: {:?})", r.stop);
    }
    let params = layout.decode(&r.best_x);
    let mut ev = Evaluator::with_kernel(&layout, objective.kernel())?;
    let rmse = ev.rmse(&r.best_x, &data);
    say!(
        "algorithm {} (seed {}, kernel {}, brdf-sls {}), stop: {:?}",
        algorithm.kind_name(),
        a.seed,
        objective.kernel(),
        env!("CARGO_PKG_VERSION"),
        r.stop
    );
    say!(
        "RMSE {rmse:.17} after {:.4} CPU s ({:.4} wall s, {} sample-evaluations)",
        r.ended_at.cpu_seconds,
        r.ended_at.wall_seconds,
        r.ended_at.evaluations.total()
    );
    if let Some(at) = r.reached_at {
        say!("target {} reached at {:.4} CPU s", a.target, at.cpu_seconds);
    }
    say!("fitted parameters:");
    for name in layout.all_names() {
        let v = params.get(name).unwrap_or(f64::NAN);
        let tag = if layout.fixed_value(name).is_some() {
            " (fixed)"
        } else {
            ""
        };
        say!("  {name:<10} {v:>22.17}{tag}");
    }
    let json = serde_json::to_string(&params).context("serialising the parameters")?;
    say!("json: {json}");
    if a.diagnose {
        let options = brdf_stress::DiagnoseOptions {
            bootstrap: a.bootstrap,
            seed: a.seed,
            ..brdf_stress::DiagnoseOptions::default()
        };
        let d = brdf_stress::diagnose(&layout, &data, &r.best_x, &options)
            .context("diagnosing the fit")?;
        say!("\n{}", d.to_markdown().trim_end());
    }
    Ok(())
}
