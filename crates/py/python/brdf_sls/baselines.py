"""The off-the-shelf optimisers a researcher would try instead of the paper's searches, as
``kind = "python"`` algorithms (``entry = "brdf_sls.baselines:NAME"``):

- ``least_squares``: scipy's ``least_squares`` (trust-region reflective, the box as bounds, the
  analytic Jacobian), restarted from the instance's start distribution until the trial ends;
  each local solve ends with a full-data RMSE of its result (as RPLS ends each descent).
- ``dual_annealing``: scipy's generalised simulated annealing with its default L-BFGS-B local
  search (finite-difference gradients of the RMSE), the natural comparator to ASA; restarted
  with a fresh seed when it stops.
- ``cma_es``: CMA-ES from the ``cma`` package in box-normalised coordinates with its bound
  handling, the mean started from the instance's start distribution, restarted with a doubled
  population (IPOP) when it stops.

They need ``scipy`` and, for ``cma_es``, ``cma`` (``pip install "brdf-sls[baselines]"``). Every
evaluation goes through the problem, so it is counted in the paper's units, budgeted and traced
like a built-in algorithm's; the CPU time includes the interpreter's and scipy's overhead, so
compare sample-evaluations beside it. Unevaluable points (overflow) are given a large finite
cost, because scipy's solvers stop on non-finite values.
"""

from __future__ import annotations

import warnings

import numpy as np

# The cost of an unevaluable point: finite (scipy stops on inf), and its square times the data
# size still finite.
UNEVALUABLE = 1e100


def _quiet(run):
    """`run` with numpy's and scipy's overflow warnings silenced: the solvers meet overflowing
    points by design (they get the cost UNEVALUABLE), and a warning per point would bury the
    run's output."""

    def quiet(problem, **settings):
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore", RuntimeWarning)
            return run(problem, **settings)

    quiet.__doc__ = run.__doc__
    quiet.__name__ = run.__name__
    return quiet


def _inside(problem, x):
    """`x` clipped to the box: the solvers' finite differences and rounding may step a few ulps
    outside it, which the problem refuses."""
    return np.clip(x, problem.lower, problem.upper)


@_quiet
def least_squares(problem, max_nfev=200, ftol=1e-8, xtol=1e-8, gtol=1e-8, x_scale="jac"):
    """Multistart bounded least squares (scipy, method ``trf``, analytic Jacobian)."""
    from scipy.optimize import least_squares as solve

    m, p = problem.sample_count, problem.dim
    failed_r = np.full(m, UNEVALUABLE)

    # The problem returns None where the model cannot be evaluated, but finite residuals can
    # still have a Jacobian that overflows (d^n ln d for large n); scipy refuses both.
    def residuals(x):
        r = problem.residuals(_inside(problem, x))
        return r if r is not None and np.isfinite(r).all() else failed_r

    def jacobian(x):
        j = problem.jacobian(_inside(problem, x))
        return j if j is not None and np.isfinite(j).all() else np.zeros((m, p))

    bounds = (problem.lower, problem.upper)
    while True:
        x0 = problem.random_pick()
        try:
            fit = solve(
                residuals,
                x0,
                jac=jacobian,
                bounds=bounds,
                method="trf",
                max_nfev=max_nfev,
                ftol=ftol,
                xtol=xtol,
                gtol=gtol,
                x_scale=x_scale,
            )
        except (ValueError, np.linalg.LinAlgError):
            # A finite but huge Jacobian near overflow makes trf's products infinite and its
            # SVD refuse them: that start failed, as a descent from an unevaluable start does.
            problem.count("failed_solves")
            continue
        problem.rmse(_inside(problem, fit.x))
        problem.count("restarts")


@_quiet
def dual_annealing(problem, maxiter=1000, initial_temp=5230.0, no_local_search=False):
    """scipy's dual annealing on the full-data RMSE, restarted with a fresh seed."""
    from scipy.optimize import dual_annealing as anneal

    def cost(x):
        v = problem.rmse(_inside(problem, x))
        return v if np.isfinite(v) else UNEVALUABLE

    bounds = list(zip(problem.lower, problem.upper))
    while True:
        anneal(
            cost,
            bounds,
            maxiter=maxiter,
            initial_temp=initial_temp,
            no_local_search=no_local_search,
            seed=int(problem.rng.integers(2**32)),
            x0=problem.random_pick(),
        )
        problem.count("restarts")


@_quiet
def cma_es(problem, sigma0=0.3, popsize=0, ipop=True):
    """CMA-ES (``cma``) in coordinates scaled to [0, 1], with IPOP restarts; ``popsize`` 0 is
    the package's default, 4 + 3 ln(dim)."""
    with warnings.catch_warnings():
        # cma warns when matplotlib is missing; its plots are not used here.
        warnings.simplefilter("ignore")
        import cma

    lo, width = problem.lower, problem.upper - problem.lower

    def cost(u):
        v = problem.rmse(_inside(problem, lo + np.asarray(u) * width))
        return v if np.isfinite(v) else UNEVALUABLE

    size = popsize or int(4 + 3 * np.log(problem.dim))
    while True:
        start = (problem.random_pick() - lo) / np.where(width > 0, width, 1.0)
        # cma draws from numpy's global generator unless given `randn`; Python trials
        # interleave on threads, so the trial's own generator keeps each path its own.
        options = {
            "bounds": [0.0, 1.0],
            "popsize": size,
            "randn": lambda *shape: problem.rng.standard_normal(shape),
            "verbose": -9,
        }
        es = cma.CMAEvolutionStrategy(start, sigma0, options)
        while not es.stop():
            candidates = es.ask()
            es.tell(candidates, [cost(u) for u in candidates])
        problem.count("restarts")
        if ipop:
            size *= 2
