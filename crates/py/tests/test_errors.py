"""Bad input raises a Python exception with the command line's message, never a panic."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

import brdf_sls as bs
from conftest import cli_error


def test_missing_file_same_message_as_cli(cli, tmp_path):
    missing = tmp_path / "nope.brdf"
    want = cli_error(cli("info", missing, check=False))
    with pytest.raises(bs.InputError) as e:
        bs.DataSet.read(missing)
    assert str(e.value) == want
    assert str(e.value).count(str(missing)) == 1, "the path is named once"


def test_unknown_extension_same_message_as_cli(cli, tmp_path):
    f = tmp_path / "data.txt"
    f.write_text("1 2 3\n")
    want = cli_error(cli("info", f, check=False))
    with pytest.raises(bs.InputError, match="cannot tell the format") as e:
        bs.DataSet.read(f)
    assert str(e.value) == want


def test_bad_csv_names_file_and_line(cli, tmp_path):
    f = tmp_path / "bad.csv"
    f.write_text("ux,uy,uz,vx,vy,vz,value\n0,0,1,0,0,1,0.5\n0,0,1,0,zero,1,0.5\n")
    p = cli("info", f, check=False)
    assert p.returncode == 2
    with pytest.raises(bs.InputError) as e:
        bs.DataSet.read(f)
    assert str(e.value) == cli_error(p)
    assert "bad.csv" in str(e.value) and "3" in str(e.value)


def python_words(message: str) -> str:
    """The command line's message with its arguments named as Python writes them."""
    message = message.replace("--algorithm/--set", "algorithm/settings")
    return re.sub(r"--([a-z-]+) (\S+):", lambda m: f"{m[1].replace('-', '_')}={m[2]}:", message)


@pytest.mark.parametrize(
    "flags,kwargs",
    [
        ({"--set": "phix=1"}, {"phix": 1}),
        ({"--set": "phi=0.5"}, {"phi": 0.5}),
        ({"--algorithm": "nope"}, {"algorithm": "nope"}),
        ({"--cpu-seconds": "0"}, {"cpu_seconds": 0.0}),
        ({"--target": "-1"}, {"target": -1.0}),
        ({"--lobes": "0"}, {"lobes": 0}),
        ({"--fix": "lobe3.n=2"}, {"fixed": {"lobe3.n": 2.0}}),
    ],
)
def test_bad_fit_arguments_same_message_as_cli(cli, krylon, flags, kwargs):
    # The algorithm named on both sides: the settings above are AED's.
    flags = {"--cpu-seconds": "1", "--algorithm": "aed", **flags}
    p = cli("fit", krylon, *(f"{k}={v}" for k, v in flags.items()), check=False)
    assert p.returncode == 2, p.stderr
    data = bs.DataSet.read(krylon)
    kwargs = {"cpu_seconds": 1.0, **kwargs}
    algorithm = kwargs.pop("algorithm", "aed")
    with pytest.raises(bs.InputError) as e:
        bs.fit(data, algorithm, **kwargs)
    want = python_words(cli_error(p))
    if algorithm == "nope":
        # The package knows one kind more than the command line: its algorithms in Python.
        assert want.endswith("`asa`")
        want += ", `python`"
    assert str(e.value) == want
    assert "--" not in str(e.value), "a Python error names no command-line flag"


def test_bad_spec_same_message_as_cli(cli, tmp_path):
    spec = tmp_path / "bad.toml"
    spec.write_text('seed = 1\ntrials = 2\nfrobnicate = 3\n[budget]\ncpu_seconds = 1.0\n')
    p = cli("run", spec, "--out", tmp_path / "out", check=False)
    assert p.returncode == 2
    with pytest.raises(bs.InputError) as e:
        bs.run(spec, tmp_path / "out2")
    assert str(e.value) == cli_error(p)
    assert "frobnicate" in str(e.value)


def test_results_of_another_spec_refused_like_cli(cli, tmp_path):
    a = tmp_path / "a.toml"
    a.write_text('seed = 1\ntrials = 1\n[budget]\nevaluations = 1e5\n[[instance]]\nname = "t"\ntargets = [0.2]\n[instance.synthetic]\nparams = "tuning"\nsamples = 300\n[[algorithm]]\nkind = "rpls"\n')
    b = tmp_path / "b.toml"
    b.write_text(a.read_text().replace("seed = 1", "seed = 2"))
    bs.run(a, tmp_path / "out", plots=False)
    p = cli("run", b, "--out", tmp_path / "out", "--no-plots", check=False)
    assert p.returncode == 2
    with pytest.raises(bs.InputError) as e:
        bs.run(b, tmp_path / "out", plots=False)
    assert str(e.value) == cli_error(p)


