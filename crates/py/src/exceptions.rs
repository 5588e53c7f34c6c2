//! The package's exception classes (`brdf_sls.InputError`, `brdf_sls.RunError`,
//! `brdf_sls.BudgetExhausted`), named as the package exports them.

use pyo3::create_exception;
use pyo3::exceptions::{PyBaseException, PyRuntimeError, PyValueError};

create_exception!(
    brdf_sls,
    InputError,
    PyValueError,
    "Bad input (a data file, a spec, a parameter, an algorithm setting): the command line \
     exits with status 2 on it. The message is the command line's."
);
create_exception!(
    brdf_sls,
    RunError,
    PyRuntimeError,
    "A failure while running (a results folder in use, a full disk, a fit that evaluated \
     nothing): the command line exits with status 1 on it. The message is the command line's."
);

create_exception!(
    brdf_sls,
    BudgetExhausted,
    PyBaseException,
    "The trial is over: its target is reached or its budget (evaluations, CPU seconds) spent. \
     Raised by every method of a Problem from then on, and in the algorithm's thread by a \
     watchdog once it runs past a CPU budget without calling them. A BaseException, so that \
     `except Exception` in an algorithm does not swallow it; let it propagate (or return)."
);
