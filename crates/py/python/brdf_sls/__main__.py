"""``python -m brdf_sls run SPEC``: runs an experiment as ``brdf-sls run SPEC`` does (the same
plan, progress, files and table), with the algorithms written in Python (``kind = "python"``)
importable; they run in worker processes, one per thread.

The flags are those of ``brdf-sls run``, and ``--no-processes`` (the Python algorithms on
threads of this interpreter); the exit status is 0 on success, 2 on bad input, 1 on a failure
while running, 130 on Ctrl-C. ``python -m brdf_sls worker`` is such a worker process: it runs
the trials its parent (``brdf-sls run`` or ``brdf_sls.run``) sends it.
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
    run.add_argument("--shard", default=None, metavar="K/N", help="run only shard K of N of the trial plan")
    run.add_argument("--progress", default="auto", help="progress display: auto, bars, plain or quiet")
    run.add_argument(
        "--no-processes",
        action="store_true",
        help="run the algorithms written in Python on threads of this interpreter (one core at a time) instead of worker processes",
    )
    sub.add_parser("worker", help=argparse.SUPPRESS)
    return p


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    if args.command == "worker":
        import signal

        # The run that started this worker answers Ctrl-C (it stops its workers).
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        from ._native import worker_main

        worker_main()
        return 0
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
            shard=args.shard,
            progress=args.progress,
            processes=not args.no_processes,
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
    # The plan, the notes and the count of new trials went to standard error as the run went.
    print(result["table"])
    print(result["summary"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
