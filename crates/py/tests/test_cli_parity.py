"""The package gives the command line's results on the same inputs: fits with the same seed,
RMSEs, synthetic data, and whole experiments (trials and statistics)."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import brdf_sls as bs

KRYLON_FIT = dict(lobes=1, kind="isotropic", target=0.037, cpu_seconds=30.0)


def parse_fit(stdout: str) -> dict:
    """RMSE, stop, sample-evaluations and parameters from `brdf-sls fit`'s output."""
    m = re.search(r"^RMSE (\S+) after \S+ CPU s \(\S+ wall s, (\d+) sample-evaluations\)", stdout, re.M)
    stop = re.search(r"stop: (\w+)", stdout).group(1)
    params = json.loads(re.search(r"^json: (.*)$", stdout, re.M).group(1))
    return {"rmse": m.group(1), "evaluations": int(m.group(2)), "stop": stop, "params": params}


@pytest.mark.parametrize(
    "algorithm,settings,seed,descent",
    [
        ("aed", {}, 3, "default"),
        ("aed", {"phi": 1.2, "rho0": 50}, 5, "default"),
        ("rpls", {}, 2, "default"),
        ("rpls", {}, 2, "n2fb"),
    ],
)
def test_fit_matches_brdf_sls_fit_with_the_same_seed(cli, krylon, algorithm, settings, seed, descent):
    sets = [a for k, v in settings.items() for a in ("--set", f"{k}={v}")]
    out = cli(
        "fit", krylon, "--max-value", 1, "--lobes", 1, "--kind", "isotropic",
        "--algorithm", algorithm, *sets, "--target", 0.037, "--cpu-seconds", 30, "--seed", seed,
        "--descent", descent,
    ).stdout
    assert f"descent {descent}," in out
    want = parse_fit(out)
    data = bs.DataSet.read(krylon, max_value=1.0)
    got = bs.fit(data, algorithm, seed=seed, descent=descent, **KRYLON_FIT, **settings)
    assert got["descent"] == descent
    # Both must have stopped on the target, so the CPU clock cannot have changed the outcome.
    assert want["stop"] == "Target" and got["stop"] == "target"
    assert got["params"] == want["params"]
    assert f"{got['rmse']:.17f}" == want["rmse"]  # Rust's {:.17}: 17 decimals
    assert got["evaluations"] == want["evaluations"]
    assert got["rmse"] <= 0.037
    tr = got["trace"]
    assert len(tr["rmse"]) >= 1 and tr["rmse"][-1] == got["best_rmse"]
    assert np.all(np.diff(tr["rmse"]) < 0) and np.all(np.diff(tr["evaluations"]) >= 0)
    for k, v in settings.items():
        assert got["algorithm"][k] == v


def test_another_seed_gives_another_fit(krylon):
    data = bs.DataSet.read(krylon, max_value=1.0)
    a = bs.fit(data, "aed", seed=1, **KRYLON_FIT)
    b = bs.fit(data, "aed", seed=2, **KRYLON_FIT)
    assert a["evaluations"] != b["evaluations"]


def test_rmse_matches_brdf_sls_eval(cli, krylon):
    for params in ("paper-bluepaint", "tuning"):
        out = cli("eval", krylon, "--max-value", 1, "--params", params, "--digits", 17).stdout
        want = float(re.search(r"RMSE (\S+)", out).group(1))
        got = bs.rmse(params, bs.DataSet.read(krylon, max_value=1.0))
        assert got == want


def test_synthetic_data_equal_brdf_sls_gen(cli, tmp_path):
    path = tmp_path / "gen.csv"
    cli("gen", "--params", "cross", "--samples", 700, "--sigma", 0.05, "--seed", 9, "--out", path)
    from_cli = bs.DataSet.read(path)
    here = bs.DataSet.synthetic("cross", samples=700, sigma=0.05, seed=9)
    assert len(here) == len(from_cli) == 700
    assert np.array_equal(here.values, from_cli.values)
    # The CSV reader normalises directions: equal to the last bit or two.
    for col in ("ux", "uy", "uz", "vx", "vy", "vz"):
        np.testing.assert_allclose(here.column(col), from_cli.column(col), rtol=0, atol=1e-15)


