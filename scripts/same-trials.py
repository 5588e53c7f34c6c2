#!/usr/bin/env python3
"""Checks that two runs of one spec took the same search paths, trial by trial: the check
behind a claim that a change keeps every figure (docs/performance.md). `brdf-sls compare`
asks whether two runs differ significantly; this asks whether they are the same.

    scripts/same-trials.py results/fig16-synthetic/trials.jsonl.gz runs/fig16-synthetic/trials.jsonl

Trials are matched by key (instance/configuration/trial), so two runs whose targets differ in
the last place still pair up. A trial that reached its target in both runs must have the same
evaluation counts, best RMSE and best parameters there. A trial that a CPU cutoff ended in
one run or both (another machine or load ends it at another point) must have made the same
improvements (evaluation counts and RMSEs) up to the earlier of its two ends.

Only the standard library. Exits 0 when every matched trial agrees, 1 when one differs (the
first few are printed), 2 on bad arguments or an unreadable file."""

import gzip
import json
import sys


def load(path):
    """The trial records of a trials.jsonl or trials.jsonl.gz file, by trial key."""
    opener = gzip.open if path.endswith(".gz") else open
    trials = {}
    with opener(path, "rt") as f:
        for number, line in enumerate(f, 1):
            try:
                record = json.loads(line)
            except json.JSONDecodeError as e:
                raise ValueError(f"{path}:{number}: not a JSON record ({e})") from e
            if not isinstance(record, dict):
                raise ValueError(f"{path}:{number}: not a JSON object")
            if record.get("type") == "trial":
                try:
                    trials[record["key"]] = record["result"]
                except KeyError as e:
                    raise ValueError(f"{path}:{number}: a trial record without {e}") from e
    return trials


def improvements(result):
    """The trial's trace: the evaluation counts and RMSE of each improvement."""
    return [(p["at"]["evaluations"], p["rmse"]) for p in result.get("trace", [])]


def same_prefix(a, b):
    ia, ib = improvements(a), improvements(b)
    m = min(len(ia), len(ib))
    return ia[:m] == ib[:m]


def same_end(a, b):
    return (
        a["reached_at"]["evaluations"] == b["reached_at"]["evaluations"]
        and a["best_rmse"] == b["best_rmse"]
        and a["best_x"] == b["best_x"]
    )


def main(argv):
    if len(argv) != 3 or argv[1] in ("-h", "--help"):
        print(__doc__.strip(), file=sys.stderr)
        return 2
    try:
        a, b = load(argv[1]), load(argv[2])
    except (OSError, ValueError, EOFError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    counts = {"matched": 0, "reached both": 0, "reached one": 0, "reached neither": 0}
    differ = []
    for key, ra in a.items():
        rb = b.get(key)
        if rb is None:
            continue
        counts["matched"] += 1
        reached = (ra["stop"] == "target", rb["stop"] == "target")
        if all(reached):
            counts["reached both"] += 1
            agree = same_end(ra, rb)
        else:
            counts["reached one" if any(reached) else "reached neither"] += 1
            agree = same_prefix(ra, rb)
        if not agree:
            differ.append(key)
    print(
        f"{counts['matched']} trials matched ({len(a)} in the first file, {len(b)} in the "
        f"second): {counts['reached both']} reached the target in both, "
        f"{counts['reached one']} in one only, {counts['reached neither']} in neither; "
        f"{len(differ)} took another path"
    )
    for key in differ[:5]:
        print(f"  differs: {key}")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
