//! `brdf_sls._native`: the Python extension module of brdf-sls, built with maturin from the
//! workspace's crates (brdf-model, sls, brdf-experiment, brdf-analysis), so nothing is
//! implemented twice.
//!
//! - [`algorithm`]: `kind = "python"`, search algorithms written in Python (the `Problem` class).
//! - [`data`]: the `DataSet` class (Cornell, CSV, MERL files, numpy arrays, synthetic data).
//! - [`model`]: the `Model` class (evaluate, residuals, RMSE, Jacobian) and `rmse`.
//! - [`fitting`]: `fit`, one seeded fit with any algorithm (`brdf_experiment::fit`).
//! - [`experiment`]: `run` an experiment spec, `read_results` of a results folder.
//! - [`exceptions`]: the exception classes.
//! - [`support`]: errors as Python exceptions, Ctrl-C, conversions.
//! - [`watchdog`]: raises `BudgetExhausted` in a Python algorithm that runs past its CPU cutoff,
//!   and `KeyboardInterrupt` in every Python algorithm of a run stopped with Ctrl-C.
//! - [`worker`]: `python -m brdf_sls worker`, the worker process that runs a run's Python
//!   trials, one per thread.
//!
//! The Python package `brdf_sls` (python/brdf_sls) re-exports these and turns results into
//! pandas-friendly records.

use pyo3::prelude::*;

pub mod algorithm;
pub mod data;
pub mod exceptions;
pub mod experiment;
pub mod fitting;
pub mod model;
pub mod support;
pub mod watchdog;
pub mod worker;

/// The extension module.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    // Before any spec is parsed: `kind = "python"` is a kind like the built-in ones.
    algorithm::register();
    // Results written from Python name the package (the command line's name none).
    brdf_experiment::run::set_program("brdf_sls (Python)", env!("CARGO_PKG_VERSION"));
    m.add("InputError", py.get_type::<support::InputError>())?;
    m.add("RunError", py.get_type::<support::RunError>())?;
    m.add("BudgetExhausted", py.get_type::<support::BudgetExhausted>())?;
    m.add_class::<algorithm::Problem>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<data::PyDataSet>()?;
    m.add_class::<model::PyModel>()?;
    m.add_function(wrap_pyfunction!(model::rmse, m)?)?;
    m.add_function(wrap_pyfunction!(model::named_params, m)?)?;
    m.add_function(wrap_pyfunction!(model::families, m)?)?;
    m.add_function(wrap_pyfunction!(fitting::fit, m)?)?;
    m.add_function(wrap_pyfunction!(experiment::run, m)?)?;
    m.add_function(wrap_pyfunction!(experiment::read_results, m)?)?;
    m.add_function(wrap_pyfunction!(worker::worker_main, m)?)?;
    Ok(())
}
