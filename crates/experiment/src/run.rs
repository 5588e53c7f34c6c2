//! Running an experiment: trials in parallel on a rayon pool, results appended as they finish.
//!
//! Each trial is independent and sequential (sls::run_trial never spawns threads), so the
//! worker thread's CPU clock measures it. Trial seeds depend only on (master seed, instance,
//! configuration, trial index), so every trial's result is the same for any thread count;
//! records are returned in plan order regardless of finishing order.

use std::collections::{BTreeMap, HashSet};
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use brdf_model::Kernel;
use rayon::prelude::*;
use sls::{AlgorithmConfig, BrdfObjective, Budget, StopReason, TrialResult};

use crate::instance::{BuiltInstance, InstanceError};
use crate::machine::{MachineInfo, unix_now};
use crate::progress::{Progress, ProgressMode};
use crate::shard::Shard;
use crate::spec::{PlannedTrial, Spec};
use crate::store::{
    FORMAT_VERSION, Header, LockedFolder, ResultStore, Session, StoreError, TrialRecord,
};

/// Runs one trial. Implementations must be deterministic in the trial's seed for the
/// seeding guarantees to hold (CPU-time cutoffs are the exception: they depend on speed).
pub trait Executor: Sync {
    /// Runs `trial` to `target` within `budget`.
    fn run(&self, trial: &PlannedTrial, target: f64, budget: Budget) -> TrialResult;

    /// What the results must record to be reproducible: the evaluation kernel and the hash of
    /// each instance's data. Empty for test executors.
    fn provenance(&self) -> Provenance {
        Provenance::default()
    }
}

/// The evaluation kernel and data hashes a run records with its results.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Provenance {
    /// The concrete kernel (`avx2`, `portable`, ...), empty when not applicable.
    pub kernel: String,
    /// The solver's concrete kernel ([`bounded_lm::kernel`]), empty when not applicable.
    pub solver_kernel: String,
    /// Instance name -> [`crate::seed::data_hash`] of its data.
    pub data_hashes: BTreeMap<String, String>,
    /// The program that runs the trials, when it named itself ([`set_program`]).
    pub program: String,
    /// Kind -> [`sls::registry::schema_hash`], for the spec's kinds that are not built in.
    pub schemas: BTreeMap<String, String>,
}

static PROGRAM: std::sync::OnceLock<String> = std::sync::OnceLock::new();

/// Names the program that runs trials in this process (`custom-algorithm 0.1.0`), recorded
/// with results ([`Provenance::program`]); the first call wins.
pub fn set_program(name: &str, version: &str) {
    let _ = PROGRAM.set(format!("{name} {version}").trim().to_string());
}

/// The schema hash of each kind of `spec` that is not built in.
pub fn schemas_of(spec: &Spec) -> BTreeMap<String, String> {
    let kinds = spec.configurations.iter().map(|c| c.algorithm.kind_name());
    kinds
        .filter(|k| !sls::registry::is_builtin(k))
        .filter_map(|k| Some((k.to_string(), sls::registry::schema_hash(k)?)))
        .collect()
}

/// The real executor: sls algorithms on brdf-model objectives built once per instance.
pub struct SlsExecutor {
    objectives: Vec<BrdfObjective>,
    configs: Vec<(AlgorithmConfig, sls::DescentModel)>,
    provenance: Provenance,
    interrupt: Option<Arc<AtomicBool>>,
}

impl SlsExecutor {
    /// Builds every instance's data set once (shared read-only by all trials), evaluated with
    /// `kernel` (resolved here; an unavailable kernel is an error), which also becomes the
    /// solver's process-wide kernel ([`bounded_lm::set_kernel`]). Returns the built instances
    /// too.
    pub fn new(spec: &Spec, kernel: Kernel) -> Result<(Self, Vec<BuiltInstance>), InstanceError> {
        let built = crate::instance::build_all(spec)?;
        Ok((Self::from_built(spec, &built, kernel)?, built))
    }

