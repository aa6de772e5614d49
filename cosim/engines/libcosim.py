"""libcosim (the Open Simulation Platform's engine) through libcosimpy.

libcosim has no FMI 3.0: it crashes the process on an FMI 3 FMU, so this engine refuses one
(:class:`~cosim.engines.base.EngineUnsupported`) before libcosim is loaded. It records the
outputs right after each step.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from cosim.cosimulation.system import SystemError_
from cosim.engines.archive import fmi3_components, fmu_fmi_version, unpacked_ssp
from cosim.engines.base import Engine, EngineUnavailable, EngineUnsupported, register, result, steps
from cosim.errors import SimulationError

NANOSECONDS = 1_000_000_000
NO_FMI3 = "libcosim has no FMI 3.0 support (an FMI 3 FMU crashes it)"


def _refuse_fmi3_fmu(fmu: str | Path) -> None:
    """:class:`EngineUnsupported` if ``fmu`` is an FMI 3 FMU (other problems are left to libcosim)."""
    version = fmu_fmi_version(fmu)
    if version and version.startswith("3."):
        raise EngineUnsupported(f"{fmu}: {NO_FMI3}, and this FMU is FMI {version}; run it in Ecos "
                                "(cosim.engines.engine('ecos').run_fmu) or use its FMI 2.0 build "
                                "(cosim build --fmi-version 2)")


def _refuse_fmi3_ssp(ssp: str | Path) -> None:
    """:class:`EngineUnsupported` naming the FMI 3 components of ``ssp``, if it has any."""
    found = fmi3_components(ssp)
    if found:
        listed = ", ".join(f"{name} ({source})" for name, source in found.items())
        raise EngineUnsupported(f"{ssp}: {NO_FMI3}, and component{'s' if len(found) > 1 else ''} "
                                f"{listed} {'are' if len(found) > 1 else 'is'} FMI 3.0; run the SSP in Ecos "
                                "(cosim.engines.engine('ecos').run_ssp) or export it with FMI 2.0 components "
                                "(cosim export-ssp --fmi-version 2)")


def _name(text) -> str:
    return text.decode() if isinstance(text, bytes) else text


@register
class Libcosim(Engine):
    """libcosim through libcosimpy: FMI 2.0 FMUs and SSPs of them, fixed step, outputs recorded
    right after each step."""

    name = "libcosim"
    module = "libcosimpy"
    fmi_versions = ("2.0",)
    sampling = "after-step"
    independent = True
    marker = "needs_libcosim"

    def load(self):
        try:
            import libcosimpy as module
            import libcosimpy.CosimExecution  # noqa: F401  loads the native library
        except (ImportError, OSError) as exc:
            raise EngineUnavailable(f"libcosim (libcosimpy) cannot be loaded: {exc}") from None
        return module

    def run_fmu(self, fmu, stop_time, step, start_values=None, outputs=None) -> np.ndarray:
        _refuse_fmi3_fmu(fmu)
        self.load()
        from libcosimpy import _internal
        from libcosimpy.CosimExecution import CosimExecution
        from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
        from libcosimpy.CosimObserver import CosimObserver
        from libcosimpy.CosimSlave import CosimLocalSlave
        from fmpy import read_model_description

        log_output_level(CosimLogLevel.WARNING)  # libcosim traces every FMI call otherwise
        md = read_model_description(str(fmu))
        refs = {v.name: v for v in md.modelVariables}
        names = outputs or [v.name for v in md.modelVariables if v.causality == "output"]
        n = steps(stop_time, step)
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

        # The first step initializes the FMU; libcosim reports values after each step.
        for k in range(1, n + 1):
            if not execution.step(1):
                raise SimulationError(f"libcosim step {k} failed: {_internal.get_last_error_message()}")
            times.append(k * step)
            for name, value in zip(names, observer.last_real_values(index, vrs)):
                columns[name].append(value)
        return result(times, columns)

    def run_ssp(self, ssp, signals, stop_time=None, step=None) -> np.ndarray:
        _refuse_fmi3_ssp(ssp)
        self.load()
        from libcosimpy import _internal
        from libcosimpy.CosimExecution import CosimExecution
        from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
        from libcosimpy.CosimObserver import CosimObserver

        log_output_level(CosimLogLevel.WARNING)
        with unpacked_ssp(ssp) as (folder, start, stop, base):
            execution = (CosimExecution.from_ssp_file(str(folder), step) if step
                         else CosimExecution.from_ssp_file(str(folder)))
            if execution is None:
                raise SimulationError(f"libcosim cannot load {ssp}: {_internal.get_last_error_message()}")
            observer = CosimObserver.create_last_value()
            execution.add_observer(observer)
            slaves = {_name(info.name): info.index for info in execution.slave_infos()}
            refs = []
            for signal in signals:
                comp, _, var = signal.partition(".")
                if comp not in slaves:
                    raise SystemError_(f"libcosim: no component '{comp}' in {ssp}")
                variables = {_name(v.name): v.reference for v in execution.slave_variables(slaves[comp])}
                refs.append((slaves[comp], variables[var]))
            h = step or base
            n = steps((stop_time or stop) - start, h)
            times, rows = [], []
            for k in range(1, n + 1):
                if not execution.step(1):
                    raise SimulationError(f"libcosim step {k} failed: {_internal.get_last_error_message()}")
                times.append(start + k * h)
                rows.append([observer.last_real_values(s, [r])[0] for s, r in refs])
        return result(times, {s: [row[j] for row in rows] for j, s in enumerate(signals)})
