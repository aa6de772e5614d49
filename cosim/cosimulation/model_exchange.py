"""Model-exchange coupling: every component integrated together as one ODE by classic Runge-Kutta 4.

The co-simulation algorithms of :mod:`cosim.cosimulation.master` (``jacobi``, ``gauss-seidel``)
hold every input over a communication step, so a feedback loop through the master is a
sampled-data system and differs from the compiled composed model to first order in the step.
Under ``algorithm = "model-exchange"`` the master instead integrates the states of all
components as one ODE ``X' = F(t, X)`` with the fixed-step classic Runge-Kutta scheme (four
stages, order 4) at the communication step, so the coupled signals are continuous in time as
in one Modelica model that connects the same parts:

* an FMU takes part through its FMI 2.0 Model Exchange interface (``fmi2SetTime``,
  ``fmi2SetContinuousStates``, ``fmi2SetReal`` of its inputs, ``fmi2GetReal`` of its outputs,
  ``fmi2GetDerivatives``) or its FMI 3.0 one (the same with ``fmi3SetFloat64``,
  ``fmi3GetFloat64`` and ``fmi3GetContinuousStateDerivatives``); its events are handled as
  the FMI state machines have it, by :mod:`cosim.fmu.access`: the event iteration after
  initialization, time events, state events (event indicators changing sign over a step, located
  by bisection) and step events (``CompletedIntegratorStep``), each by Event Mode at its time,
  after which the integration goes on from the FMU's new states; an FMU asking to terminate ends
  the run normally there;
* a Python block takes part through its continuous-time linear model ``x' = A x + B u``,
  ``y = C x + D u + r(t)`` (:meth:`~cosim.cosimulation.registry.Block.linear` and
  :meth:`~cosim.cosimulation.registry.Block.exogenous`); a block that is no finite-dimensional
  ODE (the exact transport delay reads its input history) is refused.

``F(t, X)``: each component gets its time and states; then the outputs are evaluated in an
order in which every output comes after the outputs it depends on without a state in between
(the FMUs' ModelStructure, the blocks' D matrices), each component's inputs set from the
connected outputs before its outputs are read; then every component's inputs are final and its
derivatives are read. A cycle of such dependencies (an algebraic loop) has no such order and is
refused, naming its connections. Outputs are recorded at the communication points, consistent
with the inputs there (under model-exchange both samplings of the co-simulation algorithms give
the same values).

Jumps of sources (``Pulse``, ``Step``, ``Bicycle.Sources.*``) are seen where the stages evaluate
them: one on a communication point is already on at the last stage of the step that ends there,
so with a jump the scheme is first order in the step (smooth systems: fourth order).
"""
from __future__ import annotations

from ctypes import POINTER, byref, c_bool, c_double, c_int, c_uint
from dataclasses import dataclass

import numpy as np

from fmpy.fmi1 import FMICallException

from cosim.errors import FMUError, SimulationError
from cosim.fmu.access import indicators_crossed, locate_state_event
from cosim.cosimulation.component import STATUS_NAMES, Component, FMUComponent, StepFailed
from cosim.cosimulation.outcome import Outcome, complete_message, finished, terminated
from cosim.cosimulation.registry import Block
from cosim.cosimulation.system import Connection, SystemError_

ALGORITHM = "model-exchange"
#: The Model Exchange calls of F(t, X) by their FMI 2 names (without the prefix) in FMI 3.
FMI3_CALLS = {"SetReal": "fmi3SetFloat64", "GetReal": "fmi3GetFloat64", "SetTime": "fmi3SetTime",
              "SetContinuousStates": "fmi3SetContinuousStates", "GetDerivatives": "fmi3GetContinuousStateDerivatives",
              "CompletedIntegratorStep": "fmi3CompletedIntegratorStep", "GetEventIndicators": "fmi3GetEventIndicators"}


