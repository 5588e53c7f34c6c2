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
# The same tiny spec as the tuning tests (crates/tune/tests/tune.rs, crates/harness/tests/tune.rs).
cp crates/tune/tests/data/tiny-tune.toml "$WORK/tiny-tune.toml"

start=$(date +%s)
"$BIN" tune "$WORK/tiny-tune.toml" --out "$WORK/out"
test -s "$WORK/out/elites.csv" || { echo "ci-irace: no elites.csv" >&2; exit 1; }
test -s "$WORK/out/irace/irace.out" || { echo "ci-irace: no irace output" >&2; exit 1; }
"$BIN" check "$WORK/out/tiny-tune-validation.toml" > /dev/null
"$BIN" run "$WORK/out/tiny-tune-validation.toml" --out "$WORK/validation" --no-plots --progress quiet > /dev/null
test -s "$WORK/validation/tests.csv" || { echo "ci-irace: validation wrote no tests.csv" >&2; exit 1; }
grep -q "lr_p_holm" "$WORK/validation/tests.csv" || { echo "ci-irace: tests.csv lacks the log-rank test" >&2; exit 1; }
echo "ci-irace: ok in $(( $(date +%s) - start )) s (elites: $(tail -n +2 "$WORK/out/elites.csv" | wc -l))"
