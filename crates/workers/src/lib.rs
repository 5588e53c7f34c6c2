//! Trials in worker processes.
//!
//! An algorithm written in Python runs under its interpreter's lock: on threads of one
//! interpreter, Python trials compute one at a time whatever the thread count. Here each
//! thread of a run hands its Python trials to a worker process of its own, `python -m brdf_sls
//! worker` (any program that calls [`serve`]), so N threads compute N trials at once. The run
//! itself (the results lock, resume, the store, the statistics) stays in the parent; a worker
//! only runs the trials it is sent, on its main thread, so each trial's CPU time is the
//! worker's own CPU clock, and returns their results, which are the same as in-process results
//! for the same seeds (times aside).
//!
//! - [`protocol`]: the messages, one JSON object per line.
//! - [`serve`]: the worker's loop: parse the spec it is given, build the instances, run trials.
//! - [`pool`]: the parent's side: a pool of workers started from a [`pool::WorkerCommand`]
//!   and [`pool::Routed`], the executor that runs some configurations in workers and the
//!   others in this process.
#![warn(missing_docs)]

pub mod pool;
pub mod protocol;
mod serve;

pub use serve::serve;
