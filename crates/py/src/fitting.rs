//! `fit`: one seeded fit of one data set with any algorithm, through `brdf_experiment::fit`
//! (the code behind `brdf-sls fit`), so the same seed gives the same fit as the command line.

use std::collections::BTreeMap;
use std::sync::Arc;

use brdf_fit::{FitError, FitOutcome, FitRequest, Surface};
use brdf_model::Kernel;
use numpy::PyArray1;
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::data::PyDataSet;
use crate::support::{input_err, interruptible, run_err, settings, to_python};

/// Fits `data` with one algorithm, as `brdf-sls fit DATA --algorithm ALGORITHM --set K=V ...`.
///
/// data: a DataSet (or a path, read with the defaults); algorithm: "aed", "aers", "rpls",
/// "ds", "sa", "sals", "avg", "asa", or "python" (with `entry="module:function"`, an algorithm
/// written in Python, see docs/own-algorithm.md); any other keyword argument is a setting of that
/// algorithm (`phi=1.2`, as `--set phi=1.2`; missing ones take the paper's defaults). lobes,
/// kind, exponent, fixed: the model (see `Model`); target: stop at this RMSE (0: use the whole
/// budget); cpu_seconds: the CPU-time budget of the worker thread; seed: as `--seed`;
/// descent: the descents' solver, "default", "gauss-newton" or "n2fb" (as `--descent`);
/// polish: end with full-data descents from the search's best until it rests (False: as
/// `--no-polish`).
///
/// Returns a dict: params (physical, a dict), x (optimiser coordinates), names, rmse (of the
/// fitted parameters, recomputed in full), best_rmse (the search's best, before the polish),
/// polish (dict rmse_before, rmse_after, descents, wall_seconds; None when off), stop, reached, cpu_seconds, wall_seconds,
/// evaluations (sample-evaluations), evaluation_counts, reached_at, trace (dict of arrays
/// cpu_seconds, wall_seconds, evaluations, rmse: one entry per improvement), counters,
/// algorithm (every setting, defaults included), kernel, descent, seed.
///
/// Releases the GIL while fitting; Ctrl-C stops the fit and raises KeyboardInterrupt.
#[pyfunction]
#[pyo3(signature = (data, algorithm="rpls", *, family="lafortune", lobes=1, kind=None, exponent="log1p", fixed=None, target=0.0, cpu_seconds=10.0, seed=1, kernel="auto", descent="default", polish=true, **config))]
#[allow(clippy::too_many_arguments)]
pub fn fit(
    py: Python<'_>,
    data: &Bound<'_, PyAny>,
    algorithm: &str,
    family: &str,
    lobes: usize,
    kind: Option<&str>,
    exponent: &str,
    fixed: Option<BTreeMap<String, f64>>,
    target: f64,
    cpu_seconds: f64,
    seed: u64,
    kernel: &str,
    descent: &str,
    polish: bool,
    config: Option<&Bound<'_, PyDict>>,
) -> PyResult<Py<PyAny>> {
    // The command line's order of checks, so the first error reported is the same.
    brdf_fit::check_budget(Surface::Python, cpu_seconds, target).map_err(input_err)?;
    let algorithm = brdf_fit::algorithm_config(Surface::Python, algorithm, settings(config)?)
        .map_err(input_err)?;
    let model = crate::support::model_spec(family, lobes, kind, exponent, fixed)?;
    let kernel: Kernel = kernel.parse().map_err(input_err)?;
    let descent: sls::DescentModel = descent.parse().map_err(input_err)?;
    let data = data_arg(py, data)?;
    let request = FitRequest {
        model,
        algorithm,
        seed,
        cpu_seconds,
        target,
        kernel,
        descent,
        polish,
        progress: brdf_fit::FitProgress::Quiet,
        surface: Surface::Python,
    };
    // A Python algorithm's failure is a FitError::Input with its message.
    let outcome = interruptible(py, |flag| brdf_fit::fit(data, &request, Some(flag)))?;
    match outcome {
        Ok(fit) => fit_dict(py, &request, fit),
        Err(FitError::Interrupted) => Err(PyKeyboardInterrupt::new_err("fit interrupted")),
        Err(e @ FitError::Input(_)) => Err(input_err(e)),
        Err(e) => Err(run_err(e)),
    }
}

