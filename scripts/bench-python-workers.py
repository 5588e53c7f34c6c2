#!/usr/bin/env python3
"""Trials per second of a CPU-bound pure-Python algorithm at 1 and 2 threads, in worker
processes (the default) and on threads of one interpreter (`processes=False`), for
docs/python.md. Needs the brdf_sls package installed (scripts/ci-python.sh builds it).

    python3 scripts/bench-python-workers.py [--trials 24] [--evaluations 400000] [--work 3000]
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import tempfile
import time
from pathlib import Path

import brdf_sls as bs

TESTS = Path(__file__).resolve().parents[1] / "crates" / "py" / "tests"

SPEC = """
name = "busy"
seed = 1
trials = {trials}

[budget]
evaluations = {evaluations}

[[instance]]
name = "t"
targets = [0.0]
[instance.synthetic]
params = "tuning"
samples = 200
sigma = 0.1

[[algorithm]]
label = "BUSY"
kind = "python"
entry = "pyalgos:busy"
work = {work}

[plots]
draw = []
"""


def cpu_seconds() -> float:
    """CPU seconds of this process and its finished children (the workers)."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--trials", type=int, default=24)
    p.add_argument("--evaluations", type=int, default=400_000)
    p.add_argument("--work", type=int, default=3000)
    a = p.parse_args()
    sys.path.insert(0, str(TESTS))
    with tempfile.TemporaryDirectory() as tmp:
        spec = Path(tmp) / "busy.toml"
        spec.write_text(SPEC.format(trials=a.trials, evaluations=a.evaluations, work=a.work))
        print(f"{a.trials} trials, {os.cpu_count()} logical CPUs, load {os.getloadavg()[0]:.1f}")
        print("trials/s (wall seconds; CPU seconds of the run's processes / wall = cores used)")
        print("| threads | worker processes | threads of one interpreter |")
        print("|---|---|---|")
        for threads in (1, 2):
            rates = []
            for processes in (True, False):
                out = Path(tmp) / f"out-{threads}-{processes}"
                cpu0 = cpu_seconds()
                started = time.monotonic()
                r = bs.run(spec, out, threads=threads, plots=False, progress="quiet", processes=processes)
                wall = time.monotonic() - started
                cores = (cpu_seconds() - cpu0) / wall
                assert r["new_trials"] == a.trials, r
                rates.append(f"{a.trials / wall:.2f} trials/s ({wall:.1f} s; {cores:.2f} cores)")
            print(f"| {threads} | {rates[0]} | {rates[1]} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
