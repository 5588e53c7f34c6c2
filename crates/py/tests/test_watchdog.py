"""The CPU-cutoff watchdog: a Python algorithm that loops without calling its problem is cut at
its CPU budget (BudgetExhausted raised in its thread) and recorded as such; it never hangs the
run, and algorithms that call their problem are unaffected (the other tests)."""

from __future__ import annotations

import time

import pytest

import brdf_sls as bs
from test_python_algorithm import SPEC, python_entry, records

CUTOFF = 0.3


def run_cpu_spec(tmp_path, entry: str, trials: int = 1):
    """Runs `entry` beside AED with `cpu_seconds = CUTOFF` and an unreachable target; returns
    the Python configuration's records and the run's wall seconds."""
    text = SPEC.format(name="cpu", trials=trials, evaluations=1, python=python_entry(entry))
    text = text.replace("[budget]\nevaluations = 1", f"[budget]\ncpu_seconds = {CUTOFF}")
    text = text.replace("targets = [0.105, 0.12]", "targets = [0.0]")
    spec = tmp_path / "cpu.toml"
    spec.write_text(text)
    started = time.monotonic()
    bs.run(spec, tmp_path / "out", plots=False)
    wall = time.monotonic() - started
    _, recs = records(tmp_path / "out")
    return [r for r in recs if r["config"] == "PY"], wall


def assert_cut(rec):
    result = rec["result"]
    assert result["stop"] == "cpu_budget", result
    # The watchdog raises 10% (at least 50 ms) past the cutoff, polling every 10 ms.
    assert CUTOFF <= result["ended_at"]["cpu_seconds"] < CUTOFF + 0.5, result["ended_at"]
    assert result["ended_at"]["evaluations"]["rmse_rows"] > 0


@pytest.mark.parametrize("function", ["runaway", "runaway_numpy"])
def test_a_loop_that_never_calls_the_problem_is_cut_at_the_cutoff(tmp_path, function):
    (py,), wall = run_cpu_spec(tmp_path, f"pyalgos:{function}")
    assert_cut(py)
    print(f"{function}: ended at {py['result']['ended_at']['cpu_seconds']:.3f} CPU s, run {wall:.2f} s")


def test_two_runaway_trials_on_two_threads_both_end(tmp_path):
    recs, wall = run_cpu_spec(tmp_path, "pyalgos:runaway", trials=2)
    assert len(recs) == 2
    for r in recs:
        assert_cut(r)
    print("two runaways:", [round(r["result"]["ended_at"]["cpu_seconds"], 3) for r in recs], f"run {wall:.2f} s")


def test_the_watchdog_raises_again_in_an_algorithm_that_swallows_it(tmp_path):
    (py,), _ = run_cpu_spec(tmp_path, "pyalgos:swallows_twice")
    assert_cut(py)
    assert dict(py["result"]["counters"])["caught"] == 3


def test_fit_cuts_a_runaway_algorithm():
    data = bs.DataSet.synthetic("tuning", 200, sigma=0.1, seed=3)
    a = bs.fit(data, "python", entry="pyalgos:runaway", cpu_seconds=CUTOFF, target=0.0, seed=4)
    assert a["stop"] == "cpu_budget", a
    # Nothing raised late reaches the caller: Python runs on normally after the fit.
    assert sum(range(10**6)) == 499999500000
