"""Throughput of `cosim matrix`: ten-second co-simulation runs per minute with 1 and 2 workers.

Two workloads of 10 s runs (1000 communication steps of 0.01 s, none falls, so every run is full
length), each case with its analytic prediction, classification and JSON Lines record:

* ``fmu-only``: the benchmark bicycle (WhippleLinear FMU) at self-stable speeds, perturbed by an
  initial roll angle (the master's C stepping loop);
* ``rider+delay``: the same FMU with a Python rider ``T = -k phi(t - tau)`` (Proportional and an
  exact TransportDelay).

Best of --repeat runs. "steady" counts from the moment every worker is ready; "wall" is the whole
``run_matrix`` call (spec expansion, up-to-date check of the FMU, worker start-up -- forked
workers inherit the supervisor's imports --, the runs, the records, the checks).

Then, side by side with ``--baseline REF`` (default HEAD; ``none`` skips it): the steady rate on 2
workers of each tree (what a worker's first cases cost is in it), and the CPU time of one
case (prediction, co-simulation, classification: ``cosim.matrix.worker.run_case``) in one
process with one BLAS thread, each tree in a fresh process, alternating, medians -- the cost the
throughput is made of, without the machine's scaling and the supervisor.

Targets (docs/benchmarks.md; 2 workers, 600 runs), each printed as measured / target, side by side:
  fmu-only     steady >= 150,000 runs/min
  fmu-only     wall rate >= 50 % of the steady rate (start-up must stay around <= 0.24 s)
  rider+delay  steady >= 30,000 runs/min
"""
from __future__ import annotations

import argparse
import importlib.util
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def workload(name: str, n: int) -> dict:
    speeds = [4.6 + 1.2 * k / max(n - 1, 1) for k in range(n)]  # inside 4.29-6.02 m/s
    bike = {"model": "Bicycle.Bicycles.WhippleLinear", "parameter_set": "benchmark",
            "parameters": {"v": "=v", "phi0": 0.01}}
    if name == "fmu-only":
        study = {"name": name, "observe": "bike.phi", "connections": [], "components": {"bike": bike}}
    else:
        study = {"name": name, "observe": "bike.phi",
                 "connections": ["bike.phi -> rider.phi", "rider.T -> delay.u", "delay.y -> bike.T_delta"],
                 "components": {"bike": bike, "rider": {"python": "Proportional", "parameters": {"k": 0.5}},
                                "delay": {"python": "TransportDelay", "parameters": {"tau": 0.1}}}}
    study["axes"] = {"v": speeds}
    return {"matrix": {"name": name, "stop": 10.0, "step": 0.01, "extend": 1.0}, "study": [study]}


def measure(name: str, n: int, workers: int, out: Path, repeat: int) -> dict:
    """Best of ``repeat`` runs (the machine may be shared): the best steady and the best wall time."""
    from cosim.matrix.runner import run_matrix
    from cosim.matrix.spec import spec_from_dict

    spec = spec_from_dict(workload(name, n))
    best = best_wall = None
    for k in range(repeat):
        t0 = time.perf_counter()
        result = run_matrix(spec, out / f"{name}-{workers}-{k}", workers=workers, progress=False, report=False)
        wall = time.perf_counter() - t0
        if best is None or result.timing["run"] < best.timing["run"]:
            best = result
        best_wall = wall if best_wall is None else min(best_wall, wall)
    result = best
    full = sum(1 for r in result.records if (r.get("outcome") or {}).get("steps") == 1000)
    bad = result.counts["failed"] + result.counts["disagree"]
    return {"runs": len(result.records), "full": full, "bad": bad, "steady": result.timing["run"],
            "startup": result.timing["startup"], "wall": best_wall, "start": result.timing.get("start")}


# One tree's CPU time per case: argv = root, the workload as JSON, rounds; prints the median [ms].
CASE_CHILD = r"""
import dataclasses, json, statistics, sys, time
root, data, rounds = sys.argv[1], json.loads(sys.argv[2]), int(sys.argv[3])
sys.path.insert(0, root)
import cosim
from cosim.matrix import worker
from cosim.matrix.runner import build_fmus
from cosim.matrix.spec import spec_from_dict
assert cosim.__file__.startswith(root), cosim.__file__
specs = spec_from_dict(data).cases()
cases, fmu_paths, cache = [dataclasses.asdict(c) for c in specs], build_fmus(specs, None), worker.FMUCache()
for case in cases[:20]:
    worker.run_case(case, cache, fmu_paths)
times = []
for _ in range(rounds):
    t0 = time.process_time()
    for case in cases:
        worker.run_case(case, cache, fmu_paths)
    times.append((time.process_time() - t0) / len(cases) * 1e3)
print(json.dumps(statistics.median(times)))
"""


