"""Linearization over forward speed: the sweep (:func:`cosim.bicycle.linearize.linearize_speeds`, one
FMU instance re-initialized per speed through the raw FMI functions, the lateral reduction for all
speeds in one vectorized pass) against the single-speed API loop (:func:`linearize` and
:func:`steady_motion` per speed, a new instance each), per speed and as a ratio, for the nonlinear
``Whipple`` and ``WhippleRider`` and the ``WhippleLinear`` model; the sweep by continuation (the
default: the instance stays in initialization mode and only the speed parameter changes, the
initial pitch solved from the previous speed's) against initialization from scratch at every speed
(``continuation=False``), per speed, as a ratio and with the largest difference of their A
matrices (0: the same numbers); then the command whose time docs/benchmarks.md sets a goal for,
``cosim linearize Bicycle.Bicycles.Whipple --speeds 0:10:0.01 --json`` (1001 speeds, FMU already
built): wall time of the process and the compute part (the sweep and its eigenvalues in-process).

Times are medians of ROUNDS runs (the machine may be shared); nothing is asserted.
Usage: ``python benchmarks/linearize.py [FMU_FOLDER]`` (default: COSIM_FMU_DIR or a temporary
folder; the models are built there if needed).
"""
from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


import numpy as np

from cosim.compiler.build import build_model
from cosim.compiler.library import load_library
from cosim.bicycle.linearize import linearize_speeds, steady_motion
from cosim.fmu.linearize import linearize

ROUNDS = 5
MODELS = {"Bicycle.Bicycles.Whipple": "u_R0", "Bicycle.Bicycles.WhippleRider": "u_R0",
          "Bicycle.Bicycles.WhippleLinear": "v"}
LOOP_SPEEDS = np.round(np.arange(0, 101) * 0.1, 12)  # the single-speed loop: 101 speeds (it is slow)
SWEEP_SPEEDS = np.round(np.arange(0, 1001) * 0.01, 12)  # the sweep: 1001 speeds, as in docs/benchmarks.md
RADIUS = 0.3  # rR [m] of the nonlinear models' defaults


def median_time(f, rounds: int = ROUNDS) -> float:
    times = []
    for _ in range(rounds):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def single_loop(fmu: Path, parameter: str, speeds) -> None:
    for v in speeds:
        lin = linearize(fmu, {parameter: -v / RADIUS if parameter == "u_R0" else float(v)})
        lin.eigenvalues
        if parameter == "u_R0":
            steady_motion(lin).eigenvalues


def sweep(fmu: Path, speeds, continuation: bool = True):
    s = linearize_speeds(fmu, speeds, continuation=continuation)
    s.eigenvalues
    if s.steady is not None:
        s.lateral_eigenvalues
    return s


def alternating(f, g, rounds: int = ROUNDS) -> tuple[float, float]:
    """Median times of f and g [s], run alternately (the same load for both)."""
    times = ([], [])
    for _ in range(rounds):
        for k, h in enumerate((f, g)):
            t0 = time.perf_counter()
            h()
            times[k].append(time.perf_counter() - t0)
    return statistics.median(times[0]), statistics.median(times[1])


def main(folder: Path) -> None:
    library = load_library()
    fmus = {m: build_model(m, folder, library).fmu for m in MODELS}
    print(f"per speed [ms], median of {ROUNDS} runs (loop: {len(LOOP_SPEEDS)} speeds, "
          f"sweep: {len(SWEEP_SPEEDS)} speeds)")
    print(f"{'model':<32} {'single-speed API':>17} {'sweep':>9} {'ratio':>7}")
    for model, parameter in MODELS.items():
        sweep(fmus[model], SWEEP_SPEEDS[:2])  # extraction and first load outside the timing
        loop = median_time(lambda: single_loop(fmus[model], parameter, LOOP_SPEEDS)) / len(LOOP_SPEEDS)
        fast = median_time(lambda: sweep(fmus[model], SWEEP_SPEEDS)) / len(SWEEP_SPEEDS)
        print(f"{model:<32} {loop * 1e3:>17.3f} {fast * 1e3:>9.4f} {loop / fast:>7.1f}")
    print(f"\nthe sweep by continuation vs from scratch at every speed [ms per speed], median of {ROUNDS} "
          f"alternating runs ({len(SWEEP_SPEEDS)} speeds; load average {os.getloadavg()[0]:.2f}, "
          f"{os.cpu_count()} CPUs)")
    print(f"{'model':<32} {'from scratch':>13} {'continuation':>13} {'ratio':>7} {'max |dA|':>9}")
    for model in MODELS:
        scratch, continued = alternating(lambda: sweep(fmus[model], SWEEP_SPEEDS, False),
                                         lambda: sweep(fmus[model], SWEEP_SPEEDS, True))
        a, b = sweep(fmus[model], SWEEP_SPEEDS, False), sweep(fmus[model], SWEEP_SPEEDS, True)
        difference = max(float(np.abs(x.A - y.A).max()) for x, y in zip(a.systems, b.systems))
        n = len(SWEEP_SPEEDS)
        print(f"{model:<32} {scratch / n * 1e3:>13.4f} {continued / n * 1e3:>13.4f} {scratch / continued:>7.2f} "
              f"{difference:>9.1e}")
    whipple = "Bicycle.Bicycles.Whipple"
    compute = median_time(lambda: sweep(fmus[whipple], SWEEP_SPEEDS))
    command = [sys.executable, "-m", "cosim", "linearize", whipple, "--speeds", "0:10:0.01", "--json"]
    env = {**os.environ, "COSIM_FMU_DIR": str(folder)}
    walls = []
    for _ in range(ROUNDS):
        t0 = time.perf_counter()
        r = subprocess.run(command, capture_output=True, text=True, env=env)
        walls.append(time.perf_counter() - t0)
        if r.returncode != 0:
            raise SystemExit(f"{' '.join(command[2:])} failed: {r.stderr.strip()}")
    start = median_time(lambda: subprocess.run([sys.executable, "-m", "cosim", "--help"], capture_output=True,
                                               env=env))
    print(f"\n`cosim {' '.join(command[3:])}` ({len(SWEEP_SPEEDS)} speeds, {len(r.stdout) / 1e6:.2f} MB of JSON):")
    print(f"  compute (sweep + eigenvalues, in-process): {compute:.3f} s")
    print(f"  wall (process, median of {ROUNDS}):         {statistics.median(walls):.3f} s "
          f"(min {min(walls):.3f} s; `cosim --help` alone: {start:.3f} s)")


if __name__ == "__main__":
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("fmu_folder", nargs="?", type=Path,
                        help="where the FMUs are (built there if needed); default: COSIM_FMU_DIR or a temporary folder")
    args = parser.parse_args()
    if args.fmu_folder is not None:
        main(args.fmu_folder)
    elif os.environ.get("COSIM_FMU_DIR"):
        main(Path(os.environ["COSIM_FMU_DIR"]))
    else:
        with tempfile.TemporaryDirectory() as tmp:
            main(Path(tmp))
