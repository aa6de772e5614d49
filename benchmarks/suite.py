"""The test suite's wall time, this tree side by side with a baseline tree in the same run.

Two tiers, each run as a developer runs it (``python -m pytest`` in the tree's folder, with that
tree's own ``pyproject.toml`` options: this tree runs on every core through pytest-xdist):

- quick: ``pytest -m "not slow"``, the inner loop (goal: at most 3 minutes on 2 cores);
- full: ``pytest``, everything CI runs (goal: at most 8 minutes on 2 cores).

The baseline is the committed tree (``git archive``) of ``--baseline`` (default ``ae32022``, the
suite before it ran in parallel; ``none`` skips it). Each tier runs in a fresh process with an
empty FMU folder and caches (the suite's own session folder), the trees alternating, ``--rounds``
times; medians. The summary line of each run (passed, failed, ...) is printed too: a faster run
that tests less is no gain. Times are wall seconds; the load average is printed, as the machine
may be shared.

    python benchmarks/suite.py [--baseline REF] [--tiers quick,full] [--rounds N]
"""
from __future__ import annotations

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from side_by_side import baseline_tree

ROOT = Path(__file__).resolve().parents[1]
BASELINE = "ae32022"
TIERS = {"quick": ["-m", "not slow"], "full": []}
GOALS = {"quick": 180.0, "full": 480.0}  # [s] on a 2-core machine (docs/benchmarks.md)


def run_tier(tree: Path, tier: str) -> tuple[float, str]:
    """Wall time [s] of one run of ``tier`` in ``tree`` and its pytest summary line."""
    env = {**os.environ, "PYTHONPATH": str(tree)}
    for name in ("COSIM_FMU_DIR", "COSIM_TEST_FMU_DIR", "COSIM_TEST_SESSION_TMP", "PYTEST_XDIST_WORKER"):
        env.pop(name, None)
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *TIERS[tier]],
                          cwd=tree, env=env, capture_output=True, text=True)
    seconds = time.perf_counter() - start
    lines = [line for line in done.stdout.splitlines() if re.search(r"\d+ (passed|failed|error)", line)]
    summary = lines[-1].strip("= ") if lines else f"exit {done.returncode}, no summary"
    return seconds, summary


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--baseline", default=BASELINE, help="git ref of the baseline tree, or 'none'")
    parser.add_argument("--tiers", default="quick,full", help="comma-separated: quick, full")
    parser.add_argument("--rounds", type=int, default=1)
    args = parser.parse_args(argv)
    tiers = [t for t in args.tiers.split(",") if t]
    unknown = sorted(set(tiers) - set(TIERS))
    if unknown:
        parser.error(f"unknown tier(s) {', '.join(unknown)} (known: {', '.join(TIERS)})")
    with tempfile.TemporaryDirectory(prefix="cosim-bench-suite-") as scratch:
        trees = {"this tree": ROOT}
        if args.baseline != "none":
            trees[f"baseline {args.baseline}"] = baseline_tree(args.baseline, Path(scratch) / "baseline", ())
        print(f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f} at the start")
        results: dict[tuple[str, str], list[float]] = {}
        for _ in range(args.rounds):
            for tier in tiers:
                for label, tree in trees.items():
                    seconds, summary = run_tier(tree, tier)
                    results.setdefault((tier, label), []).append(seconds)
                    print(f"  {tier:5s} {label:22s} {seconds:7.1f} s  ({summary})", flush=True)
        print(f"load average {os.getloadavg()[0]:.2f} at the end\n")
        print(f"{'tier':6s} {'tree':22s} {'median [s]':>10s}  goal")
        for tier in tiers:
            for label in trees:
                median = statistics.median(results[(tier, label)])
                verdict = ""
                if label == "this tree":
                    verdict = f"<= {GOALS[tier]:.0f} s: {'meets' if median <= GOALS[tier] else 'MISSES'}"
                print(f"{tier:6s} {label:22s} {median:10.1f}  {verdict}")
            if len(trees) == 2:
                base = statistics.median(results[(tier, list(trees)[1])])
                print(f"{tier:6s} {'ratio baseline/this':22s} {base / statistics.median(results[(tier, 'this tree')]):10.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
