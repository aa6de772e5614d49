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

``--scaling`` measures instead, side by side in one run, the steady rate of one spec (fmu-only,
--scaling-runs runs) against the workers: the local pool with 1 and 2 workers and a Dask
LocalCluster with more workers than cores (--dask-workers, default 4); the supervisor's CPU time
per case; the Dask client's and scheduler's CPU time per task (message) and per case, separated by
running the same cases at 1 and at 32 cases per task; and, on paper, the runs per minute at 1 to
100 nodes that these costs allow (Amdahl: the scheduler's serial cost per case bounds the rate,
whatever the number of nodes). docs/matrix-scaling.md shows one run and states the assumptions.
"""
from __future__ import annotations

import argparse
import importlib.util
import json
import logging
import math
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


# --------------------------------------------------------------------------- --scaling

#: Cases per Dask task of the two runs that separate the scheduler's cost per task from its cost per case.
CHUNKS = (1, 32)
#: Seconds a case may take (as a spec's default timeout): no case here comes near it.
CASE_TIMEOUT = 120.0
#: Nodes of the projection.
NODES = (1, 2, 4, 10, 25, 50, 100)


def _recorder(store):
    """What `cosim matrix` does with each record the workers send (:func:`cosim.matrix.runner._dispatch`):
    append it to results.jsonl -- part of the scheduler's work per case."""
    def on_record(record: dict) -> None:
        if "line" in record:
            store.append_line(record["key"], record["line"])
        else:
            store.append(record)
    return on_record


def _local_rate(payload: list, init: dict, workers: int, folder: Path, repeat: int) -> dict:
    """Best of ``repeat`` runs on the local pool: steady rate [runs/min] and the supervisor's CPU per case [s]."""
    from cosim.matrix.pool import run_local
    from cosim.matrix.store import ResultStore

    best = None
    for k in range(repeat):
        out = folder / f"local-{workers}-{k}"
        with ResultStore(out, False) as store:
            cpu = time.process_time()
            timing = run_local(payload, init, workers, _recorder(store), CASE_TIMEOUT, out)
            cpu = time.process_time() - cpu
        m = {"rate": len(payload) / timing["run"] * 60, "cpu_case": cpu / len(payload), "tasks": None}
        best = m if best is None or m["rate"] > best["rate"] else best
    return best


def _dask_rates(payload: list, init: dict, workers: int, folder: Path, repeat: int) -> dict:
    """Best of ``repeat`` runs on a Dask LocalCluster of ``workers`` single-threaded worker processes,
    at each of :data:`CHUNKS` cases per task: steady rate [runs/min], the CPU of this process (client
    and scheduler: a LocalCluster's scheduler runs in it) per case [s] and the number of tasks."""
    from distributed import Client, LocalCluster  # deferred: the optional extra `cluster`

    from cosim.matrix.pool import run_dask
    from cosim.matrix.store import ResultStore

    found = {}
    # the workers' scratch space in the temporary folder: the run leaves nothing behind
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=logging.ERROR, local_directory=str(folder)) as cluster, Client(cluster) as client:
        # every Dask worker starts its own worker process on its first task: not part of the rates
        run_dask(payload[:8 * workers], init, client, lambda record: None, CASE_TIMEOUT, chunk_size=1)
        for chunk in CHUNKS:
            best = None
            for k in range(repeat):
                with ResultStore(folder / f"dask-{workers}-{chunk}-{k}", False) as store:
                    cpu, t0 = time.process_time(), time.perf_counter()
                    run_dask(payload, init, client, _recorder(store), CASE_TIMEOUT, chunk_size=chunk)
                    wall, cpu = time.perf_counter() - t0, time.process_time() - cpu
                m = {"rate": len(payload) / wall * 60, "cpu_case": cpu / len(payload),
                     "tasks": math.ceil(len(payload) / chunk), "cpu": cpu}
                best = m if best is None or m["rate"] > best["rate"] else best
            found[chunk] = best
    return found


def scheduler_costs(dask: dict, cases: int) -> tuple[float, float]:
    """The scheduler's CPU per task and per case [s] from the runs at :data:`CHUNKS` cases per task:
    ``cpu = cases * per_case + tasks * per_task`` for both (each clipped at 0: noise)."""
    fine, coarse = dask[CHUNKS[0]], dask[CHUNKS[1]]
    per_task = max(0.0, (fine["cpu"] - coarse["cpu"]) / (fine["tasks"] - coarse["tasks"]))
    per_case = max(0.0, (coarse["cpu"] - coarse["tasks"] * per_task) / cases)
    return per_task, per_case


def chunk_size(cases: int, workers: int) -> int:
    """Cases per Dask task of :func:`cosim.matrix.pool.run_dask` (its rule, repeated here to project it)."""
    return max(1, min(32, math.ceil(cases / (4 * workers))))


