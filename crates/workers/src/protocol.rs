//! The messages between a run and its workers: one JSON object per line, the parent's on the
//! worker's standard input, the worker's on a copy of its standard output (the worker points
//! its own standard output at standard error, so that what an algorithm prints cannot break a
//! line).

use std::collections::BTreeMap;
use std::io::{BufRead, Write};
use std::path::PathBuf;

use serde::{Deserialize, Serialize};
use sls::{Budget, TrialResult};

/// What the parent sends.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ToWorker {
    /// First message: the experiment to run trials of.
    Setup(Setup),
    /// Run one trial and reply with its result.
    Trial(TrialRequest),
}

/// The experiment a worker runs trials of: the spec as the parent read it (parsed again in
/// the worker, so configurations and instances are the same) and the evaluation kernel the
/// parent resolved.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Setup {
    /// The spec's TOML text.
    pub text: String,
    /// What names the spec in errors (its path).
    pub origin: String,
    /// The experiment's name (the stem when the text names none).
    pub name: String,
    /// The directory the spec's relative paths resolve against.
    pub base_dir: PathBuf,
    /// The concrete evaluation kernel (`avx2`, ...).
    pub kernel: String,
}

/// One trial of the plan.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TrialRequest {
    /// Index of the instance in the spec.
    pub instance: usize,
    /// Index of the configuration in the spec.
    pub config: usize,
    /// Trial index.
    pub trial: u32,
    /// The trial's seed.
    pub seed: u64,
    /// The trial's key.
    pub key: String,
    /// The target RMSE, as bits (a NaN target crosses too).
    pub target_bits: u64,
    /// The budget.
    pub budget: Budget,
}

/// What a worker replies.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FromWorker {
    /// Set up: the hash of each instance's data, which must equal the parent's.
    Ready {
        /// Instance name -> data hash.
        data_hashes: BTreeMap<String, String>,
    },
    /// The setup failed: the spec does not parse here (an algorithm's module cannot be
    /// imported, say) or an instance cannot be built. `input`: bad input (exit status 2).
    Refused {
        /// Why.
        message: String,
        /// Whether the user's input is at fault.
        input: bool,
    },
    /// A trial's result.
    Result(Box<WireResult>),
}

/// A trial's result on the wire: JSON writes no infinity, so the best RMSE (infinite when
/// nothing was evaluated) crosses as bits.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct WireResult {
    /// The result, its best RMSE zeroed.
    pub result: TrialResult,
    /// The best RMSE's bits.
    pub best_rmse_bits: u64,
}

impl WireResult {
    /// `result` ready to send.
    pub fn new(mut result: TrialResult) -> Self {
        let best_rmse_bits = result.best_rmse.to_bits();
        result.best_rmse = 0.0;
        WireResult {
            result,
            best_rmse_bits,
        }
    }

    /// The result as it was sent.
    pub fn into_result(self) -> TrialResult {
        let mut result = self.result;
        result.best_rmse = f64::from_bits(self.best_rmse_bits);
        result
    }
}

/// Writes one message as a line and flushes it.
pub fn send<T: Serialize>(out: &mut impl Write, message: &T) -> std::io::Result<()> {
    let mut line = serde_json::to_string(message).map_err(std::io::Error::other)?;
    line.push('\n');
    out.write_all(line.as_bytes())?;
    out.flush()
}

/// Reads one message; `None` at the end of the input.
pub fn receive<T: for<'de> Deserialize<'de>>(
    input: &mut impl BufRead,
) -> std::io::Result<Option<T>> {
    let mut line = String::new();
    if input.read_line(&mut line)? == 0 {
        return Ok(None);
    }
    parse(&line).map(Some)
}

/// Parses one line.
pub fn parse<T: for<'de> Deserialize<'de>>(line: &str) -> std::io::Result<T> {
    serde_json::from_str(line.trim_end()).map_err(|e| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("bad message from the other side of a worker's pipe: {e}"),
        )
    })
}

/// A result of a trial that never ran to its end (`stop` [`sls::StopReason::Interrupted`] or
/// [`sls::StopReason::Failed`] with `failure`): nothing evaluated, never stored.
pub fn ended(stop: sls::StopReason, failure: Option<String>) -> TrialResult {
    TrialResult {
        stop,
        reached_at: None,
        ended_at: sls::Stamp::default(),
        best_rmse: f64::INFINITY,
        best_x: Vec::new(),
        trace: Vec::new(),
        counters: Vec::new(),
        failure,
    }
}
