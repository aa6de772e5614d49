"""Steps per second of our co-simulation master, libcosim and Ecos on the same SSP, side by side.

Each bundled system is exported as SSP (Python blocks replaced by their Modelica twins); our master
runs the same FMUs with the same fixed-step Jacobi algorithm, libcosim (libcosimpy) and Ecos
(ecospy) load the SSP archive. Every engine starts from the unpacked FMU files, instantiates,
initializes and steps to the stop time without recording (what a batch study pays per run); the
rate is steps per second of that whole run. Each measurement is the median of --repeat runs,
the engines taking turns so that a busy machine slows all of them alike.

Targets (docs/benchmarks.md): our master >= 30x libcosim and >= 2x Ecos on every system.

``--baseline REF``: instead, the step cost of the nonlinear bicycles' FMUs built by this tree and by
the committed tree REF, side by side in one process (alternating, medians): Co-Simulation steps of
the FMU's own integrator (10 ms communication steps from a leaning start at 5 m/s) and Model
Exchange derivative evaluations at that state. Target (the standard-Modelica library): the
current tree costs at most 1.2x the baseline's.
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

from side_by_side import baseline_tree

ROOT = Path(__file__).resolve().parents[1]
SYSTEMS = ["lqr-autopilot", "riderless-push", "lane-change"]
TARGETS = {"libcosim": 30.0, "Ecos": 2.0}


def engines(spec, steps: int, folder: Path, tmp: str) -> dict:
    """One callable per engine that runs the whole SSP once (instantiate .. terminate)."""
    from cosim.cosimulation.factory import create_components
    from cosim.cosimulation.master import assemble
    from cosim.cosimulation.ssp import PARAMETER_SET
    from cosim.engines import engine

    engine("ecos").load()  # Ecos needs TBB loaded first
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


STEP_MODELS = ["Bicycle.Bicycles.Whipple", "Bicycle.Bicycles.WhippleRider"]
STEP_TARGET = 1.2


def build_tree(ref: str, folder: Path, models: list[str]) -> dict[str, Path]:
    """The FMUs of ``models`` built by the committed ``cosim/`` and ``modelica/`` of ``ref`` (``None``:
    this tree), in a fresh process."""
    import subprocess

    root = ROOT if ref is None else baseline_tree(ref, folder / "tree")
    out = folder / "fmus"
    code = (f"import sys; sys.path.insert(0, {str(root)!r}); from cosim.compiler.build import build_model; "
            f"from cosim.compiler.library import Library; "
            + "; ".join(f"build_model({m!r}, {str(out)!r}, Library({str(root / 'modelica')!r}))" for m in models))
    env = {k: v for k, v in os.environ.items() if k not in ("COSIM_FMU_DIR", "COSIM_MODELICA_PATH")}
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, cwd=folder, env=env)
    return {m: out / f"{m.replace('.', '_')}.fmu" for m in models}


class StepCost:
    """One instance of an FMU for Co-Simulation and one for Model Exchange, started leaning at 5 m/s."""

    def __init__(self, fmu: Path, tmp: str):
        from ctypes import c_double

        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Model, FMU2Slave

        md = read_model_description(str(fmu))
        folder = extract(str(fmu), unzipdir=tempfile.mkdtemp(dir=tmp))
        vr = {v.name: v.valueReference for v in md.modelVariables}
        kw = dict(guid=md.guid, unzipDirectory=folder, modelIdentifier=md.coSimulation.modelIdentifier)
        self.cs = FMU2Slave(instanceName="cs", **kw)
        self.me = FMU2Model(instanceName="me", **{**kw, "modelIdentifier": md.modelExchange.modelIdentifier})
        self.nx = md.numberOfContinuousStates
        self.dx = (c_double * self.nx)()
        for unit in (self.cs, self.me):
            unit.instantiate()
            unit.setupExperiment(startTime=0.0)
            unit.setReal([vr["phi0"]], [0.1])
            unit.enterInitializationMode()
            unit.exitInitializationMode()
        self.me.enterContinuousTimeMode()
        self.x = (c_double * self.nx)()
        self.me.getContinuousStates(self.x, self.nx)
        self.time = 0.0

    def steps(self, count: int, h: float = 0.01) -> None:
        for _ in range(count):
            self.cs.doStep(self.time, h)  # (FMPy raises on an error status)
            self.time += h

    def derivatives(self, count: int) -> None:
        # a new state each call (the runtime keeps the derivatives of an unchanged state)
        x, k = self.x, 3  # the roll angle
        for i in range(count):
            x[k] += 1e-9 if i % 2 else -1e-9
            self.me.setContinuousStates(x, self.nx)
            self.me.getDerivatives(self.dx, self.nx)

    def close(self) -> None:
        for unit in (self.cs, self.me):
            unit.terminate()
            unit.freeInstance()


def step_costs(ref: str, repeat: int) -> int:
    """FMU step cost of this tree against ``ref`` (see the module docstring)."""
    print(f"CPUs: {os.cpu_count()}, load average (1 min): {os.getloadavg()[0]:.2f}; FMU step cost, "
          f"this tree against {ref}, median of {repeat} alternating runs")
    print(f"{'model':<30} {'what':<24} {'baseline':>12} {'current':>12} {'current/baseline':>17}")
    worst = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        trees = {"baseline": build_tree(ref, Path(tempfile.mkdtemp(dir=tmp)), STEP_MODELS),
                 "current": build_tree(None, Path(tempfile.mkdtemp(dir=tmp)), STEP_MODELS)}
        for model in STEP_MODELS:
            units = {label: StepCost(fmus[model], tmp) for label, fmus in trees.items()}
            for what, run, count in (("CS steps of 10 ms", StepCost.steps, 100),
                                     ("ME derivative calls", StepCost.derivatives, 2000)):
                times = {label: [] for label in units}
                for _ in range(repeat):
                    for label, unit in units.items():
                        t0 = time.perf_counter()
                        run(unit, count)
                        times[label].append((time.perf_counter() - t0) / count)
                cost = {label: statistics.median(t) for label, t in times.items()}
                ratio = cost["current"] / cost["baseline"]
                worst = max(worst, ratio)
                print(f"{model:<30} {what:<24} {cost['baseline'] * 1e6:9.1f} us {cost['current'] * 1e6:9.1f} us "
                      f"{ratio:16.2f}x")
            for unit in units.values():
                unit.close()
    met = worst <= STEP_TARGET
    print(f"largest cost ratio current/baseline: {worst:.2f}x ({'meets' if met else 'MISSES'} <= {STEP_TARGET:g}x)")
    return 0 if met else 1


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--stop", type=float, default=60.0, help="simulated time per run [s] (default 60)")
    parser.add_argument("--repeat", type=int, default=5, help="runs per engine and system (median kept)")
    parser.add_argument("--baseline", metavar="REF",
                        help="measure the nonlinear bicycles' FMU step cost against the committed tree REF instead")
    args = parser.parse_args(argv)
    if args.baseline:
        return step_costs(args.baseline, args.repeat)

    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level

    from cosim.cosimulation.factory import create_components
    from cosim.cosimulation.modelica_twins import with_twins
    from cosim.cosimulation.ssp import export_ssp
    from cosim.cosimulation.system import load_system
    from cosim.engines.archive import unpacked_ssp

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
            with unpacked_ssp(ssp) as (folder, *_):
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
