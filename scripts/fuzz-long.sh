#!/usr/bin/env bash
# Long fuzz run of the reader and parameter properties (crates/model/tests/fuzz_readers.rs):
# parse_cornell, parse_csv, the ALTA reader (io::parse), MerlBrdf::from_bytes, parameter
# JSON + validate + try_synthetic, and the try_synthetic limits; and of the spec parser
# (crates/experiment/tests/fuzz_spec.rs).
# Then the probes from outside (crates/harness/tests/probes.rs): FIFOs and links to them as
# specs, results files, results folders and output files for every command that reads or
# writes them; absurd --threads and budgets; huge labels; a locked folder; edited results.
# `cargo test` runs a few hundred cases of each; this runs CASES per property in release mode
# and reports the total number of executions.
#
# Usage: scripts/fuzz-long.sh [CASES]
#   CASES  cases per property (default: $PROPTEST_CASES, else 200000; 7 properties give
#          1,400,000 executions). FUZZ_THREADS sets the test threads (default 2).
# Exits non-zero when a property fails (proptest prints the minimal failing input).
set -uo pipefail
cd "$(dirname "$0")/.."
cases=${1:-${PROPTEST_CASES:-200000}}
threads=${FUZZ_THREADS:-2}
log=$(mktemp)
trap 'rm -f "$log"' EXIT
start=$(date +%s)
PROPTEST_CASES=$cases cargo test --release -p brdf-model --test fuzz_readers \
    -- --nocapture --test-threads="$threads" >"$log" 2>&1
status=$?
if [ "$status" -eq 0 ]; then
    PROPTEST_CASES=$cases cargo test --release -p brdf-experiment --test fuzz_spec \
        -- --nocapture --test-threads="$threads" >>"$log" 2>&1
    status=$?
fi
if [ "$status" -eq 0 ]; then
    cargo test --release -p harness --test probes -- --test-threads="$threads" >>"$log" 2>&1
    status=$?
fi
secs=$(( $(date +%s) - start ))
grep -E '^FUZZ |^test result|panicked|minimal failing' "$log" || true
total=$(awk '/^FUZZ /{s += $(NF-1)} END {print s + 0}' "$log")
if [ "$status" -ne 0 ]; then
    tail -n 40 "$log"
    echo "fuzz-long: FAILED after $total executions in ${secs}s ($cases cases per property)"
    exit "$status"
fi
echo "fuzz-long: $total executions in ${secs}s ($cases cases per property), no failure"