def test_bad_arrays_raise():
    u = np.tile([0.0, 0.0, 1.0], (4, 1))
    with pytest.raises(bs.InputError, match=r"shape \(n, 3\)"):
        bs.DataSet.from_arrays(u[:, :2], u, np.zeros(4))
    with pytest.raises(bs.InputError, match="same number of rows"):
        bs.DataSet.from_arrays(u, u, np.zeros(3))
    with pytest.raises(bs.InputError, match=r"values\[2\]"):
        bs.DataSet.from_arrays(u, u, [0, 0, np.nan, 0])
    bad = u.copy()
    bad[1, 0] = np.inf
    with pytest.raises(bs.InputError, match=r"v\[1\]"):
        bs.DataSet.from_arrays(u, bad, np.zeros(4))


def test_bad_model_and_parameters_raise():
    with pytest.raises(bs.InputError, match="kind=weird"):
        bs.Model(kind="weird")
    with pytest.raises(bs.InputError, match="lobes=65"):
        bs.Model(lobes=65)
    with pytest.raises(bs.InputError, match="kernel"):
        bs.Model(kernel="gpu")
    m = bs.Model()
    data = bs.DataSet.synthetic("tuning", samples=50)
    with pytest.raises(bs.InputError, match="6 free parameters"):
        m.rmse(np.zeros(3), data)
    with pytest.raises(bs.InputError, match="not a known name"):
        m.rmse("shiny", data)
    with pytest.raises(bs.InputError):
        m.encode({"kd": 2.0, "lobes": []})
    with pytest.raises(bs.InputError, match="column"):
        data.column("w")


def test_unknown_descent_names_it_and_the_choices(krylon):
    data = bs.DataSet.read(krylon)
    with pytest.raises(bs.InputError, match="unknown descent `port`.*n2fb"):
        bs.fit(data, "aed", cpu_seconds=1.0, descent="port")


def test_reading_a_folder_without_results_raises(tmp_path):
    with pytest.raises(bs.InputError, match=str(tmp_path)):
        bs.read_results(tmp_path)


def test_a_budget_too_small_to_evaluate_is_a_run_error():
    data = bs.DataSet.synthetic("tuning", samples=200000)
    with pytest.raises(bs.RunError, match="evaluated no candidate"):
        bs.fit(data, "ds", cpu_seconds=1e-9)


def _edit_first_trial(path, edit):
    """Applies `edit` to the first trial line of the results file `path`."""
    lines = path.read_text().splitlines()
    at = next(i for i, line in enumerate(lines) if '"type":"trial"' in line)
    record = json.loads(lines[at])
    edit(record)
    lines[at] = json.dumps(record)
    path.write_text("\n".join(lines) + "\n")


def _set_seed(r):
    r["seed"] ^= 1


def _set_target(r):
    r["target"] = 0.5


def _set_negative_time(r):
    r["result"]["ended_at"]["cpu_seconds"] = -1.0


EDITS = {"seed": (_set_seed, "has seed"), "target": (_set_target, "has target 0.5"), "time": (_set_negative_time, "is -1")}


@pytest.mark.parametrize("what", sorted(EDITS))
def test_edited_results_refused_like_cli(cli, tmp_path, what):
    """An edited seed or target, or a negative time, in a results file is bad input for the
    command line (exit status 2, naming file, line and key): InputError here too, when running
    again and when reading the results (it was RunError, and read_results used the edit)."""
    edit, says = EDITS[what]
    spec = tmp_path / "a.toml"
    spec.write_text('seed = 1\ntrials = 2\n[budget]\nevaluations = 1e5\n[[instance]]\nname = "t"\ntargets = [0.2]\n[instance.synthetic]\nparams = "tuning"\nsamples = 300\n[[algorithm]]\nkind = "rpls"\n')
    out = tmp_path / "out"
    bs.run(spec, out, plots=False, progress="quiet")
    _edit_first_trial(out / "trials.jsonl", edit)
    p = cli("stats", out, "--print-only", check=False)
    assert p.returncode == 2, p.stderr
    assert says in p.stderr
    with pytest.raises(bs.InputError, match="trials.jsonl:[0-9]+") as e:
        bs.read_results(out)
    assert says in str(e.value)
    p = cli("run", spec, "--out", out, "--no-plots", "--progress", "quiet", check=False)
    assert p.returncode == 2, p.stderr
    with pytest.raises(bs.InputError) as e:
        bs.run(spec, out, plots=False, progress="quiet")
    assert str(e.value) == cli_error(p)
    assert says in str(e.value)
