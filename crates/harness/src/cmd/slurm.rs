//! `brdf-sls slurm`: sbatch scripts that run an experiment as a Slurm job array (one shard of
//! the trial plan per array task, see [`brdf_experiment::shard`]) and a merge job after it; with
//! `--submit`, submits both and prints their job IDs. Nothing cluster-specific is built in:
//! partition, time, memory and CPUs come from the flags, everything else from Slurm's defaults.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, anyhow};
use brdf_experiment::shard::{MAX_SHARDS, Shard};

use super::shared::{default_out, load_spec};
use super::{bail_input, note, say};
use crate::cli::SlurmArgs;

/// The files written into `<out>/slurm/`.
const ARRAY_SCRIPT: &str = "array.sbatch";
const MERGE_SCRIPT: &str = "merge.sbatch";
const SUBMIT_SCRIPT: &str = "submit.sh";

/// Quotes `s` for a POSIX shell (single quotes).
fn sh_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}

fn sh_path(p: &Path) -> String {
    sh_quote(&p.to_string_lossy())
}

/// Refuses values that would break an `#SBATCH` line (whitespace, quotes, `#`).
fn check_sbatch_value(flag: &str, value: &Option<String>) -> Result<()> {
    if let Some(v) = value
        && (v.is_empty()
            || v.chars()
                .any(|c| c.is_whitespace() || c.is_control() || "'\"#\\$`".contains(c)))
    {
        bail_input!("{flag} {v:?}: expected a single word such as sbatch accepts");
    }
    Ok(())
}

/// `#SBATCH` lines of the optional resource flags.
fn resource_lines(a: &SlurmArgs) -> String {
    let mut s = String::new();
    for (flag, v) in [
        ("partition", &a.partition),
        ("time", &a.time),
        ("mem", &a.mem),
    ] {
        if let Some(v) = v {
            s.push_str(&format!("#SBATCH --{flag}={v}\n"));
        }
    }
    s
}

