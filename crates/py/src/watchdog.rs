//! The CPU-cutoff watchdog of Python algorithms.
//!
//! A Python algorithm's CPU cutoff is noticed when it calls a method of its `Problem`; one that
//! loops in Python (or numpy) without calling the problem would run on past its budget and hold
//! the run up, and no other thread can stop a Python thread by force. CPython can, however,
//! raise an exception asynchronously in another thread (`PyThreadState_SetAsyncExc`): it is
//! delivered at that thread's next bytecode. So while a Python algorithm runs with a CPU budget,
//! its thread is [`Watch`]ed: one watchdog thread per process (started at the first watch)
//! reads each watched thread's CPU clock every [`POLL`] and, once it passes the budget plus a
//! grace ([`grace`]: the algorithm's own next problem call should end it first, the ordinary
//! way), raises `BudgetExhausted` in it; again every [`REFIRE`] of CPU time while the thread
//! stays watched (a function that swallows `BaseException` gets it again, but one that swallows
//! it forever is never stopped). A single long C call (one huge numpy operation) is interrupted
//! only when it returns to Python.
//!
//! The trial's thread ends its watch with the GIL held, right after the call returns and before
//! any more bytecode runs in it, and clears an exception raised but not yet delivered; the
//! watchdog raises only with the GIL held and only in threads still watched (under the
//! registry's lock), so no exception can reach the harness after the call. Lock order: the GIL,
//! then the registry (the watchdog reads the clocks under the registry's lock alone, without
//! waiting for the GIL there).
//!
//! The same watch serves Ctrl-C: while a run or a fit is being interrupted ([`interrupt_all`]),
//! the watchdog raises `KeyboardInterrupt` in every watched thread (again every [`REFIRE`]
//! seconds of wall time), so that an algorithm that never calls its problem stops too, with
//! or without a CPU budget.
//!
//! Linux only (a thread's CPU clock read from another thread: `pthread_getcpuclockid`); on
//! other systems [`Watch::start`] watches nothing.

use std::os::raw::c_long;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, MutexGuard, Once, PoisonError};
use std::time::{Duration, Instant};

use pyo3::ffi;
use pyo3::prelude::*;

use crate::exceptions::BudgetExhausted;

/// How often the watchdog reads the watched threads' CPU clocks.
const POLL: Duration = Duration::from_millis(10);

/// CPU seconds between two exceptions in a thread that caught the first one and runs on.
const REFIRE: f64 = 0.1;

/// CPU seconds past the budget before the watchdog raises: 10% of the budget, at least 50 ms.
fn grace(cpu_seconds: f64) -> f64 {
    (0.1 * cpu_seconds).max(0.05)
}

/// A watched thread.
struct Entry {
    key: u64,
    thread: libc::pthread_t,
    clock: libc::clockid_t,
    /// Reading of `clock` at which to raise next.
    due: f64,
    /// BudgetExhausted raised so far.
    fired: u32,
    /// KeyboardInterrupt raised so far, and when last.
    interrupts: u32,
    interrupted_at: Option<Instant>,
}

/// Whether a run is being interrupted: see [`interrupt_all`].
static INTERRUPTING: AtomicBool = AtomicBool::new(false);

/// Starts (`true`) or ends (`false`) the interruption of every watched Python algorithm:
/// while on, the watchdog raises `KeyboardInterrupt` in each watched thread (Ctrl-C during a
/// run or a fit).
pub fn interrupt_all(on: bool) {
    INTERRUPTING.store(on, Ordering::SeqCst);
}

/// What the watchdog raised in a watched call.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Fired {
    /// `BudgetExhausted` at the CPU cutoff.
    pub budget: u32,
    /// `KeyboardInterrupt` on an interrupt.
    pub interrupts: u32,
}

struct Registry {
    next_key: u64,
    entries: Vec<Entry>,
}

static REGISTRY: Mutex<Registry> = Mutex::new(Registry {
    next_key: 0,
    entries: Vec::new(),
});

static WATCHDOG: Once = Once::new();

fn registry() -> MutexGuard<'static, Registry> {
    REGISTRY.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The current thread watched for the duration of a Python algorithm's call; ends on
/// [`Watch::finish`] or when dropped, whichever comes first.
pub struct Watch {
    key: u64,
    thread: libc::pthread_t,
    done: bool,
}

