"""`cosim matrix SPEC.toml`: run a co-simulation test matrix and report.

The lead hooks the subcommand into ``cosim/cli.py`` with::

    from .matrix import cli as matrix_cli
    matrix_cli.add_parser(sub)

(``python -m cosim.matrix ...`` runs the same command on its own.)
"""
from __future__ import annotations

import argparse
import sys

__all__ = ["add_parser", "run", "parser", "main"]

EPILOG = """\
exit status: 0 when every case agrees with its prediction (marginal cases excluded), no case failed
and every check of the spec passes; 1 otherwise; 2 for a spec or usage error.
Bundled specs (give the name instead of a file): {bundled}
"""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``cosim matrix`` on an ``argparse`` subparsers object."""
    from .spec import bundled_specs

    p = subparsers.add_parser(
        "matrix", help="run a co-simulation test matrix (cases x analytic predictions) and report",
        description="Run every case of a matrix spec (co-simulation + analytic prediction + classification), "
                    "in parallel, persisting each finished case; then check the spec's claims and write "
                    "DIR/report.md, DIR/report.html and heat maps.",
        epilog=EPILOG.format(bundled=", ".join(bundled_specs()) or "none"),
        formatter_class=argparse.RawDescriptionHelpFormatter)
    _arguments(p)
    p.set_defaults(func=run)
    return p


def _arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("spec", help="matrix spec (TOML file) or the name of a bundled spec")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="local worker processes (default: number of CPUs)")
    p.add_argument("--scheduler", default=None, metavar="tcp://HOST:PORT",
                   help="run the cases on this Dask scheduler instead of local processes")
    p.add_argument("-o", "--output", default=None, metavar="DIR",
                   help="output folder (default: matrix-<spec name>)")
    p.add_argument("--resume", action="store_true",
                   help="keep the results in DIR and run only the missing cases")
    p.add_argument("--fmu-dir", default=None, metavar="DIR", help="where models are built (default: fmus/)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")


def run(args) -> int:
    import json

    from ..errors import CosimError
    from .runner import run_matrix

    if args.workers is not None and args.workers < 1:
        print("error: --workers must be at least 1", file=sys.stderr)
        return 2
    try:
        result = run_matrix(args.spec, args.output, workers=args.workers, scheduler=args.scheduler,
                            resume=args.resume, fmu_dir=args.fmu_dir, progress=not args.no_progress)
    except CosimError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    c = result.counts
    if args.json:
        print(json.dumps(json.loads((result.directory / "summary.json").read_text()), indent=2))
    else:
        print(f"{result.spec.name}: {c['cases']} cases ({result.ran} run, {result.resumed} resumed) in "
              f"{result.seconds:.1f} s: {c['agree']} agree, {c['disagree']} disagree, {c['marginal']} marginal, "
              f"{c['failed']} failed")
        for ch in result.checks:
            if not ch.passed:
                print(f"FAIL {ch.study}: {ch.title}: {ch.details}")
        print(f"{'PASS' if result.passed else 'FAIL'}: report in {result.report.get('markdown')} and "
              f"{result.report.get('html')}")
    return result.exit_code


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="cosim matrix", description="Run a co-simulation test matrix.")
    _arguments(p)
    return p


def main(argv: list[str] | None = None) -> int:
    return run(parser().parse_args(argv))
