"""Small search algorithms written in Python, for the tests of ``kind = "python"``: a working one
and one for each way an algorithm can go wrong."""

from __future__ import annotations

import math
import os

import numpy as np

from brdf_sls import BudgetExhausted

# Set by the tests: the name of an algorithm that should fail until it is unset.
FAIL_ENV = "BRDF_SLS_TEST_FAIL"


def walk(problem, step=0.2, descents=False):
    """Random restarts of a random walk that keeps improvements; with `descents`, a descent
    from each restart. Uses every method of the problem once in a while."""
    lo, hi = problem.lower, problem.upper
    assert problem.decode(problem.encode(problem.decode(lo))).shape == (problem.dim,)
    while True:
        x = problem.random_pick()
        if descents:
            x, _code = problem.descend(x, sample_size=max(1, problem.sample_count // 4), iterations=5)
        fx = problem.rmse(x)
        for _ in range(20):
            y = np.clip(x + step * (hi - lo) * problem.rng.standard_normal(problem.dim), lo, hi)
            fy = problem.rmse(y, bound=fx)
            if fy is not None and fy < fx:
                x, fx = y, fy
                problem.count("improvements")
        r = problem.residuals(x)
        if r is not None:
            assert r.shape == (problem.sample_count,)
            assert math.isclose(math.sqrt(float(np.mean(r * r))), fx, rel_tol=1e-9)
        j = problem.jacobian(x)
        if j is not None:
            assert j.shape == (problem.sample_count, problem.dim)


def flaky(problem):
    """`walk`, but raises at once while the environment says so."""
    if os.environ.get(FAIL_ENV) == "flaky":
        raise ValueError("flaky was told to fail")
    walk(problem)


def raises(problem):
    problem.rmse(problem.random_pick())
    raise ValueError("a bug in the algorithm")


def nan_point(problem):
    x = problem.random_pick()
    x[0] = float("nan")
    problem.rmse(x)


def outside(problem):
    try:
        problem.rmse(problem.upper + 1.0)
    except ValueError:
        pass  # caught, but the trial fails all the same
    walk(problem)


def wrong_shape(problem):
    problem.residuals(np.zeros(problem.dim + 1))


def wrong_type(problem):
    problem.jacobian("not a point")


def returns_nan(problem):
    problem.rmse(problem.random_pick())
    return float("nan")


def ignores_budget(problem):
    """Catches BudgetExhausted and keeps calling: every call raises again; it gives up after a
    thousand (an algorithm that never gives up would never end, see docs/own-algorithm.md)."""
    refused = 0
    while refused < 1000:
        try:
            problem.rmse(problem.random_pick())
        except BudgetExhausted:
            refused += 1
            assert problem.stopped
    problem.count("refused")


KEPT = []


def keeps_problem(problem):
    KEPT.append(problem)
    walk(problem)


not_callable = 42


def runaway(problem):
    """One evaluation, then pure Python forever without calling the problem: only the watchdog
    (the CPU cutoff raised in its thread) ends it."""
    problem.rmse(problem.random_pick())
    while True:
        x = sum(range(1000))  # noqa: F841


def runaway_numpy(problem):
    """`runaway` busy in numpy: many small operations, each returning to Python."""
    problem.rmse(problem.random_pick())
    a = problem.rng.random(1000)
    while True:
        a = np.sqrt(a * a + 1.0) - 0.5


def swallows_twice(problem):
    """Catches the watchdog's BudgetExhausted twice and loops on; the third ends it."""
    problem.rmse(problem.random_pick())
    caught = 0
    while True:
        try:
            while True:
                x = sum(range(1000))  # noqa: F841
        except BudgetExhausted:
            caught += 1
            if caught == 3:
                problem.count("caught")
                raise
            problem.count("caught")


# Set by the tests: a file a spinning algorithm writes its process ID to.
PID_ENV = "BRDF_SLS_TEST_PID_FILE"


def spins(problem):
    """One evaluation, then pure Python forever without calling the problem, saying where it
    runs (its process ID in the file named by PID_ENV): under an evaluation budget alone only
    an interrupt (Ctrl-C) ends it."""
    problem.rmse(problem.random_pick())
    path = os.environ.get(PID_ENV)
    if path:
        with open(path, "w") as f:
            f.write(str(os.getpid()))
    while True:
        x = sum(range(1000))  # noqa: F841


def busy(problem, work=3000):
    """A CPU-bound algorithm in pure Python: a random pick, `work` steps of Python arithmetic,
    one RMSE, again, until the budget ends it."""
    while True:
        x = problem.random_pick()
        s = 0.0
        for i in range(work):
            s += (i % 7) * 0.5
        problem.rmse(x)
