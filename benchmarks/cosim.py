"""Steps per second of our co-simulation master, libcosim and Ecos on the same SSP, side by side.

Each bundled system is exported as SSP (Python blocks replaced by their Modelica twins); our master
runs the same FMUs with the same fixed-step Jacobi algorithm, libcosim (libcosimpy) and Ecos
(ecospy) load the SSP archive. Every engine starts from the unpacked FMU files, instantiates,
initializes and steps to the stop time without recording (what a batch study pays per run); the
rate is steps per second of that whole run. Each measurement is the median of --repeat runs,
the engines taking turns so that a busy machine slows all of them alike.

Targets (issue 14): our master >= 30x libcosim and >= 2x Ecos on every system.
"""
from __future__ import annotations

import argparse
import dataclasses
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# Python puts this folder first on sys.path, where benchmarks/cosim.py would shadow the cosim package.
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]
SYSTEMS = ["lqr-autopilot", "riderless-push", "lane-change"]
TARGETS = {"libcosim": 30.0, "Ecos": 2.0}


def engines(spec, steps: int, folder: Path, tmp: str) -> dict:
    """One callable per engine that runs the whole SSP once (instantiate .. terminate)."""
    from cosim.cosimulation.factory import create_components
    from cosim.cosimulation.master import assemble
    from cosim.cosimulation.ssp import PARAMETER_SET
    from cosim.fmu.engines import ecospy

    ecospy()
    from ecospy import EcosSimulation
    from libcosimpy.CosimExecution import CosimExecution

    def ours():
        assemble(spec, create_components(spec, tmp)).run()

    def libcosim():
        execution = CosimExecution.from_ssp_file(str(folder))
        execution.simulate_until(int(round(spec.stop * 1e9)))

    def ecos():
        simulation = EcosSimulation(ssp_path=str(folder), step_size=spec.step)
        simulation.init(parameter_set=PARAMETER_SET)
        simulation.step(steps)
        simulation.terminate()
        simulation.free()

    return {"ours": ours, "libcosim": libcosim, "Ecos": ecos}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--stop", type=float, default=60.0, help="simulated time per run [s] (default 60)")
    parser.add_argument("--repeat", type=int, default=5, help="runs per engine and system (median kept)")
    args = parser.parse_args(argv)

    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level

    from cosim.cosimulation.factory import create_components
    from cosim.cosimulation.modelica_twins import with_twins
    from cosim.cosimulation.ssp import export_ssp
    from cosim.cosimulation.system import load_system
    from cosim.fmu.engines import _unpacked_ssp

    log_output_level(CosimLogLevel.WARNING)
    print(f"CPUs: {os.cpu_count()}, load average (1 min): {os.getloadavg()[0]:.2f}, "
          f"{args.stop:g} s simulated per run, median of {args.repeat}")
    print(f"{'system':<16} {'steps':>7} {'ours [steps/s]':>15} {'libcosim':>10} {'Ecos':>10} "
          f"{'vs libcosim':>12} {'vs Ecos':>8}")
    worst = {peer: float("inf") for peer in TARGETS}
    with tempfile.TemporaryDirectory() as tmp:
        for name in SYSTEMS:
            spec, _ = with_twins(load_system(ROOT / "cosim" / "systems" / f"{name}.toml"))
            spec = dataclasses.replace(spec, stop=args.stop, fall_signal=None, fall_limit=None)
            ssp, _ = export_ssp(spec, Path(tmp) / f"{name}.ssp", tmp)
            steps = int(round((spec.stop - spec.start) / spec.step))
            # Every engine starts from FMU files: no model build check inside the timed runs.
            built = create_components(spec, tmp)
            fmu_files = {n: str(c.fmu.path) for n, c in built.items()}
            for c in built.values():
                c.close()
            spec = dataclasses.replace(spec, components={
                n: dataclasses.replace(c, kind="fmu", source=fmu_files[n]) for n, c in spec.components.items()})
            with _unpacked_ssp(ssp) as (folder, *_):
                runs = engines(spec, steps, folder, tmp)
                times = {engine: [] for engine in runs}
                for _ in range(args.repeat):
                    for engine, run in runs.items():
                        t0 = time.perf_counter()
                        run()
                        times[engine].append(time.perf_counter() - t0)
            rate = {engine: steps / statistics.median(t) for engine, t in times.items()}
            ratio = {peer: rate["ours"] / rate[peer] for peer in TARGETS}
            for peer in TARGETS:
                worst[peer] = min(worst[peer], ratio[peer])
            print(f"{name:<16} {steps:>7} {rate['ours']:15.0f} {rate['libcosim']:10.0f} {rate['Ecos']:10.0f} "
                  f"{ratio['libcosim']:11.1f}x {ratio['Ecos']:7.2f}x")
    ok = True
    for peer, target in TARGETS.items():
        met = worst[peer] >= target
        ok &= met
        print(f"smallest ratio to {peer}: {worst[peer]:.2f}x ({'meets' if met else 'MISSES'} >= {target:g}x)")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
