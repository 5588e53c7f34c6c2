//! The parent's side: a pool of worker processes and the executor that routes trials to it.

use std::collections::BTreeMap;
use std::ffi::OsString;
use std::io::{BufRead, BufReader};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Duration;

use brdf_experiment::instance::{BuiltInstance, InstanceError};
use brdf_experiment::run::{Executor, Provenance, SlsExecutor};
use brdf_experiment::spec::{Configuration, PlannedTrial, Spec};
use brdf_model::Kernel;
use sls::{Budget, StopReason, TrialResult};

use crate::protocol::{FromWorker, Setup, ToWorker, TrialRequest, WireResult, ended, send};

/// How often a thread waiting for a worker looks at the run's interrupt flag.
const POLL: Duration = Duration::from_millis(50);

/// The program a worker is: `python3 -m brdf_sls worker`, say.
#[derive(Clone, Debug)]
pub struct WorkerCommand {
    /// The program.
    pub program: OsString,
    /// Its arguments.
    pub args: Vec<OsString>,
    /// Environment variables to set.
    pub env: Vec<(OsString, OsString)>,
}

/// Why a pool could not start.
#[derive(Debug, thiserror::Error)]
pub enum PoolError {
    /// The spec or an instance is refused in the worker (bad input: exit status 2): the
    /// worker's message, which names the spec file and line as the spec reader does.
    #[error("{0}")]
    Refused(String),
    /// The worker could not be started or broke off.
    #[error("worker process `{program}`: {message}")]
    Worker {
        /// The program.
        program: String,
        /// What happened.
        message: String,
    },
}

/// One worker process, between trials.
struct Worker {
    child: Child,
    stdin: Option<ChildStdin>,
    replies: Receiver<String>,
}

impl Worker {
    fn send(&mut self, message: &ToWorker) -> std::io::Result<()> {
        match self.stdin.as_mut() {
            Some(stdin) => send(stdin, message),
            None => Err(std::io::Error::other("the worker's input is closed")),
        }
    }

    /// Stops the worker at once (its trial, if any, is abandoned).
    fn kill(mut self) {
        let _ = self.child.kill();
        self.stdin = None;
        let _ = self.child.wait();
    }

    /// The worker's exit, for messages.
    fn exit_text(&mut self) -> String {
        self.stdin = None;
        match self.child.wait() {
            Ok(status) => format!("exited ({status})"),
            Err(e) => format!("cannot be waited for: {e}"),
        }
    }
}

impl Drop for Worker {
    /// Closes the worker's input, which ends it, and reaps it.
    fn drop(&mut self) {
        self.stdin = None;
        let _ = self.child.wait();
    }
}

/// Worker processes for the trials of one spec: one started (and checked) at once, more as
/// threads need them; each runs one trial at a time.
pub struct Pool {
    command: WorkerCommand,
    setup: Setup,
    hashes: BTreeMap<String, String>,
    idle: Mutex<Vec<Worker>>,
    interrupt: Option<Arc<AtomicBool>>,
}

impl Pool {
    /// Starts the first worker for `spec` (read from `origin`), evaluated with the concrete
    /// `kernel`, and checks that it built the same data as `hashes` (instance name -> data
    /// hash, the parent's provenance).
    pub fn start(
        command: WorkerCommand,
        spec: &Spec,
        origin: &str,
        kernel: &str,
        hashes: BTreeMap<String, String>,
    ) -> Result<Pool, PoolError> {
        let pool = Pool {
            command,
            setup: Setup {
                text: spec.text.clone(),
                origin: origin.to_string(),
                name: spec.name.clone(),
                base_dir: spec.base_dir.clone(),
                kernel: kernel.to_string(),
            },
            hashes,
            idle: Mutex::new(Vec::new()),
            interrupt: None,
        };
        let first = pool.spawn()?;
        pool.idle().push(first);
        Ok(pool)
    }

    /// Makes every trial in a worker stop once `flag` is raised: the worker is killed and the
    /// trial ends as interrupted (never stored).
    pub fn set_interrupt(&mut self, flag: Arc<AtomicBool>) {
        self.interrupt = Some(flag);
    }