/// The command line that wrote the scripts (for their header).
fn invocation() -> String {
    std::env::args()
        .skip(1)
        .map(|a| {
            if a.chars()
                .all(|c| c.is_ascii_alphanumeric() || "-_./=:,+".contains(c))
            {
                a
            } else {
                sh_quote(&a)
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

struct Scripts {
    array: String,
    merge: String,
    submit: String,
}

fn scripts(
    a: &SlurmArgs,
    name: &str,
    exe: &Path,
    spec: &Path,
    out: &Path,
    slurm_dir: &Path,
) -> Scripts {
    let n = a.shards;
    let version = brdf_experiment::PROGRAM_VERSION;
    let job = format!("brdf-sls-{name}");
    let logs = slurm_dir.join("logs");
    let resources = resource_lines(a);
    let array_path = slurm_dir.join(ARRAY_SCRIPT);
    let merge_path = slurm_dir.join(MERGE_SCRIPT);
    let array = format!(
        r#"#!/bin/bash
# brdf-sls {version}: experiment `{name}` as a Slurm job array of {n} shards.
# Written by: brdf-sls {invocation}
#
# Array task K (1..{n}) runs shard K/{n} of the trial plan: trial t of instance i and
# configuration c (from 0) when (t + i + c) mod {n} = K-1, each with the seed it has in a
# single run (see `brdf-sls run --help`, --shard). Its results go to
#   {out}/shard-K-of-{n}/
# and its log to {logs}/.
# It runs as many worker threads as Slurm gives it CPUs (SLURM_CPUS_PER_TASK).
#
# Resume a failed or timed-out task K (finished trials are kept):
#   sbatch --array=K {array_path}
# The merge job ({MERGE_SCRIPT}) must run after the whole array:
#   sbatch --dependency=afterok:<array job id> {merge_path}
# {SUBMIT_SCRIPT} next to this file submits both.
#SBATCH --job-name={job}
#SBATCH --array=1-{n}
#SBATCH --cpus-per-task={cpus}
#SBATCH --output={logs}/%x-%A-%a.out
{resources}
set -euo pipefail

BRDF_SLS={exe_q}  # the program that wrote this script
SPEC={spec_q}
OUT={out_q}
N={n}
K=${{SLURM_ARRAY_TASK_ID:?submit this script with sbatch; SLURM_ARRAY_TASK_ID is not set}}
THREADS=${{SLURM_CPUS_PER_TASK:-1}}

echo "brdf-sls: shard $K/$N of $SPEC on $(hostname), $THREADS thread(s)"
exec "$BRDF_SLS" run "$SPEC" --shard "$K/$N" --out "$OUT/shard-$K-of-$N" \
    --threads "$THREADS" --progress plain --no-plots
"#,
        invocation = invocation(),
        out = out.display(),
        logs = logs.display(),
        array_path = array_path.display(),
        merge_path = merge_path.display(),
        cpus = a.cpus_per_task,
        exe_q = sh_path(exe),
        spec_q = sh_path(spec),
        out_q = sh_path(out),
    );
    let shard_dirs: Vec<String> = (1..=n)
        .map(|k| format!("    \"$OUT\"/shard-{k}-of-{n}"))
        .collect();
    let merge = format!(
        r#"#!/bin/bash
# brdf-sls {version}: merge the {n} shards of experiment `{name}` into
#   {out}/
# (trials.jsonl, statistics, table and plots). Submit it after the array ({ARRAY_SCRIPT}):
#   sbatch --dependency=afterok:<array job id> {merge_path}
# It fails (exit status 1, nothing written) when a trial is missing; its log lists them.
# Merging again after resuming a shard is safe: trials already merged are kept once.
#SBATCH --job-name={job}-merge
#SBATCH --cpus-per-task=1
#SBATCH --output={logs}/%x-%j.out
{resources}
set -euo pipefail

BRDF_SLS={exe_q}
OUT={out_q}

exec "$BRDF_SLS" merge "$OUT" \
{dirs}
"#,
        out = out.display(),
        logs = logs.display(),
        merge_path = merge_path.display(),
        exe_q = sh_path(exe),
        out_q = sh_path(out),
        dirs = shard_dirs.join(" \\\n"),
    );
    let submit = format!(
        r#"#!/bin/bash
# Submits the array ({ARRAY_SCRIPT}) and the merge job ({MERGE_SCRIPT}) after it.
set -euo pipefail
array=$(sbatch --parsable {array_q})
array=${{array%%;*}}
merge=$(sbatch --parsable --dependency=afterok:"$array" {merge_q})
merge=${{merge%%;*}}
echo "array job $array ({n} tasks), merge job $merge"
echo "follow: squeue -j $array,$merge    afterwards: sacct -j $array,$merge"
"#,
        array_q = sh_path(&array_path),
        merge_q = sh_path(&merge_path),
    );
    Scripts {
        array,
        merge,
        submit,
    }
}

fn write_script(path: &Path, text: &str) -> Result<()> {
    brdf_experiment::store::write_atomic(path, text.as_bytes())
        .with_context(|| format!("writing {}", path.display()))?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755))
            .with_context(|| format!("making {} executable", path.display()))?;
    }
    Ok(())
}

/// Runs `sbatch --parsable ARGS...` and returns the job ID.
fn sbatch(args: &[&str], script: &Path) -> Result<String> {
    let output = Command::new("sbatch")
        .arg("--parsable")
        .args(args)
        .arg(script)
        .output()
        .map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                anyhow!(
                    "sbatch not found (is this a Slurm login node?); the scripts are written, submit them from a node that has Slurm with {}",
                    script.with_file_name(SUBMIT_SCRIPT).display()
                )
            } else {
                anyhow!("running sbatch: {e}")
            }
        })?;
    if !output.status.success() {
        return Err(anyhow!(
            "sbatch {} failed ({}): {}",
            script.display(),
            output.status,
            String::from_utf8_lossy(&output.stderr).trim()
        ));
    }
    let text = String::from_utf8_lossy(&output.stdout);
    let id = text.trim().split(';').next().unwrap_or("").to_string();
    if id.is_empty() || !id.chars().all(|c| c.is_ascii_digit()) {
        return Err(anyhow!(
            "sbatch {}: unexpected output {:?} (expected a job ID)",
            script.display(),
            text.trim()
        ));
    }
    Ok(id)
}