    /// The executor of `spec` on instances already built (`built[i]` is instance `i`, as
    /// `brdf_best_known::prepare::prepare` gives them), evaluated with `kernel` (resolved here), which
    /// also becomes the solver's process-wide kernel ([`bounded_lm::set_kernel`]).
    pub fn from_built(
        spec: &Spec,
        built: &[BuiltInstance],
        kernel: Kernel,
    ) -> Result<Self, InstanceError> {
        let kernel = kernel.resolve()?;
        let solver_kernel = bounded_lm::set_kernel(kernel)?;
        let objectives = built
            .iter()
            .zip(&spec.instances)
            .map(|(b, i)| {
                BrdfObjective::with_samples_and_kernel(
                    b.data.clone(),
                    b.samples.clone(),
                    b.layout.clone(),
                    kernel,
                )
                .map(|o| o.with_starts(i.model.starts))
            })
            .collect::<Result<_, _>>()?;
        let provenance = Provenance {
            kernel: kernel.to_string(),
            solver_kernel: solver_kernel.to_string(),
            data_hashes: spec
                .instances
                .iter()
                .zip(built)
                .map(|(i, b)| (i.name.clone(), crate::seed::data_hash(&b.data)))
                .collect(),
            program: PROGRAM.get().cloned().unwrap_or_default(),
            schemas: schemas_of(spec),
        };
        Ok(SlsExecutor {
            objectives,
            configs: spec
                .configurations
                .iter()
                .map(|c| (c.algorithm.clone(), c.descent))
                .collect(),
            provenance,
            interrupt: None,
        })
    }
}

impl SlsExecutor {
    /// Makes every trial stop with [`StopReason::Interrupted`] once `flag` is raised; the
    /// runner then stores none of the interrupted trials and returns [`RunError::Interrupted`]
    /// (how the Python package answers Ctrl-C). Trials are unchanged while the flag is down.
    pub fn set_interrupt(&mut self, flag: Arc<AtomicBool>) {
        self.interrupt = Some(flag);
    }
}

impl Executor for SlsExecutor {
    fn provenance(&self) -> Provenance {
        self.provenance.clone()
    }

    fn run(&self, trial: &PlannedTrial, target: f64, budget: Budget) -> TrialResult {
        let (algorithm, descent) = &self.configs[trial.config];
        let settings = sls::TrialSettings {
            interrupt: self.interrupt.clone(),
            descent: *descent,
        };
        sls::run_trial_with(
            &self.objectives[trial.instance],
            algorithm,
            trial.seed,
            budget,
            target,
            &settings,
        )
    }
}

/// Options of a run.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Worker threads.
    pub threads: usize,
    /// Move an existing results file aside instead of resuming or refusing it.
    pub fresh: bool,
    /// Progress display.
    pub progress: ProgressMode,
    /// Run at most this many new trials, then stop (the rest can be resumed later).
    pub limit: Option<usize>,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            threads: default_threads(),
            fresh: false,
            progress: ProgressMode::Auto,
            limit: None,
        }
    }
}

/// All logical CPUs.
pub fn default_threads() -> usize {
    std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1)
}

/// Errors of a run.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The results store failed or refused.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// A stored trial has another seed than the plan's for its key.
    #[error("{0}")]
    Seed(#[from] crate::seed_check::SeedMismatch),
    /// A trial panicked (a bug in the algorithm or model); finished trials are kept.
    #[error(
        "trial {key} (seed {seed}) panicked: {message}; the trials finished so far are saved, rerun to resume"
    )]
    TrialPanicked {
        /// The trial's key.
        key: String,
        /// The trial's seed, to reproduce it.
        seed: u64,
        /// The panic message.
        message: String,
    },
    /// The folder holds results of another shard (or of the whole plan) of the same spec.
    #[error(
        "{dir} holds {found} of this spec, not {requested}; write elsewhere with --out DIR, or start over with --fresh"
    )]
    ShardMismatch {
        /// The results folder.
        dir: std::path::PathBuf,
        /// What the folder holds (`shard K/N` or `the whole plan`).
        found: String,
        /// What was asked for.
        requested: String,
    },
    /// The run was interrupted (Ctrl-C); the trials finished before are saved.
    #[error("interrupted; the trials finished so far are saved, run again to resume")]
    Interrupted,
    /// The thread pool could not be built.
    #[error("cannot start {threads} worker threads: {message}")]
    Pool {
        /// Threads requested.
        threads: usize,
        /// rayon's message.
        message: String,
    },
}

/// What a run did.
#[derive(Clone, Debug)]
pub struct RunOutcome {
    /// Every record of the plan present now (resumed and new), in plan order.
    pub records: Vec<TrialRecord>,
    /// Trials run in this session.
    pub new_trials: usize,
    /// Trials found already finished.
    pub resumed: usize,
    /// Trials of the plan still missing (after `limit`).
    pub missing: usize,
    /// The results file's header (the first session's; this session's for a new file).
    pub header: Header,
    /// The results file's sessions, this one last.
    pub sessions: Vec<Session>,
    /// Notes from the store (torn line recovered, old file moved).
    pub notes: Vec<String>,
    /// Wall seconds of this session's trials.
    pub wall_seconds: f64,
    /// This session's machine.
    pub machine: MachineInfo,
    /// Configurations whose algorithm failed ([`StopReason::Failed`]) in this session, the
    /// first failure of each: none of their failed trials is stored and their remaining
    /// trials were skipped (counted in `missing`), while the others ran to the end.
    pub failures: Vec<ConfigFailure>,
}

