"""The baselines of results/baselines (``brdf_sls.baselines``: scipy's least_squares and
dual_annealing, CMA-ES from ``cma``) run as ``kind = "python"`` algorithms: each is counted,
budgeted and seeded like a built-in, and the least-squares multistart reaches an easy target."""

from __future__ import annotations

import json

import pytest

import brdf_sls as bs

pytest.importorskip("scipy")
pytest.importorskip("cma")

SPEC = """
name = "baselines-small"
seed = 5
trials = 2
threads = 2

[budget]
evaluations = 400000

[[instance]]
name = "tuning"
targets = [{ relative = 0.05 }]
[instance.synthetic]
params = "tuning"
samples = 300
sigma = 0.1
seed = 3

[[algorithm]]
label = "LSQ-TRF"
kind = "python"
entry = "brdf_sls.baselines:least_squares"

[[algorithm]]
label = "DUAL-ANNEALING"
kind = "python"
entry = "brdf_sls.baselines:dual_annealing"

[[algorithm]]
label = "CMA-ES"
kind = "python"
entry = "brdf_sls.baselines:cma_es"
popsize = 8

[plots]
draw = []

[stats]
bootstrap = 50
"""


def trials(out):
    with open(out / "trials.jsonl") as f:
        lines = [json.loads(line) for line in f]
    return [r for r in lines[1:] if "key" in r]


def test_each_baseline_runs_counted_budgeted_and_seeded(tmp_path):
    spec = tmp_path / "baselines.toml"
    spec.write_text(SPEC)
    ran = bs.run(spec, tmp_path / "a", plots=False)
    assert ran["new_trials"] == 6
    recs = trials(tmp_path / "a")
    by_config = {}
    for r in recs:
        by_config.setdefault(r["config"], []).append(r["result"])
    assert sorted(by_config) == ["CMA-ES", "DUAL-ANNEALING", "LSQ-TRF"]
    for config, results in by_config.items():
        for res in results:
            counts = res["ended_at"]["evaluations"]
            total = counts["residual_rows"] + counts["jacobian_rows"] + counts["rmse_rows"]
            assert 0 < total <= 400_000, config
            assert res["stop"] in ("target", "evaluation_budget"), (config, res["stop"])
            assert res["trace"] and res["trace"][-1]["rmse"] == res["best_rmse"], config
    # The least-squares multistart uses residuals and the Jacobian, the others only RMSEs.
    lsq = by_config["LSQ-TRF"][0]["ended_at"]["evaluations"]
    assert lsq["residual_rows"] > 0 and lsq["jacobian_rows"] > 0
    for config in ("DUAL-ANNEALING", "CMA-ES"):
        counts = by_config[config][0]["ended_at"]["evaluations"]
        assert counts["residual_rows"] == 0 and counts["rmse_rows"] > 0, config
    # 300 samples, 5% above the best-known RMSE: a bounded least-squares multistart gets there.
    assert all(res["stop"] == "target" for res in by_config["LSQ-TRF"])
    # Seeded from the trial: a second run from scratch takes the same paths.
    bs.run(spec, tmp_path / "b", plots=False)

    def path(r):
        res = r["result"]
        return (r["key"], res["best_x"], res["stop"], res["ended_at"]["evaluations"])

    assert sorted(map(path, recs)) == sorted(map(path, trials(tmp_path / "b")))
