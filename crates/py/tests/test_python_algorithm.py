"""Search algorithms written in Python (``kind = "python"``): run beside AED, counted, resumed and
summarised like the built-in ones; every way such an algorithm can go wrong is an error that
names its configuration, and no finished trial is lost."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

import brdf_sls as bs
import pyalgos
from conftest import REPO

TESTS = os.path.dirname(os.path.abspath(__file__))

SPEC = """
name = "{name}"
seed = 11
trials = {trials}
threads = 2

[budget]
evaluations = {evaluations}

[[instance]]
name = "tuning"
targets = [0.105, 0.12]
[instance.synthetic]
params = "tuning"
samples = 200
sigma = 0.1
seed = 3

[[algorithm]]
kind = "aed"

{python}

[plots]
draw = []

[stats]
bootstrap = 50
"""


def python_entry(entry: str, label: str = "PY", **settings) -> str:
    lines = ["[[algorithm]]", f'label = "{label}"', 'kind = "python"', f'entry = "{entry}"']
    lines += [f"{k} = {json.dumps(v)}" for k, v in settings.items()]
    return "\n".join(lines)


def write_spec(tmp_path, python: str, name="mixed", trials=3, evaluations=60_000):
    spec = tmp_path / f"{name}.toml"
    spec.write_text(SPEC.format(name=name, trials=trials, evaluations=evaluations, python=python))
    return spec


def records(out):
    with open(out / "trials.jsonl") as f:
        lines = [json.loads(line) for line in f]
    return lines[0], [r for r in lines[1:] if "key" in r]


def test_python_beside_aed_records_resume_and_stats(tmp_path):
    spec = write_spec(tmp_path, python_entry("pyalgos:walk", step=0.1, descents=True))
    out = tmp_path / "out"
    first = bs.run(spec, out, plots=False)
    assert first["new_trials"] == 6 and first["resumed"] == 0 and first["missing"] == 0

    header, recs = records(out)
    configs = header["spec"]["configurations"]
    py = next(c for c in configs if c["label"] == "PY")
    assert py["algorithm"] == {"kind": "python", "entry": "pyalgos:walk", "descents": True, "step": 0.1}
    by_config = {c: [r for r in recs if r["config"] == c] for c in ("AED", "PY")}
    assert [len(v) for v in by_config.values()] == [3, 3]
    for r in by_config["PY"]:
        res = r["result"]
        counts = res["ended_at"]["evaluations"]
        # Every kind of evaluation was counted in sample-evaluations (200 samples).
        assert counts["rmse_rows"] > 0 and counts["rmse_rows"] % 200 == 0
        assert counts["residual_rows"] > 0 and counts["jacobian_rows"] > 0
        total = counts["residual_rows"] + counts["jacobian_rows"] + counts["rmse_rows"]
        assert total <= 60_000
        assert res["stop"] in ("target", "evaluation_budget")
        assert res["trace"], "the anytime trace is recorded"
        assert res["trace"][-1]["rmse"] == res["best_rmse"]
        assert len(res["best_x"]) == 6
        assert dict(res["counters"]).get("improvements", 0) > 0
        assert dict(res["counters"]).get("descents", 0) > 0
    # Trials are seeded: another run from scratch gives the same results (clocks aside).
    again = bs.run(spec, tmp_path / "again", plots=False)
    assert again["new_trials"] == 6
    _, recs2 = records(tmp_path / "again")

    def strip(r):
        res = r["result"]
        return (r["key"], r["seed"], res["best_x"], res["stop"], res["ended_at"]["evaluations"])

    assert sorted(map(strip, recs)) == sorted(map(strip, recs2))

    resumed = bs.run(spec, out, plots=False)
    assert resumed["new_trials"] == 0 and resumed["resumed"] == 6
    results = bs.read_results(out)
    assert results.present == 6
    assert {row["config"] for row in results.stats} == {"AED", "PY"}
    assert any(row["config"] == "PY" and row["trials"] == 3 for row in results.stats)
    table = (out / "table.txt").read_text()
    assert "PY" in table and "AED" in table
    assert "note: PY run in Python: their CPU seconds include the interpreter's overhead" in table
    assert "PY" in (out / "stats.csv").read_text()


def test_budget_ignoring_algorithm_is_recorded_as_cut(tmp_path):
    spec = write_spec(tmp_path, python_entry("pyalgos:ignores_budget"), trials=1, evaluations=20_000)
    out = tmp_path / "out"
    bs.run(spec, out, plots=False)
    _, recs = records(out)
    (py,) = [r for r in recs if r["config"] == "PY"]
    assert py["result"]["stop"] in ("evaluation_budget", "target")
    assert dict(py["result"]["counters"])["refused"] == 1


def test_cpu_cutoff_ends_a_python_trial(tmp_path):
    text = SPEC.format(name="cpu", trials=1, evaluations=10**12, python=python_entry("pyalgos:walk"))
    text = text.replace("[budget]\nevaluations = 1000000000000", "[budget]\ncpu_seconds = 0.3")
    text = text.replace("targets = [0.105, 0.12]", "targets = [0.0]")
    spec = tmp_path / "cpu.toml"
    spec.write_text(text)
    out = tmp_path / "out"
    bs.run(spec, out, plots=False)
    _, recs = records(out)
    (py,) = [r for r in recs if r["config"] == "PY"]
    ended = py["result"]["ended_at"]
    assert py["result"]["stop"] == "cpu_budget"
    # Cut at the first call after the cutoff: one walk step of a 200-sample RMSE is far below
    # 0.2 s even in a debug build.
    assert 0.3 <= ended["cpu_seconds"] < 0.5, ended


@pytest.mark.parametrize(
    "entry,message",
    [
        ("no_such_module:f", "cannot import `no_such_module`: ModuleNotFoundError"),
        ("pyalgos:missing", "module `pyalgos` has no `missing`"),
        ("pyalgos:not_callable", "`pyalgos:not_callable` is not callable"),
        ("pyalgos", "must be `package.module:function`"),
    ],
)
def test_an_entry_that_cannot_be_imported_is_a_spec_error(tmp_path, entry, message):
    spec = write_spec(tmp_path, python_entry(entry))
    with pytest.raises(bs.InputError) as e:
        bs.run(spec, tmp_path / "out", plots=False)
    assert "algorithm `PY`" in str(e.value) and message in str(e.value), str(e.value)
    assert not (tmp_path / "out" / "trials.jsonl").exists()


def test_an_unknown_kind_lists_python_among_the_kinds(tmp_path):
    spec = write_spec(tmp_path, '[[algorithm]]\nkind = "pyhton"\nentry = "pyalgos:walk"')
    with pytest.raises(bs.InputError, match=r"unknown `kind` `pyhton` \(expected one of aed, .*, python\)"):
        bs.run(spec, tmp_path / "out", plots=False)


@pytest.mark.parametrize(
    "function,message",
    [
        ("raises", "raised ValueError: a bug in the algorithm (at "),
        ("nan_point", "x[0] is NaN, not a finite number"),
        ("outside", "is outside the bounds"),
        ("wrong_shape", "x: expected shape (6,), found shape [7]"),
        ("wrong_type", "x: expected an array of 6 numbers, found 'not a point'"),
        ("returns_nan", "returned nan; it must return None"),
    ],
)
def test_a_failing_algorithm_fails_its_configuration_with_its_message(tmp_path, function, message):
    spec = write_spec(tmp_path, python_entry(f"pyalgos:{function}"), trials=2)
    with pytest.raises(bs.InputError) as e:
        bs.run(spec, tmp_path / "out", plots=False)
    text = str(e.value)
    assert f"configuration `PY` failed in trial" in text, text
    assert f"python `pyalgos:{function}`" in text and message in text, text
    # Both PY trials are missing: the failed one and the one skipped (or failed too) after it.
    assert "trials missing: 2; the other configurations ran and every finished trial is saved" in text
    # The failed configuration's trials are neither stored nor run on; AED's all ran.
    _, recs = records(tmp_path / "out")
    assert sorted(r["key"] for r in recs) == ["tuning/AED/0", "tuning/AED/1"]
    assert "AED" in (tmp_path / "out" / "table.txt").read_text()


def test_no_finished_trial_is_lost_and_a_fixed_algorithm_resumes(tmp_path, monkeypatch):
    python = python_entry("pyalgos:walk", label="WALK") + "\n\n" + python_entry("pyalgos:flaky", label="FLAKY")
    spec = write_spec(tmp_path, python, name="flaky", trials=4, evaluations=20_000)
    out = tmp_path / "out"
    # The first five trials of the plan (trial-major: AED, WALK, FLAKY, AED, WALK) finish first.
    bs.run(spec, out, plots=False, limit=5, threads=1)
    _, before = records(out)
    assert len(before) == 5
    monkeypatch.setenv(pyalgos.FAIL_ENV, "flaky")
    with pytest.raises(bs.InputError, match="configuration `FLAKY` failed.*flaky was told to fail"):
        bs.run(spec, out, plots=False)
    _, after = records(out)
    keys_after = {r["key"] for r in after}
    assert {r["key"] for r in before} <= keys_after
    # Every trial of AED and WALK ran; FLAKY's failed at once and the rest were skipped.
    assert len(after) == 4 + 4 + 1
    # The one FLAKY trial that finished before is still there; none was added.
    assert [r["key"] for r in after if r["config"] == "FLAKY"] == [r["key"] for r in before if r["config"] == "FLAKY"]
    monkeypatch.delenv(pyalgos.FAIL_ENV)
    fixed = bs.run(spec, out, plots=False)
    assert fixed["resumed"] == len(after) and fixed["new_trials"] == 12 - len(after)
    _, final = records(out)
    assert len({r["key"] for r in final}) == 12


def test_a_problem_kept_after_its_trial_raises(tmp_path):
    pyalgos.KEPT.clear()
    spec = write_spec(tmp_path, python_entry("pyalgos:keeps_problem"), trials=1, evaluations=5_000)
    # On threads of this interpreter, so the problem kept is in this process.
    bs.run(spec, tmp_path / "out", plots=False, processes=False)
    (problem,) = pyalgos.KEPT
    assert problem.stopped and problem.dim == 6
    with pytest.raises(RuntimeError, match="is over"):
        problem.rmse(problem.lower)


def test_python_m_brdf_sls_run(tmp_path):
    spec = write_spec(tmp_path, python_entry("pyalgos:walk"), trials=1, evaluations=5_000)
    env = {**os.environ, "PYTHONPATH": TESTS}
    p = subprocess.run(
        [sys.executable, "-m", "brdf_sls", "run", str(spec), "--out", str(tmp_path / "out"), "--no-plots"],
        capture_output=True, text=True, env=env, cwd=tmp_path,
    )
    assert p.returncode == 0, p.stderr
    assert "2 new trials" in p.stderr and "PY" in p.stdout
    # What `brdf-sls run` prints: the plan, the machine, the instances and progress with an
    # ETA (plain lines: standard error is not a terminal), then the table and the files.
    for line in ("experiment `mixed`", "master seed 11", "machine: ", "instance tuning: 200 samples",
                 "2/2 trials (", "new trials in "):
        assert line in p.stderr, (line, p.stderr)
    assert "wrote 6 files to" in p.stdout, p.stdout
    bad = write_spec(tmp_path, python_entry("pyalgos:raises"), name="bad", trials=1, evaluations=5_000)
    p = subprocess.run(
        [sys.executable, "-m", "brdf_sls", "run", str(bad), "--out", str(tmp_path / "bad"), "--no-plots"],
        capture_output=True, text=True, env=env, cwd=tmp_path,
    )
    assert p.returncode == 2 and "configuration `PY` failed" in p.stderr, p.stderr


def test_fit_runs_a_python_algorithm():
    data = bs.DataSet.synthetic("tuning", 200, sigma=0.1, seed=3)
    a = bs.fit(data, "python", entry="pyalgos:walk", step=0.1, cpu_seconds=0.3, target=0.12, seed=4)
    assert a["algorithm"] == {"kind": "python", "entry": "pyalgos:walk", "step": 0.1}
    assert a["evaluations"] > 0 and a["stop"] in ("target", "cpu_budget")
    with pytest.raises(bs.InputError, match=r"python `pyalgos:raises` raised ValueError: a bug"):
        bs.fit(data, "python", entry="pyalgos:raises", cpu_seconds=0.3)
    with pytest.raises(bs.InputError, match=r"`entry` module `pyalgos` has no `nope`"):
        bs.fit(data, "python", entry="pyalgos:nope", cpu_seconds=0.3)


def test_settings_can_be_swept(tmp_path):
    python = python_entry("pyalgos:walk") + "\n[algorithm.sweep]\nstep = [0.05, 0.2]"
    spec = write_spec(tmp_path, python, name="sweep", trials=1, evaluations=5_000)
    out = tmp_path / "out"
    bs.run(spec, out, plots=False)
    header, recs = records(out)
    settings = {c["label"]: c["algorithm"] for c in header["spec"]["configurations"]}
    assert settings["PY step=0.05"] == {"kind": "python", "entry": "pyalgos:walk", "step": 0.05}
    assert settings["PY step=0.2"]["step"] == 0.2
    assert sorted(r["config"] for r in recs) == ["AED", "PY step=0.05", "PY step=0.2"]


@pytest.mark.parametrize(
    "function,line",
    [("nan_point", "x[0] = float(\"nan\")"), ("outside", "problem.rmse(problem.upper + 1.0)"), ("wrong_shape", "problem.residuals(")],
)
def test_a_bad_point_names_the_python_file_and_line(tmp_path, function, line):
    source = open(pyalgos.__file__).read().splitlines()
    start = source.index(f"def {function}(problem):")
    # The line of the call that passed the point (for nan_point: the rmse call after it).
    at = next(i for i in range(start, len(source)) if "problem." in source[i] and ("rmse" in source[i] or "residuals" in source[i]))
    spec = write_spec(tmp_path, python_entry(f"pyalgos:{function}"), trials=1)
    with pytest.raises(bs.InputError) as e:
        bs.run(spec, tmp_path / "out", plots=False)
    assert f"pyalgos.py:{at + 1} in {function})" in str(e.value), str(e.value)


def test_exceptions_are_named_as_the_package_exports_them():
    import traceback

    for cls in (bs.InputError, bs.RunError, bs.BudgetExhausted):
        assert cls.__module__ == "brdf_sls", cls.__module__
    try:
        bs.DataSet.read("no-such-file.brdf")
    except bs.InputError as e:
        last = traceback.format_exception_only(type(e), e)[-1]
        assert last.startswith("brdf_sls.InputError: "), last


def strip_clocks(rec):
    """A trial record without its clock readings (CPU and wall seconds)."""
    res = json.loads(json.dumps(rec["result"]))
    for stamp in [res["ended_at"], res.get("reached_at")] + [p["at"] for p in res["trace"]]:
        if stamp:
            stamp.pop("cpu_seconds")
            stamp.pop("wall_seconds")
    return {**rec, "result": res}


def test_worker_processes_give_the_threads_results(tmp_path):
    python = python_entry("pyalgos:walk", step=0.1, descents=True) + "\n\n" + python_entry("pyalgos:busy", label="BUSY", work=200)
    spec = write_spec(tmp_path, python, name="same", trials=3, evaluations=20_000)
    bs.run(spec, tmp_path / "procs", plots=False, threads=2)
    bs.run(spec, tmp_path / "threads", plots=False, threads=2, processes=False)
    _, a = records(tmp_path / "procs")
    _, b = records(tmp_path / "threads")
    assert len(a) == len(b) == 9
    by_key = lambda recs: {r["key"]: strip_clocks(r) for r in recs}  # noqa: E731
    assert by_key(a) == by_key(b)
    # Each trial's CPU time is its own: a worker's clock, not the parent's.
    assert all(r["result"]["ended_at"]["cpu_seconds"] > 0 for r in a)


def test_the_command_line_names_an_entry_its_workers_cannot_import(cli, tmp_path):
    """`brdf-sls run` checks the entry in its first worker, before any trial runs: bad input."""
    spec = write_spec(tmp_path, python_entry("no_such_module:f"))
    env = {**os.environ, "BRDF_SLS_PYTHON": sys.executable, "PYTHONPATH": TESTS}
    p = subprocess.run([str(cli.binary), "run", str(spec), "--out", str(tmp_path / "out")],
                       capture_output=True, text=True, env=env, cwd=tmp_path)
    assert p.returncode == 2, p.stderr
    assert "algorithm `PY`" in p.stderr and "cannot import `no_such_module`: ModuleNotFoundError" in p.stderr, p.stderr
    assert not (tmp_path / "out" / "trials.jsonl").exists()
