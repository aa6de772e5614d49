"""Ecos, a co-simulation engine written in C++, through its Python package ecospy.

Ecos runs FMI 2.0 and FMI 3.0 Co-Simulation FMUs and SSPs of either; it records the outputs
once the connected inputs took the values of the step.
"""
from __future__ import annotations

import ctypes
import site
import sys
from pathlib import Path

import numpy as np

from cosim.cosimulation.ssp import PARAMETER_SET
from cosim.engines.archive import unpacked_ssp
from cosim.engines.base import Engine, EngineUnavailable, register, result, steps
from cosim.errors import SimulationError


def preload_tbb() -> None:
    """Load Intel TBB's ``libtbb.so.12`` by path, for Ecos.

    Ecos' native library links ``libtbb.so.12``. The pip ``tbb`` wheel (part of the test extra)
    installs it into ``<prefix>/lib``, which the dynamic loader does not search; a library that is
    already loaded satisfies the dependency by its soname, so loading it first with RTLD_GLOBAL
    makes ``import ecospy`` work without Debian's ``libtbb12``.
    """
    for prefix in dict.fromkeys((sys.prefix, site.USER_BASE or "", sys.base_prefix)):
        candidate = Path(prefix) / "lib" / "libtbb.so.12"
        if prefix and candidate.is_file():
            ctypes.CDLL(str(candidate), mode=ctypes.RTLD_GLOBAL)
            return


@register
class Ecos(Engine):
    """Ecos through ecospy: FMI 2.0 and 3.0 FMUs and SSPs of them, fixed step, outputs recorded
    after the transfer of the step's values to the connected inputs."""

    name = "ecos"
    module = "ecospy"
    fmi_versions = ("2.0", "3.0")
    sampling = "after-transfer"
    independent = True
    marker = "needs_ecos"

    def load(self):
        preload_tbb()
        try:
            import ecospy as module
        except ImportError as exc:
            raise EngineUnavailable(f"Ecos (ecospy) is not installed: pip install ecospy ({exc})") from None
        except OSError as exc:
            raise EngineUnavailable(f"Ecos (ecospy) cannot load its native library: {exc}; "
                                    "pip install tbb (in the test extra) or apt-get install libtbb12") from None
        return module

    def run_fmu(self, fmu, stop_time, step, start_values=None, outputs=None) -> np.ndarray:
        self.load()
        from ecospy import EcosSimulation
        from ecospy.EcosSimulationStructure import EcosSimulationStructure
        from fmpy import read_model_description

        md = read_model_description(str(fmu))
        names = outputs or [v.name for v in md.modelVariables if v.causality == "output"]
        n = steps(stop_time, step)
        try:
            structure = EcosSimulationStructure()
            structure.add_model("model", str(Path(fmu).resolve()))
            if start_values:
                structure.add_parameter_set("start", {f"model::{k}": v for k, v in start_values.items()})
            simulation = EcosSimulation(structure=structure, step_size=step)
            simulation.init(parameter_set="start" if start_values else None)
            times, columns = [], {name: [] for name in names}
            for _ in range(n):
                times.append(simulation.step(1))
                for name in names:
                    columns[name].append(simulation.get_real(f"model::{name}"))
            simulation.terminate()
        except Exception as exc:
            raise SimulationError(f"Ecos: {exc}") from None
        return result(times, columns)

    def run_ssp(self, ssp, signals, stop_time=None, step=None) -> np.ndarray:
        self.load()
        from ecospy import EcosSimulation

        with unpacked_ssp(ssp) as (folder, start, stop, base):
            h = step or base
            n = steps((stop_time or stop) - start, h)
            try:
                simulation = EcosSimulation(ssp_path=str(folder), step_size=h)
                simulation.init(parameter_set=PARAMETER_SET)
                times, columns = [], {s: [] for s in signals}
                for _ in range(n):
                    times.append(simulation.step(1))
                    for s in signals:
                        comp, _, var = s.partition(".")
                        columns[s].append(simulation.get_real(f"{comp}::{var}"))
                simulation.terminate()
            except Exception as exc:
                raise SimulationError(f"Ecos: {exc}") from None
        return result(times, columns)
