//! `kind = "python"`: search algorithms written in Python, run by the harness like the
//! built-in ones.
//!
//! [`PythonAlgorithm`] is an ordinary [`sls::registry::Algorithm`] (registered when the
//! extension module loads): the experiment file names a function, `entry =
//! "package.module:function"`, and every other key of the entry is passed to it as a keyword
//! argument. Its [`Algorithm::run`] takes the GIL and calls `function(problem, **settings)`
//! with a [`Problem`]: the trial's [`Search`] seen from Python. Every sample-evaluation goes
//! through the same [`sls::TrialContext`] as a built-in algorithm's, so counts, budgets, the
//! target, the best candidate and the trace are recorded the same way.
//!
//! A budget stop (target reached, evaluations or CPU seconds spent) raises
//! [`BudgetExhausted`] (a `BaseException`, so `except Exception` in the algorithm does not
//! swallow it) and sets `problem.stopped`; every later call raises again. One that loops
//! without calling the problem past its CPU budget gets it from [`crate::watchdog`] and is
//! recorded as cut at its CPU budget all the same (the watchdog reads the budget from
//! [`Search::budget`]). An algorithm that fails (raises, passes a point outside the box,
//! returns something) ends its trial with [`Search::fail`] and its message, which the harness
//! reports, naming the configuration; it stores no failed trial. When the run is interrupted
//! (Ctrl-C) the watchdog raises `KeyboardInterrupt` in the algorithm's thread, so that one that
//! never calls its problem stops too; the trial ends as interrupted.

use std::ptr::NonNull;
use std::sync::{Mutex, MutexGuard, PoisonError};

use brdf_experiment::python_kind::PythonEntry;
use numpy::ndarray::{Array2, ShapeBuilder};
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArrayLikeDyn, PyUntypedArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rand::Rng;
use serde::{Deserialize, Serialize};
use sls::registry::Algorithm;
use sls::{ConfigError, DescentLimits, Rows, Search, Stop};

use crate::exceptions::BudgetExhausted;

/// An algorithm written in Python: `[[algorithm]] kind = "python"`, `entry =
/// "package.module:function"`, and any other keys, which are passed to the function as keyword
/// arguments (`function(problem, **settings)`). The configuration is the harness's
/// [`PythonEntry`] (the command line reads the same records).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct PythonAlgorithm(pub PythonEntry);

impl Algorithm for PythonAlgorithm {
    const KIND: &'static str = brdf_experiment::python_kind::KIND;

    /// Checks the entry's form, then imports the module and looks the function up (so a
    /// misspelt entry is an error of the experiment file, before any trial runs).
    fn validate(&self) -> Result<(), ConfigError> {
        self.0.check_form()?;
        let (module, function) = self.0.split_entry()?;
        Python::attach(|py| {
            resolve(py, module, function)
                .map(drop)
                .map_err(|message| ConfigError::new(Self::KIND, "entry", message))
        })
    }

    fn run(&self, search: &mut dyn Search) -> Result<(), Stop> {
        let outcome = Python::attach(|py| self.run_in_python(py, search));
        outcome.unwrap_or_else(|message| {
            Err(search.fail(format!("python `{}` {message}", self.0.entry)))
        })
    }
}

/// Registers `kind = "python"`; called when the extension module loads (a second load in the
/// same process finds it registered).
pub fn register() {
    // The only possible error is the kind being taken already, by this same type.
    let _ = sls::registry::register::<PythonAlgorithm>();
}

