"""The Python example of docs/own-algorithm.md ("Benchmark your own algorithm") runs as written:
its algorithm and spec, from the folder that holds them, with `python -m brdf_sls run` and with
`brdf-sls run` (which runs its Python configurations in worker processes). The guide's Rust
example runs as a doc test of sls."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys

import pytest

from conftest import REPO


def guide_blocks():
    text = (REPO / "docs" / "own-algorithm.md").read_text()
    python_part = text[text.index("## Python algorithms") :]
    code = re.findall(r"```python\n(.*?)```", python_part, re.S)
    spec = re.findall(r"```toml\n(.*?)```", python_part, re.S)
    assert len(code) == 1 and len(spec) == 1, "expected one python and one toml block"
    return code[0], spec[0]


@pytest.fixture
def example(tmp_path):
    code, spec = guide_blocks()
    assert len(code.strip().splitlines()) <= 22, "the guide promises about 20 lines"
    (tmp_path / "compass.py").write_text(code)
    (tmp_path / "compass.toml").write_text(spec)
    return tmp_path


def check_results(out):
    lines = [json.loads(line) for line in (out / "trials.jsonl").read_text().splitlines()]
    recs = [r for r in lines if "key" in r]
    assert sorted({r["config"] for r in recs}) == ["AED", "Compass"]
    compass = [r for r in recs if r["config"] == "Compass"]
    assert len(compass) == 5
    for r in compass:
        res = r["result"]
        assert res["stop"] in ("target", "evaluation_budget")
        assert 0 < res["ended_at"]["evaluations"]["rmse_rows"] <= 300_000
        assert res["trace"]
    # At least one trial of the compass search reaches the looser target (0.12).
    assert any(min(p["rmse"] for p in r["result"]["trace"]) <= 0.12 for r in compass)
    assert "Compass" in (out / "table.txt").read_text()


def test_guide_example_runs_with_python_m(example):
    p = subprocess.run(
        [sys.executable, "-m", "brdf_sls", "run", "compass.toml", "--no-plots"],
        cwd=example, capture_output=True, text=True, timeout=600,
    )
    assert p.returncode == 0, p.stderr
    assert "10 new trials" in p.stderr
    check_results(example / "runs" / "compass")


def test_guide_example_runs_with_the_command_line(cli, example):
    env = {**os.environ, "BRDF_SLS_PYTHON": sys.executable}
    p = subprocess.run(
        [str(cli.binary), "run", "compass.toml", "--out", "out", "--threads", "2"],
        cwd=example, env=env, capture_output=True, text=True, timeout=600,
    )
    assert p.returncode == 0, p.stderr
    check_results(example / "out")
    # The same files as any other run: the report page too.
    assert (example / "out" / "report.html").is_file()
    assert "page: report.html" in p.stdout, p.stdout
    # The commands that only read specs and results know the kind without Python.
    stats = cli("stats", example / "out", "--print-only")
    assert "Compass" in stats.stdout
    check = cli("check", example / "compass.toml")
    assert "Compass" in check.stdout + check.stderr


def test_the_command_line_says_what_to_install(cli, example):
    env = {**os.environ, "BRDF_SLS_PYTHON": str(example / "no-such-python")}
    p = subprocess.run(
        [str(cli.binary), "run", "compass.toml", "--out", "out"],
        cwd=example, env=env, capture_output=True, text=True,
    )
    assert p.returncode == 2, p.stderr
    assert "no-such-python" in p.stderr and "cannot import it" in p.stderr
    assert "maturin develop --release -m crates/py/Cargo.toml" in p.stderr
    assert not (example / "out" / "trials.jsonl").exists()


def test_the_command_line_runs_python_shards(cli, example):
    """Shards of a spec with Python algorithms run (in worker processes) and merge."""
    env = {**os.environ, "BRDF_SLS_PYTHON": sys.executable}
    for k in (1, 2):
        p = subprocess.run(
            [str(cli.binary), "run", "compass.toml", "--shard", f"{k}/2", "--out", f"shard-{k}", "--no-plots"],
            cwd=example, env=env, capture_output=True, text=True, timeout=600,
        )
        assert p.returncode == 0, p.stderr
    cli("merge", example / "merged", example / "shard-1", example / "shard-2", "--no-plots")
    check_results(example / "merged")