SPEC = """
name = "py-parity"
seed = 11
trials = 6
[budget]
cpu_seconds = 60.0
evaluations = 4e6
[[instance]]
name = "tuning-small"
targets = [0.105, 0.11]
[instance.synthetic]
params = "tuning"
samples = 1500
sigma = 0.1
seed = 3
[[algorithm]]
kind = "aed"
[[algorithm]]
kind = "rpls"
[[algorithm]]
kind = "ds"
[plots]
draw = ["rtd"]
formats = ["png"]
"""


def _deterministic(rows):
    """Trial rows without the clocks (what the same seed must reproduce bit for bit)."""
    drop = {"cpu_seconds", "wall_seconds", "reached_cpu_seconds"}
    return sorted(({k: v for k, v in r.items() if k not in drop} for r in rows), key=lambda r: r["key"])


def test_run_equals_brdf_sls_run_trial_for_trial(cli, tmp_path):
    spec = tmp_path / "parity.toml"
    spec.write_text(SPEC)
    cli("run", spec, "--out", tmp_path / "cli", "--threads", 2, "--progress", "quiet", "--no-plots")
    ran = bs.run(spec, tmp_path / "py", threads=1)
    assert ran["new_trials"] == 18 and ran["missing"] == 0
    assert (tmp_path / "py" / "stats.csv").is_file()
    assert list((tmp_path / "py" / "plots").glob("*-rtd-*.png"))
    a = bs.read_results(tmp_path / "cli")
    b = bs.read_results(tmp_path / "py")
    assert a.planned == b.planned == a.present == b.present == 18
    assert _deterministic(a.trials) == _deterministic(b.trials)
    xa = {r["key"]: r["result"]["best_x"] for r in a.raw}
    xb = {r["key"]: r["result"]["best_x"] for r in b.raw}
    assert xa == xb
    ta = [(t["key"], t["evaluations"], t["rmse"]) for t in a.traces]
    tb = [(t["key"], t["evaluations"], t["rmse"]) for t in b.traces]
    assert sorted(ta) == sorted(tb)
    # Statistics in sample-evaluations depend on the trials only: equal to the CLI's.
    ea = [r for r in a.stats if r["measure"] == "evaluations"]
    eb = [r for r in b.stats if r["measure"] == "evaluations"]
    assert ea == eb and len(ea) == 3 * 2
    # And the statistics read here are the ones `brdf-sls run` wrote to stats.json.
    written = json.loads((tmp_path / "cli" / "stats.json").read_text())
    evals = {(c["config"], c["target"]): c["evaluations"] for c in written["configs"]}
    for r in ea:
        w = evals[(r["config"], r["target"])]
        assert (r["successes"], r["trials"], r["ert"]) == (w["successes"], w["trials"], w["ert"])
    # A second run resumes: nothing new.
    again = bs.run(spec, tmp_path / "py", threads=1)
    assert again["new_trials"] == 0 and again["resumed"] == 18


def test_frames_are_pandas_dataframes(cli, tmp_path):
    pd = pytest.importorskip("pandas")
    spec = tmp_path / "parity.toml"
    spec.write_text(SPEC.replace("trials = 6", "trials = 2"))
    bs.run(spec, tmp_path / "out", threads=2, plots=False)
    frames = bs.read_results(tmp_path / "out").frames()
    assert isinstance(frames["trials"], pd.DataFrame)
    assert len(frames["trials"]) == 6
    assert set(frames["trials"]["config"]) == {"AED", "RPLS", "DS"}
    assert frames["traces"].groupby("key")["rmse"].is_monotonic_decreasing.all()
    assert len(frames["stats"]) == 3 * 2 * 2


@pytest.mark.parametrize("algorithm", ["aed", "aers", "rpls", "ds", "sa", "sals", "avg", "asa"])
def test_every_algorithm_fits_from_python(algorithm):
    data = bs.DataSet.synthetic("tuning", samples=500, sigma=0.05, seed=1)
    r = bs.fit(data, algorithm, cpu_seconds=0.3, seed=4)
    assert r["algorithm"]["kind"] == algorithm
    assert r["stop"] in {"cpu_budget", "finished"}
    # The fit polishes the search's best: never above it.
    assert np.isfinite(r["rmse"]) and r["rmse"] <= r["best_rmse"] * (1 + 1e-12)
    assert r["polish"]["rmse_before"] == pytest.approx(r["best_rmse"], rel=1e-12)
    assert r["evaluations"] > 0 and r["cpu_seconds"] > 0
    assert bs.Model().rmse(r["x"], data) == r["rmse"]
