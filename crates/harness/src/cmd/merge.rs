//! `brdf-sls merge`: shard results folders into one results folder, then its statistics,
//! table and plots (see [`brdf_merge`]).

use std::collections::BTreeMap;

use anyhow::{Context, Result, anyhow};
use brdf_merge::merge as merge_folders;

use super::{note, say};
use crate::cli::MergeArgs;

/// Missing trial keys listed one by one (the rest are counted).
const LIST_MISSING: usize = 20;

/// `brdf-sls merge`.
pub fn merge(a: MergeArgs) -> Result<()> {
    brdf_experiment::input_file::check_out_dir(&a.out)
        .map_err(|e| super::input_error(format!("{}: {e}", a.out.display())))?;
    let outcome = merge_folders(&a.out, &a.shards, a.allow_partial)
        .with_context(|| format!("merging into {}", a.out.display()))?;
    for i in &outcome.inputs {
        note!(
            "read {} trials from {}{}{}",
            i.trials,
            i.path.display(),
            i.shard.map(|s| format!(" (shard {s})")).unwrap_or_default(),
            if i.existing_output {
                " (already in the output)"
            } else {
                ""
            }
        );
    }
    for n in &outcome.notes {
        note!("warning: {n}");
    }
    let again = outcome.already_present();
    if again > 0 {
        note!(
            "{again} trials were already in {} (kept as they are)",
            a.out.display()
        );
    }
    let others: Vec<_> = outcome
        .duplicates
        .iter()
        .filter(|d| {
            !outcome
                .inputs
                .iter()
                .any(|i| i.existing_output && i.path == d.kept_from)
        })
        .collect();
    if !others.is_empty() {
        let differing = others.iter().filter(|d| !d.same_outcome).count();
        note!(
            "removed {} duplicate trial copies (kept the first copy of each){}",
            others.len(),
            if differing > 0 {
                format!("; {differing} of them had a different outcome than the copy kept")
            } else {
                String::new()
            }
        );
        for d in others.iter().take(LIST_MISSING) {
            note!(
                "  duplicate {}: kept {}, dropped {}",
                d.key,
                d.kept_from.display(),
                d.dropped_from.display()
            );
        }
    }
    if outcome.outside_plan > 0 {
        note!(
            "ignored {} trials outside the plan of the stored spec",
            outcome.outside_plan
        );
    }
    let planned = outcome.spec.trials_plan().len();
    if !outcome.missing.is_empty() {
        note!("missing {} of {planned} trials:", outcome.missing.len());
        for m in outcome.missing.iter().take(LIST_MISSING) {
            note!(
                "  {} (seed {}){}",
                m.key,
                m.seed,
                m.shard.map(|s| format!(", shard {s}")).unwrap_or_default()
            );
        }
        if outcome.missing.len() > LIST_MISSING {
            note!("  ... and {} more", outcome.missing.len() - LIST_MISSING);
        }
        let mut per_shard: BTreeMap<String, usize> = BTreeMap::new();
        for m in &outcome.missing {
            if let Some(s) = m.shard {
                *per_shard.entry(s.to_string()).or_default() += 1;
            }
        }
        for (s, n) in &per_shard {
            note!(
                "  shard {s}: {n} missing; resume it with `brdf-sls run SPEC --shard {s}` (same --out as before), then merge again"
            );
        }
    }
    let Some(path) = &outcome.written else {
        return Err(anyhow!(
            "{} trials of the plan are missing; nothing was written to {}. Run the missing \
             shards and merge again, or pass --allow-partial to merge what there is",
            outcome.missing.len(),
            a.out.display()
        ));
    };
    note!(
        "wrote {} ({} of {planned} trials{})",
        path.display(),
        outcome.records.len(),
        if outcome.missing.is_empty() {
            ""
        } else {
            ", partial"
        }
    );
    let report = brdf_analysis::report::write_report(
        &outcome.spec,
        &outcome.records,
        &outcome.sessions,
        &a.out,
        !a.no_plots,
    )
    .context("writing statistics and plots")?;
    say!("{}", report.table);
    say!(
        "{}",
        super::written_summary(report.files.len(), &a.out, !a.no_plots, false)
    );
    Ok(())
}