impl PythonAlgorithm {
    /// Calls the function with a [`Problem`] over `search`; `Err` is a failure's message.
    fn run_in_python(
        &self,
        py: Python<'_>,
        search: &mut dyn Search,
    ) -> Result<Result<(), Stop>, String> {
        let (module, function) = self.0.split_entry().map_err(|e| e.to_string())?;
        let function = resolve(py, module, function)?;
        // One draw from the trial's generator seeds numpy's: reproducible from the trial seed.
        let seed = search.rng().next_u64();
        let rng = py
            .import("numpy.random")
            .and_then(|m| m.call_method1("default_rng", (seed,)))
            .map_err(|e| describe(py, &e))?
            .unbind();
        let kwargs = PyDict::new(py);
        for (key, value) in &self.0.settings {
            let value = crate::support::to_python(py, value).map_err(|e| describe(py, &e))?;
            kwargs.set_item(key, value).map_err(|e| describe(py, &e))?;
        }
        let problem = Problem::new(search, self.0.entry.clone(), rng);
        let problem = Py::new(py, problem).map_err(|e| describe(py, &e))?;
        let live = Live {
            py,
            problem: problem.clone_ref(py),
        };
        let cpu_left = search.budget().cpu_seconds_left();
        let mut watch = crate::watchdog::Watch::start(cpu_left);
        let returned = function.call(py, (problem.clone_ref(py),), Some(&kwargs));
        // Before any other bytecode runs on this thread (see crate::watchdog).
        let fired = watch
            .as_mut()
            .map_or_else(Default::default, crate::watchdog::Watch::finish);
        let p = problem.borrow(py);
        if fired.interrupts > 0
            || matches!(&returned, Err(e) if e.is_instance_of::<pyo3::exceptions::PyKeyboardInterrupt>(py))
        {
            // The run was interrupted (Ctrl-C): the trial is incomplete, never stored.
            drop(live);
            return Ok(Err(Stop::Interrupted));
        }
        let raised_stop = matches!(&returned, Err(e) if e.is_instance_of::<BudgetExhausted>(py));
        if lock(&p.stop).is_none() && (fired.budget > 0 || raised_stop) {
            // The watchdog's BudgetExhausted came from no problem method, so no stop is
            // recorded: read the trial's clock, which records the CPU-budget stop as a method
            // would have (the watchdog raises only after the budget is spent).
            let _ = p.with(|_| Ok(()));
        }
        drop(live);
        if let Some(message) = lock(&p.failure).take() {
            return Err(message);
        }
        let stop = *lock(&p.stop);
        match returned {
            Ok(value) if value.is_none(py) => Ok(stop.map_or(Ok(()), Err)),
            Ok(value) => Err(format!(
                "returned {}; it must return None (the trial's result is the best point it evaluated)",
                repr(value.bind(py))
            )),
            Err(e) if e.is_instance_of::<BudgetExhausted>(py) => match stop {
                Some(stop) => Ok(Err(stop)),
                None => Err("raised BudgetExhausted while its budget was not spent".into()),
            },
            Err(e) => Err(format!("raised {}", describe(py, &e))),
        }
    }
}

/// Imports `module` and returns its callable `function`, or says why not.
fn resolve(py: Python<'_>, module: &str, function: &str) -> Result<Py<PyAny>, String> {
    let m = py
        .import(module)
        .map_err(|e| format!("cannot import `{module}`: {}", describe(py, &e)))?;
    let f = m
        .getattr(function)
        .map_err(|_| format!("module `{module}` has no `{function}`"))?;
    if !f.is_callable() {
        return Err(format!("`{module}:{function}` is not callable"));
    }
    Ok(f.unbind())
}

/// `ExceptionType: message (at file:line in function)`, the innermost frame of the traceback.
fn describe(py: Python<'_>, e: &PyErr) -> String {
    let kind = e
        .get_type(py)
        .name()
        .map_or_else(|_| "exception".to_string(), |n| n.to_string());
    let message = e
        .value(py)
        .str()
        .map_or_else(|_| String::new(), |s| s.to_string());
    let head = if message.is_empty() {
        kind
    } else {
        format!("{kind}: {message}")
    };
    let frame = e.traceback(py).and_then(|tb| {
        let mut tb = tb;
        while let Ok(next) = tb.getattr("tb_next") {
            match next.cast_into::<pyo3::types::PyTraceback>() {
                Ok(n) => tb = n,
                Err(_) => break,
            }
        }
        let code = tb.getattr("tb_frame").ok()?.getattr("f_code").ok()?;
        let file: String = code.getattr("co_filename").ok()?.extract().ok()?;
        let name: String = code.getattr("co_name").ok()?.extract().ok()?;
        let line: i64 = tb.getattr("tb_lineno").ok()?.extract().ok()?;
        Some(format!(" (at {file}:{line} in {name})"))
    });
    head + &frame.unwrap_or_default()
}

