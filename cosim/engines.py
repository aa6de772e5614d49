"""Run an FMU in independent FMI engines: libcosim (libcosimpy) and Ecos (ecospy).

Used to prove that the FMUs load and run unmodified in other tools; both engines step with a
fixed communication step and the results are returned as FMPy-style structured arrays.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .errors import SimulationError

NANOSECONDS = 1_000_000_000


def _result(times, columns: dict[str, list[float]]) -> np.ndarray:
    dtype = [("time", np.float64)] + [(n, np.float64) for n in columns]
    rows = list(zip(times, *columns.values()))
    return np.array(rows, dtype=dtype)


def _steps(stop_time: float, step: float) -> int:
    n = int(round(stop_time / step))
    if n <= 0 or abs(n * step - stop_time) > 1e-9 * max(1.0, stop_time):
        raise SimulationError(f"stop time {stop_time} is not a whole number of steps {step}")
    return n


def run_libcosim(fmu: str | Path, stop_time: float, step: float, start_values: dict | None = None,
                 outputs: list[str] | None = None) -> np.ndarray:
    """Simulate one FMU in libcosim with a fixed step; returns time and the ``outputs`` columns."""
    from libcosimpy import _internal
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from fmpy import read_model_description

    log_output_level(CosimLogLevel.WARNING)  # libcosim traces every FMI call otherwise
    md = read_model_description(str(fmu))
    refs = {v.name: v for v in md.modelVariables}
    names = outputs or [v.name for v in md.modelVariables if v.causality == "output"]
    n = _steps(stop_time, step)
    execution = CosimExecution.from_step_size(int(round(step * NANOSECONDS)))
    index = execution.add_local_slave(CosimLocalSlave(fmu_path=str(Path(fmu).resolve()), instance_name="model"))
    if index < 0:
        raise SimulationError(f"libcosim could not load {fmu}: {_internal.get_last_error_message()}")
    for name, value in (start_values or {}).items():
        v = refs[name]
        setter = {"Real": execution.real_initial_value, "Integer": execution.integer_initial_value,
                  "Boolean": execution.boolean_initial_value}[v.type]
        if not setter(index, v.valueReference, value):
            raise SimulationError(f"libcosim: cannot set {name}: {_internal.get_last_error_message()}")
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    vrs = [refs[name].valueReference for name in names]
    times, columns = [], {name: [] for name in names}

    def record(t):
        values = observer.last_real_values(index, vrs)
        times.append(t)
        for name, value in zip(names, values):
            columns[name].append(value)

    # The first step initializes the FMU; libcosim reports values after each step.
    for k in range(1, n + 1):
        if not execution.step(1):
            raise SimulationError(f"libcosim step {k} failed: {_internal.get_last_error_message()}")
        record(k * step)
    return _result(times, columns)


def run_ecos(fmu: str | Path, stop_time: float, step: float, start_values: dict | None = None,
             outputs: list[str] | None = None) -> np.ndarray:
    """Simulate one FMU in Ecos with a fixed step; returns time and the ``outputs`` columns."""
    from ecospy import EcosSimulation
    from ecospy.EcosSimulationStructure import EcosSimulationStructure
    from fmpy import read_model_description

    md = read_model_description(str(fmu))
    names = outputs or [v.name for v in md.modelVariables if v.causality == "output"]
    n = _steps(stop_time, step)
    try:
        structure = EcosSimulationStructure()
        structure.add_model("model", str(Path(fmu).resolve()))
        if start_values:
            structure.add_parameter_set("start", {f"model::{k}": v for k, v in start_values.items()})
        simulation = EcosSimulation(structure=structure, step_size=step)
        simulation.init(parameter_set="start" if start_values else None)
        times, columns = [], {name: [] for name in names}
        for _ in range(n):
            t = simulation.step(1)
            times.append(t)
            for name in names:
                columns[name].append(simulation.get_real(f"model::{name}"))
        simulation.terminate()
    except Exception as exc:
        raise SimulationError(f"Ecos: {exc}") from None
    return _result(times, columns)
