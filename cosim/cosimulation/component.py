"""The one protocol every co-simulation component follows, and its FMU implementation.

A component has named Real inputs and outputs (fixed order: the master addresses them by index,
never by name, while stepping), may pass inputs straight through to outputs (``feedthrough``),
and can save and restore its state.
"""
from __future__ import annotations

from ctypes import POINTER, c_double, c_uint
from pathlib import Path

import numpy as np

from ..errors import SimulationError


class Component:
    """Base class: subclasses set ``inputs``, ``outputs`` and implement the methods."""

    inputs: list[str] = []
    outputs: list[str] = []

    def __init__(self, name: str):
        self.name = name

    def feedthrough(self, output: str) -> set[str]:
        """Inputs that ``output`` depends on without delay (default: all)."""
        return set(self.inputs)

    def setup(self, start_time: float) -> None:
        """Instantiate and enter initialization (parameters are already set)."""

    def end_initialization(self) -> None:
        """Leave initialization; the first step follows."""

    def initial_inputs(self) -> np.ndarray:
        """Input values after setup (unconnected inputs keep them)."""
        return np.zeros(len(self.inputs))

    def set_inputs(self, values: np.ndarray) -> None:
        raise NotImplementedError

    def get_outputs(self) -> np.ndarray:
        raise NotImplementedError

    def step(self, t: float, h: float) -> None:
        raise NotImplementedError

    def get_state(self):
        raise NotImplementedError

    def set_state(self, state) -> None:
        raise NotImplementedError

    def close(self) -> None:
        """Release resources."""


class FMUComponent(Component):
    """An FMI 2.0 Co-Simulation FMU behind the component protocol.

    Inputs and outputs are the FMU's Real variables of causality input/output; value references
    and ctypes buffers are prepared once, so a step costs three calls into the FMU.
    """

    def __init__(self, name: str, path: str | Path, parameters: dict | None = None, tolerance: float | None = None):
        from ..fmi import FMU

        super().__init__(name)
        self.fmu = FMU(path)
        md = self.fmu.description
        if md.coSimulation is None:
            raise SimulationError(f"{name}: {path} does not support Co-Simulation")
        # Every variable by name: (causality, type), to explain a connection that cannot be made.
        self.variables = {v.name: (v.causality, v.type) for v in md.modelVariables}
        self.inputs = [v.name for v in md.modelVariables if v.causality == "input" and v.type == "Real"]
        self.outputs = [v.name for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
        self.parameters = dict(parameters or {})
        self.tolerance = tolerance
        self._depends = self._output_dependencies()
        self._in_vr = (c_uint * len(self.inputs))(*[self.fmu.vr[n] for n in self.inputs])
        self._out_vr = (c_uint * len(self.outputs))(*[self.fmu.vr[n] for n in self.outputs])
        self._in = np.zeros(len(self.inputs))
        self._out = np.zeros(len(self.outputs))
        self._in_ptr = self._in.ctypes.data_as(POINTER(c_double))
        self._out_ptr = self._out.ctypes.data_as(POINTER(c_double))
        self.instance = None

    def _output_dependencies(self) -> dict[str, set[str]]:
        """Inputs each output depends on, from ModelStructure (all inputs where not stated)."""
        md = self.fmu.description
        inputs = {v.name for v in md.modelVariables if v.causality == "input"}
        found = {}
        for unknown in md.outputs:
            deps = unknown.dependencies
            found[unknown.variable.name] = inputs if deps is None else {d.name for d in deps if d.name in inputs}
        return found

    def feedthrough(self, output: str) -> set[str]:
        return self._depends.get(output, set(self.inputs))

    def _instantiate(self) -> None:
        """A fresh FMI instance (subclasses may reuse one, see cosim.matrix.worker)."""
        self.instance = self.fmu.instantiate("cs", name=self.name)

    def setup(self, start_time: float) -> None:
        self._instantiate()
        try:
            self.fmu.set(self.instance, self.parameters)
        except KeyError as exc:
            raise SimulationError(f"{self.name}: unknown parameter {exc}") from None
        self.instance.setupExperiment(tolerance=self.tolerance, startTime=start_time)
        self.instance.enterInitializationMode()

        # The raw C functions (argument types already declared by FMPy): no wrapper per call.
        functions = self.instance._functions
        self._component = self.instance.component
        self._set_real, self._get_real = functions["fmi2SetReal"], functions["fmi2GetReal"]
        self._do_step = functions["fmi2DoStep"]

    def end_initialization(self) -> None:
        self.instance.exitInitializationMode()

    def initial_inputs(self) -> np.ndarray:
        if len(self._in):
            self._get_real(self._component, self._in_vr, len(self._in), self._in_ptr)
        return self._in.copy()

    def set_inputs(self, values: np.ndarray) -> None:
        if len(self._in):
            self._in[:] = values
            if self._set_real(self._component, self._in_vr, len(self._in), self._in_ptr) > 1:
                raise SimulationError(f"{self.name}: fmi2SetReal failed")

    def get_outputs(self) -> np.ndarray:
        if len(self._out):
            if self._get_real(self._component, self._out_vr, len(self._out), self._out_ptr) > 1:
                raise SimulationError(f"{self.name}: fmi2GetReal failed")
        return self._out

    def step(self, t: float, h: float) -> None:
        status = self._do_step(self._component, t, h, 1)
        if status > 1:  # fmi2Discard or worse
            raise SimulationError(f"{self.name}: fmi2DoStep failed at t = {t:g} s (status {status})")

    def get_state(self):
        return self.instance.getFMUstate()

    def set_state(self, state) -> None:
        self.instance.setFMUstate(state)

    def close(self) -> None:
        if self.instance is not None:
            try:
                self.instance.terminate()
            finally:
                self.instance.freeInstance()
                self.instance = None
        self.fmu.close()