    fn idle(&self) -> std::sync::MutexGuard<'_, Vec<Worker>> {
        self.idle.lock().unwrap_or_else(PoisonError::into_inner)
    }

    fn error(&self, message: impl Into<String>) -> PoolError {
        PoolError::Worker {
            program: self.command.program.to_string_lossy().into_owned(),
            message: message.into(),
        }
    }

    /// Starts a worker and waits until it is set up.
    fn spawn(&self) -> Result<Worker, PoolError> {
        let mut child = Command::new(&self.command.program)
            .args(&self.command.args)
            .envs(self.command.env.iter().map(|(k, v)| (k, v)))
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .map_err(|e| self.error(format!("cannot start it: {e}")))?;
        let stdout = child.stdout.take().expect("piped");
        let (lines, replies) = mpsc::channel();
        std::thread::Builder::new()
            .name("brdf-sls-worker-replies".into())
            .spawn(move || {
                for line in BufReader::new(stdout).lines() {
                    let Ok(line) = line else { break };
                    if lines.send(line).is_err() {
                        break;
                    }
                }
            })
            .map_err(|e| self.error(format!("cannot start a reader thread: {e}")))?;
        let mut worker = Worker {
            stdin: child.stdin.take(),
            child,
            replies,
        };
        worker
            .send(&ToWorker::Setup(self.setup.clone()))
            .map_err(|e| self.error(format!("cannot send its setup: {e}")))?;
        let Ok(line) = worker.replies.recv() else {
            let exit = worker.exit_text();
            return Err(self.error(format!("{exit} before it was ready")));
        };
        match crate::protocol::parse::<FromWorker>(&line) {
            Ok(FromWorker::Ready { data_hashes }) => {
                if let Some((name, _)) = self
                    .hashes
                    .iter()
                    .find(|(name, hash)| data_hashes.get(*name) != Some(hash))
                {
                    return Err(self.error(format!(
                        "it built other data for instance `{name}` than this run"
                    )));
                }
                Ok(worker)
            }
            Ok(FromWorker::Refused { message, input }) => Err(if input {
                PoolError::Refused(message)
            } else {
                self.error(message)
            }),
            Ok(FromWorker::Result(_)) => Err(self.error("it sent a result before its setup")),
            Err(e) => Err(self.error(e.to_string())),
        }
    }

    /// Runs `trial` in an idle worker (started if none is idle) and returns its result. A
    /// worker that breaks off fails the trial ([`StopReason::Failed`], naming the worker); an
    /// interrupt kills the worker and ends the trial as interrupted.
    pub fn run(&self, trial: &PlannedTrial, target: f64, budget: Budget) -> TrialResult {
        let taken = self.idle().pop();
        let mut worker = match taken {
            Some(w) => w,
            None => match self.spawn() {
                Ok(w) => w,
                Err(e) => return ended(StopReason::Failed, Some(e.to_string())),
            },
        };
        let request = ToWorker::Trial(TrialRequest {
            instance: trial.instance,
            config: trial.config,
            trial: trial.trial,
            seed: trial.seed,
            key: trial.key.clone(),
            target_bits: target.to_bits(),
            budget,
        });
        if let Err(e) = worker.send(&request) {
            let exit = worker.exit_text();
            let message = format!("cannot send the trial ({e}); it {exit}");
            return ended(StopReason::Failed, Some(self.error(message).to_string()));
        }
        loop {
            if self
                .interrupt
                .as_ref()
                .is_some_and(|f| f.load(Ordering::Relaxed))
            {
                worker.kill();
                return ended(StopReason::Interrupted, None);
            }
            match worker.replies.recv_timeout(POLL) {
                Ok(line) => {
                    return match crate::protocol::parse::<FromWorker>(&line) {
                        Ok(FromWorker::Result(wire)) => {
                            self.idle().push(worker);
                            WireResult::into_result(*wire)
                        }
                        Ok(_) => {
                            worker.kill();
                            let message = self.error("it sent something else than a result");
                            ended(StopReason::Failed, Some(message.to_string()))
                        }
                        Err(e) => {
                            worker.kill();
                            ended(
                                StopReason::Failed,
                                Some(self.error(e.to_string()).to_string()),
                            )
                        }
                    };
                }
                Err(RecvTimeoutError::Timeout) => continue,
                Err(RecvTimeoutError::Disconnected) => {
                    let exit = worker.exit_text();
                    let message = format!("it {exit} during the trial");
                    return ended(StopReason::Failed, Some(self.error(message).to_string()));
                }
            }
        }
    }
}

impl Drop for Pool {
    /// Ends the idle workers (closing their input) before the run returns.
    fn drop(&mut self) {
        self.idle().clear();
    }
}

/// The executor of a run whose configurations run partly in worker processes: those that
/// `remote` selects go to a [`Pool`], the others run in this process ([`SlsExecutor`]).
pub struct Routed {
    local: SlsExecutor,
    pool: Option<Pool>,
    remote: Vec<bool>,
}

impl Routed {
    /// The executor of `spec` on the instances `built` once, with `kernel`: configurations for
    /// which `remote` says so run in workers started with `command` (the pool starts only when
    /// there is one), named `origin` in their messages.
    pub fn new(
        spec: &Spec,
        built: &[BuiltInstance],
        kernel: Kernel,
        remote: impl Fn(&Configuration) -> bool,
        command: impl FnOnce() -> WorkerCommand,
        origin: &str,
    ) -> Result<Routed, RoutedError> {
        let local = SlsExecutor::from_built(spec, built, kernel)?;
        let remote: Vec<bool> = spec.configurations.iter().map(remote).collect();
        let pool = if remote.contains(&true) {
            let provenance = local.provenance();
            Some(Pool::start(
                command(),
                spec,
                origin,
                &provenance.kernel,
                provenance.data_hashes,
            )?)
        } else {
            None
        };
        Ok(Routed {
            local,
            pool,
            remote,
        })
    }

    /// Stops every trial, in this process or in a worker, once `flag` is raised.
    pub fn set_interrupt(&mut self, flag: Arc<AtomicBool>) {
        self.local.set_interrupt(flag.clone());
        if let Some(pool) = &mut self.pool {
            pool.set_interrupt(flag);
        }
    }
}

/// Why a [`Routed`] executor could not be built.
#[derive(Debug, thiserror::Error)]
pub enum RoutedError {
    /// An instance or the kernel.
    #[error(transparent)]
    Instance(#[from] InstanceError),
    /// The workers.
    #[error(transparent)]
    Pool(#[from] PoolError),
}

impl Executor for Routed {
    fn run(&self, trial: &PlannedTrial, target: f64, budget: Budget) -> TrialResult {
        match &self.pool {
            Some(pool) if self.remote[trial.config] => pool.run(trial, target, budget),
            _ => self.local.run(trial, target, budget),
        }
    }

    fn provenance(&self) -> Provenance {
        self.local.provenance()
    }
}
