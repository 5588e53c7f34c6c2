#!/usr/bin/env bash
# Reproduces every figure and table of the paper's section 3 that this repository covers:
# runs each experiments/fig*.toml into results/<name>/ (resuming what is already there) and
# renders Figures 8, 12 and 18. About 10 minutes of wall time on 2 cores.
#
# The raw results are committed gzipped (results/<name>/trials.jsonl.gz, about 7x smaller).
# brdf-sls reads the packed file directly and unpacks it itself before resuming; this script
# packs the results again after each run. (A plain `brdf-sls run SPEC` writes to runs/<name>/,
# apart from these committed results.)
#
#   scripts/reproduce-all.sh            # resume: finished trials are kept, the rest run
#   scripts/reproduce-all.sh --fresh    # move existing results aside and start over
set -euo pipefail
cd "$(dirname "$0")/.."

fresh=()
if [[ "${1:-}" == "--fresh" ]]; then
    fresh=(--fresh)
fi

cargo build --release --locked -p harness
bin=target/release/brdf-sls

start=$(date +%s)
for spec in experiments/fig*.toml; do
    echo "== $spec"
    t0=$(date +%s)
    out="results/$(basename "$spec" .toml)"
    "$bin" run "$spec" --out "$out" "${fresh[@]}" --progress plain
    gzip -9 -k -f "$out/trials.jsonl"
    echo "== $spec: $(( $(date +%s) - t0 )) s"
done

echo "== Figures 8, 12 and 18 (renderings and polar plots)"
scripts/figures-render-polar.sh

echo "== all done in $(( $(date +%s) - start )) s"
