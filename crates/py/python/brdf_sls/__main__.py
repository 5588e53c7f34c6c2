"""``python -m brdf_sls run SPEC``: runs an experiment as ``brdf-sls run SPEC`` does, with the
algorithms written in Python (``kind = "python"``) importable. ``brdf-sls run`` hands specs with
such algorithms to this command (in ``$BRDF_SLS_PYTHON``, else ``python3``).

The flags are those of ``brdf-sls run`` that ``brdf_sls.run`` supports; the exit status is 0
on success, 2 on bad input, 1 on a failure while running, 130 on Ctrl-C.
"""

from __future__ import annotations

import argparse
import os
import sys


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m brdf_sls", description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run or resume an experiment spec, then write statistics and plots")
    run.add_argument("spec", nargs="?", help="experiment spec (TOML); omit for the built-in default experiment")
    run.add_argument("--out", help="output directory (default: runs/<spec file stem>/)")
    run.add_argument("--threads", type=int, default=None, help="worker threads (default: $BRDF_SLS_THREADS, else the spec's, else all CPUs)")
    run.add_argument("--fresh", action="store_true", help="move an existing results file aside and start over")
    run.add_argument("--limit", type=int, default=None, metavar="N", help="run at most N new trials")
    run.add_argument("--no-plots", action="store_true", help="skip the plots")
    run.add_argument("--kernel", default=None, help="evaluation kernel: auto, avx512, avx2, portable or scalar")
    # Accepted so that `brdf-sls run`'s flags pass through; this command prints no progress.
    run.add_argument("--progress", default="auto", help=argparse.SUPPRESS)
    return p


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    from . import InputError, RunError, run

    threads = args.threads
    if threads is None and os.environ.get("BRDF_SLS_THREADS"):
        try:
            threads = int(os.environ["BRDF_SLS_THREADS"])
        except ValueError:
            print(f"error: BRDF_SLS_THREADS={os.environ['BRDF_SLS_THREADS']}: expected a number of threads", file=sys.stderr)
            return 2
    try:
        result = run(
            args.spec,
            args.out,
            threads=threads,
            fresh=args.fresh,
            limit=args.limit,
            plots=not args.no_plots,
            kernel=args.kernel,
        )
    except InputError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except RunError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("error: interrupted; the trials finished so far are saved, run again to resume", file=sys.stderr)
        return 130
    for line in result["notes"] + result["warnings"]:
        print(f"note: {line}", file=sys.stderr)
    print(
        f"{result['new_trials']} new trials ({result['resumed']} resumed)"
        + (f"; {result['missing']} trials still to run (run again to resume)" if result["missing"] else ""),
        file=sys.stderr,
    )
    print(result["table"])
    print(f"results: {result['out']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
