#!/usr/bin/env bash
# CI check of tuning with irace (called by .ci/run): installs irace when missing, runs a tiny
# tuning end to end (120 irace experiments of a few milliseconds each on 400-sample instances;
# about a minute on 2 cores), and checks that the elites exist and that the validation spec
# passes `brdf-sls check`. Usage: scripts/ci-irace.sh [BRDF_SLS_BINARY]
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-irace.sh

BIN="${1:-}"
if [ -z "$BIN" ]; then
    cargo build --release -q -p harness --bin brdf-sls
    BIN="${CARGO_TARGET_DIR:-target}/release/brdf-sls"
fi
BIN="$(cd "$(dirname "$BIN")" && pwd)/$(basename "$BIN")"

WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
cat > "$WORK/ci-tune.toml" <<'TOML'
name = "ci-tune"
seed = 5
trials = 3

[budget]
evaluations = 400000

[tune]
train = ["s3", "s4"]
test = ["s5"]
budget = 120
cost = "evaluations"
cutoff = 400000
seed = 2
parallel = 2
elites = 2
validation_trials = 3

[[tune.parameter]]
name = "phi"
type = "real"
range = [1.1, 2.0]

[[tune.parameter]]
name = "rho0"
type = "int"
range = [10, 80]
log = true

[[instance]]
name = "s3"
targets = [0.105]
synthetic = { params = "tuning", samples = 400, sigma = 0.1, seed = 3 }

[[instance]]
name = "s4"
targets = [0.105]
synthetic = { params = "tuning", samples = 400, sigma = 0.1, seed = 4 }

[[instance]]
name = "s5"
targets = [0.105]
synthetic = { params = "tuning", samples = 400, sigma = 0.1, seed = 5 }

[[algorithm]]
label = "AED"
kind = "aed"
TOML

start=$(date +%s)
"$BIN" tune "$WORK/ci-tune.toml" --out "$WORK/out"
test -s "$WORK/out/elites.csv" || { echo "ci-irace: no elites.csv" >&2; exit 1; }
test -s "$WORK/out/irace/irace.out" || { echo "ci-irace: no irace output" >&2; exit 1; }
"$BIN" check "$WORK/out/ci-tune-validation.toml" > /dev/null
"$BIN" run "$WORK/out/ci-tune-validation.toml" --out "$WORK/validation" --no-plots --progress quiet > /dev/null
test -s "$WORK/validation/tests.csv" || { echo "ci-irace: validation wrote no tests.csv" >&2; exit 1; }
grep -q "lr_p_holm" "$WORK/validation/tests.csv" || { echo "ci-irace: tests.csv lacks the log-rank test" >&2; exit 1; }
echo "ci-irace: ok in $(( $(date +%s) - start )) s (elites: $(tail -n +2 "$WORK/out/elites.csv" | wc -l))"