class _FMUModel:
    """An FMU of the system driven through Model Exchange.

    The co-simulation component (:class:`FMUComponent`) is kept: its FMU, parameters, tolerance,
    inputs, outputs and dependencies are used as they are, and the Model Exchange instance is
    stored as its ``instance``, so the master's closing of the components terminates and frees
    it with the same rules as a Co-Simulation instance.
    """

    def __init__(self, component: FMUComponent, where: str):
        self.component = comp = component
        self.name = comp.name
        md = comp.fmu.description
        if md.modelExchange is None:
            raise SystemError_(f"{where}: component '{comp.name}': {comp.fmu.path.name} has no Model Exchange "
                               f"interface, which algorithm = \"{ALGORITHM}\" needs")
        self.inputs, self.outputs = list(comp.inputs), list(comp.outputs)
        self.nx = len(md.derivatives)
        vr = comp.fmu.vr
        # Signals of other types than Real (Integer, Boolean, ...: the component's other_inputs and
        # other_outputs) are read by their own calls; such inputs are discrete, which FMI lets a
        # Model Exchange FMU take in Event Mode only, so they are never set here (ModelExchange
        # refuses a connection to one). The Real inputs come first, as in the component.
        real = [n for n in self.inputs if n not in comp.other_inputs]
        self.other_inputs = list(comp.other_inputs)
        self._other_out = [n for n in self.outputs if n in comp.other_outputs]
        self._real_out = np.array([k for k, n in enumerate(self.outputs) if n not in comp.other_outputs], dtype=int)
        self._other_out_idx = np.array([k for k, n in enumerate(self.outputs) if n in comp.other_outputs], dtype=int)
        self._n_real_in, self._n_real_out = len(real), len(self._real_out)
        # Value references from the names (not the component's own arrays): the outputs listed
        # may be any Real variables of the FMU (a test observes local variables this way).
        self._in_vr = (c_uint * max(1, len(real)))(*[vr[n] for n in real])
        self._out_vr = (c_uint * max(1, self._n_real_out))(*[vr[self.outputs[k]] for k in self._real_out])
        self._u, self._y = np.zeros(len(self.inputs)), np.zeros(len(self.outputs))
        self._y_real = self._y if not self._other_out else np.zeros(self._n_real_out)
        self._x, self._dx = np.zeros(self.nx), np.zeros(self.nx)
        self.nz = int(md.numberOfEventIndicators or 0)
        self._z = np.zeros(self.nz)
        self._ptr = {k: getattr(self, k).ctypes.data_as(POINTER(c_double))
                     for k in ("_u", "_y_real", "_x", "_dx", "_z")}
        self.t = 0.0
        self.next_time: float | None = None  # the next time event the FMU announced [s]
        self.step_event = False  # CompletedIntegratorStep asked for event mode
        self.terminate = False  # the FMU asked to terminate the simulation

    def feedthrough(self, output: str) -> set[str]:
        return self.component.feedthrough(output)

    # ------------------------------------------------------------------ start

    def setup(self, start_time: float) -> None:
        """Instantiate for Model Exchange, set the parameters and enter initialization mode
        (what :meth:`FMUComponent.setup` does for Co-Simulation)."""
        comp = self.component
        comp.enter_initialization(start_time, "me")
        functions = comp.instance._functions  # the raw C functions: no FMPy wrapper per call
        self._c = comp.instance.component
        self._names = FMI3_CALLS if comp.fmu.is_fmi3 else {k: f"fmi2{k}" for k in FMI3_CALLS}
        self._f = {k: functions[name] for k, name in self._names.items()}
        if comp.fmu.is_fmi3:  # fmi3Set/GetFloat64 also take the number of values (scalars here: the same)
            set_float64, get_float64 = self._f["SetReal"], self._f["GetReal"]
            self._f["SetReal"] = lambda c, vr, n, values: set_float64(c, vr, n, values, n)
            self._f["GetReal"] = lambda c, vr, n, values: get_float64(c, vr, n, values, n)
        self.t = float(start_time)

    def initial_inputs(self) -> np.ndarray:
        if self._n_real_in:
            self._check(self._f["GetReal"](self._c, self._in_vr, self._n_real_in, self._ptr["_u"]),
                        self._names["GetReal"])
        if self.other_inputs:
            self._u[self._n_real_in:] = self._other(self.other_inputs)
        return self._u.copy()

    def _other(self, names: list[str]) -> np.ndarray:
        """Values of signals of other types than Real (``getInteger``, ``getBoolean``, ...)."""
        comp = self.component
        try:
            return comp.fmu.get(comp.instance, names)
        except FMICallException as exc:
            what = f"{comp.calls[0][:4]}Get{comp.fmu.variables[names[0]].type}"
            self._check(int(getattr(exc, "status", 3) or 3), what)
            raise

    def end_initialization(self) -> np.ndarray:
        """Leave initialization, do the event iteration FMI 2.0 and 3.0 require then
        (:meth:`cosim.fmu.access.FMU.event_iteration`), switch to continuous time; the initial
        states. ``terminate`` says whether the FMU asked to end the run there.
        """
        comp, instance = self.component, self.component.instance
        fmi = comp.calls[0][:4]  # fmi2 or fmi3
        comp._call(f"{fmi}ExitInitializationMode", instance.exitInitializationMode)
        update = self._event("the initial event iteration", lambda: comp.fmu.event_iteration(instance))
        self.terminate, self.next_time = update.terminate, update.next_time
        if not update.terminate:
            comp._call(f"{fmi}EnterContinuousTimeMode", instance.enterContinuousTimeMode)
        return self.states()

    def states(self) -> np.ndarray:
        """The FMU's continuous states (after initialization or an event that changed them)."""
        comp, instance = self.component, self.component.instance
        if self.nx:
            comp._call(f"{comp.calls[0][:4]}GetContinuousStates",
                       lambda: instance.getContinuousStates(self._ptr["_x"], self.nx))
        return self._x.copy()

    def _event(self, what: str, call):
        """An event call of :mod:`cosim.fmu.access`; a refusal names the component and the time."""
        comp = self.component
        try:
            return call()
        except FMUError as exc:
            raise SimulationError(f"{self.name}: {exc} (t = {self.t:g} s)") from None
        except FMICallException as exc:
            comp.status = max(comp.status, int(getattr(exc, "status", 3) or 3))
            said = comp.fmu_said()
            raise StepFailed(f"{self.name}: {what} failed at t = {self.t:g} s" + (f": {said}" if said else f" ({exc})"),
                             self.name, self.t, comp.status, None, said) from None

    def handle_event(self) -> bool:
        """Event Mode at the current time and back (:meth:`cosim.fmu.access.FMU.handle_event`): the
        FMU's next time event is updated; True if its continuous states changed. ``terminate``
        says whether it asked to end the run."""
        comp = self.component
        update = self._event("the event iteration", lambda: comp.fmu.handle_event(comp.instance))
        self.terminate, self.next_time, self.step_event = update.terminate, update.next_time, False
        return update.states_changed

    # ------------------------------------------------------------------ F(t, X)

    def _check(self, status: int, what: str) -> None:
        if status > 1:  # Discard or worse: record it for close(), quote the FMU
            comp = self.component
            comp.status = max(comp.status, int(status))
            said = comp.fmu_said()
            raise StepFailed(f"{self.name}: {what} failed at t = {self.t:g} s (status "
                             f"{STATUS_NAMES.get(status, status)})" + (f": {said}" if said else ""),
                             self.name, self.t, int(status), None, said)

    def set_point(self, t: float, x: np.ndarray) -> None:
        self.t = t
        self._check(self._f["SetTime"](self._c, t), self._names["SetTime"])
        if self.nx:
            self._x[:] = x
            self._check(self._f["SetContinuousStates"](self._c, self._ptr["_x"], self.nx),
                        self._names["SetContinuousStates"])

    def feed(self, u: np.ndarray) -> None:
        self._u[:] = u
        if self._n_real_in:
            self._check(self._f["SetReal"](self._c, self._in_vr, self._n_real_in, self._ptr["_u"]),
                        self._names["SetReal"])

    def read(self) -> np.ndarray:
        if self._n_real_out:
            self._check(self._f["GetReal"](self._c, self._out_vr, self._n_real_out, self._ptr["_y_real"]),
                        self._names["GetReal"])
        if self._other_out:
            self._y[self._real_out] = self._y_real
            self._y[self._other_out_idx] = self._other(self._other_out)
        return self._y

    def derivatives(self) -> np.ndarray:
        if self.nx:
            self._check(self._f["GetDerivatives"](self._c, self._ptr["_dx"], self.nx), self._names["GetDerivatives"])
        return self._dx

    def indicators(self) -> np.ndarray:
        """The event indicators at the point last set (``fmi2/fmi3GetEventIndicators``)."""
        if self.nz:
            self._check(self._f["GetEventIndicators"](self._c, self._ptr["_z"], self.nz),
                        self._names["GetEventIndicators"])
        return self._z

    def completed_step(self) -> None:
        """``fmi2CompletedIntegratorStep``/``fmi3CompletedIntegratorStep`` at the accepted point
        (FMI requires the call); a step event it asks for is noted in ``step_event``, a request to
        terminate in ``terminate``."""
        flag = c_bool if self.component.fmu.is_fmi3 else c_int  # fmi3Boolean is C's bool
        event, terminate = flag(0), flag(0)
        self._check(self._f["CompletedIntegratorStep"](self._c, 1, byref(event), byref(terminate)),
                    self._names["CompletedIntegratorStep"])
        self.step_event, self.terminate = bool(event.value), bool(terminate.value)


