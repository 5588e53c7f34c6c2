"""Long calls release the GIL and stop on Ctrl-C."""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap
import threading
import time

import os

import pytest

import brdf_sls as bs

TESTS = os.path.dirname(os.path.abspath(__file__))


def test_fit_releases_the_gil():
    data = bs.DataSet.synthetic("tuning", samples=3000, sigma=0.1, seed=1)
    done = threading.Event()
    ticks = 0

    def work():
        bs.fit(data, "aed", cpu_seconds=1.5, target=0.0)
        done.set()

    t = threading.Thread(target=work)
    t.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    t.join()
    # Python ran all along the 1.5 CPU-second fit (a held GIL would give 0 or 1 tick).
    assert ticks > 100


def _interrupt(code: str, tmp_path, delay: float):
    """Runs `code`, which prints a line when its long call starts; sends SIGINT `delay`
    seconds after that line; returns (stdout, stderr, seconds from SIGINT to exit)."""
    script = tmp_path / "long.py"
    # A shell that starts a job in the background without job control (a CI runner, `cmd &`
    # in a script) makes it ignore SIGINT, and Python then installs no KeyboardInterrupt
    # handler: the child restores it, so the test does not depend on how it was launched.
    restore = "import signal\nsignal.signal(signal.SIGINT, signal.default_int_handler)\n"
    script.write_text(restore + textwrap.dedent(code))
    p = subprocess.Popen([sys.executable, str(script)], cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    first = p.stdout.readline()
    assert first.strip() == "started", (first, p.stderr.read() if p.poll() is not None else "")
    time.sleep(delay)
    start = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    return out, err, time.monotonic() - start


def test_ctrl_c_stops_a_long_fit(tmp_path):
    out, err, took = _interrupt(
        """
        import brdf_sls as bs
        data = bs.DataSet.synthetic("tuning", samples=5000, sigma=0.1)
        print("started", flush=True)
        try:
            bs.fit(data, "aed", cpu_seconds=120.0, target=0.0)
        except KeyboardInterrupt:
            print("interrupted", flush=True)
        """,
        tmp_path,
        delay=1.0,
    )
    assert "interrupted" in out, err
    assert took < 5.0


def test_ctrl_c_stops_a_run_and_stores_only_finished_trials(tmp_path):
    spec = tmp_path / "long.toml"
    spec.write_text(
        'seed = 1\ntrials = 40\n[budget]\ncpu_seconds = 2.0\n[[instance]]\nname = "t"\n'
        'targets = [0.0]\n[instance.synthetic]\nparams = "tuning"\nsamples = 2000\nsigma = 0.1\n'
        '[[algorithm]]\nkind = "rpls"\n'
    )
    out, err, took = _interrupt(
        f"""
        import brdf_sls as bs
        print("started", flush=True)
        try:
            bs.run({str(spec)!r}, "out", threads=2, plots=False)
        except KeyboardInterrupt as e:
            print("interrupted:", e, flush=True)
        """,
        tmp_path,
        delay=12.0,
    )
    assert "interrupted" in out, err
    assert took < 5.0
    # Every stored trial ran its whole budget: none was cut short by the interrupt.
    res = bs.read_results(tmp_path / "out")
    assert 0 < res.present < 40
    assert all(t["stop"] == "cpu_budget" for t in res.trials)
    assert all(t["cpu_seconds"] >= 2.0 for t in res.trials)


SPINS = """
seed = 1
trials = 1

[budget]
evaluations = 100000

[[instance]]
name = "t"
targets = [0.0]
[instance.synthetic]
params = "tuning"
samples = 200

[[algorithm]]
label = "SPINS"
kind = "python"
entry = "pyalgos:spins"
"""


@pytest.mark.parametrize("processes", [True, False])
def test_ctrl_c_stops_a_python_algorithm_that_never_calls_its_problem(tmp_path, processes):
    """Under an evaluation budget alone no watchdog cuts it: Ctrl-C must (issue 45.6)."""
    spec = tmp_path / "spins.toml"
    spec.write_text(SPINS)
    pid_file = tmp_path / "pid"
    out, err, took = _interrupt(
        f"""
        import os, sys, time
        sys.path.insert(0, {TESTS!r})
        os.environ["BRDF_SLS_TEST_PID_FILE"] = {str(pid_file)!r}
        import brdf_sls as bs
        print("started", flush=True)
        try:
            bs.run({str(spec)!r}, "out", plots=False, progress="quiet", processes={processes})
        except KeyboardInterrupt as e:
            print("interrupted:", e, flush=True)
        """,
        tmp_path,
        delay=3.0,
    )
    assert "interrupted" in out, err
    assert took < 5.0
    assert pid_file.exists(), "the algorithm was running"
    if processes:
        assert _gone(int(pid_file.read_text())), "the worker process was stopped"


def _gone(pid: int, wait: float = 5.0) -> bool:
    """Whether process `pid` ends within `wait` seconds."""
    end = time.monotonic() + wait
    while time.monotonic() < end:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return True
        time.sleep(0.05)
    return False


def test_the_command_lines_workers_leave_with_it(cli, tmp_path):
    """`brdf-sls run` runs Python trials in worker processes: killed by Ctrl-C, it leaves none
    behind, even one whose algorithm never returns."""
    spec = tmp_path / "spins.toml"
    spec.write_text(SPINS)
    pid_file = tmp_path / "pid"
    env = {**os.environ, "BRDF_SLS_PYTHON": sys.executable, "PYTHONPATH": TESTS, "BRDF_SLS_TEST_PID_FILE": str(pid_file)}
    p = subprocess.Popen([str(cli.binary), "run", str(spec), "--out", str(tmp_path / "out"), "--no-plots"],
                         cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    end = time.monotonic() + 60
    while not pid_file.exists() and time.monotonic() < end and p.poll() is None:
        time.sleep(0.1)
    assert pid_file.exists(), p.communicate()[1] if p.poll() is not None else "no worker started"
    time.sleep(0.5)
    p.send_signal(signal.SIGINT)
    p.communicate(timeout=10)
    assert _gone(int(pid_file.read_text())), "the worker outlived the command line"
