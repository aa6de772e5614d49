"""`cosim figures` (all seven) and `cosim demo`, measured side by side with a baseline in one run.

The baseline is the committed tree (``git archive``) of ``--baseline`` (default ``ae32022``, before
the figures ran in parallel and the demo's validation skipped FMPy's name parser for plain names).
The FMUs are built once beforehand into one shared ``COSIM_FMU_DIR`` (by both trees: each finds
them up to date), so that both commands measure with the FMUs built, as after ``cosim build``.
Each measurement is a fresh ``python -m cosim ...`` with ``PYTHONPATH`` pointing to the tree;
the trees alternate, ``--rounds`` times; medians of wall and CPU time (the command and its worker
processes). The targets of docs/benchmarks.md are printed with "meets" or "MISSES":
``cosim figures`` <= 8 s and ``cosim demo`` <= 15 s on a quiet 2-core machine.

Content check: the files of both trees' last runs compared, JSON numbers (largest relative
difference, target 0: bit for bit) and PNG pixels (decoded by matplotlib; the PNG metadata may
differ), the demo's CSV files byte for byte. The machine may be shared: the load average before
and after is printed, and the CPU time shows what the commands did whatever the load.

    python benchmarks/figures.py [--baseline REF] [--rounds N] [--jobs N]
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from side_by_side import baseline_tree, children_cpu, verdict

ROOT = Path(__file__).resolve().parents[1]
ROUNDS = 3
# The targets of docs/benchmarks.md (wall seconds on this project's 2-core machines, FMUs built)
FIGURES_TARGET, DEMO_TARGET = 8.0, 15.0


def run(root: Path, argv: list[str], fmus: Path, scratch: Path) -> tuple[float, float]:
    """``python -m cosim ARGV`` with the tree ``root`` first on the path: (wall [s], CPU [s])."""
    env = {k: v for k, v in os.environ.items() if k not in ("COSIM_MODELICA_PATH", "PYTHONPATH")}
    env.update(PYTHONPATH=str(root), COSIM_FMU_DIR=str(fmus))
    t0, c0 = time.perf_counter(), children_cpu()
    result = subprocess.run([sys.executable, "-m", "cosim", *argv], capture_output=True, text=True, env=env,
                            cwd=scratch)
    wall, cpu = time.perf_counter() - t0, children_cpu() - c0
    if result.returncode != 0:
        raise RuntimeError(f"cosim {' '.join(argv)} in {root} failed ({result.returncode}):\n{result.stderr[-3000:]}")
    return wall, cpu


def _numbers(value, path=""):
    if isinstance(value, dict):
        for key, item in value.items():
            yield from _numbers(item, f"{path}/{key}")
    elif isinstance(value, list):
        for i, item in enumerate(value):
            yield from _numbers(item, f"{path}[{i}]")
    else:
        yield path, value


def compare(a: Path, b: Path) -> tuple[list[str], float]:
    """The differences between the files of two output folders (one line each) and the largest
    relative difference of a JSON number."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    problems, worst = [], 0.0
    names = sorted({p.name for p in a.iterdir()} | {p.name for p in b.iterdir()})
    for name in names:
        fa, fb = a / name, b / name
        if not (fa.is_file() and fb.is_file()):
            problems.append(f"{name}: written by one tree only")
        elif name.endswith(".png"):
            pa, pb = plt.imread(fa), plt.imread(fb)
            if pa.shape != pb.shape or not np.array_equal(pa, pb):
                problems.append(f"{name}: pixels differ")
        elif name.endswith(".json"):
            na, nb = dict(_numbers(json.loads(fa.read_text()))), dict(_numbers(json.loads(fb.read_text())))
            if na.keys() != nb.keys():
                problems.append(f"{name}: different keys")
                continue
            for key, x in na.items():
                y = nb[key]
                if isinstance(x, (int, float)) and isinstance(y, (int, float)) and not isinstance(x, bool):
                    if x != y:
                        worst = max(worst, abs(x - y) / max(abs(x), abs(y), 1e-300))
                elif x != y:
                    problems.append(f"{name}: {key} differs: {x!r} / {y!r}")
        elif fa.read_bytes() != fb.read_bytes():
            problems.append(f"{name}: bytes differ")
    if worst > 0.0:
        problems.append(f"JSON numbers differ, largest relative difference {worst:.3g}")
    return problems, worst


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", default="ae32022", help="git ref of the baseline (default: ae32022)")
    parser.add_argument("--rounds", type=int, default=ROUNDS, help=f"repetitions, medians (default: {ROUNDS})")
    args = parser.parse_args()
    load_before = os.getloadavg()
    with tempfile.TemporaryDirectory(prefix="cosim-bench-") as tmp:
        scratch = Path(tmp)
        trees = {"baseline": baseline_tree(args.baseline, scratch / "baseline"), "current": ROOT}
        fmus = scratch / "fmus"
        for root in trees.values():  # built once (the second tree finds them up to date)
            run(root, ["build", "-j", "2"], fmus, scratch)
        commands = {"figures": ["figures"], "demo": ["demo"]}
        times: dict[tuple[str, str], list[tuple[float, float]]] = {}
        for k in range(args.rounds):
            for command, argv in commands.items():
                for label, root in trees.items():
                    out = scratch / f"{command}-{label}"
                    times.setdefault((command, label), []).append(run(root, [*argv, "-o", str(out)], fmus, scratch))
        load_after = os.getloadavg()
        print(f"median of {args.rounds} alternating runs, each a fresh process, FMUs built; baseline "
              f"{args.baseline}; {os.cpu_count()} CPUs, load average {load_before[0]:.2f} before, "
              f"{load_after[0]:.2f} after (1 min)\n")
        medians = {key: [statistics.median(t[i] for t in runs) for i in (0, 1)] for key, runs in times.items()}
        for command in commands:
            b, c = medians[(command, "baseline")], medians[(command, "current")]
            print(f"cosim {command:8s} baseline {b[0]:6.2f} s wall {b[1]:6.2f} s CPU | current {c[0]:6.2f} s wall "
                  f"{c[1]:6.2f} s CPU   current/baseline: {c[0] / b[0]:5.2f}x wall {c[1] / b[1]:5.2f}x CPU")
        verdict("cosim figures (all seven)", medians[("figures", "current")][0], FIGURES_TARGET)
        verdict("cosim demo", medians[("demo", "current")][0], DEMO_TARGET)
        print()
        for command in commands:
            problems, worst = compare(scratch / f"{command}-baseline", scratch / f"{command}-current")
            files = len(list((scratch / f"{command}-current").iterdir()))
            print(f"content of cosim {command} ({files} files), baseline vs current: "
                  + ("the same (PNG pixels, JSON numbers bit for bit, other files byte for byte)" if not problems
                     else "; ".join(problems))
                  + f" ({'meets' if worst <= 1e-12 and not [p for p in problems if 'JSON numbers' not in p] else 'MISSES'}"
                  " <= 1e-12 relative)")


if __name__ == "__main__":
    main()