/// The first failure of a configuration's algorithm in a run.
#[derive(Clone, Debug, PartialEq)]
pub struct ConfigFailure {
    /// Index into [`Spec::configurations`].
    pub config: usize,
    /// `configuration `LABEL` failed in trial KEY (seed S): MESSAGE`.
    pub message: String,
}

/// The results header for `spec` on this machine, with the executor's provenance.
pub fn header_for(spec: &Spec, threads: usize, provenance: &Provenance) -> Header {
    Header {
        format: FORMAT_VERSION,
        experiment: spec.name.clone(),
        fingerprint: spec.fingerprint(),
        created_unix: unix_now(),
        machine: MachineInfo::current(threads),
        spec: spec.canonical(),
        spec_text: spec.text.clone(),
        program_version: crate::PROGRAM_VERSION.to_string(),
        kernel: provenance.kernel.clone(),
        solver_kernel: provenance.solver_kernel.clone(),
        data_hashes: provenance.data_hashes.clone(),
        shard: None,
        best_known: spec.best_known(),
        program: provenance.program.clone(),
        schemas: provenance.schemas.clone(),
    }
}

/// Runs (or resumes) `spec` into `out` with `executor`.
pub fn run_experiment<E: Executor>(
    spec: &Spec,
    out: &Path,
    options: &RunOptions,
    executor: &E,
) -> Result<RunOutcome, RunError> {
    run_shard(spec, None, out, options, executor)
}

/// Runs (or resumes) the trials of `spec`'s plan that belong to `shard` (all of them for
/// `None`) into `out`. Each trial keeps the seed and key it has in the whole plan, so shards
/// merged by the `brdf-merge` crate equal a single run. The shard is recorded in the header, and a
/// folder written for another shard is refused ([`RunError::ShardMismatch`]).
pub fn run_shard<E: Executor>(
    spec: &Spec,
    shard: Option<Shard>,
    out: &Path,
    options: &RunOptions,
    executor: &E,
) -> Result<RunOutcome, RunError> {
    run_locked(spec, shard, LockedFolder::lock(out)?, options, executor)
}

