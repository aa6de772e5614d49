"""`cosim app --export` on a machine that never built, measured side by side with a baseline.

Each run is ``python -m cosim app --export SITE`` in a fresh process with an empty
``XDG_CACHE_HOME`` (no pymoca parse cache, no compiled runtime, no Zig cache: Zig compiles its
wasi-libc again) and an empty ``COSIM_FMU_DIR``, the tree measured first on ``PYTHONPATH``. The
baseline (the committed ``cosim/`` and ``modelica/`` of ``--baseline``, default ``ae32022``, the
tree before the app shipped its WebAssembly modules, unpacked with ``git archive``) and this tree
alternate, ROUNDS times; medians of wall and CPU time (the process and its children: pool
workers, gcc, Zig) are printed with the ratio and whether the goals of docs/benchmarks.md are met
(<= 5 s on 2 cores, >= 6x faster than the baseline). The bundles (bundle.js) of every run are
compared byte for byte: the page must not change.

    python benchmarks/app.py [--baseline REF] [--rounds N]
"""
from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from side_by_side import baseline_tree, children_cpu

ROOT = Path(__file__).resolve().parents[1]
ROUNDS = 3
TARGET, SPEEDUP = 5.0, 6.0  # [s] wall on 2 cores; baseline / current


def export(root: Path, scratch: Path) -> tuple[float, float, bytes]:
    """One fresh export with the tree ``root``: wall [s], CPU [s] and the bundle's bytes."""
    with tempfile.TemporaryDirectory(dir=scratch) as tmp:
        tmp = Path(tmp)
        env = {k: v for k, v in os.environ.items() if k != "COSIM_MODELICA_PATH"}
        env.update(PYTHONPATH=str(root), XDG_CACHE_HOME=str(tmp / "cache"), COSIM_FMU_DIR=str(tmp / "fmus"))
        c0, t0 = children_cpu(), time.perf_counter()
        done = subprocess.run([sys.executable, "-m", "cosim", "app", "--export", str(tmp / "site")],
                              capture_output=True, text=True, env=env, cwd=tmp)
        wall, cpu = time.perf_counter() - t0, children_cpu() - c0
        if done.returncode != 0:
            raise RuntimeError(f"cosim app --export with {root} failed ({done.returncode}):\n{done.stderr[-3000:]}")
        return wall, cpu, (tmp / "site" / "bundle.js").read_bytes()


def differing_keys(a: bytes, b: bytes) -> list[str]:
    """The keys of ``window.COSIM_DATA`` that differ between two bundles (``<scripts>`` if the
    rest of the bundle does)."""
    def split(bundle):
        text = bundle.decode("utf-8")
        line = re.search(r"^window\.COSIM_DATA = (.*);$", text, re.M)
        return json.loads(line.group(1)), text[:line.start()] + text[line.end():]

    (da, ra), (db, rb) = split(a), split(b)
    keys = sorted(k for k in da.keys() | db.keys() if da.get(k) != db.get(k))
    return keys + (["<scripts>"] if ra != rb else [])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--baseline", default="ae32022", help="git ref of the baseline (default ae32022)")
    parser.add_argument("--rounds", type=int, default=ROUNDS)
    args = parser.parse_args()
    print(f"load average {' '.join(f'{x:.2f}' for x in os.getloadavg())}, {os.cpu_count()} CPUs")
    with tempfile.TemporaryDirectory(prefix="cosim-bench-app-") as scratch:
        scratch = Path(scratch)
        trees = {"baseline": baseline_tree(args.baseline, scratch / "baseline"), "current": ROOT}
        runs = {label: [] for label in trees}
        bundles = {}
        for k in range(args.rounds):
            for label, root in trees.items():
                wall, cpu, bundle = export(root, scratch)
                runs[label].append((wall, cpu))
                bundles.setdefault(label, bundle)
                if bundle != bundles[label]:
                    print(f"  {label}: the bundle of round {k + 1} differs from round 1 "
                          f"({', '.join(differing_keys(bundles[label], bundle))})")
                print(f"  round {k + 1} {label:8s} {wall:6.2f} s wall {cpu:6.2f} s CPU")
    med = {label: [statistics.median(r[i] for r in runs[label]) for i in (0, 1)] for label in runs}
    for label, (wall, cpu) in med.items():
        print(f"{label:8s} median of {args.rounds}: {wall:6.2f} s wall {cpu:6.2f} s CPU")
    speedup = med["baseline"][0] / med["current"][0]
    print(f"baseline/current: {speedup:.1f}x wall, {med['baseline'][1] / med['current'][1]:.1f}x CPU")
    print(f"  target: fresh `cosim app --export` <= {TARGET:g} s on 2 cores: {med['current'][0]:.2f} s, "
          f"{'meets' if med['current'][0] <= TARGET else 'MISSES'}")
    print(f"  target: >= {SPEEDUP:g}x faster than the baseline: {speedup:.1f}x, "
          f"{'meets' if speedup >= SPEEDUP else 'MISSES'}")
    same = bundles["baseline"] == bundles["current"]
    print(f"bundle.js of both trees: {'byte for byte identical' if same else 'DIFFERENT'}"
          + ("" if same else f" (COSIM_DATA keys: {', '.join(differing_keys(bundles['baseline'], bundles['current']))})")
          + f", {len(bundles['current'])} bytes")
    print(f"load average {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
