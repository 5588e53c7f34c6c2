#!/usr/bin/env bash
# The Python package (crates/py): builds its abi3 wheel with maturin in a virtual environment,
# installs it, runs its tests (which compare it with the `brdf-sls` command line), and lints the
# crate, which lives outside the workspace so that `cargo test --workspace` needs no Python.
# Needs python3 (3.9 or newer) with venv or pip, and PyPI and crates.io. Called by .ci/run.
set -euo pipefail
cd "$(dirname "$0")/.."

section() { echo; echo "== python: $* ($(date +%H:%M:%S))"; }
started=$(date +%s)

export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$PWD/target}"
python=${PYTHON:-python3}
venv="$CARGO_TARGET_DIR/py-venv"
wheels="$CARGO_TARGET_DIR/py-wheels"

section "virtual environment ($("$python" --version 2>&1))"
if [[ ! -x "$venv/bin/python" ]]; then
    if ! "$python" -m venv "$venv"; then
        # Debian's python3 without the python3-venv package: virtualenv from PyPI instead.
        rm -rf "$venv"
        "$python" -m pip install --quiet --target "$CARGO_TARGET_DIR/py-virtualenv" 'virtualenv>=20,<21'
        PYTHONPATH="$CARGO_TARGET_DIR/py-virtualenv" "$python" -m virtualenv "$venv"
    fi
fi
vpy="$venv/bin/python"
"$vpy" -m pip install --quiet --disable-pip-version-check \
    'maturin>=1.7,<2' 'numpy>=2,<3' 'pandas>=2,<3' 'pytest>=8,<9' 'matplotlib>=3.8,<4' \
    'scipy>=1.11,<2' 'cma>=3.2,<5'

section "the command line the tests compare with"
cargo build --release --locked --bin brdf-sls
export BRDF_SLS_BIN="$CARGO_TARGET_DIR/release/brdf-sls"

section "wheel (maturin, release)"
rm -rf "$wheels"
"$venv/bin/maturin" build --release --locked -m crates/py/Cargo.toml --out "$wheels"
"$vpy" -m pip install --quiet --disable-pip-version-check --force-reinstall --no-deps "$wheels"/*.whl

section "pytest"
# From the tests' folder, so `import brdf_sls` is the installed wheel, not the source tree.
(cd crates/py/tests && MPLBACKEND=Agg "$vpy" -m pytest -q -p no:cacheprovider .)

section "rustfmt and clippy of crates/py"
cargo fmt --manifest-path crates/py/Cargo.toml -- --check
PYO3_PYTHON="$vpy" cargo clippy --manifest-path crates/py/Cargo.toml --locked --all-targets -- -D warnings

echo "python package: built, tested and linted in $(( $(date +%s) - started )) s"
