"""Long calls release the GIL and stop on Ctrl-C."""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap
import threading
import time

import brdf_sls as bs


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