impl Watch {
    /// Watches the current thread: `BudgetExhausted` is raised in it once it has spent
    /// `cpu_seconds` of CPU time from now (plus the grace; never without a CPU budget), and
    /// `KeyboardInterrupt` while the run is interrupted. `None` where threads' CPU clocks
    /// cannot be read.
    pub fn start(cpu_seconds: Option<f64>) -> Option<Self> {
        let due_in = match cpu_seconds {
            Some(c) if c.is_finite() => c + grace(c),
            _ => f64::INFINITY,
        };
        // SAFETY: pthread_self has no preconditions.
        let thread = unsafe { libc::pthread_self() };
        let clock = thread_clock(thread)?;
        let now = cpu_now(clock)?;
        let key = {
            let mut r = registry();
            r.next_key += 1;
            let key = r.next_key;
            r.entries.push(Entry {
                key,
                thread,
                clock,
                due: now + due_in,
                fired: 0,
                interrupts: 0,
                interrupted_at: None,
            });
            key
        };
        WATCHDOG.call_once(|| {
            // Without the thread (the system refused one) nothing is watched: as before.
            let _ = std::thread::Builder::new()
                .name("brdf-sls-watchdog".into())
                .spawn(patrol);
        });
        Some(Self {
            key,
            thread,
            done: false,
        })
    }

    /// Ends the watch and returns what the watchdog raised in the call. Call it with the GIL
    /// held, right after the call returns, so that no bytecode runs in between.
    pub fn finish(&mut self) -> Fired {
        if self.done {
            return Fired::default();
        }
        self.done = true;
        // The GIL first (the watchdog's order); re-entrant when the caller holds it already.
        Python::attach(|_py| {
            let fired = {
                let mut r = registry();
                let i = r.entries.iter().position(|e| e.key == self.key);
                i.map_or_else(Fired::default, |i| {
                    let e = r.entries.swap_remove(i);
                    Fired {
                        budget: e.fired,
                        interrupts: e.interrupts,
                    }
                })
            };
            if fired != Fired::default() {
                // An exception raised but not delivered yet would surface in the harness's
                // next Python code on this thread: withdraw it. Safe with the GIL held; the
                // thread is no longer watched, so none follows.
                // SAFETY: a NULL exception clears the pending one of the thread with this id.
                unsafe {
                    ffi::PyThreadState_SetAsyncExc(self.thread as c_long, std::ptr::null_mut())
                };
            }
            fired
        })
    }
}

impl Drop for Watch {
    fn drop(&mut self) {
        self.finish();
    }
}

/// The CPU clock of `thread` (the current one), readable from other threads.
#[cfg(target_os = "linux")]
fn thread_clock(thread: libc::pthread_t) -> Option<libc::clockid_t> {
    let mut clock: libc::clockid_t = 0;
    // SAFETY: `thread` is the live current thread; `clock` is a valid out-pointer.
    (unsafe { libc::pthread_getcpuclockid(thread, &mut clock) } == 0).then_some(clock)
}

#[cfg(not(target_os = "linux"))]
fn thread_clock(_thread: libc::pthread_t) -> Option<libc::clockid_t> {
    None
}

/// Reading of a thread's CPU clock, in seconds.
fn cpu_now(clock: libc::clockid_t) -> Option<f64> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid out-pointer; a stale clock id fails with EINVAL, not UB.
    if unsafe { libc::clock_gettime(clock, &mut ts) } != 0 {
        return None;
    }
    Some(ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9)
}

/// Whether an interrupted thread is due a (first or further) `KeyboardInterrupt`.
fn interrupt_due(e: &Entry) -> bool {
    e.interrupted_at
        .is_none_or(|at| at.elapsed().as_secs_f64() >= REFIRE)
}

/// The watchdog thread's loop.
fn patrol() {
    loop {
        std::thread::sleep(POLL);
        // Without the GIL: most polls find nothing due and leave the Python threads alone.
        let interrupting = INTERRUPTING.load(Ordering::SeqCst);
        let due = registry().entries.iter().any(|e| {
            (interrupting && interrupt_due(e)) || cpu_now(e.clock).is_some_and(|t| t >= e.due)
        });
        if !due {
            continue;
        }
        // `try_attach`: nothing to do once the interpreter is finalizing.
        let _ = Python::try_attach(|py| {
            let exception = py.get_type::<BudgetExhausted>();
            let keyboard = py.get_type::<pyo3::exceptions::PyKeyboardInterrupt>();
            let mut r = registry();
            for e in &mut r.entries {
                if interrupting && interrupt_due(e) {
                    // SAFETY: as below.
                    unsafe {
                        ffi::PyThreadState_SetAsyncExc(e.thread as c_long, keyboard.as_ptr())
                    };
                    e.interrupts += 1;
                    e.interrupted_at = Some(Instant::now());
                    continue;
                }
                let Some(t) = cpu_now(e.clock) else { continue };
                if t >= e.due {
                    // SAFETY: with the GIL held, as the call requires; `e.thread` is watched,
                    // so it is in its algorithm's call (it unwatches itself under this lock).
                    unsafe {
                        ffi::PyThreadState_SetAsyncExc(e.thread as c_long, exception.as_ptr())
                    };
                    e.fired += 1;
                    e.due = t + REFIRE;
                }
            }
        });
    }
}
