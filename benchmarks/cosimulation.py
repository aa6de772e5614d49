"""Steps per second of our co-simulation master and of libcosim on the same SSP (side by side).

Each bundled system is exported as SSP (Python blocks replaced by their Modelica twins); our
master runs the same FMUs with the same fixed-step Jacobi algorithm. Best of several repetitions.
Target: our master at least 3x libcosim.
"""
from __future__ import annotations

import dataclasses
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SYSTEMS = ["lqr-autopilot", "riderless-push", "lane-change"]
STOP = 60.0  # s of simulated time per run
REPEAT = 3


def best_of(run) -> float:
    times = []
    for _ in range(REPEAT):
        t0 = time.perf_counter()
        run()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> int:
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level

    from cosim.cosimulation.factory import create_components
    from cosim.cosimulation.master import assemble
    from cosim.cosimulation.modelica_twins import with_twins
    from cosim.cosimulation.ssp import export_ssp
    from cosim.cosimulation.system import load_system
    from cosim.fmu.engines import _unpacked_ssp

    log_output_level(CosimLogLevel.WARNING)
    print(f"{'system':<16} {'steps':>7} {'ours [steps/s]':>15} {'libcosim [steps/s]':>19} {'ratio':>7}")
    ratios = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in SYSTEMS:
            spec, _ = with_twins(load_system(ROOT / "cosim" / "systems" / f"{name}.toml"))
            spec = dataclasses.replace(spec, stop=STOP, fall_signal=None, fall_limit=None)
            ssp, _ = export_ssp(spec, Path(tmp) / f"{name}.ssp", tmp)
            steps = int(round((spec.stop - spec.start) / spec.step))
            # Both sides start from FMU files: no model build check inside the timed runs.
            built = {n: c for n, c in create_components(spec, tmp).items()}
            fmu_files = {n: str(c.fmu.path) for n, c in built.items()}
            for c in built.values():
                c.close()
            spec = dataclasses.replace(spec, components={
                n: dataclasses.replace(c, kind="fmu", source=fmu_files[n]) for n, c in spec.components.items()})

            def ours():
                assemble(spec, create_components(spec, tmp)).run()

            with _unpacked_ssp(ssp) as (folder, *_):
                def libcosim():
                    execution = CosimExecution.from_ssp_file(str(folder))
                    execution.simulate_until(int(round(STOP * 1e9)))

                t_ours, t_lib = best_of(ours), best_of(libcosim)
            ratio = t_lib / t_ours
            ratios.append(ratio)
            print(f"{name:<16} {steps:>7} {steps / t_ours:15.0f} {steps / t_lib:19.0f} {ratio:6.2f}x")
    print(f"smallest ratio: {min(ratios):.2f}x (target >= 3x)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
