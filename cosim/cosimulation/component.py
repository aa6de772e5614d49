"""The one protocol every co-simulation component follows, and its FMU implementation.

A component has named inputs and outputs carried as doubles (Real ones; an FMU's Integer, Boolean,
... signals as their values, see :data:`OTHER_SIGNAL_TYPES`) in a fixed order (the master addresses
them by index, never by name, while stepping) and may pass inputs straight through to outputs
(``feedthrough``).

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

from ctypes import POINTER, addressof, byref, c_bool, c_double, c_uint
from pathlib import Path

import numpy as np
from fmpy.fmi1 import FMICallException

from cosim.errors import SimulationError
from cosim.cosimulation import fastloop  # fastloop.library looked up when used: a replacement is seen
from cosim.cosimulation.fastloop import address, fmi3_adapters, Fmi3Adapter
from cosim.fmu.access import ALL_FMI_VERSIONS, FMU


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
        SimulationEnded
            If an FMU asks to terminate the simulation (``terminateSimulation``) without an
            error: its outputs are those where it ended.
        """
        raise NotImplementedError

    def close(self) -> None:
        """Release resources (called once, also after a failure)."""


class StepFailed(SimulationError):
    """An FMU's ``fmi2DoStep``/``fmi3DoStep`` (or a get/set around it) failed part-way through a run.

    Attributes
    ----------
    component : str
        The component's name.
    time : float
        Start of the communication step that failed [s].
    status : int
        The FMI status returned (2 Discard, 3 Error, 4 Fatal).
    last_successful_time : float or None
        After a Discard, how far the FMU got [s]: ``fmi2LastSuccessfulTime`` (FMI 2, where the
        FMU reports it) or fmi3DoStep's ``lastSuccessfulTime``.
    fmu_message : str or None
        The FMU's last logged error message.
    """

    def __init__(self, message: str, component: str, time: float, status: int,
                 last_successful_time: float | None = None, fmu_message: str | None = None):
        super().__init__(message)
        self.component, self.time, self.status = component, time, status
        self.last_successful_time, self.fmu_message = last_successful_time, fmu_message


class SimulationEnded(SimulationError):
    """An FMU ended the run itself without an error (``terminateSimulation``: FMI 2 ``fmi2DoStep``
    returning fmi2Discard with ``fmi2GetBooleanStatus(fmi2Terminated)`` true, FMI 3 ``fmi3DoStep``'s
    ``terminateSimulation`` out-argument): a normal end of the model, not a failure.

    Attributes
    ----------
    component : str
        The component's name.
    time : float
        How far the FMU got [s] (``fmi2LastSuccessfulTime``, fmi3DoStep's ``lastSuccessfulTime``,
        or the end of the step where the FMU does not say).
    """

    def __init__(self, component: str, time: float):
        super().__init__(f"{component}: the FMU ended the simulation at t = {time:g} s (terminateSimulation)")
        self.component, self.time = component, time


STATUS_NAMES = {0: "OK", 1: "Warning", 2: "Discard", 3: "Error", 4: "Fatal", 5: "Pending"}


def _is_real_scalar(v) -> bool:
    """A variable the master connects: FMI 2 ``Real``, FMI 3 ``Float64`` without dimensions."""
    return v.type == "Real" or (v.type == "Float64" and not v.dimensions)


def _signal_type(v) -> str:
    """The variable's type as a refused connection names it (FMI 3 arrays as such)."""
    return f"{v.type} array" if getattr(v, "dimensions", None) else v.type


#: Scalar types besides FMI 2 Real / FMI 3 Float64 that the master carries as signals (their values
#: as doubles: integers exactly up to 2**53, Booleans as 0 and 1) and connects to the same type only.
OTHER_SIGNAL_TYPES = frozenset({"Integer", "Boolean", "Enumeration", "Float32", "Int8", "UInt8", "Int16", "UInt16",
                                "Int32", "UInt32", "Int64", "UInt64"})
#: Types that are one type across FMI versions (FMI 2 Integer is a 32-bit integer).
_SAME_TYPE = {"Float64": "Real", "Int32": "Integer"}


def _is_other_scalar(v) -> bool:
    return v.type in OTHER_SIGNAL_TYPES and not getattr(v, "dimensions", None)


def connection_type(v) -> str:
    """The type by which a connection is checked: equal for variables that may be connected
    (FMI 2 Real and FMI 3 Float64; Integer and Int32; an enumeration with its declared type)."""
    if v.type == "Enumeration":
        declared = getattr(getattr(v, "declaredType", None), "name", None)
        return f"Enumeration {declared}" if declared else "Enumeration"
    return _SAME_TYPE.get(v.type, v.type)