fn absolute(p: &Path, what: &str) -> Result<PathBuf> {
    p.canonicalize()
        .with_context(|| format!("{what} {}", p.display()))
}

/// `brdf-sls slurm`.
pub fn slurm(a: SlurmArgs) -> Result<()> {
    if a.shards == 0 || a.shards > MAX_SHARDS {
        bail_input!("--shards {}: expected 1 to {MAX_SHARDS}", a.shards);
    }
    if a.cpus_per_task == 0 {
        bail_input!("--cpus-per-task must be at least 1");
    }
    check_sbatch_value("--partition", &a.partition)?;
    check_sbatch_value("--time", &a.time)?;
    check_sbatch_value("--mem", &a.mem)?;
    let spec = load_spec(&a.spec)?;
    let plan = spec.trials_plan().len();
    if (a.shards as usize) > plan {
        note!(
            "warning: {} shards for {plan} trials: some shards will have nothing to run",
            a.shards
        );
    }
    let spec_path = absolute(&a.spec, "resolving the spec path")?;
    let out = a.out.clone().unwrap_or_else(|| default_out(Some(&a.spec)));
    let slurm_dir = out.join("slurm");
    std::fs::create_dir_all(slurm_dir.join("logs"))
        .with_context(|| format!("creating {}", slurm_dir.join("logs").display()))?;
    let out = absolute(&out, "resolving --out")?;
    let slurm_dir = out.join("slurm");
    let exe = std::env::current_exe().context("finding the path of this program")?;
    let s = scripts(&a, &spec.name, &exe, &spec_path, &out, &slurm_dir);
    let array_path = slurm_dir.join(ARRAY_SCRIPT);
    let merge_path = slurm_dir.join(MERGE_SCRIPT);
    write_script(&array_path, &s.array)?;
    write_script(&merge_path, &s.merge)?;
    write_script(&slurm_dir.join(SUBMIT_SCRIPT), &s.submit)?;
    let per_shard = Shard::all(a.shards)
        .map(|v| v.iter().map(|s| s.select(spec.trials_plan()).len()).max())
        .ok()
        .flatten()
        .unwrap_or(0);
    say!(
        "wrote {} ({} array tasks, up to {per_shard} of {plan} trials each), {} and {}",
        array_path.display(),
        a.shards,
        merge_path.display(),
        slurm_dir.join(SUBMIT_SCRIPT).display()
    );
    if !a.submit {
        say!(
            "submit with: {}   (or rerun with --submit)",
            slurm_dir.join(SUBMIT_SCRIPT).display()
        );
        return Ok(());
    }
    let array_id = sbatch(&[], &array_path)?;
    let merge_id = match sbatch(&[&format!("--dependency=afterok:{array_id}")], &merge_path) {
        Ok(id) => id,
        Err(e) => {
            return Err(e.context(format!(
                "the array job {array_id} was submitted, the merge job was not: submit it with `sbatch --dependency=afterok:{array_id} {}`",
                merge_path.display()
            )));
        }
    };
    say!("array_job={array_id}");
    say!("merge_job={merge_id}");
    say!(
        "submitted array job {array_id} ({} tasks) and merge job {merge_id} (runs when every task succeeded)",
        a.shards
    );
    say!("follow:     squeue -j {array_id},{merge_id}");
    say!("afterwards: sacct -j {array_id},{merge_id} (if accounting is enabled)");
    say!("logs:       {}", slurm_dir.join("logs").display());
    say!(
        "results:    {} (merged), {}/shard-K-of-{}/ (shards)",
        out.display(),
        out.display(),
        a.shards
    );
    Ok(())
}
