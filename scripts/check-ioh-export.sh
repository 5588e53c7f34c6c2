#!/usr/bin/env bash
# Checks `brdf-sls export --format ioh` with IOHprofiler's own Python reader (the `iohinspector`
# package from PyPI, which reads the same JSON + .dat format as IOHanalyzer): exports a results
# folder, loads it with iohinspector.DataManager, and asserts that every (configuration,
# instance) has as many runs as the results folder has trials, that each run's best value
# equals the trial's best RMSE, and that every run's trajectory ends at that value.
#
# Usage: scripts/check-ioh-export.sh [RESULTS_DIR] [BRDF_SLS_BINARY]
#   RESULTS_DIR defaults to results/default. A virtual environment is made (once) in
#   runs/ioh-venv/ (override with IOH_VENV=...); pip needs network access the first time.
set -euo pipefail
cd "$(dirname "$0")/.."

RESULTS="${1:-results/default}"
BIN="${2:-}"
if [ -z "$BIN" ]; then
    cargo build --release -q -p harness --bin brdf-sls
    BIN="${CARGO_TARGET_DIR:-target}/release/brdf-sls"
fi

VENV="${IOH_VENV:-runs/ioh-venv}"
if [ ! -x "$VENV/bin/python" ]; then
    python3 -m venv "$VENV"
    "$VENV/bin/pip" install --quiet --upgrade pip
    "$VENV/bin/pip" install --quiet "iohinspector==0.0.8"
fi

OUT="$(mktemp -d)"
trap 'rm -rf "$OUT"' EXIT
"$BIN" export --format ioh "$RESULTS" --out "$OUT/ioh"

"$VENV/bin/python" - "$RESULTS" "$OUT/ioh" <<'PY'
import gzip, json, math, os, sys
from collections import defaultdict

import iohinspector
import polars as pl

results, exported = sys.argv[1], sys.argv[2]

# What the results folder holds, read independently of brdf-sls.
path = os.path.join(results, "trials.jsonl")
opener = open if os.path.exists(path) else gzip.open
path = path if os.path.exists(path) else path + ".gz"
best = defaultdict(list)
with opener(path, "rt") as f:
    for line in f:
        line = line.strip()
        if not line:
            continue
        rec = json.loads(line)
        if rec.get("type") == "trial":
            y = rec["result"]["best_rmse"]
            best[(rec["config"], rec["instance"])].append(math.inf if y is None else y)

dm = iohinspector.DataManager()
dm.add_folder(exported)
ov = dm.overview
assert len(ov) == sum(len(v) for v in best.values()), (len(ov), sum(len(v) for v in best.values()))
got = defaultdict(list)
for row in ov.iter_rows(named=True):
    got[(row["algorithm_name"], row["function_name"])].append(row["best_y"])
assert set(got) == set(best), (sorted(got), sorted(best))
for key, ys in best.items():
    want = sorted(min(y, sys.float_info.max) for y in ys)
    have = sorted(got[key])
    assert len(have) == len(want), (key, len(have), len(want))
    for a, b in zip(have, want):
        assert a == b, (key, a, b)

# The trajectories: one run per trial, each starting at evaluation 1 and ending at its best.
# monotonic=False: iohinspector 0.0.8's monotonic filter compares a run's first row with the
# previous run's last one, so a run that starts at the value where the previous run ended (an
# RPLS trial whose first descent lands on the optimum, after one that ended there) vanishes.
data = dm.load(monotonic=False, include_meta_data=True)
runs = data.group_by("data_id").agg(
    pl.col("evaluations").min().alias("first"),
    pl.col("raw_y").min().alias("final"),
)
assert len(runs) == len(ov), (len(runs), len(ov))
assert (runs["first"] == 1).all(), "a run does not start at evaluation 1"
finals = dict(zip(runs["data_id"], runs["final"]))
for row in ov.iter_rows(named=True):
    assert finals[row["data_id"]] == row["best_y"], (row, finals[row["data_id"]])

print(f"iohinspector {getattr(iohinspector, '__version__', '?')}: {len(ov)} runs of "
      f"{len(got)} (algorithm, function) pairs load; run counts and best RMSEs match {results}")
PY