#: The calls of a communication step by FMI version: (set inputs, step, get outputs), as messages name them.
CALLS = {"2": ("fmi2SetReal", "fmi2DoStep", "fmi2GetReal"), "3": ("fmi3SetFloat64", "fmi3DoStep", "fmi3GetFloat64")}


class FMUComponent(Component):
    """An FMI 2.0 or FMI 3.0 Co-Simulation FMU behind the component protocol.

    Inputs and outputs are the FMU's scalar variables of causality input/output: the real ones
    (FMI 2 ``Real``, FMI 3 ``Float64`` without dimensions) first, then those of the other types
    of :data:`OTHER_SIGNAL_TYPES` (``other_inputs``, ``other_outputs``; ``signal_types`` gives
    every signal's type for the connection rules). Value references and ctypes buffers are
    prepared once, so a step of an FMU with real signals only costs three calls into the FMU.

    Both versions are driven through the FMI 2 signatures of ``fmi2SetReal``, ``fmi2DoStep`` and
    ``fmi2GetReal`` (``_set_real``, ``_do_step``, ``_get_real`` on ``_component``): an FMI 3 FMU
    through the adapters of fastloop.c (:func:`~cosim.cosimulation.fastloop.fmi3_adapters`),
    whose ``_component`` is an :class:`~cosim.cosimulation.fastloop.Fmi3Adapter`. FMI 3 inputs
    are held over each step (zero-order hold; FMI 3 has no input derivatives, and the FMU is
    instantiated without event mode, early return or intermediate update).

    The worst FMI status seen (``status``) decides what :meth:`close` may still call: after a
    Discard the instance is terminated and freed, after an Error only freed (FMI allows no
    Terminate in the error state), after Fatal left alone.
    """

    def __init__(self, name: str, path: str | Path, parameters: dict | None = None, tolerance: float | None = None):
        super().__init__(name)
        self.fmu = FMU(path, versions=ALL_FMI_VERSIONS)
        md = self.fmu.description
        if md.coSimulation is None:
            raise SimulationError(f"{name}: {path} does not support Co-Simulation")
        self.calls = CALLS[self.fmu.fmi_version[:1]]
        self._prefix = self.calls[0][:4]  # fmi2 or fmi3, for messages
        # Every variable by name: (causality, type), to explain a connection that cannot be made.
        self.variables = {v.name: (v.causality, _signal_type(v)) for v in md.modelVariables}
        # Signals: the Real ones first (the C loop's fmi2SetReal/fmi2GetReal take them as one
        # array), then the other scalar types (OTHER_SIGNAL_TYPES), set and read by their own calls.
        signals = {kind: ([v.name for v in md.modelVariables if v.causality == kind and _is_real_scalar(v)],
                          [v.name for v in md.modelVariables if v.causality == kind and _is_other_scalar(v)])
                   for kind in ("input", "output")}
        # FMI 3 array outputs of these types are signals element by element (``y[1]``, ``y[2]``, ...:
        # recorded and connectable as scalars), read by one call per array.
        elements = {v.name: self.fmu.elements([v.name]) for v in md.modelVariables
                    if v.causality == "output" and getattr(v, "dimensions", None)
                    and (v.type == "Float64" or v.type in OTHER_SIGNAL_TYPES)}
        signals["output"][1].extend(e for array in elements.values() for e in array)
        self.inputs = signals["input"][0] + signals["input"][1]
        self.outputs = signals["output"][0] + signals["output"][1]
        self.other_inputs, self.other_outputs = signals["input"][1], signals["output"][1]
        #: The type of every signal, as connections are checked (:func:`connection_type`).
        self.signal_types = {v.name: connection_type(v) for v in md.modelVariables
                             if v.name in self.inputs or v.name in self.outputs}
        self.signal_types.update({e: connection_type(self.fmu.variables[name])
                                  for name, array in elements.items() for e in array})
        self.parameters = dict(parameters or {})
        self.tolerance = tolerance
        self._depends = self._output_dependencies()
        for name, array in elements.items():  # an element depends on what its array depends on
            self._depends.update(dict.fromkeys(array, self._depends.get(name, set(self.inputs))))
        real_in, real_out = signals["input"][0], signals["output"][0]
        self._in_vr = (c_uint * len(real_in))(*[self.fmu.vr[n] for n in real_in])
        self._out_vr = (c_uint * len(real_out))(*[self.fmu.vr[n] for n in real_out])
        self._n_real = (len(real_in), len(real_out))
        self._in = np.zeros(len(self.inputs))
        self._out = np.zeros(len(self.outputs))
        self._in_ptr = self._in.ctypes.data_as(POINTER(c_double))
        self._out_ptr = self._out.ctypes.data_as(POINTER(c_double))
        self.instance = None
        self._adapter = None  # FMI 3: the Fmi3Adapter the calls go through (see setup)
        self.status = 0
        self.last_outputs: dict[str, float] = {}  # outputs at the last successful time after a Discard
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
        if self.fmu.is_fmi3:
            self._setup_fmi3(functions)
            return
        self._component = self.instance.component
        self._set_real, self._get_real = functions["fmi2SetReal"], functions["fmi2GetReal"]
        self._do_step = functions["fmi2DoStep"]

    def _setup_fmi3(self, functions) -> None:
        """The FMI 2 signatures on an FMI 3 instance: fastloop.c's adapters, or where the loop's
        library cannot be had (no C compiler) the same adaptation in Python."""
        set_float64, get_float64 = functions["fmi3SetFloat64"], functions["fmi3GetFloat64"]
        do_step = functions["fmi3DoStep"]
        adapter = self._adapter = Fmi3Adapter(self.instance.component, address(set_float64), address(get_float64),
                                              address(do_step), 0, 0, 0, 0, self.now)
        lib = fastloop.library()
        if lib is not None:
            self._component = addressof(adapter)
            self._set_real, self._get_real, self._do_step = fmi3_adapters(lib)
            return
        self._component = self.instance.component

        def set_real(instance, vr, n, values):
            return set_float64(instance, vr, n, values, n)

        def get_real(instance, vr, n, values):
            return get_float64(instance, vr, n, values, n)

        def step(instance, t, h, no_set_state_prior):  # as cosim_fmi3_do_step in fastloop.c
            flags, last = [c_bool(False) for _ in range(3)], c_double(t)
            status = do_step(instance, t, h, bool(no_set_state_prior), *map(byref, flags), byref(last))
            adapter.status = status
            adapter.event_handling_needed, adapter.terminate_simulation, adapter.early_return = (
                int(f.value) for f in flags)
            adapter.last_successful_time = last.value
            return 2 if status <= 1 and (flags[1].value or flags[2].value) else status

        self._set_real, self._get_real, self._do_step = set_real, get_real, step

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
        if self.fmu.is_fmi3:  # FMI 3 has no setupExperiment: the experiment comes with initialization
            self._call("fmi3EnterInitializationMode", lambda: self.instance.enterInitializationMode(
                tolerance=self.tolerance, startTime=start_time))
            return
        self._call("fmi2SetupExperiment", lambda: self.instance.setupExperiment(tolerance=self.tolerance,
                                                                               startTime=start_time))
        self._call("fmi2EnterInitializationMode", self.instance.enterInitializationMode)

    def end_initialization(self) -> None:
        self._call(f"{self._prefix}ExitInitializationMode", self.instance.exitInitializationMode)

    def initial_inputs(self) -> np.ndarray:
        if self._n_real[0]:
            self._get_real(self._component, self._in_vr, self._n_real[0], self._in_ptr)
        if self.other_inputs:
            self._in[self._n_real[0]:] = self._get_other(self.other_inputs)
        return self._in.copy()

    def _get_other(self, names: list[str]) -> np.ndarray:
        """The values of signals of the other types (``OTHER_SIGNAL_TYPES``) by name."""
        try:
            return self.fmu.get(self.instance, names)
        except FMICallException as exc:
            raise self.failed(f"{self._prefix}Get{self.fmu.variables[names[0]].type}", self.now,
                              int(getattr(exc, "status", 3) or 3)) from None

    def _set_other(self, values: np.ndarray) -> None:
        try:
            self.fmu.set(self.instance, dict(zip(self.other_inputs, values)))
        except FMICallException as exc:
            raise self.failed(f"{self._prefix}Set{self.fmu.variables[self.other_inputs[0]].type}", self.now,
                              int(getattr(exc, "status", 3) or 3)) from None

    def failed(self, what: str, t: float, status: int) -> StepFailed:
        """Record a failed call (status 2 Discard or worse) and describe it."""
        self.status = max(self.status, int(status))
        last = None
        self.last_outputs = {}
        requested = self._fmi3_request(what)
        if status == 2:  # after a Discard the FMU says how far it got, and its outputs there
            try:
                if self._adapter is not None:
                    last = float(self._adapter.last_successful_time) if what == self.calls[1] else None
                else:
                    from fmpy.fmi2 import fmi2LastSuccessfulTime

                    last = float(self.instance.getRealStatus(fmi2LastSuccessfulTime))
                values = self.fmu.get(self.instance, self.outputs)
                self.last_outputs = {f"{self.name}.{n}": float(v) for n, v in zip(self.outputs, values)}
            except FMICallException:  # the FMU does not tell: the last communicated values remain
                last = None if self._adapter is None else last
        said = self.fmu_said()
        if requested:
            message = f"{self.name}: {what} at t = {t:g} s: {requested}"
        else:
            message = f"{self.name}: {what} failed at t = {t:g} s (status {STATUS_NAMES.get(status, status)})"
        if last is not None and last > t:
            message += f", last successful time {last:g} s"
        if said:
            message += f": {said}"
        return StepFailed(message, self.name, t, int(status), last, said)

    def end_requested(self, what: str, t: float, h: float, status: int) -> float | None:
        """If the call ``what`` (the step from ``t`` over ``h`` [s]) returned ``status`` because
        the FMU asks to terminate the simulation without an error: how far it got [s]
        (:class:`SimulationEnded`); None for a failure. An FMI 3 early return is a failure (the
        instance does not allow it), and so is a request to terminate with an error message
        logged (an FMI 2 FMU whose integrator failed may report fmi2Terminated: as ``cosim
        simulate`` tells the two apart)."""
        if what != self.calls[1] or self.fmu_said():
            return None
        adapter = self._adapter
        if adapter is not None:
            if adapter.status > 1 or not adapter.terminate_simulation:
                return None
            reached = float(adapter.last_successful_time)
            return reached if t < reached <= t + h else t + h
        if status != 2:  # FMI 2 asks by fmi2Discard, then fmi2Terminated says why
            return None
        from fmpy.fmi2 import fmi2LastSuccessfulTime, fmi2Terminated

        try:
            if not self.instance.getBooleanStatus(fmi2Terminated):
                return None
        except FMICallException:  # the FMU does not say: a Discard
            return None
        try:
            reached = float(self.instance.getRealStatus(fmi2LastSuccessfulTime))
        except FMICallException:  # optional in FMI 2: the step is taken as done
            return t + h
        return reached if t < reached <= t + h * (1 + 1e-9) else t + h

    def _fmi3_request(self, what: str) -> str | None:
        """What an FMI 3 step that returned OK but ended the run asked for (None otherwise)."""
        adapter = self._adapter
        if adapter is None or what != self.calls[1] or adapter.status > 1:
            return None
        if adapter.terminate_simulation:
            return "the FMU asks to terminate the simulation (terminateSimulation)"
        if adapter.early_return:
            return "the FMU returned early (earlyReturn), which its instantiation did not allow"
        return None

    def set_inputs(self, values: np.ndarray) -> None:
        if len(self._in):
            self._in[:] = values
            if self._n_real[0]:
                status = self._set_real(self._component, self._in_vr, self._n_real[0], self._in_ptr)
                if status > 1:
                    raise self.failed(self.calls[0], self.now, status)
            if self.other_inputs:
                self._set_other(self._in[self._n_real[0]:])

    def get_outputs(self) -> np.ndarray:
        if self._n_real[1]:
            status = self._get_real(self._component, self._out_vr, self._n_real[1], self._out_ptr)
            if status > 1:
                raise self.failed(self.calls[2], self.now, status)
        if self.other_outputs:
            self._out[self._n_real[1]:] = self._get_other(self.other_outputs)
        return self._out

    def step(self, t: float, h: float) -> None:
        status = self._do_step(self._component, t, h, 1)
        if status > 1:  # Discard or worse (or an FMI 3 request to stop, see cosim_fmi3_do_step)
            reached = self.end_requested(self.calls[1], t, h, status)
            if reached is not None:
                self.now = reached
                raise SimulationEnded(self.name, reached)
            raise self.failed(self.calls[1], t, status)
        self.now = t + h  # the C loop (fastloop.c) keeps the same time

    def close(self) -> None:
        """Terminate (where FMI allows it) and free the instance; raises only if the Terminate
        call fails after a run without failures."""
        instance, self.instance = self.instance, None
        error = None
        if instance is not None and self.status < 4:
            if self.status < 3:
                try:
                    instance.terminate()
                except Exception as exc:
                    if self.status == 0:  # a run that went well must not hide this
                        said = instance.log.last_error() if getattr(instance, "log", None) else None
                        error = SimulationError(f"{self.name}: {self._prefix}Terminate failed: {said or exc}")
            try:
                instance.freeInstance()
            except Exception:  # nothing more can be done for this instance
                pass
        self.fmu.close()
        if error is not None:
            raise error
