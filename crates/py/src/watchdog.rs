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
//! Linux only (a thread's CPU clock read from another thread: `pthread_getcpuclockid`); on
//! other systems [`Watch::start`] watches nothing.

use std::os::raw::c_long;
use std::sync::{Mutex, MutexGuard, Once, PoisonError};
use std::time::Duration;

use pyo3::ffi;
use pyo3::prelude::*;

use crate::support::BudgetExhausted;

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
    /// Exceptions raised so far.
    fired: u32,
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
    /// `cpu_seconds` of CPU time from now (plus the grace). `None` where threads' CPU clocks
    /// cannot be read.
    pub fn start(cpu_seconds: f64) -> Option<Self> {
        if !cpu_seconds.is_finite() {
            return None;
        }
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
                due: now + cpu_seconds + grace(cpu_seconds),
                fired: 0,
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

    /// Ends the watch and returns how many times the watchdog raised in the call. Call it with
    /// the GIL held, right after the call returns, so that no bytecode runs in between.
    pub fn finish(&mut self) -> u32 {
        if self.done {
            return 0;
        }
        self.done = true;
        // The GIL first (the watchdog's order); re-entrant when the caller holds it already.
        Python::attach(|_py| {
            let fired = {
                let mut r = registry();
                let i = r.entries.iter().position(|e| e.key == self.key);
                i.map_or(0, |i| r.entries.swap_remove(i).fired)
            };
            if fired > 0 {
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

/// The watchdog thread's loop.
fn patrol() {
    loop {
        std::thread::sleep(POLL);
        // Without the GIL: most polls find nothing due and leave the Python threads alone.
        let due = registry()
            .entries
            .iter()
            .any(|e| cpu_now(e.clock).is_some_and(|t| t >= e.due));
        if !due {
            continue;
        }
        // `try_attach`: nothing to do once the interpreter is finalizing.
        let _ = Python::try_attach(|py| {
            let exception = py.get_type::<BudgetExhausted>();
            let mut r = registry();
            for e in &mut r.entries {
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
