#!/usr/bin/env bash
# CI: the Slurm integration test on a one-node cluster started here.
#
# Starts the cluster with scripts/slurm-local.sh (installs slurm-wlm and munge when missing),
# runs `BRDF_SLS_SLURM=1 cargo test -p harness --test slurm -- --nocapture`, and always stops
# the daemons it started (trap), whatever the test did. Needs root. About 1 minute for the
# install and start on a fresh machine, plus the build; the test itself takes ~10 s.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
cd "$root"

cleanup() {
    local status=$?
    "$here/slurm-local.sh" stop || true
    exit "$status"
}
trap cleanup EXIT INT TERM

"$here/slurm-local.sh" start
BRDF_SLS_SLURM=1 timeout 600 cargo test -p harness --test slurm -- --nocapture