/// ` (at FILE:LINE in FUNCTION)`: the Python code calling into the problem now (the frame on
/// top of the interpreter's stack: a method of `Problem` pushes none).
fn caller(py: Python<'_>) -> Option<String> {
    let frame = py
        .import("sys")
        .ok()?
        .call_method1("_getframe", (0,))
        .ok()?;
    let code = frame.getattr("f_code").ok()?;
    let file: String = code.getattr("co_filename").ok()?.extract().ok()?;
    let name: String = code.getattr("co_name").ok()?.extract().ok()?;
    let line: i64 = frame.getattr("f_lineno").ok()?.extract().ok()?;
    Some(format!(" (at {file}:{line} in {name})"))
}

fn repr(v: &Bound<'_, PyAny>) -> String {
    v.repr()
        .map_or_else(|_| "a value".into(), |r| r.to_string())
}

/// Clears the problem's link to the trial when the call ends, however it ends: a Problem kept
/// by Python afterwards raises instead of touching a finished trial.
struct Live<'py> {
    py: Python<'py>,
    problem: Py<Problem>,
}

impl Drop for Live<'_> {
    fn drop(&mut self) {
        *lock(&self.problem.borrow(self.py).search) = None;
    }
}

/// The trial, as the Python function sees it: the box, the data size, the full-data RMSE
/// (with an early-exit bound), residuals, the Jacobian, descents, random picks, the
/// exponent coordinates (`encode`/`decode`), a seeded numpy generator and the budget. Every
/// method that evaluates counts sample-evaluations as the built-in algorithms do; every method
/// raises BudgetExhausted once the trial is over (target reached or budget spent). Valid only
/// during the call that received it.
#[pyclass(frozen, module = "brdf_sls", name = "Problem")]
pub struct Problem {
    /// The trial's search, set only during the algorithm's call ([`Live`] clears it); locked
    /// for each use, so two Python threads cannot use it at once.
    search: Mutex<Option<SearchPtr>>,
    /// The stop a call returned; the trial ends with it.
    stop: Mutex<Option<Stop>>,
    /// Bad input from the algorithm (a point outside the box, ...): fails the trial even if the
    /// algorithm catches the ValueError.
    failure: Mutex<Option<String>>,
    entry: String,
    dim: usize,
    samples: usize,
    lower: Vec<f64>,
    upper: Vec<f64>,
    rng: Py<PyAny>,
}

impl Problem {
    fn new(search: &mut dyn Search, entry: String, rng: Py<PyAny>) -> Self {
        let ptr: NonNull<dyn Search + '_> = NonNull::from(search);
        // SAFETY: only the lifetime is erased. The pointer is used only while the algorithm's
        // call runs (the `Live` guard clears it before `run_in_python` returns), and the trial
        // context it points to is mutably borrowed by `run` for all that time.
        let ptr: NonNull<dyn Search + 'static> = unsafe { std::mem::transmute(ptr) };
        // SAFETY: `ptr` was made from a live `&mut` just above.
        let s = unsafe { ptr.as_ref() };
        Self {
            dim: s.dim(),
            samples: s.sample_count(),
            lower: s.lower().to_vec(),
            upper: s.upper().to_vec(),
            search: Mutex::new(Some(SearchPtr(ptr))),
            stop: Mutex::new(None),
            failure: Mutex::new(None),
            entry,
            rng,
        }
    }

    /// Runs `f` on the trial's search after a budget check; a stop raises BudgetExhausted.
    fn with<T>(&self, f: impl FnOnce(&mut dyn Search) -> Result<T, Stop>) -> PyResult<T> {
        let mut guard = lock(&self.search);
        let ptr = guard.as_mut().ok_or_else(|| self.over())?;
        // SAFETY: set only while the trial's context is exclusively lent to the algorithm's
        // call (see `Problem::new`), and used under the lock; Search methods never call back
        // into Python, so this is the only reference in use.
        let search = unsafe { ptr.0.as_mut() };
        let result = search.check_budget().and_then(|()| f(search));
        drop(guard);
        result.map_err(|stop| {
            *lock(&self.stop) = Some(stop);
            BudgetExhausted::new_err(stop_name(stop))
        })
    }

    /// The error of a call after the trial ended.
    fn over(&self) -> PyErr {
        PyRuntimeError::new_err(format!(
            "the trial of this problem ({}) is over: a Problem is valid only during the call that received it",
            self.entry
        ))
    }

