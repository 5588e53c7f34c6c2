"""brdf-sls from Python: BRDF model families (Lafortune, GGX, ...), seeded SLS fits, experiments and results.

Everything runs in the Rust crates of the brdf-sls workspace (the extension module
``brdf_sls._native``); this package adds pandas-friendly records of results folders.

- :class:`DataSet`: samples from Cornell/CSV/MERL files (``DataSet.read``), numpy arrays
  (``DataSet.from_arrays``) or synthetic (``DataSet.synthetic``).
- :class:`Model`: a model family with a layout: evaluate parameters at directions, residuals,
  RMSE and the Jacobian; :func:`families` lists the families.
- :func:`fit`: one seeded fit with any algorithm and its settings as keyword arguments.
- :func:`run`: run or resume an experiment spec (as ``brdf-sls run``).
- :func:`read_results`: a results folder as records (trials, traces, statistics).
- :func:`rmse`: the RMSE of given parameters (as ``brdf-sls eval``).
- :class:`Problem` and :class:`BudgetExhausted`: what a search algorithm written in Python
  receives (``kind = "python"`` in an experiment file; see docs/own-algorithm.md).

Errors are :class:`InputError` (a ``ValueError``: bad input) or :class:`RunError` (a
``RuntimeError``: a failure while running), with the command line's messages. Long calls
release the GIL and stop on Ctrl-C with ``KeyboardInterrupt``.
"""

from ._native import (
    BudgetExhausted,
    DataSet,
    InputError,
    Model,
    Problem,
    RunError,
    __version__,
    families,
    fit,
    named_params,
    rmse,
    run,
)
from .results import Results, read_results

__all__ = [
    "BudgetExhausted",
    "DataSet",
    "InputError",
    "Model",
    "Problem",
    "Results",
    "RunError",
    "__version__",
    "families",
    "fit",
    "named_params",
    "read_results",
    "rmse",
    "run",
]