/// The data argument: a DataSet, or a path read as `brdf-sls fit PATH` reads it.
fn data_arg(py: Python<'_>, data: &Bound<'_, PyAny>) -> PyResult<Arc<brdf_model::DataSet>> {
    if let Ok(d) = data.cast::<PyDataSet>() {
        let d = d.get().data.clone();
        if d.is_empty() {
            return Err(input_err("data: no samples"));
        }
        return Ok(d);
    }
    let path: std::path::PathBuf = data
        .extract()
        .map_err(|_| input_err("data: expected a DataSet or the path of a data file"))?;
    let fs = brdf_experiment::spec::FileSpec::plain(path);
    let (d, _) = py
        .detach(|| brdf_fit::load_non_empty(&fs))
        .map_err(input_err)?;
    Ok(Arc::new(d))
}

/// The result dict of [`fit`]; arrays are handed to numpy without copying.
fn fit_dict(py: Python<'_>, request: &FitRequest, fit: FitOutcome) -> PyResult<Py<PyAny>> {
    let r = &fit.result;
    let d = PyDict::new(py);
    d.set_item("params", to_python(py, &fit.params)?)?;
    d.set_item("names", fit.layout.free_names().to_vec())?;
    d.set_item("rmse", fit.rmse)?;
    d.set_item("best_rmse", r.best_rmse)?;
    d.set_item("stop", to_python(py, &r.stop)?)?;
    d.set_item("reached", r.reached())?;
    d.set_item("cpu_seconds", r.ended_at.cpu_seconds)?;
    d.set_item("wall_seconds", r.ended_at.wall_seconds)?;
    d.set_item("evaluations", r.ended_at.evaluations.total())?;
    d.set_item("evaluation_counts", to_python(py, &r.ended_at.evaluations)?)?;
    d.set_item("reached_at", to_python(py, &r.reached_at)?)?;
    d.set_item("trace", trace_dict(py, r)?)?;
    d.set_item(
        "counters",
        to_python(py, &r.counters.iter().cloned().collect::<BTreeMap<_, _>>())?,
    )?;
    d.set_item("algorithm", to_python(py, &request.algorithm)?)?;
    d.set_item("kernel", fit.kernel.to_string())?;
    d.set_item("descent", request.descent.to_string())?;
    d.set_item("seed", request.seed)?;
    let polish = fit.polish.map(|p| {
        BTreeMap::from([
            ("rmse_before", p.rmse_before),
            ("rmse_after", p.rmse_after),
            ("descents", p.descents as f64),
            ("wall_seconds", p.wall_seconds),
        ])
    });
    d.set_item("polish", polish)?;
    d.set_item("x", PyArray1::from_vec(py, fit.x))?;
    Ok(d.into_any().unbind())
}

/// The anytime trace as a dict of equal-length arrays.
fn trace_dict<'py>(py: Python<'py>, r: &sls::TrialResult) -> PyResult<Bound<'py, PyDict>> {
    let t = &r.trace;
    let d = PyDict::new(py);
    let f = |g: fn(&sls::TracePoint) -> f64| PyArray1::from_vec(py, t.iter().map(g).collect());
    d.set_item("cpu_seconds", f(|p| p.at.cpu_seconds))?;
    d.set_item("wall_seconds", f(|p| p.at.wall_seconds))?;
    let evaluations: Vec<u64> = t.iter().map(|p| p.at.evaluations.total()).collect();
    d.set_item("evaluations", PyArray1::from_vec(py, evaluations))?;
    d.set_item("rmse", f(|p| p.rmse))?;
    Ok(d)
}