    /// A ValueError that also fails the trial (the algorithm cannot catch its way past it);
    /// the failure names the Python file and line of the call.
    fn bad(&self, message: String) -> PyErr {
        let at = Python::attach(caller).unwrap_or_default();
        lock(&self.failure).get_or_insert_with(|| format!("{message}{at}"));
        PyValueError::new_err(message)
    }

    /// `x` as `dim` finite numbers, in the box when `in_box`.
    fn point(&self, name: &str, x: &Bound<'_, PyAny>, in_box: bool) -> PyResult<Vec<f64>> {
        let arr: PyArrayLikeDyn<'_, f64, AllowTypeChange> = x.extract().map_err(|_| {
            self.bad(format!(
                "{name}: expected an array of {} numbers, found {}",
                self.dim,
                repr(x)
            ))
        })?;
        if arr.ndim() != 1 || arr.len() != self.dim {
            return Err(self.bad(format!(
                "{name}: expected shape ({},), found shape {:?}",
                self.dim,
                arr.shape()
            )));
        }
        let v: Vec<f64> = arr.as_array().iter().copied().collect();
        for (i, &xi) in v.iter().enumerate() {
            if !xi.is_finite() {
                return Err(self.bad(format!("{name}[{i}] is {xi}, not a finite number")));
            }
            let (lo, hi) = (self.lower[i], self.upper[i]);
            if in_box && !(lo..=hi).contains(&xi) {
                return Err(self.bad(format!(
                    "{name}[{i}] = {xi} is outside the bounds [{lo}, {hi}]"
                )));
            }
        }
        Ok(v)
    }
}

/// The trial's search, lent to a [`Problem`] for the duration of the algorithm's call.
struct SearchPtr(NonNull<dyn Search>);

// SAFETY: dereferenced only under the Problem's lock while the call that lent it runs (the
// trial's context stays mutably borrowed by `run` all that time), whichever Python thread asks.
unsafe impl Send for SearchPtr {}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

fn stop_name(stop: Stop) -> &'static str {
    match stop {
        Stop::Target => "target reached",
        Stop::CpuBudget => "CPU-time budget spent",
        Stop::EvaluationBudget => "evaluation budget spent",
        Stop::Interrupted => "interrupted",
        Stop::Failed => "failed",
    }
}

/// Counter names are `&'static str` in results: each distinct name is leaked once.
fn counter_name(name: &str) -> &'static str {
    static NAMES: Mutex<Vec<&'static str>> = Mutex::new(Vec::new());
    let mut names = NAMES.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(n) = names.iter().find(|n| **n == name) {
        return n;
    }
    let leaked: &'static str = Box::leak(name.to_string().into_boxed_str());
    names.push(leaked);
    leaked
}

#[pymethods]
impl Problem {
    /// Number of free parameters.
    #[getter]
    fn dim(&self) -> usize {
        self.dim
    }

    /// Number of samples in the full data set (`m`).
    #[getter]
    fn sample_count(&self) -> usize {
        self.samples
    }

