"""`cosim matrix SPEC.toml`: run a co-simulation test matrix and report."""
from __future__ import annotations

import argparse
import json
import sys

from cosim.cli_options import library_option, positive_int
from cosim.progress import active
from cosim.matrix.spec import MAX_CASES, bundled_specs

__all__ = ["add_parser", "run"]

EPILOG = """\
an output folder that already holds results is refused unless --resume (keep them: run only the
missing cases, and the failed ones again unless --keep-failed) or --force (discard them) is given.
One run writes a folder at a time: a run on a folder that another run is writing is refused, naming
that run (pid, command, start time); the lock of a killed run ends with it (--resume continues).
--scheduler needs the optional extra `cluster` (pip install 'bicycle-cosim[cluster]').
exit status: 0 when every case agrees with its prediction (marginal cases excluded), no case failed
and every check of the spec passes; 1 otherwise; 2 for a spec or usage error (one line
`cosim matrix: error: ...`); 4 when results cannot be written (disk full, quota, ...: the message
names the file; the cases recorded so far are kept, --resume runs the rest); 130 when interrupted
(the finished cases are kept).
Bundled specs (give the name instead of a file): {bundled}
"""


def _bundled() -> list[str]:
    return bundled_specs()


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``cosim matrix`` on an ``argparse`` subparsers object."""
    p = subparsers.add_parser(
        "matrix", help="run a co-simulation test matrix (cases x analytic predictions) and report",
        description="Run every case of a matrix spec (co-simulation + analytic prediction + classification), "
                    "in parallel, persisting each finished case; then check the spec's claims and write "
                    "DIR/report.md, DIR/report.html and heat maps.",
        epilog=EPILOG.format(bundled=", ".join(_bundled()) or "none"),
        formatter_class=argparse.RawDescriptionHelpFormatter)
    _arguments(p)
    p.set_defaults(func=run)
    return p


def _arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("spec", help="matrix spec (TOML file) or the name of a bundled spec")
    p.add_argument("--workers", type=positive_int, default=None, metavar="N",
                   help="local worker processes, >= 1 (default: number of CPUs)")
    p.add_argument("--scheduler", default=None, metavar="tcp://HOST:PORT",
                   help="run the cases on this Dask scheduler instead of local processes (contacted first; "
                        "an unreachable one is an error within a few seconds; needs the extra `cluster`)")
    p.add_argument("-o", "--output", default=None, metavar="DIR",
                   help="output folder (default: matrix-<spec name>)")
    again = p.add_mutually_exclusive_group()
    again.add_argument("--resume", action="store_true",
                       help="keep the results in DIR and run only the missing cases, and the failed ones again "
                            "(a crashed or killed worker, a timeout) unless --keep-failed")
    again.add_argument("--force", action="store_true",
                       help="discard the results already in DIR and run every case")
    p.add_argument("--keep-failed", action="store_true",
                   help="with --resume: keep failed cases as they are instead of running them again")
    p.add_argument("--max-cases", type=positive_int, default=None, metavar="N",
                   help="run at most N cases: a spec with more runs a stratified sample of N, the same every run, "
                        "in which every value of every axis appears when N allows (stderr and the report say so); "
                        f"without it a spec of more than {MAX_CASES} cases is refused before its axes are expanded")
    p.add_argument("--fmu-dir", default=None, metavar="DIR",
                   help="where models are built (default: $COSIM_FMU_DIR, else ./fmus)")
    library_option(p)
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")


def run(args) -> int:
    """Run ``cosim matrix`` with parsed ``args``; returns the exit status.

    Raises
    ------
    CosimError
        For a spec, output-folder or usage error (printed by :func:`cosim.cli.main`).
    """
    from cosim.matrix.runner import run_matrix  # deferred: not needed to build the parser of every verb

    try:
        result = run_matrix(args.spec, args.output, workers=args.workers, scheduler=args.scheduler,
                            resume=args.resume, force=args.force, keep_failed=args.keep_failed,
                            max_cases=args.max_cases, fmu_dir=args.fmu_dir, progress=not (args.no_progress or active().quiet))
    except KeyboardInterrupt:
        print("cosim matrix: interrupted (the finished cases are kept: --resume runs the rest)", file=sys.stderr)
        return 130
    c = result.counts
    if args.json:
        print(json.dumps(json.loads((result.directory / "summary.json").read_text()), indent=2))
    else:
        again = f", {result.retried} failed run again" if result.retried else ""
        sampled = f" (a sample of the spec's {result.total})" if result.sample else ""
        print(f"{result.spec.name}: {c['cases']} cases{sampled} ({result.ran} run, {result.resumed} resumed{again}) "
              f"in "
              f"{result.seconds:.1f} s: {c['agree']} agree, {c['disagree']} disagree, {c['marginal']} marginal, "
              f"{c['failed']} failed")
        for ch in result.checks:
            if not ch.passed:
                print(f"FAIL {ch.study}: {ch.title}: {ch.details}")
        print(f"{'PASS' if result.passed else 'FAIL'}: report in {result.report.get('markdown')} and "
              f"{result.report.get('html')}")
    return result.exit_code
