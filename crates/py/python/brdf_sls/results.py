"""A results folder as flat records: one dict per trial, per trace point and per statistic,
ready for ``pandas.DataFrame(records)``."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any

from . import _native

@dataclass
class Results:
    """What :func:`read_results` returns.

    Attributes:
        name: the experiment's name.
        planned: trials in the folder's plan; ``present``: how many are there (fewer when the
            run is partial).
        trials: one record per trial (key, instance, config, trial, seed, target, stop,
            reached, best_rmse, cpu_seconds, wall_seconds, evaluations, reached_cpu_seconds,
            reached_evaluations, budget_cpu_seconds, budget_evaluations).
        traces: one record per improvement of a trial's best RMSE (key, instance, config,
            trial, cpu_seconds, wall_seconds, evaluations, rmse).
        stats: one record per (instance, config, target, measure) with the columns of
            ``stats.csv`` (trials, successes, success_rate, q10..q90, ert, ert_sd, ert_p10,
            ert_p50, ert_p90, restart_p10..restart_p90, km_censoring); ``measure`` is ``cpu``
            or ``evaluations``.
        tests, finals: the pairwise tests and final-quality rows, as records.
        header: the results file's header (spec text, machine, kernel, data hashes).
        raw: the trial records as stored (nested dicts).
        warnings: what could not be established (e.g. best-known RMSEs of an older folder).
    """

    name: str
    planned: int
    present: int
    trials: list[dict[str, Any]] = field(default_factory=list)
    traces: list[dict[str, Any]] = field(default_factory=list)
    stats: list[dict[str, Any]] = field(default_factory=list)
    tests: list[dict[str, Any]] = field(default_factory=list)
    finals: list[dict[str, Any]] = field(default_factory=list)
    header: dict[str, Any] = field(default_factory=dict)
    raw: list[dict[str, Any]] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)

    def frames(self) -> dict[str, Any]:
        """The records as pandas DataFrames: ``trials``, ``traces``, ``stats``, ``tests`` and
        ``finals`` (pandas is imported here, so it is needed only for this)."""
        import pandas as pd

        return {
            name: pd.DataFrame(getattr(self, name))
            for name in ("trials", "traces", "stats", "tests", "finals")
        }


def _total(counts: dict[str, int] | None) -> int | None:
    """Sample-evaluations in the paper's count (residual + Jacobian + RMSE rows)."""
    if counts is None:
        return None
    return counts["residual_rows"] + counts["jacobian_rows"] + counts["rmse_rows"]


def _trial_row(rec: dict[str, Any]) -> dict[str, Any]:
    r = rec["result"]
    reached = r["reached_at"]
    best = r["best_rmse"]
    return {
        "key": rec["key"],
        "instance": rec["instance"],
        "config": rec["config"],
        "trial": rec["trial"],
        "seed": rec["seed"],
        "target": rec["target"],
        "stop": r["stop"],
        "reached": reached is not None,
        # A trial that never evaluated a point is stored with best_rmse null (+inf).
        "best_rmse": float("inf") if best is None else best,
        "cpu_seconds": r["ended_at"]["cpu_seconds"],
        "wall_seconds": r["ended_at"]["wall_seconds"],
        "evaluations": _total(r["ended_at"]["evaluations"]),
        "reached_cpu_seconds": None if reached is None else reached["cpu_seconds"],
        "reached_evaluations": None if reached is None else _total(reached["evaluations"]),
        "budget_cpu_seconds": rec["budget"].get("cpu_seconds"),
        "budget_evaluations": rec["budget"].get("sample_evaluations"),
    }


def _trace_rows(rec: dict[str, Any]) -> list[dict[str, Any]]:
    return [
        {
            "key": rec["key"],
            "instance": rec["instance"],
            "config": rec["config"],
            "trial": rec["trial"],
            "cpu_seconds": p["at"]["cpu_seconds"],
            "wall_seconds": p["at"]["wall_seconds"],
            "evaluations": _total(p["at"]["evaluations"]),
            "rmse": p["rmse"],
        }
        for p in rec["result"]["trace"]
    ]


def read_results(folder: str | os.PathLike[str]) -> Results:
    """Reads a results folder written by ``brdf-sls run`` or :func:`brdf_sls.run` (a plain or
    packed ``trials.jsonl``), with the statistics ``brdf-sls stats`` computes from it.

    Raises :class:`brdf_sls.InputError` naming the folder when it holds no readable results.
    """
    d = _native.read_results(os.fspath(folder))
    records = d["records"]
    stats = d["stats"]
    # The records are rendered by the library from its one analysis, like stats.csv.
    return Results(
        name=d["spec_name"],
        planned=d["planned"],
        present=d["present"],
        trials=[_trial_row(r) for r in records],
        traces=[row for r in records for row in _trace_rows(r)],
        stats=d["stats_rows"],
        tests=stats["tests"],
        finals=stats["finals"],
        header=d["header"],
        raw=records,
        warnings=d["warnings"],
    )
