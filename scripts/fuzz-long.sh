#!/usr/bin/env bash
# Long fuzz run of the reader and parameter properties (crates/model/tests/fuzz_readers.rs):
# parse_cornell, parse_csv, the ALTA reader (io::parse), MerlBrdf::from_bytes, parameter
# JSON + validate + try_synthetic, and the try_synthetic limits; of the spec parser
# (crates/experiment/tests/fuzz_spec.rs); and of results folders (crates/analysis/tests/
# fuzz_results.rs: committed results with header timestamps, labels, times and other numbers
# set to extremes, lines dropped, duplicated or torn, plain or gzip, read, analysed and
# rendered as statistics, report and comparison pages; each case may take 60 s at most).
# Then the probes from outside (crates/harness/tests/probes.rs): FIFOs and links to them as
# specs, results files, results folders and output files for every command that reads or
# writes them; absurd --threads and budgets; huge labels; a locked folder; edited results;
# and crates/harness/tests/trust.rs (torn packed files, links, escapes, edited seeds/targets).
# `cargo test` runs a few hundred cases of each; this runs CASES per property in release mode
# and reports the total number of executions.
#
# Usage: scripts/fuzz-long.sh [CASES]
#   CASES  cases per property (default: $PROPTEST_CASES, else 200000; 7 properties give
#          1,400,000 executions; the results folders get CASES/10). FUZZ_THREADS sets the test threads (default 2).
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
    # Each results case reads, analyses and renders a whole folder: a tenth of the cases.
    PROPTEST_CASES=$(( cases / 10 + 1 )) cargo test --release -p brdf-analysis --test fuzz_results \
        -- --nocapture --test-threads="$threads" >>"$log" 2>&1
    status=$?
fi
if [ "$status" -eq 0 ]; then
    cargo test --release -p harness --test probes --test trust -- --test-threads="$threads" >>"$log" 2>&1
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
