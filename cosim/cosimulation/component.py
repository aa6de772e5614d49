"""The one protocol every co-simulation component follows, and its FMU implementation.

A component has named Real inputs and outputs (fixed order: the master addresses them by index,
never by name, while stepping) and may pass inputs straight through to outputs (``feedthrough``).

The master drives every component the same way (:class:`cosim.cosimulation.master.System`)::

    configure_step(h)                     # once, the base communication step
    setup(t0)                             # parameters set; initialization mode
    initial_inputs()                      # values of the inputs nothing is connected to
    set_inputs(u); get_outputs()          # repeated while initializing (feedthrough chains)
    end_initialization()
    for each communication point t_k, h_k = t_(k+1) - t_k:
        set_inputs(u(t_k))                # outputs now valid at t_k for these inputs
        step(t_k, h_k)                    # inputs held over [t_k, t_k + h_k]
        get_outputs()                     # valid at t_k + h_k, inputs still u(t_k)
    close()

Times are in seconds of simulation time. No state is ever saved or restored by the master (a
rejected step is not retried), so the protocol has no get/set-state methods.
"""
from __future__ import annotations

from ctypes import POINTER, c_double, c_uint
from pathlib import Path

import numpy as np
from fmpy.fmi1 import FMICallException

from cosim.errors import SimulationError


class Component:
    """Base class: subclasses set ``inputs``, ``outputs`` and implement the protocol (module docstring).

    Attributes
    ----------
    name : str
        The component's name in the system (prefix of its recorded signals).
    inputs, outputs : list of str
        Names of the Real inputs and outputs; the order is that of the vectors passed to
        :meth:`set_inputs` and returned by :meth:`get_outputs`.
    """

    inputs: list[str] = []
    outputs: list[str] = []

    def __init__(self, name: str):
        self.name = name

    def feedthrough(self, output: str) -> set[str]:
        """Inputs that ``output`` depends on without delay (default: all); Gauss-Seidel orders
        components by it and refuses a loop of feedthrough."""
        return set(self.inputs)

    def configure_step(self, h: float) -> None:
        """The base communication step [s] of the master, told once before :meth:`setup` (a
        transport delay at least that long has no feedthrough). Default: ignored."""

    def setup(self, start_time: float) -> None:
        """Instantiate and enter initialization at ``start_time`` [s] (parameters are already set)."""

    def end_initialization(self) -> None:
        """Leave initialization; the first :meth:`step` follows."""

    def initial_inputs(self) -> np.ndarray:
        """Input values after :meth:`setup` (inputs nothing is connected to keep them)."""
        return np.zeros(len(self.inputs))

    def set_inputs(self, values: np.ndarray) -> None:
        """Set every input (order of ``inputs``) at the current communication point.

        Afterwards :meth:`get_outputs` returns the outputs at the same time with these inputs
        (outputs with feedthrough change, the others do not). Setting the same values again
        changes nothing.
        """
        raise NotImplementedError

    def get_outputs(self) -> np.ndarray:
        """The outputs (order of ``outputs``) at the current communication point: after
        :meth:`setup`, :meth:`set_inputs` or :meth:`step`. The array may be the component's own
        buffer: copy it to keep it past the next call."""
        raise NotImplementedError

    def step(self, t: float, h: float) -> None:
        """Advance from the communication point ``t`` [s] to ``t + h`` [s] (``h`` > 0), the
        inputs held at the values last set (zero-order hold). Afterwards the current time is
        ``t + h`` and :meth:`get_outputs` returns the outputs there, still for the old inputs.

        Raises
        ------
        StepFailed
            If the component cannot complete the step (FMUs: fmi2Discard or worse).
        """
        raise NotImplementedError

    def close(self) -> None:
        """Release resources (called once, also after a failure)."""


class StepFailed(SimulationError):
    """An FMU's ``fmi2DoStep`` (or a get/set around it) failed part-way through a run.

    Attributes
    ----------
    component : str
        The component's name.
    time : float
        Start of the communication step that failed [s].
    status : int
        The FMI status returned (2 Discard, 3 Error, 4 Fatal).
    last_successful_time : float or None
        ``fmi2LastSuccessfulTime`` after a Discard, where the FMU reports it [s].
    fmu_message : str or None
        The FMU's last logged error message.
    """

    def __init__(self, message: str, component: str, time: float, status: int,
                 last_successful_time: float | None = None, fmu_message: str | None = None):
        super().__init__(message)
        self.component, self.time, self.status = component, time, status
        self.last_successful_time, self.fmu_message = last_successful_time, fmu_message


STATUS_NAMES = {0: "OK", 1: "Warning", 2: "Discard", 3: "Error", 4: "Fatal", 5: "Pending"}


