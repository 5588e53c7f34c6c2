"""Shared fixtures: the repository, the `brdf-sls` binary the results are compared with, and a
helper that runs it."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[3]
KRYLON = REPO / "experiments" / "data" / "krylon_blue.brdf"


def _binary() -> Path:
    # scripts/ci-python.sh builds the command line and names it here.
    env = os.environ.get("BRDF_SLS_BIN")
    path = Path(env) if env else REPO / "target" / "release" / "brdf-sls"
    if not path.is_file():
        pytest.fail(f"{path}: the brdf-sls binary is missing; run `cargo build --release --bin brdf-sls` or set BRDF_SLS_BIN")
    return path


@pytest.fixture(scope="session")
def cli():
    """Runs `brdf-sls ARGS...`; returns the CompletedProcess (text mode)."""
    binary = _binary()

    def run(*args, check=True, cwd=None):
        p = subprocess.run(
            [str(binary), *map(str, args)],
            capture_output=True,
            text=True,
            cwd=cwd,
        )
        if check and p.returncode != 0:
            raise AssertionError(f"brdf-sls {' '.join(map(str, args))} failed ({p.returncode}): {p.stderr}")
        return p

    run.binary = binary
    return run


def cli_error(p: subprocess.CompletedProcess) -> str:
    """The message of a failed command: from its `error: ` line to the end (spec errors quote
    the offending line on further lines), without the prefix."""
    at = p.stderr.rfind("error: ")
    assert at >= 0, f"no error line in: {p.stderr!r}"
    return p.stderr[at + len("error: ") :].rstrip("\n")


@pytest.fixture(scope="session")
def krylon():
    return KRYLON