class _BlockModel:
    """A Python block as its continuous-time linear model ``x' = A x + B u``,
    ``y = C x + D u + r(t)`` (the same matrices the block steps with, so nothing is approximated)."""

    def __init__(self, block: Block, where: str):
        self.block, self.name = block, block.name
        kind = type(block).__name__
        try:
            model = block.linear({})
        except NotImplementedError:
            raise SystemError_(f"{where}: component '{block.name}' ({kind}) has no continuous-time model, "
                               f"which algorithm = \"{ALGORITHM}\" needs") from None
        if block.interpolates:
            # Its linear model is a Pade approximation: integrating that would change the system.
            raise SystemError_(f"{where}: component '{block.name}' ({kind}) reads its input history (an exact "
                               f"delay is no ODE) and cannot take part in algorithm = \"{ALGORITHM}\"; "
                               "use a PadeDelay block, or algorithm = \"jacobi\"")
        if list(model.inputs) != list(block.inputs) or list(model.outputs) != list(block.outputs):
            raise SystemError_(f"{where}: component '{block.name}' ({kind}): its linear model's signals "
                               f"{model.inputs} -> {model.outputs} are not the block's {block.inputs} -> "
                               f"{block.outputs}")
        self.model = model
        self.inputs, self.outputs, self.nx = list(block.inputs), list(block.outputs), model.n
        self._u, self._x, self.t = np.zeros(len(self.inputs)), np.zeros(self.nx), 0.0

    def feedthrough(self, output: str) -> set[str]:
        row = self.model.D[self.outputs.index(output)]
        return {name for name, d in zip(self.inputs, row) if d != 0}

    def setup(self, start_time: float) -> None:
        self.block.setup(start_time)
        self.t = float(start_time)
        self._x[:] = self._initial_state()  # the outputs read while initializing see it

    def _initial_state(self) -> np.ndarray:
        # A block with states starts where its Python stepping starts it (Linear.x0).
        x0 = np.asarray(getattr(self.block, "x", np.zeros(self.nx)), float).reshape(-1)
        if x0.size != self.nx:
            raise SimulationError(f"{self.name}: {x0.size} initial states, its linear model has {self.nx}")
        return x0

    def initial_inputs(self) -> np.ndarray:
        return np.zeros(len(self.inputs))

    def end_initialization(self) -> np.ndarray:
        return self._initial_state().copy()

    def set_point(self, t: float, x: np.ndarray) -> None:
        self.t = t
        self._x[:] = x

    def feed(self, u: np.ndarray) -> None:
        self._u[:] = u

    def read(self) -> np.ndarray:
        m = self.model
        return m.C @ self._x + m.D @ self._u + self.block.exogenous(self.t)

    def derivatives(self) -> np.ndarray:
        m = self.model
        return m.A @ self._x + m.B @ self._u

    def completed_step(self) -> None:
        """Nothing to tell a block."""

    # A block has no events: its sources' jumps are seen where the stages evaluate them.
    nz, next_time, step_event, terminate = 0, None, False, False

    def indicators(self) -> np.ndarray:
        return np.zeros(0)

    def handle_event(self) -> bool:
        return False

    def states(self) -> np.ndarray:
        return self._x.copy()