class FMUComponent(Component):
    """An FMI 2.0 Co-Simulation FMU behind the component protocol.

    Inputs and outputs are the FMU's Real variables of causality input/output; value references
    and ctypes buffers are prepared once, so a step costs three calls into the FMU.

    The worst FMI status seen (``status``) decides what :meth:`close` may still call: after
    fmi2Discard the instance is terminated and freed, after fmi2Error only freed (FMI 2.0 allows
    no fmi2Terminate in the error state), after fmi2Fatal left alone.
    """

    def __init__(self, name: str, path: str | Path, parameters: dict | None = None, tolerance: float | None = None):
        from cosim.fmu.access import FMU

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
        self.status = 0
        self.last_outputs: dict[str, float] = {}  # outputs at fmi2LastSuccessfulTime after a Discard
        self.now = 0.0  # the FMU's communication point [s]: start, then t + h of each step

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

    def fmu_said(self) -> str | None:
        """The FMU's last logged error message (None if it logged none)."""
        log = getattr(self.instance, "log", None)
        return log.last_error() if log is not None else None

    def _call(self, what: str, function, *args):
        """An FMPy call during set-up; a refusal becomes a SimulationError quoting the FMU."""
        try:
            return function(*args)
        except FMICallException as exc:
            self.status = max(self.status, int(getattr(exc, "status", 3) or 3))
            said = self.fmu_said()
            raise SimulationError(f"{self.name}: {what} failed" + (f": {said}" if said else f" ({exc})")) from None

    def setup(self, start_time: float) -> None:
        self.enter_initialization(start_time)
        self.now = float(start_time)
        # The raw C functions (argument types already declared by FMPy): no wrapper per call.
        functions = self.instance._functions
        self._component = self.instance.component
        self._set_real, self._get_real = functions["fmi2SetReal"], functions["fmi2GetReal"]
        self._do_step = functions["fmi2DoStep"]

    def enter_initialization(self, start_time: float, kind: str = "cs") -> None:
        """A fresh instance (``kind`` 'cs' or 'me') with the parameters set, in initialization
        mode at ``start_time`` [s]: the set-up both couplings share (see model_exchange)."""
        self.status = 0
        if kind == "cs":
            self._instantiate()
        else:
            self.instance = self.fmu.instantiate(kind, name=self.name)
        try:
            self.fmu.set(self.instance, self.parameters)
        except KeyError as exc:
            raise SimulationError(f"{self.name}: unknown parameter {exc}") from None
        except FMICallException as exc:
            self.status = max(self.status, int(getattr(exc, "status", 3) or 3))
            raise SimulationError(f"{self.name}: setting the parameters failed: {self.fmu_said() or exc}") from None
        self._call("fmi2SetupExperiment", lambda: self.instance.setupExperiment(tolerance=self.tolerance,
                                                                               startTime=start_time))
        self._call("fmi2EnterInitializationMode", self.instance.enterInitializationMode)

    def end_initialization(self) -> None:
        self._call("fmi2ExitInitializationMode", self.instance.exitInitializationMode)

    def initial_inputs(self) -> np.ndarray:
        if len(self._in):
            self._get_real(self._component, self._in_vr, len(self._in), self._in_ptr)
        return self._in.copy()

    def failed(self, what: str, t: float, status: int) -> StepFailed:
        """Record a failed call (status 2 Discard or worse) and describe it."""
        self.status = max(self.status, int(status))
        last = None
        self.last_outputs = {}
        if status == 2:  # after fmi2Discard the FMU says how far it got, and its outputs there
            try:
                from fmpy.fmi2 import fmi2LastSuccessfulTime

                last = float(self.instance.getRealStatus(fmi2LastSuccessfulTime))
                values = self.instance.getReal(list(self._out_vr))
                self.last_outputs = {f"{self.name}.{n}": float(v) for n, v in zip(self.outputs, values)}
            except FMICallException:  # the FMU does not tell: the last communicated values remain
                last = None
        said = self.fmu_said()
        message = f"{self.name}: {what} failed at t = {t:g} s (status {STATUS_NAMES.get(status, status)})"
        if last is not None and last > t:
            message += f", last successful time {last:g} s"
        if said:
            message += f": {said}"
        return StepFailed(message, self.name, t, int(status), last, said)

    def set_inputs(self, values: np.ndarray) -> None:
        if len(self._in):
            self._in[:] = values
            status = self._set_real(self._component, self._in_vr, len(self._in), self._in_ptr)
            if status > 1:
                raise self.failed("fmi2SetReal", self.now, status)

    def get_outputs(self) -> np.ndarray:
        if len(self._out):
            status = self._get_real(self._component, self._out_vr, len(self._out), self._out_ptr)
            if status > 1:
                raise self.failed("fmi2GetReal", self.now, status)
        return self._out

    def step(self, t: float, h: float) -> None:
        status = self._do_step(self._component, t, h, 1)
        if status > 1:  # fmi2Discard or worse
            raise self.failed("fmi2DoStep", t, status)
        self.now = t + h  # the C loop (fastloop.c) keeps the same time

    def close(self) -> None:
        """Terminate (where FMI allows it) and free the instance; raises only if fmi2Terminate
        fails after a run without failures."""
        instance, self.instance = self.instance, None
        error = None
        if instance is not None and self.status < 4:
            if self.status < 3:
                try:
                    instance.terminate()
                except Exception as exc:
                    if self.status == 0:  # a run that went well must not hide this
                        said = instance.log.last_error() if getattr(instance, "log", None) else None
                        error = SimulationError(f"{self.name}: fmi2Terminate failed: {said or exc}")
            try:
                instance.freeInstance()
            except Exception:  # nothing more can be done for this instance
                pass
        self.fmu.close()
        if error is not None:
            raise error