# One tree's steady rate [runs/min] on 2 workers: argv = root, the workload as JSON, workers, repeat.
RATE_CHILD = r"""
import json, sys, tempfile
root, data, workers, repeat = sys.argv[1], json.loads(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
sys.path.insert(0, root)
import cosim
from cosim.matrix.runner import build_fmus, run_matrix
from cosim.matrix.spec import spec_from_dict
assert cosim.__file__.startswith(root), cosim.__file__
spec = spec_from_dict(data)
build_fmus(spec.cases(), None)
with tempfile.TemporaryDirectory() as tmp:
    runs = [run_matrix(spec, f"{tmp}/{k}", workers=workers, progress=False, report=False) for k in range(repeat)]
print(json.dumps(max(len(r.records) / r.timing["run"] * 60 for r in runs)))
"""


def _child(code: str, root: Path, fmu_dir: Path, *args) -> float:
    """Run a measurement on the tree ``root`` in a fresh process, its FMUs built into ``fmu_dir``."""
    env = {**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
           "COSIM_FMU_DIR": str(fmu_dir)}
    result = subprocess.run([sys.executable, "-c", code, str(root), *map(str, args)], capture_output=True, text=True,
                            env=env, cwd=tempfile.gettempdir())
    if result.returncode != 0:
        raise RuntimeError(f"measurement in {root} failed:\n{result.stderr[-3000:]}")
    return float(result.stdout.strip().splitlines()[-1])


#: Matrices per process of the side-by-side steady rate (the best is kept).
RATE_REPEAT = 2


def steady_rate(root: Path, fmu_dir: Path, name: str, n: int, workers: int = 2, repeat: int = RATE_REPEAT) -> float:
    """Best steady rate [runs/min] of ``repeat`` matrices of the workload ``name`` on the tree ``root``."""
    return _child(RATE_CHILD, root, fmu_dir, json.dumps(workload(name, n)), workers, repeat)


def case_cpu(root: Path, fmu_dir: Path, name: str, n: int = 200, rounds: int = 3) -> float:
    """Median CPU time [ms] of one case of the workload ``name`` in a fresh process on the tree ``root``."""
    return _child(CASE_CHILD, root, fmu_dir, json.dumps(workload(name, n)), rounds)