@dataclass
class _Edge:
    """Output ``target`` depends on output ``source`` through ``connection`` without a state."""

    source: int
    target: int
    connection: Connection


class ModelExchange:
    """The model-exchange coupling of an assembled :class:`~cosim.cosimulation.master.System`.

    Created when the system is assembled, so a system it cannot integrate (an algebraic loop, a
    block without an ODE, a connection to an FMU's discrete input) is refused before anything
    runs.

    Parameters
    ----------
    system : System
        The assembled system (components, connections, signal vector, recording).

    Raises
    ------
    SystemError_
        For a component that cannot take part, or an algebraic loop (the message names the
        connections around it).
    """

    def __init__(self, system):
        self.system = system
        where = str(system.spec.path or system.spec.name)
        self.parts = [self._part(system.components[n], where) for n in system.names]
        for c in system.connections:
            part = self.parts[system.names.index(c.target)]
            if c.input in getattr(part, "other_inputs", ()):
                raise SystemError_(f"{where}: connection '{c}': '{c.target}.{c.input}' is a discrete input "
                                   f"({part.component.signal_types[c.input]}), which a Model Exchange FMU takes in "
                                   f"Event Mode only; algorithm = \"{ALGORITHM}\" sets inputs in continuous time "
                                   "(use algorithm = \"jacobi\" or \"gauss-seidel\")")
        # States of part i in X[self.slices[i]].
        sizes = np.cumsum([0] + [p.nx for p in self.parts])
        self.slices = [slice(int(a), int(b)) for a, b in zip(sizes[:-1], sizes[1:])]
        self.nx = int(sizes[-1])
        self.schedule, self.final_feeds = self._schedule(where)

    @staticmethod
    def _part(component: Component, where: str):
        if isinstance(component, FMUComponent):
            return _FMUModel(component, where)
        if isinstance(component, Block):
            return _BlockModel(component, where)
        raise SystemError_(f"{where}: component '{component.name}' ({type(component).__name__}) has neither a "
                           f"Model Exchange interface nor a linear model, which algorithm = \"{ALGORITHM}\" needs")

    # ------------------------------------------------------------------ evaluation order

    def _schedule(self, where: str) -> tuple[list[int], list[int]]:
        """Which part to evaluate (feed its inputs, read its outputs) when, so every output is
        read after the outputs it depends on without a state; and the parts whose inputs must
        be fed once more afterwards (their last evaluation had inputs that were not final).

        The graph has one node per output (global signal index), an edge from an output to each
        output that depends on the input it is connected to. Kahn's algorithm orders it by
        evaluations: one evaluation of a part reads every output of it whose dependencies are
        already read. Parts' outputs, not parts, are ordered (unlike the Gauss-Seidel order of the
        master): at a point (t, X) a bicycle's roll angle, which depends on its state only, must
        be read before the controller it feeds, whose steer angle the bicycle then takes.
        """
        system = self.system
        owner = np.empty(len(system.signals), dtype=int)
        for i, name in enumerate(system.names):
            owner[system.offset[name]:system.offset[name] + len(self.parts[i].outputs)] = i
        link = {(c.target, c.input): c for c in system.connections}
        edges: list[_Edge] = []
        for i, (name, part) in enumerate(zip(system.names, self.parts)):
            source_of = {part.inputs[k]: int(s) for k, s in zip(system.targets[name], system.sources[name])}
            for j, output in enumerate(part.outputs):
                for input_ in sorted(part.feedthrough(output) & set(source_of)):
                    edges.append(_Edge(source_of[input_], system.offset[name] + j, link[(name, input_)]))
        n = len(system.signals)
        after = [[] for _ in range(n)]
        waiting = np.zeros(n, dtype=int)
        for e in edges:
            after[e.source].append(e)
            waiting[e.target] += 1
        ready = [k for k in range(n) if waiting[k] == 0]
        done_at = np.full(n, -1)  # position in the schedule of the evaluation that reads an output
        schedule: list[int] = []
        while ready:
            # One evaluation of a part reads every output of it whose dependencies are read.
            part = int(owner[min(ready)])
            batch = [k for k in ready if owner[k] == part]
            ready = [k for k in ready if owner[k] != part]
            schedule.append(part)
            for k in batch:
                done_at[k] = len(schedule) - 1
                for e in after[k]:
                    waiting[e.target] -= 1
                    if waiting[e.target] == 0:
                        ready.append(e.target)
        if np.any(done_at < 0):
            raise SystemError_(f"{where}: {self._loop_message(edges, done_at >= 0)}")
        # An input is final once the output it comes from is read: a part whose last
        # evaluation was not after that is fed once more before its derivatives are read.
        last = {part: position for position, part in enumerate(schedule)}
        final_feeds = [i for i, name in enumerate(system.names) if system.sources[name].size
                       and any(done_at[int(s)] >= last.get(i, -1) for s in system.sources[name])]
        return schedule, final_feeds

    def _loop_message(self, edges: list[_Edge], done: np.ndarray) -> str:
        """One algebraic loop among the outputs that could not be ordered, as its connections."""
        # Every output left waits for another output left: walking back along those
        # dependencies must repeat an output, which closes a loop.
        before: dict[int, _Edge] = {}
        for e in edges:
            if not done[e.source] and not done[e.target]:
                before.setdefault(e.target, e)
        node = next(iter(before))
        path, seen = [], {}
        while node not in seen:
            seen[node] = len(path)
            path.append(before[node])
            node = before[node].source
        cycle = path[seen[node]:][::-1]
        links = ", ".join(f"'{e.connection}'" for e in cycle)
        names = sorted({e.connection.source for e in cycle} | {e.connection.target for e in cycle},
                       key=self.system.names.index)
        return (f"algebraic loop under algorithm = \"{ALGORITHM}\" through {', '.join(names)}: {links} (each "
                "output depends on the connected input without a state in between, so the coupled system is "
                "no explicit ODE); break it with a component whose output depends on its state only (no direct "
                "feedthrough), or use algorithm = \"jacobi\", which holds the inputs over a step")

    # ------------------------------------------------------------------ F(t, X)

    def _evaluate_outputs(self) -> None:
        """Read every output in schedule order (times and states already set), then feed the
        parts whose inputs were not final at their last reading."""
        system, parts = self.system, self.parts
        names, signals = system.names, system.signals
        for i in self.schedule:
            name = names[i]
            self._feed(i)
            start = system.offset[name]
            signals[start:start + len(parts[i].outputs)] = parts[i].read()
        for i in self.final_feeds:
            self._feed(i)

    def _feed(self, i: int) -> None:
        name = self.system.names[i]
        targets = self.system.targets[name]
        if targets.size:
            u = self._inputs[i]
            u[targets] = self.system.signals[self.system.sources[name]]
            self.parts[i].feed(u)

    def derivatives(self, t: float, x: np.ndarray, out: np.ndarray) -> np.ndarray:
        """``F(t, X)`` into ``out``; afterwards the system's signal vector holds the outputs at
        ``(t, X)``."""
        for part, where in zip(self.parts, self.slices):
            part.set_point(t, x[where])
        self._evaluate_outputs()
        for part, where in zip(self.parts, self.slices):
            if part.nx:
                out[where] = part.derivatives()
        return out

    # ------------------------------------------------------------------ the run

    def indicators(self) -> np.ndarray:
        """Every FMU part's event indicators at the point last evaluated, one vector."""
        return np.concatenate([np.zeros(0)] + [p.indicators().copy() for p in self.parts if p.nz])

    def _rk4(self, t: float, x: np.ndarray, h: float, k1: np.ndarray) -> np.ndarray:
        """One classic RK4 step from ``(t, x)`` over ``h`` [s]; ``k1`` is F at ``(t, x)``."""
        k2, k3, k4 = self._stages
        self.derivatives(t + h / 2, x + h / 2 * k1, k2)
        self.derivatives(t + h / 2, x + h / 2 * k2, k3)
        self.derivatives(t + h, x + h * k3, k4)
        return x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)

    def _events(self, t: float, x: np.ndarray, due: list) -> tuple[np.ndarray, str | None]:
        """Handle the events of the parts ``due`` at ``t`` [s] (states ``x``): the new states, and
        the name of the first part that asked to terminate (None if none did)."""
        for i in due:
            part = self.parts[i]
            if part.handle_event():
                x = x.copy()
                x[self.slices[i]] = part.states()
            if part.terminate:
                return x, part.name
        return x, None

    def _time_events(self, t: float, resolution: float) -> list[int]:
        return [i for i, p in enumerate(self.parts) if p.next_time is not None and p.next_time <= t + resolution]

    def run(self):
        """Initialize, integrate over the communication grid with RK4, handling the FMUs' events,
        record.

        Between communication points the integration stops at every event (FMI 2.0 and 3.0 Model
        Exchange, handled by :mod:`cosim.fmu.access`): a time event an FMU announced, a state
        event (an event indicator changing its sign over a step, located by bisection of the
        step to :attr:`event_resolution` of it) and a step event (``CompletedIntegratorStep``);
        each FMU with an event enters Event Mode there, and the step goes on from the event with
        the states the FMU reports. An FMU asking to terminate ends the run normally there (a
        last row at that time if it is no communication point).

        Returns
        -------
        RunResult
            As :meth:`System.run`: the recorded outputs at every communication point and the
            outcome (completed, terminated, fell, diverged; failed raises).

        Raises
        ------
        RunFailed
            If an FMU call failed (fmi2Discard or worse); it carries the rows up to the last
            completed communication point.
        """
        system, spec = self.system, self.system.spec
        grid, data = system.recording_buffer()
        n_steps = len(grid) - 1
        record_names, record_idx = system.record
        parts, signals = self.parts, system.signals
        rows, outcome = 1, Outcome("completed", spec.stop, complete_message(spec.stop, n_steps, grid))
        self._stages = tuple(np.zeros(self.nx) for _ in range(3))
        try:
            for part in parts:
                part.setup(spec.start)
            self._inputs = [part.initial_inputs() for part in parts]
            if spec.initialize:  # the initial outputs reach the connected inputs, as in the other algorithms
                self._evaluate_outputs()
            x = np.concatenate([np.zeros(0)] + [part.end_initialization() for part in parts])
            k1 = np.zeros(self.nx)
            t = float(grid[0])
            try:
                self.derivatives(t, x, k1)
                data[0, 0], data[0, 1:] = t, signals[record_idx]
                ender = next((p.name for p in parts if p.terminate), None)
                stop = terminated(ender, t) if ender else system._check_outcome(t)
                if stop is not None:
                    outcome, n_steps = stop, 0
                z = self.indicators()
                for k in range(n_steps):
                    t_end = float(grid[k + 1])
                    resolution = self.event_resolution * (t_end - float(grid[k]))
                    ender = None
                    while t_end - t > resolution and ender is None:
                        t, x, k1, z, ender = self._advance(t, x, k1, z, t_end, resolution)
                    if not np.all(np.isfinite(x)):
                        bad = int(np.flatnonzero(~np.isfinite(x))[0])
                        name = next(p.name for p, s in zip(parts, self.slices) if s.start <= bad < s.stop)
                        outcome = Outcome("diverged", t, f"a state of {name} is not finite at t = {t:g} s")
                        break
                    # On the communication point (within the resolution of events), or an end
                    # between points: a last row at that time.
                    data[k + 1, 0] = t_end if t_end - t <= resolution else t
                    data[k + 1, 1:] = signals[record_idx]
                    rows = k + 2
                    if ender is not None:
                        outcome = terminated(ender, float(data[k + 1, 0]))
                        break
                    stop = system._check_outcome(t)
                    if stop is not None:
                        outcome = stop
                        break
            except StepFailed as exc:
                outcome = system._failed_outcome(exc.component, exc.time, str(exc))
        finally:
            system._close_all()
        return finished(data, rows, record_names, outcome)

    #: Width of the bracket a state event is located to, as a fraction of the communication step.
    event_resolution = 1e-10

    def _advance(self, t: float, x: np.ndarray, k1: np.ndarray, z: np.ndarray, t_end: float, resolution: float):
        """One RK4 step from ``t`` towards ``t_end`` [s], shortened to the next time event or the
        first state event, with the events there handled: ``(t, x, k1, z, ender)`` after it
        (``ender``: the part that asked to terminate, or None). The signal vector holds the
        outputs at the new point."""
        parts = self.parts
        # A time event within the resolution of the communication point is taken at its own time.
        times = [p.next_time for p in parts if p.next_time is not None and p.next_time <= t_end + resolution]
        t_next = max(t, min(times)) if times else t_end
        h = t_next - t
        x_new = self._rk4(t, x, h, k1)
        k1_new = np.zeros(self.nx)
        self.derivatives(t_next, x_new, k1_new)
        z_new = self.indicators()
        crossed = indicators_crossed(z, z_new)
        if np.any(crossed):
            def indicators_at(tau: float) -> np.ndarray:
                x_tau = self._rk4(t, x, tau - t, k1)
                self.derivatives(tau, x_tau, k1_new)
                return self.indicators()

            t_next = locate_state_event(indicators_at, t, t_next, z, resolution)
            x_new = self._rk4(t, x, t_next - t, k1)
            self.derivatives(t_next, x_new, k1_new)
            z_new = self.indicators()
            crossed = indicators_crossed(z, z_new)
        for part in parts:
            part.completed_step()
        ender = next((p.name for p in parts if p.terminate), None)
        if ender is not None:
            return t_next, x_new, k1_new, z_new, ender
        due = set(self._time_events(t_next, resolution)) | {i for i, p in enumerate(parts) if p.step_event}
        offset = 0
        for i, p in enumerate(parts):
            if p.nz and np.any(crossed[offset:offset + p.nz]):
                due.add(i)
            offset += p.nz
        if due:
            x_new, ender = self._events(t_next, x_new, sorted(due))
            if ender is None:  # F and the outputs after the event
                self.derivatives(t_next, x_new, k1_new)
            z_new = self.indicators()
        return t_next, x_new, k1_new, z_new, ender
