"""The README's Python example runs as written (matplotlib's Agg backend, from the repository
root, as a reader would run it)."""

from __future__ import annotations

import os
import re
import subprocess
import sys

from conftest import REPO


def test_readme_python_example_runs(tmp_path):
    readme = (REPO / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", readme, re.S)
    assert len(blocks) == 1, "expected one ```python block in README.md"
    script = tmp_path / "readme_example.py"
    script.write_text(blocks[0])
    env = {**os.environ, "MPLBACKEND": "Agg"}
    p = subprocess.run([sys.executable, str(script)], cwd=REPO, env=env, capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    png = REPO / "runs" / "fig17-rtd.png"
    assert png.is_file() and png.stat().st_size > 10_000
    assert "RMSE" in p.stdout