def baseline_tree(ref: str, folder: Path) -> Path:
    """``benchmarks/build.py``'s committed tree of ``ref`` (loaded by path: ``build`` is also the
    name of a PyPA package)."""
    spec = importlib.util.spec_from_file_location("cosim_bench_build", Path(__file__).with_name("build.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.baseline_tree(ref, folder)


def _medians(trees: dict, rounds: int, measure) -> tuple[float, float]:
    """Medians of ``measure(root, fmu_dir)`` for the baseline and the current tree, alternating."""
    values = {label: [] for label in trees}
    for _ in range(rounds):
        for label, tree in trees.items():
            values[label].append(measure(*tree))
    return statistics.median(values["baseline"]), statistics.median(values["current"])


def side_by_side(baseline: str, rounds: int, runs: int) -> None:
    """Steady rate on 2 workers and CPU per case of the current tree and ``baseline`` (a git ref),
    alternating fresh processes, medians."""
    with tempfile.TemporaryDirectory(prefix="cosim-bench-") as tmp:
        # (tree, its FMU folder): the children run in the temporary folder, whose ./fmus they would fill
        trees = {"baseline": (baseline_tree(baseline, Path(tmp) / "baseline"), Path(tmp) / "fmus-baseline"),
                 "current": (ROOT, Path(tmp) / "fmus-current")}
        print(f"steady rate of {runs} runs on 2 workers (best of {RATE_REPEAT} per process), median of {rounds} alternating "
              f"fresh processes; baseline: {baseline}")
        for name in ("fmu-only", "rider+delay"):
            b, c = _medians(trees, rounds, lambda root, fmus: steady_rate(root, fmus, name, runs))
            print(f"  {name:<12} baseline {b:8.0f} /min   current {c:8.0f} /min   current/baseline {c / b:5.2f}x")
        print(f"CPU per case in one process (one BLAS thread), median of {rounds} alternating fresh processes; "
              f"baseline: {baseline}")
        for name in ("fmu-only", "rider+delay"):
            b, c = _medians(trees, rounds, lambda root, fmus: case_cpu(root, fmus, name))
            print(f"  {name:<12} baseline {b:6.3f} ms   current {c:6.3f} ms   current/baseline {c / b:5.2f}x")


#: Targets: runs per minute on 2 workers (steady), and the wall rate of 600 runs over the steady rate.
TARGETS = {"fmu-only": 150_000, "rider+delay": 30_000}
WALL_FRACTION = 0.5


def _burn(n: int) -> None:
    s = 0
    for i in range(n):
        s += i


def machine_scaling(n: int = 15_000_000) -> float:
    """Speed-up of 2 processes over 1 on pure Python arithmetic: what this machine allows."""
    from multiprocessing import get_context

    ctx = get_context("spawn")
    times = {}
    for procs in (1, 2):
        ps = [ctx.Process(target=_burn, args=(n,)) for _ in range(procs)]
        t0 = time.perf_counter()
        for p in ps:
            p.start()
        for p in ps:
            p.join()
        times[procs] = time.perf_counter() - t0
    return 2 * times[1] / times[2]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=600, help="runs per workload and worker count")
    parser.add_argument("--repeat", type=int, default=2, help="repetitions per measurement (best is kept)")
    parser.add_argument("--baseline", default="HEAD", help="git ref of the per-case comparison, or 'none' (default: HEAD)")
    parser.add_argument("--rounds", type=int, default=3, help="alternating rounds of the per-case comparison")
    args = parser.parse_args(argv)
    from cosim.matrix.runner import build_fmus
    from cosim.matrix.spec import spec_from_dict

    build_fmus(spec_from_dict(workload("fmu-only", 2)).cases(), None)  # build once, outside the timings
    load = os.getloadavg()[0]
    ideal = machine_scaling()
    print(f"CPUs: {os.cpu_count()}, load average (1 min) before: {load:.2f}"
          + ("  -- the machine is busy: speed-ups are understated" if load > 0.5 else ""))
    print(f"machine: 2 CPU-bound processes run {ideal:.2f}x as fast as 1 (the ceiling for any speed-up here)")
    print(f"{'workload':<12} {'workers':>7} {'runs':>5} {'steady [runs/min]':>18} {'wall [runs/min]':>16} "
          f"{'start-up [s]':>12} {'start':>6}")
    ok = True
    verdicts = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in ("fmu-only", "rider+delay"):
            rates, walls = {}, {}
            for workers in (1, 2):
                m = measure(name, args.runs, workers, Path(tmp), args.repeat)
                if m["full"] != m["runs"] or m["bad"]:
                    print(f"  warning: {m['runs'] - m['full']} runs shorter than 10 s, {m['bad']} failed/disagreeing")
                rates[workers] = m["runs"] / m["steady"] * 60
                walls[workers] = m["runs"] / m["wall"] * 60
                print(f"{name:<12} {workers:>7} {m['runs']:>5} {rates[workers]:>18.0f} "
                      f"{walls[workers]:>16.0f} {m['startup']:>12.3f} {m['start'] or '-':>6}")
            speedup = rates[2] / rates[1]
            print(f"{'':<12} load average now: {os.getloadavg()[0]:.2f}")
            print(f"{name:<12} speed-up 1 -> 2 workers: {speedup:.2f}x ({speedup / ideal:.0%} of the machine's "
                  f"{ideal:.2f}x)")
            target = TARGETS[name]
            met = rates[2] >= target
            ok &= met
            verdicts.append(f"{name:<12} steady, 2 workers: {rates[2]:>8.0f} runs/min = {rates[2] / target:.2f} x "
                            f"the target {target:,} ({'meets' if met else 'MISSES'})")
            if name == "fmu-only":
                fraction = walls[2] / rates[2]
                met = fraction >= WALL_FRACTION
                ok &= met
                verdicts.append(f"{name:<12} wall / steady, {args.runs} runs, 2 workers: {fraction:.2f} = "
                                f"{fraction / WALL_FRACTION:.2f} x the target {WALL_FRACTION:.2f} "
                                f"({'meets' if met else 'MISSES'})")
    if args.baseline != "none":
        side_by_side(args.baseline, args.rounds, args.runs)
    print(f"targets (load average now: {os.getloadavg()[0]:.2f}):")
    for line in verdicts:
        print("  " + line)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
