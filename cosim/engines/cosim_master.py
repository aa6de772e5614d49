"""This project's own co-simulation master (:mod:`cosim.cosimulation.master`) as an engine:
one FMU as the only component of a system, its inputs held by Step blocks."""
from __future__ import annotations

import numpy as np

import cosim
from cosim.cosimulation.factory import run_system
from cosim.cosimulation.system import system_from_dict
from cosim.engines.base import Engine, register
from cosim.errors import SimulationError
from cosim.fmu.access import ALL_FMI_VERSIONS, read_fmu

COMPONENT = "model"


@register
class CosimMaster(Engine):
    """Our master under Jacobi with a fixed step: the FMU's parameters among the start values
    are its parameters in the system, each input among them is driven by a ``Step`` block of
    that amplitude from the start; outputs recorded right after each step."""

    name = "cosim"
    module = "cosim"
    fmi_versions = ("2.0", "3.0")
    sampling = "after-step"

    def load(self):
        return cosim

    def run_fmu(self, fmu, stop_time, step, start_values=None, outputs=None) -> np.ndarray:
        md = read_fmu(fmu, ALL_FMI_VERSIONS)
        inputs = {v.name for v in md.modelVariables if v.causality == "input"}
        names = outputs or [v.name for v in md.modelVariables if v.causality == "output"]
        start_values = start_values or {}
        components = {COMPONENT: {"fmu": str(fmu),
                                  "parameters": {k: v for k, v in start_values.items() if k not in inputs}}}
        connections = []
        for name, value in start_values.items():
            if name in inputs:
                components[f"start_{name}"] = {"python": "Step", "parameters": {"amplitude": value, "start": 0.0}}
                connections.append(f"start_{name}.y -> {COMPONENT}.{name}")
        spec = system_from_dict({
            "system": {"stop": stop_time, "step": step, "algorithm": "jacobi",
                       "record": [f"{COMPONENT}.{n}" for n in names]},
            "components": components, "connections": connections})
        run = run_system(spec)
        if run.outcome.status != "completed":
            raise SimulationError(f"{fmu}: {run.outcome.message}")
        data = run.data[1:]
        columns = {"time": data["time"], **{n: data[f"{COMPONENT}.{n}"] for n in names}}
        out = np.empty(len(data), dtype=[(n, np.float64) for n in columns])
        for n, values in columns.items():
            out[n] = values
        return out
