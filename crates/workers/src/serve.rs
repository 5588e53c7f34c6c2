//! The worker's side: [`serve`].

use std::io::{BufRead, Write};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use brdf_experiment::run::{Executor, SlsExecutor};
use brdf_experiment::spec::{PlannedTrial, Spec};
use brdf_model::Kernel;

use crate::protocol::{FromWorker, Setup, ToWorker, WireResult, parse, send};

/// How long a worker whose run is gone (its input closed in the middle of a trial) lets the
/// trial stop by itself before it leaves.
const ORPHAN_GRACE: Duration = Duration::from_secs(1);

/// The worker's loop: reads the [`Setup`] from `input`, parses the spec and builds its
/// instances (replying [`FromWorker::Ready`] or [`FromWorker::Refused`]), then runs each trial
/// it is sent on the calling thread and replies with its result, until `input` ends.
///
/// The kinds the spec names must be registered with their runners in this process (the Python
/// package registers `kind = "python"` when it loads). Should `input` end while a trial runs
/// (the run was killed), the trial is interrupted, and the process leaves after a second
/// whatever the trial does (an algorithm that never returns holds nothing up).
pub fn serve(input: impl BufRead + Send + 'static, mut output: impl Write) -> std::io::Result<()> {
    let busy = Arc::new(AtomicBool::new(false));
    let interrupt = Arc::new(AtomicBool::new(false));
    let (lines, received) = mpsc::channel::<String>();
    {
        let (busy, interrupt) = (busy.clone(), interrupt.clone());
        std::thread::Builder::new()
            .name("brdf-sls-worker-input".into())
            .spawn(move || read_input(input, lines, &busy, &interrupt))?;
    }
    let Ok(first) = received.recv() else {
        return Ok(());
    };
    let ToWorker::Setup(setup) = parse::<ToWorker>(&first)? else {
        return Err(std::io::Error::other(
            "a worker's first message must be its setup",
        ));
    };
    let mut executor = match set_up(&setup) {
        Ok(executor) => executor,
        Err(refused) => return send(&mut output, &refused),
    };
    executor.set_interrupt(interrupt);
    let data_hashes = executor.provenance().data_hashes;
    send(&mut output, &FromWorker::Ready { data_hashes })?;
    while let Ok(line) = received.recv() {
        let ToWorker::Trial(t) = parse::<ToWorker>(&line)? else {
            return Err(std::io::Error::other("a second setup sent to a worker"));
        };
        let trial = PlannedTrial {
            instance: t.instance,
            config: t.config,
            trial: t.trial,
            seed: t.seed,
            key: t.key,
        };
        busy.store(true, Ordering::SeqCst);
        let result = executor.run(&trial, f64::from_bits(t.target_bits), t.budget);
        busy.store(false, Ordering::SeqCst);
        send(
            &mut output,
            &FromWorker::Result(Box::new(WireResult::new(result))),
        )?;
    }
    Ok(())
}

/// Reads lines into `lines` until the input ends; then, if a trial is running, interrupts it
/// and leaves the process after [`ORPHAN_GRACE`].
fn read_input(
    mut input: impl BufRead,
    lines: mpsc::Sender<String>,
    busy: &AtomicBool,
    interrupt: &AtomicBool,
) {
    loop {
        let mut line = String::new();
        match input.read_line(&mut line) {
            Ok(n) if n > 0 => {
                if lines.send(line).is_err() {
                    return;
                }
            }
            _ => break,
        }
    }
    drop(lines);
    if busy.load(Ordering::SeqCst) {
        interrupt.store(true, Ordering::SeqCst);
        std::thread::sleep(ORPHAN_GRACE);
        if busy.load(Ordering::SeqCst) {
            leave();
        }
    }
}

/// Ends the process at once, running no exit handlers (the main thread may be anywhere).
fn leave() -> ! {
    #[cfg(unix)]
    // SAFETY: _exit ends the process; it touches no state of this program.
    unsafe {
        libc::_exit(1)
    }
    #[cfg(not(unix))]
    std::process::exit(1)
}

/// Parses the spec and builds the executor, or says why not.
fn set_up(setup: &Setup) -> Result<SlsExecutor, FromWorker> {
    let refused = |message: String, input: bool| FromWorker::Refused { message, input };
    let spec = Spec::parse(&setup.text, &setup.origin, &setup.name, &setup.base_dir)
        .map_err(|e| refused(e.to_string(), true))?;
    let kernel: Kernel = setup
        .kernel
        .parse()
        .map_err(|e: brdf_model::KernelError| refused(e.to_string(), true))?;
    let built = brdf_experiment::instance::build_all(&spec)
        .map_err(|e| refused(format!("building the instances: {e}"), true))?;
    SlsExecutor::from_built(&spec, &built, kernel)
        .map_err(|e| refused(format!("building the instances: {e}"), true))
}
