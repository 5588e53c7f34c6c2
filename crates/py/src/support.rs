//! What every binding needs: the exception classes, running long calls without the GIL while
//! answering Ctrl-C, and conversions of Python values (parameters among them).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use brdf_model::Params;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString};

pub use crate::exceptions::{BudgetExhausted, InputError, RunError};

/// An [`InputError`] with `message`.
pub fn input_err(message: impl std::fmt::Display) -> PyErr {
    InputError::new_err(message.to_string())
}

/// A [`RunError`] with `message`.
pub fn run_err(message: impl std::fmt::Display) -> PyErr {
    RunError::new_err(message.to_string())
}

/// An error and its causes as the command line prints them: its own function, so a cause
/// that repeats its parent (a refused seed inside the run's error) is printed once here too.
pub fn chain(e: anyhow::Error) -> String {
    brdf_analysis::errors::message(&e)
}

/// How often a waiting call looks for Ctrl-C.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Runs `work` on a worker thread while the calling thread waits without the GIL, checking for
/// signals every 50 ms. On Ctrl-C (or any signal handler raising) the flag given to `work` is
/// raised, the watchdog interrupts the Python algorithms running in this process
/// ([`crate::watchdog::interrupt_all`], for those that never call their problem), the worker
/// is waited for (it stops at its next evaluation) and the handler's exception
/// (KeyboardInterrupt) is returned. A panic in `work` becomes a [`RunError`] instead
/// of crossing into Python.
pub fn interruptible<T, F>(py: Python<'_>, work: F) -> PyResult<T>
where
    T: Send,
    F: FnOnce(Arc<AtomicBool>) -> T + Send,
{
    let flag = Arc::new(AtomicBool::new(false));
    std::thread::scope(|scope| {
        let worker_flag = flag.clone();
        let handle = scope.spawn(move || work(worker_flag));
        let mut signal = None;
        while !handle.is_finished() {
            py.detach(|| std::thread::sleep(SIGNAL_POLL));
            if let Err(e) = py.check_signals() {
                flag.store(true, Ordering::Relaxed);
                crate::watchdog::interrupt_all(true);
                signal = Some(e);
                break;
            }
        }
        let joined = py.detach(move || handle.join());
        crate::watchdog::interrupt_all(false);
        if let Some(e) = signal {
            return Err(e);
        }
        joined.map_err(|p| {
            let message = p
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| p.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            run_err(format!("internal error (a bug, please report): {message}"))
        })
    })
}

/// A Python value as a TOML value, for algorithm settings (`phi=1.2` as `--set phi=1.2`).
pub fn toml_value(key: &str, v: &Bound<'_, PyAny>) -> PyResult<toml::Value> {
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        let i: i64 = v
            .extract()
            .map_err(|_| input_err(format!("{key}={v}: integer out of range")))?;
        return Ok(toml::Value::Integer(i));
    }
    if v.is_instance_of::<PyFloat>() {
        let f: f64 = v.extract()?;
        if !f.is_finite() {
            return Err(input_err(format!(
                "`{key}={f}`: expected a finite number, found {f}"
            )));
        }
        return Ok(toml::Value::Float(f));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(v.extract()?));
    }
    if let Ok(list) = v.cast::<PyList>() {
        let items = list
            .iter()
            .map(|item| toml_value(key, &item))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(items));
    }
    Err(input_err(format!(
        "{key}: expected a number, a string, a bool or a list, found {}",
        v.get_type().name()?
    )))
}

/// A serde value as a Python object, through JSON (exact for f64: the shortest round-trip
/// decimal is written and Python's float() reads it back bit for bit).
pub fn to_python<T: serde::Serialize>(py: Python<'_>, value: &T) -> PyResult<Py<PyAny>> {
    let text = serde_json::to_string(value).map_err(run_err)?;
    let json = py.import("json")?;
    Ok(json.call_method1("loads", (text,))?.unbind())
}

/// Parameters from Python: a paper name ("tuning", "cross", "paper-bluepaint",
/// "pbrt-bluepaint"), a dict `{"kd": .., "lobes": [{"cx", "cy", "cz", "n", "pan_deg"}]}` (another
/// family: `{"family": "ggx", "kd": .., "lobes": [{"ks", "ax", "ay", "f0", "pan"}]}`), its
/// JSON text (the `json:` line of `brdf-sls fit`) or `"@FILE"` holding that JSON; read by
/// `brdf_experiment::params` (what `--params` and specs use) and checked against its family's
/// box.
pub fn parse_params(p: &Bound<'_, PyAny>) -> PyResult<Params> {
    let text: String = if p.is_instance_of::<PyString>() {
        p.extract()?
    } else if p.is_instance_of::<PyDict>() {
        let json = p.py().import("json")?;
        json.call_method1("dumps", (p,))?.extract()?
    } else {
        return Err(input_err(format!(
            "params: expected a name, a dict or JSON text, found {}",
            p.get_type().name()?
        )));
    };
    brdf_experiment::params::parse_params(
        "params",
        brdf_experiment::params::ParamsInput::Text(&text),
    )
    .map(|g| g.params)
    .map_err(input_err)
}

/// A Python dict of settings as `(name, TOML value)` pairs.
pub fn settings(config: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, toml::Value)>> {
    let Some(config) = config else {
        return Ok(Vec::new());
    };
    config
        .iter()
        .map(|(k, v)| {
            let key: String = k.extract()?;
            let value = toml_value(&key, &v)?;
            Ok((key, value))
        })
        .collect()
}

/// A library enum by its serde name (`anisotropic`, `log1p`, `green`, ...), as the command
/// line parses it.
pub fn enum_value<T: serde::de::DeserializeOwned>(keyword: &str, s: &str) -> PyResult<T> {
    toml::Value::String(s.trim().to_string())
        .try_into()
        .map_err(|e: toml::de::Error| input_err(format!("{keyword}={s}: {}", e.message())))
}

/// The model `fit` and `Model` take: `family` (a registered family's name), `lobes`, `kind`
/// (`None`: anisotropic where the family has it), `exponent` and `fixed`, checked as
/// `brdf-sls fit` checks `--family`, `--lobes`, `--kind`, `--exponent` and `--fix`.
pub fn model_spec(
    family: &str,
    lobes: usize,
    kind: Option<&str>,
    exponent: &str,
    fixed: Option<std::collections::BTreeMap<String, f64>>,
) -> PyResult<brdf_experiment::spec::ModelSpec> {
    let family = brdf_model::family(family).map_err(|e| input_err(format!("family: {e}")))?;
    let kind = match kind {
        Some(k) => enum_value::<brdf_model::LobeKind>("kind", k)?,
        None if family.kinds().contains(&brdf_model::LobeKind::Anisotropic) => {
            brdf_model::LobeKind::Anisotropic
        }
        None => family.kinds()[0],
    };
    brdf_fit::model_spec(
        brdf_fit::Surface::Python,
        family,
        lobes,
        kind,
        enum_value::<brdf_model::ExponentCoord>("exponent", exponent)?,
        fixed.unwrap_or_default(),
    )
    .map_err(input_err)
}