/// [`run_shard`] into a folder already locked and read (`brdf_best_known::prepare::prepare`): the
/// results file is not read again.
pub fn run_locked<E: Executor>(
    spec: &Spec,
    shard: Option<Shard>,
    folder: LockedFolder,
    options: &RunOptions,
    executor: &E,
) -> Result<RunOutcome, RunError> {
    let threads = options.threads.max(1);
    let mut header = header_for(spec, threads, &executor.provenance());
    header.shard = shard;
    if !options.fresh
        && let Some(existing) = folder.contents()
        && existing.header.fingerprint == header.fingerprint
        && existing.header.shard != shard
    {
        let show = |s: Option<Shard>| {
            s.map_or_else(|| "the whole plan".to_string(), |s| format!("shard {s}"))
        };
        return Err(RunError::ShardMismatch {
            dir: folder.dir().to_path_buf(),
            found: show(existing.header.shard),
            requested: show(shard),
        });
    }
    let machine = header.machine.clone();
    let file_header = match folder.contents() {
        Some(existing) if !options.fresh => existing.header.clone(),
        _ => header.clone(),
    };
    let opened = ResultStore::open_locked(folder, header, options.fresh)?;
    let plan = match shard {
        Some(s) => s.select(spec.trials_plan()),
        None => spec.trials_plan(),
    };
    crate::seed_check::check_resume(opened.store.path(), &opened.records, spec, &plan)?;
    let plan_keys: HashSet<&str> = plan.iter().map(|t| t.key.as_str()).collect();
    let done: HashSet<String> = opened
        .records
        .iter()
        .filter(|r| plan_keys.contains(r.key.as_str()))
        .map(|r| r.key.clone())
        .collect();
    let mut pending: Vec<&PlannedTrial> = plan.iter().filter(|t| !done.contains(&t.key)).collect();
    let missing_after = pending
        .len()
        .saturating_sub(options.limit.unwrap_or(usize::MAX));
    if let Some(l) = options.limit {
        pending.truncate(l);
    }

    // Progress per configuration (summed over instances).
    let labels = spec.config_labels();
    let nc = labels.len();
    let mut totals = vec![0u64; nc];
    for t in &plan {
        totals[t.config] += 1;
    }
    let mut done_c = vec![0u64; nc];
    let mut ok_c = vec![0u64; nc];
    for r in opened.records.iter().filter(|r| done.contains(&r.key)) {
        if let Some(ci) = labels.iter().position(|l| *l == r.config) {
            done_c[ci] += 1;
            ok_c[ci] += u64::from(r.result.reached());
        }
    }
    let progress = Progress::new(options.progress, &labels, &totals, &done_c, &ok_c);

    let pool = rayon::ThreadPoolBuilder::new()
        // More threads than trials left would only idle.
        .num_threads(threads.min(pending.len()).max(1))
        .thread_name(|i| format!("trial-{i}"))
        .build()
        .map_err(|e| RunError::Pool {
            threads,
            message: e.to_string(),
        })?;
    let fresh_records = Mutex::new(Vec::with_capacity(pending.len()));
    let failures: Mutex<Vec<ConfigFailure>> = Mutex::new(Vec::new());
    let failed = |c: usize| lock(&failures).iter().any(|f| f.config == c);
    let skipped = AtomicUsize::new(0);
    let started = Instant::now();
    let store = &opened.store;
    let result: Result<(), RunError> = pool.install(|| {
        pending
            .par_iter()
            // One trial per task: trials are long and uneven, so no batching.
            .with_max_len(1)
            .try_for_each(|t| {
                if failed(t.config) {
                    skipped.fetch_add(1, Ordering::Relaxed);
                    return Ok(());
                }
                let inst = &spec.instances[t.instance];
                let target = inst.run_target();
                let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    executor.run(t, target, spec.budget)
                }))
                .map_err(|p| RunError::TrialPanicked {
                    key: t.key.clone(),
                    seed: t.seed,
                    message: p
                        .downcast_ref::<&str>()
                        .map(|s| s.to_string())
                        .or_else(|| p.downcast_ref::<String>().cloned())
                        .unwrap_or_else(|| "unknown panic".into()),
                })?;
                // A failed trial fails its configuration: none of its trials is run or stored
                // from now on (trials in flight may fail too: the first says it).
                if result.stop == StopReason::Failed {
                    let mut all = lock(&failures);
                    if !all.iter().any(|f| f.config == t.config) {
                        let label = &spec.configurations[t.config].label;
                        let why = result.failure.as_deref().unwrap_or("failed");
                        all.push(ConfigFailure {
                            config: t.config,
                            message: format!(
                                "configuration `{label}` failed in trial {} (seed {}): {why}",
                                t.key, t.seed
                            ),
                        });
                    }
                    skipped.fetch_add(1, Ordering::Relaxed);
                    return Ok(());
                }
                // An interrupted trial is incomplete: storing it would record a censored run
                // that never happened.
                if result.stop == StopReason::Interrupted {
                    return Err(RunError::Interrupted);
                }
                let record = TrialRecord {
                    key: t.key.clone(),
                    instance: inst.name.clone(),
                    config: spec.configurations[t.config].label.clone(),
                    trial: t.trial,
                    seed: t.seed,
                    target,
                    budget: spec.budget,
                    result,
                };
                store.append(&record).map_err(RunError::Store)?;
                progress.trial_done(t.config, record.result.reached());
                lock(&fresh_records).push(record);
                Ok(())
            })
    });
    progress.finish();
    result?;
    let wall_seconds = started.elapsed().as_secs_f64();
    let fresh_records = fresh_records
        .into_inner()
        .unwrap_or_else(|e| e.into_inner());
    let new_trials = fresh_records.len();
    let mut all: Vec<TrialRecord> = opened
        .records
        .into_iter()
        .filter(|r| done.contains(&r.key))
        .chain(fresh_records)
        .collect();
    let order: std::collections::HashMap<&str, usize> = plan
        .iter()
        .enumerate()
        .map(|(i, t)| (t.key.as_str(), i))
        .collect();
    all.sort_by_key(|r| order.get(r.key.as_str()).copied().unwrap_or(usize::MAX));
    Ok(RunOutcome {
        records: all,
        new_trials,
        resumed: done.len(),
        missing: missing_after + skipped.into_inner(),
        header: file_header,
        sessions: opened.sessions,
        notes: opened.notes,
        wall_seconds,
        machine,
        failures: failures.into_inner().unwrap_or_else(|e| e.into_inner()),
    })
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}
