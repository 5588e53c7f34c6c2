#!/usr/bin/env bash
# The out-of-tree algorithm example (examples/custom-algorithm/, not a workspace member): lints
# and builds it from its own manifest and lock file, runs its tiny spec into a temporary folder,
# checks that trials.jsonl holds the custom kind's trials (and names the program and the kind's
# schema) and that the statistics name it,
# runs the spec again and checks that it resumed every trial and ran none, then runs it as two
# shards, merges them and writes their statistics and report with the same program. Called by .ci/run.
set -euo pipefail
cd "$(dirname "$0")/.."

section() { echo; echo "== custom algorithm: $* ($(date +%H:%M:%S))"; }
fail() { echo "error: $*" >&2; exit 1; }

# The workspace's target folder: the example's dependencies are the workspace's crates with the
# same versions and profile, so they are built once.
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/target}"
manifest=examples/custom-algorithm/Cargo.toml
bin="$CARGO_TARGET_DIR/release/custom-algorithm"

section "rustfmt and clippy"
cargo fmt --manifest-path "$manifest" -- --check
cargo clippy --manifest-path "$manifest" --all-targets --locked -- -D warnings

section build
cargo build --release --locked --manifest-path "$manifest"

out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

section "the tiny spec"
"$bin" run examples/custom-algorithm/tiny.toml --out "$out/tiny" --threads 2 2>&1 | tee "$out/first.txt"
trials="$out/tiny/trials.jsonl"
test -s "$trials" || fail "$trials is missing or empty"
grep -q '"kind":"coordinate-search"' "$trials" \
    || fail "the results header does not record the coordinate-search configuration"
custom=$(grep -c '"config":"COORDINATE-SEARCH"' "$trials" || true)
planned=$(awk '/^trials *=/ { print $3 }' examples/custom-algorithm/tiny.toml)
[[ "$custom" -eq "$planned" ]] \
    || fail "trials.jsonl holds $custom COORDINATE-SEARCH trials, expected $planned"
grep -q 'COORDINATE-SEARCH' "$out/tiny/stats.csv" || fail "stats.csv does not name COORDINATE-SEARCH"
grep -q 'COORDINATE-SEARCH' "$out/tiny/table.txt" || fail "table.txt does not name COORDINATE-SEARCH"
head -1 "$trials" | grep -q '"program":"custom-algorithm 0.1.0"' \
    || fail "the results header does not name the program that wrote it"
head -1 "$trials" | grep -q '"schemas":{"coordinate-search":"[0-9a-f]\{16\}"}' \
    || fail "the results header does not record the coordinate-search schema hash"
echo "trials.jsonl holds $custom COORDINATE-SEARCH trials, names its program and the kind's schema; the statistics name it"

section "running it again resumes"
"$bin" run examples/custom-algorithm/tiny.toml --out "$out/tiny" --threads 2 2>&1 | tee "$out/second.txt"
grep -q '^0 new trials' "$out/second.txt" || fail "the second run ran new trials"
echo "resumed with 0 new trials"

section "the rest of the command line knows the kind: shards, merge, stats, report"
for k in 1 2; do
    "$bin" run examples/custom-algorithm/tiny.toml --out "$out/shard-$k" --shard "$k/2" \
        --threads 2 --no-plots > /dev/null
done
"$bin" merge "$out/merged" "$out/shard-1" "$out/shard-2" > /dev/null
merged=$(grep -c '"config":"COORDINATE-SEARCH"' "$out/merged/trials.jsonl" || true)
[[ "$merged" -eq "$planned" ]] \
    || fail "the merged shards hold $merged COORDINATE-SEARCH trials, expected $planned"
"$bin" stats "$out/merged" --print-only | grep -q 'COORDINATE-SEARCH' \
    || fail "stats of the merged folder does not name COORDINATE-SEARCH"
"$bin" report "$out/merged" > /dev/null
grep -q 'COORDINATE-SEARCH' "$out/merged/report.html" || fail "report.html does not name it"
echo "two shards merged into $merged COORDINATE-SEARCH trials; stats and report name them"
