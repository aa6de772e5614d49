"""`cosim matrix SPEC.toml`: run a co-simulation test matrix and report.

The lead hooks the subcommand into ``cosim/cli.py`` with::

    from .matrix import cli as matrix_cli
    matrix_cli.add_parser(sub)

(``python -m cosim.matrix ...`` runs the same command on its own.)
"""
from __future__ import annotations

import argparse
import sys

from ..cli import positive_int

__all__ = ["add_parser", "run", "parser", "main"]

EPILOG = """\
an output folder that already holds results is refused unless --resume (keep them: run only the
missing cases, and the failed ones again unless --keep-failed) or --force (discard them) is given.
exit status: 0 when every case agrees with its prediction (marginal cases excluded), no case failed
and every check of the spec passes; 1 otherwise; 2 for a spec or usage error.
Bundled specs (give the name instead of a file): {bundled}
"""


def _bundled() -> list[str]:
    from .spec import bundled_specs

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
    from .spec import MAX_CASES

    p.add_argument("spec", help="matrix spec (TOML file) or the name of a bundled spec")
    p.add_argument("--workers", type=positive_int, default=None, metavar="N",
                   help="local worker processes, >= 1 (default: number of CPUs)")
    p.add_argument("--scheduler", default=None, metavar="tcp://HOST:PORT",
                   help="run the cases on this Dask scheduler instead of local processes (contacted first; "
                        "an unreachable one is an error within a few seconds)")
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
    p.add_argument("--max-cases", type=positive_int, default=MAX_CASES, metavar="N",
                   help=f"refuse specs with more than N cases, checked before they are expanded (default: {MAX_CASES})")
    p.add_argument("--fmu-dir", default=None, metavar="DIR", help="where models are built (default: fmus/)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")


def run(args) -> int:
    import json

    from ..errors import CosimError
    from .runner import run_matrix

    if args.keep_failed and not args.resume:
        print("cosim matrix: error: --keep-failed applies only with --resume", file=sys.stderr)
        return 2
    try:
        result = run_matrix(args.spec, args.output, workers=args.workers, scheduler=args.scheduler,
                            resume=args.resume, force=args.force, keep_failed=args.keep_failed,
                            max_cases=args.max_cases, fmu_dir=args.fmu_dir, progress=not args.no_progress)
    except CosimError as exc:
        print(f"cosim matrix: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("cosim matrix: interrupted (the finished cases are kept: --resume runs the rest)", file=sys.stderr)
        return 130
    c = result.counts
    if args.json:
        print(json.dumps(json.loads((result.directory / "summary.json").read_text()), indent=2))
    else:
        again = f", {result.retried} failed run again" if result.retried else ""
        print(f"{result.spec.name}: {c['cases']} cases ({result.ran} run, {result.resumed} resumed{again}) in "
              f"{result.seconds:.1f} s: {c['agree']} agree, {c['disagree']} disagree, {c['marginal']} marginal, "
              f"{c['failed']} failed")
        for ch in result.checks:
            if not ch.passed:
                print(f"FAIL {ch.study}: {ch.title}: {ch.details}")
        print(f"{'PASS' if result.passed else 'FAIL'}: report in {result.report.get('markdown')} and "
              f"{result.report.get('html')}")
    return result.exit_code


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="cosim matrix", description="Run a co-simulation test matrix.",
                                epilog=EPILOG.format(bundled=", ".join(_bundled()) or "none"),
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    _arguments(p)
    return p


def main(argv: list[str] | None = None) -> int:
    return run(parser().parse_args(argv))