def projection(t_case: float, per_task: float, per_case: float, node_cores: int, cases: int) -> list[dict]:
    """Runs per minute at each of :data:`NODES` nodes of ``node_cores`` workers, from the measured
    worker time per case ``t_case`` [s] and the scheduler's serial costs [s]: Amdahl (the
    scheduler's work not overlapped with the workers': ``60 / (s + t_case / P)``) and the bound
    with full overlap (``60 * min(P / t_case, 1 / s)``), ``s = per_case + per_task / chunk``."""
    rows = []
    for nodes in NODES:
        workers = nodes * node_cores
        chunk = chunk_size(cases, workers)
        serial = per_case + per_task / chunk
        rows.append({"nodes": nodes, "workers": workers, "chunk": chunk, "serial": serial,
                     "ideal": workers / t_case * 60, "amdahl": 60 / (serial + t_case / workers),
                     "bound": 60 * min(workers / t_case, 1 / serial if serial else math.inf)})
    return rows


def scaling(runs: int, repeat: int, dask_workers: int, node_cores: int, project_cases: int) -> int:
    """Measure and print the ``--scaling`` tables (see the module docstring)."""
    from cosim.matrix.runner import build_fmus
    from cosim.matrix.spec import spec_from_dict

    cases = spec_from_dict(workload("fmu-only", runs)).cases()
    init = {"imports": [], "fmu_paths": build_fmus(cases, None)}
    payload = [c.to_dict() for c in cases]
    print(f"CPUs: {os.cpu_count()}, load average (1 min) before: {os.getloadavg()[0]:.2f}; workload fmu-only, "
          f"{runs} ten-second runs, best of {repeat}")
    rows = []
    with tempfile.TemporaryDirectory(prefix="cosim-scaling-") as tmp:
        for workers in (1, 2):
            rows.append((f"local pool, {workers} worker{'s' if workers > 1 else ''}", workers,
                         _local_rate(payload, init, workers, Path(tmp), repeat)))
        try:
            dask = _dask_rates(payload, init, dask_workers, Path(tmp), repeat)
        except ImportError:
            dask = None
            print("Dask rows skipped: dask.distributed (the extra `cluster`) is not installed")
    if dask:
        for chunk in CHUNKS:
            rows.append((f"Dask LocalCluster, {dask_workers} workers, {chunk} case{'s' if chunk > 1 else ''}/task",
                         dask_workers, dask[chunk]))
    base = rows[0][2]["rate"]
    print(f"{'execution':<46} {'workers':>7} {'runs/min':>10} {'vs 1 worker':>11} {'tasks':>6} "
          f"{'scheduler CPU/case':>18}")
    for label, workers, m in rows:
        print(f"{label:<46} {workers:>7} {m['rate']:>10.0f} {m['rate'] / base:>10.2f}x "
              f"{m['tasks'] if m['tasks'] else '-':>6} {m['cpu_case'] * 1e6:>15.1f} us")
    print(f"load average now: {os.getloadavg()[0]:.2f} (the local pool's CPU/case includes starting its workers)")
    if not dask:
        return 0
    per_task, per_case = scheduler_costs(dask, runs)
    t_case = 60 / base
    print(f"scheduler (Dask client + scheduler, one process): {per_task * 1e6:.0f} us CPU per task (message), "
          f"{per_case * 1e6:.1f} us per case; one worker: {t_case * 1e3:.3f} ms per case")
    print(f"projection on paper: nodes of {node_cores} workers as fast as one here, a spec of {project_cases} "
          f"cases, run_dask's cases per task; Amdahl = 60 / (s + t/P), bound = 60 min(P/t, 1/s)")
    print(f"{'nodes':>5} {'workers P':>9} {'cases/task':>10} {'s [us/case]':>11} {'ideal [runs/min]':>17} "
          f"{'Amdahl [runs/min]':>17} {'efficiency':>10} {'bound [runs/min]':>16}")
    for r in projection(t_case, per_task, per_case, node_cores, project_cases):
        print(f"{r['nodes']:>5} {r['workers']:>9} {r['chunk']:>10} {r['serial'] * 1e6:>11.1f} {r['ideal']:>17,.0f} "
              f"{r['amdahl']:>17,.0f} {r['amdahl'] / r['ideal']:>9.0%} {r['bound']:>16,.0f}")
    serial = per_case + per_task / 32
    if serial:
        print(f"the scheduler saturates at P = t / s = {t_case / serial:.0f} workers "
              f"({t_case / serial / node_cores:.1f} nodes): beyond, at most {60 / serial:,.0f} runs/min")
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=600, help="runs per workload and worker count")
    parser.add_argument("--repeat", type=int, default=2, help="repetitions per measurement (best is kept)")
    parser.add_argument("--baseline", default="HEAD", help="git ref of the per-case comparison, or 'none' (default: HEAD)")
    parser.add_argument("--rounds", type=int, default=3, help="alternating rounds of the per-case comparison")
    parser.add_argument("--scaling", action="store_true",
                        help="only the rate against the workers, the scheduler's costs and the projection to 100 nodes")
    parser.add_argument("--scaling-runs", type=int, default=2000, help="runs of the --scaling spec")
    parser.add_argument("--dask-workers", type=int, default=4, help="workers of the Dask LocalCluster (--scaling)")
    parser.add_argument("--node-cores", type=int, default=os.cpu_count() or 1,
                        help="workers per node of the --scaling projection (default: this machine's CPUs)")
    parser.add_argument("--project-cases", type=int, default=100_000,
                        help="cases of the spec of the --scaling projection (sets the cases per task)")
    args = parser.parse_args(argv)
    if args.scaling:
        return scaling(args.scaling_runs, args.repeat, args.dask_workers, args.node_cores, args.project_cases)
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