    /// Lower bounds of the box (a new array).
    #[getter]
    fn lower<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.lower)
    }

    /// Upper bounds of the box (a new array).
    #[getter]
    fn upper<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.upper)
    }

    /// A numpy Generator seeded from the trial's seed: use it for every random choice, so
    /// the trial is reproducible.
    #[getter]
    fn rng(&self, py: Python<'_>) -> Py<PyAny> {
        self.rng.clone_ref(py)
    }

    /// Whether the trial is over (target reached or budget spent): every method raises
    /// BudgetExhausted from then on.
    #[getter]
    fn stopped(&self) -> bool {
        lock(&self.stop).is_some()
    }

    /// The entry of the algorithm (`package.module:function`).
    #[getter]
    fn entry(&self) -> &str {
        &self.entry
    }

    /// Raises BudgetExhausted if the trial is over; costs nothing. Call it in long stretches
    /// without evaluations, so the CPU-time cutoff is noticed.
    fn check(&self) -> PyResult<()> {
        self.with(|_| Ok(()))
    }

    /// A uniform random point of the box (the paper's RandomPick), from the trial's
    /// generator. Costs no evaluation.
    fn random_pick<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let mut x = vec![0.0; self.dim];
        self.with(|s| {
            s.random_pick(&mut x);
            Ok(())
        })?;
        Ok(PyArray1::from_vec(py, x))
    }

    /// The full-data RMSE of `x` (inf when it cannot be evaluated), counted as `m`
    /// sample-evaluations. With `bound`: None when the RMSE is above it (and above the best so
    /// far), which may be found before summing every sample (counted the same).
    #[pyo3(signature = (x, bound=None))]
    fn rmse(&self, x: &Bound<'_, PyAny>, bound: Option<f64>) -> PyResult<Option<f64>> {
        let x = self.point("x", x, true)?;
        match bound {
            None => self.with(|s| s.evaluate(&x)).map(Some),
            Some(b) if b.is_nan() => Err(self.bad("bound is NaN".into())),
            Some(b) => self.with(|s| s.evaluate_below(&x, b)),
        }
    }

    /// Residuals `model_i(x) - y_i` over the full data set (shape (m,)), counted as `m`
    /// sample-evaluations (as a descent's residual evaluation); None when they cannot be
    /// computed.
    fn residuals<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
    ) -> PyResult<Option<Bound<'py, PyArray1<f64>>>> {
        let x = self.point("x", x, true)?;
        let mut r = vec![0.0; self.samples];
        let ok = self.with(|s| s.residuals(&x, &mut r))?;
        Ok(ok.then(|| PyArray1::from_vec(py, r)))
    }

    /// The Jacobian of the residuals at `x` (shape (m, dim), Fortran order), counted as `m`
    /// sample-evaluations; None when it cannot be computed.
    fn jacobian<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
    ) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        let x = self.point("x", x, true)?;
        let (m, p) = (self.samples, self.dim);
        let mut jac = vec![0.0; m * p];
        if !self.with(|s| s.jacobian(&x, &mut jac))? {
            return Ok(None);
        }
        let a = Array2::from_shape_vec((m, p).f(), jac)
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        Ok(Some(PyArray2::from_owned_array(py, a)))
    }

    /// A bounded least-squares descent (the built-in algorithms' N2FB) from `x`, over the full
    /// data or a fresh random subsample of `sample_size` samples. Returns the new point and
    /// N2FB's return code (10: iteration limit, 63: the start could not be evaluated).
    #[pyo3(signature = (x, *, sample_size=None, iterations=150, evaluations=200))]
    fn descend<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        sample_size: Option<usize>,
        iterations: usize,
        evaluations: usize,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, u8)> {
        let mut x = self.point("x", x, true)?;
        if sample_size == Some(0) || iterations == 0 || evaluations == 0 {
            return Err(self.bad(
                "descend: sample_size, iterations and evaluations must be at least 1".into(),
            ));
        }
        let rows = sample_size.map_or(Rows::Full, Rows::Subsample);
        let limits = DescentLimits {
            iterations,
            evaluations,
        };
        let descent = self.with(|s| s.descend(&mut x, rows, limits))?;
        Ok((PyArray1::from_vec(py, x), descent.code()))
    }

    /// Optimiser coordinates from natural ones (the exponents `n` as `ln(1 + n)`).
    fn encode<'py>(
        &self,
        py: Python<'py>,
        natural: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let v = self.point("natural", natural, false)?;
        let x = self.with(|s| Ok((0..v.len()).map(|i| s.optimiser_value(i, v[i])).collect()))?;
        Ok(PyArray1::from_vec(py, x))
    }

    /// Natural coordinates of `x` (the exponents `n` from `ln(1 + n)`); inverse of `encode`.
    fn decode<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let x = self.point("x", x, false)?;
        let v = self.with(|s| Ok((0..x.len()).map(|i| s.natural_value(i, x[i])).collect()))?;
        Ok(PyArray1::from_vec(py, v))
    }

    /// Adds one to the counter `name`, reported with the trial's counters. Also after the
    /// trial's budget is spent (counting costs nothing).
    fn count(&self, name: &str) -> PyResult<()> {
        let name = counter_name(name);
        let mut guard = lock(&self.search);
        let ptr = guard.as_mut().ok_or_else(|| self.over())?;
        // SAFETY: as in `Problem::with`.
        unsafe { ptr.0.as_mut() }.count(name);
        Ok(())
    }

    fn __repr__(&self) -> String {
        format!(
            "Problem({}: {} parameters, {} samples{})",
            self.entry,
            self.dim,
            self.samples,
            if self.stopped() { ", stopped" } else { "" }
        )
    }
}
