"""The co-simulation master: fixed-step Jacobi or Gauss-Seidel over components (and, under
``algorithm = "model-exchange"``, one ODE integrated by RK4: :mod:`cosim.cosimulation.model_exchange`).

Signals travel through one preallocated vector holding every component output; each
component reads its inputs from it with a precomputed index array, so a step involves no
name lookups.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np

from cosim.errors import SimulationError
from cosim.cosimulation import algorithms
from cosim.cosimulation.component import Component, FMUComponent, SimulationEnded, StepFailed
from cosim.cosimulation.model_exchange import ModelExchange
from cosim.cosimulation.outcome import Outcome, RunFailed, RunResult, complete_message, finished, terminated
from cosim.cosimulation.system import MAX_STEPS, Connection, SystemError_, SystemSpec
from cosim.cosimulation import fastloop  # fastloop.library looked up when used: a replacement is seen
from cosim.cosimulation.fastloop import address, fast_block, FastComponent
from cosim.fmu.simulate import physical_cause
from cosim.progress import active as progress


#: Largest recording one run keeps in memory [bytes].
MAX_RECORD_BYTES = 2 * 1024**3


def step_grid(start: float, stop: float, step: float) -> np.ndarray:
    """The communication points from ``start`` to ``stop`` [s]: every ``step``, and ``stop``
    itself last. If ``step`` does not divide the span (beyond round-off, 1e-9 of a step) the
    last step is the shorter remainder, so a run always ends on ``stop`` exactly.

    The array is read-only: grids of up to :data:`CACHED_GRID_STEPS` steps are made once per
    (start, stop, step) and shared (a matrix runs thousands of cases on one grid).

    Raises
    ------
    SystemError_
        If step or span are not finite and positive, or the grid would have more than
        :data:`MAX_STEPS` steps.
    """
    if abs(stop - start) <= CACHED_GRID_STEPS * abs(step):
        return _cached_grid(float(start), float(stop), float(step))
    times = _make_grid(start, stop, step)
    times.setflags(write=False)
    return times


#: Calls of the C loop over one run's grid: between them the terminal shows how far the run is.
CHUNKS = 50


def _show_time(grid: np.ndarray, k: int) -> None:
    """How far a run is at the start of its step ``k`` (of a grid of at least one step)."""
    progress().fraction((grid[k] - grid[0]) / (grid[-1] - grid[0]), f"t = {grid[k]:.4g} of {grid[-1]:.4g} s")

#: Longest grid that :func:`step_grid` keeps (100,000 steps: 0.8 MB).
CACHED_GRID_STEPS = 100_000


@lru_cache(maxsize=32)
def _cached_grid(start: float, stop: float, step: float) -> np.ndarray:
    times = _make_grid(start, stop, step)
    times.setflags(write=False)
    return times


def _make_grid(start: float, stop: float, step: float) -> np.ndarray:
    span = stop - start
    if not (np.isfinite(step) and step > 0 and np.isfinite(span) and span > 0):
        raise SystemError_(f"step ({step:g} s) must be finite and > 0, and stop ({stop:g} s) finite and after "
                           f"start ({start:g} s)")
    count = span / step
    if not count <= MAX_STEPS:
        raise SystemError_(f"step {step:g} s from {start:g} s to {stop:g} s would take {count:.3g} steps "
                           f"(at most {MAX_STEPS:,}); use a larger step")
    full = int(np.floor(count + 1e-9))
    times = start + step * np.arange(full + 1, dtype=float)
    if span - full * step > 1e-9 * step:
        times = np.append(times, stop)
    times[-1] = stop  # exactly, not start + n * step
    return times


class System:
    """Components wired by connections, ready to run.

    Parameters
    ----------
    spec : SystemSpec
        Settings and connections.
    components : dict
        Component objects by name (created by :func:`cosim.cosimulation.factory.create_components`).
    """

    def __init__(self, spec: SystemSpec, components: dict[str, Component]):
        self.spec = spec
        self.components = components
        self.names = list(components)
        where = str(spec.path or spec.name)
        # Global output vector: offsets of each component's outputs.
        self.offset, size = {}, 0
        for name in self.names:
            self.offset[name] = size
            size += len(components[name].outputs)
        self.signals = np.zeros(size)
        self.sources: dict[str, np.ndarray] = {}
        self.targets: dict[str, np.ndarray] = {}
        connected: dict[tuple, Connection] = {}
        for c in spec.connections:
            self._check(c, where)
            key = (c.target, c.input)
            if key in connected:
                raise SystemError_(f"{where}: input {c.target}.{c.input} is connected twice: "
                                   f"'{connected[key]}' and '{c}'")
            connected[key] = c
        for name in self.names:
            comp = components[name]
            pairs = [(comp.inputs.index(c.input), self.offset[c.source] + components[c.source].outputs.index(c.output))
                     for c in connected.values() if c.target == name]
            self.targets[name] = np.array([p[0] for p in pairs], dtype=int)
            self.sources[name] = np.array([p[1] for p in pairs], dtype=int)
        self.connections = list(connected.values())
        for comp in components.values():  # a delay longer than the step has no feedthrough
            comp.configure_step(spec.step)
        self.algorithm = algorithms.algorithm(spec.algorithm)
        self.order = self._gauss_seidel_order(where) if self.algorithm.sequential else self.names
        self.fall_index = None
        if spec.fall_signal:
            comp, _, var = spec.fall_signal.partition(".")
            if comp not in components or var not in components[comp].outputs:
                raise SystemError_(f"{where}: fall signal '{spec.fall_signal}' is not a component output")
            self.fall_index = self.offset[comp] + components[comp].outputs.index(var)
        self.record = self._record_indices(where)
        self.coupling = None
        if self.algorithm.one_ode:  # one ODE, not stepped components: its own module
            self.coupling = ModelExchange(self)

    def _check(self, c: Connection, where: str) -> None:
        self._check_ends(c, where)
        source, target = self.components[c.source], self.components[c.target]
        types = [getattr(comp, "signal_types", {}).get(var, "Real")
                 for comp, var in ((source, c.output), (target, c.input))]
        if types[0] != types[1]:
            raise SystemError_(f"{where}: connection '{c}': type mismatch: '{c.source}.{c.output}' is "
                               f"{self._type_name(source, c.output)} and '{c.target}.{c.input}' is "
                               f"{self._type_name(target, c.input)}; a connection joins variables of one type")

    @staticmethod
    def _type_name(component: Component, var: str) -> str:
        fmu = getattr(component, "fmu", None)
        if fmu is None:
            return "Real"
        v = fmu.variables[var]
        return component.signal_types[var] if v.type == "Enumeration" else v.type

    def _check_ends(self, c: Connection, where: str) -> None:
        for comp, var, kind, attr in ((c.source, c.output, "output", "outputs"), (c.target, c.input, "input", "inputs")):
            if comp not in self.components:
                raise SystemError_(f"{where}: connection '{c}': unknown component '{comp}' "
                                   f"(components: {', '.join(self.names)})")
            component = self.components[comp]
            if var in getattr(component, attr):
                continue
            causality, type_ = getattr(component, "variables", {}).get(var, (None, None))
            if causality is None:
                causality = next((k for k, a in (("input", "inputs"), ("output", "outputs"))
                                  if var in getattr(component, a)), None)
                type_ = "Real" if causality else None
            if causality is None:
                listed = ", ".join(getattr(component, attr)) or "none"
                raise SystemError_(f"{where}: connection '{c}': '{comp}' has no {kind} '{var}' ({kind}s: {listed})")
            if causality != kind:
                raise SystemError_(f"{where}: connection '{c}': causality mismatch: '{comp}.{var}' is "
                                   f"{'an' if causality[0] in 'aeiou' else 'a'} {causality}, not an {kind}")
            raise SystemError_(f"{where}: connection '{c}': type mismatch: '{comp}.{var}' is {type_}; "
                               "connections carry numbers and Booleans (scalars), not strings, binaries, "
                               "clocks or arrays")

    def _gauss_seidel_order(self, where: str) -> list[str]:
        """Topological order of the components along connections with direct feedthrough.

        An edge a -> b orders a before b unless the connected output of a does not depend on
        a's inputs without delay (its value at the end of the step is known before a steps)."""
        edges = {name: set() for name in self.names}
        via = {}
        for c in self.connections:
            source = self.components[c.source]
            if source.feedthrough(c.output):
                edges[c.source].add(c.target)
                via[(c.source, c.target)] = c
        order, state = [], {name: 0 for name in self.names}  # 0 new, 1 on stack, 2 done
        stack_path: list[str] = []

        def visit(node):
            state[node] = 1
            stack_path.append(node)
            for nxt in sorted(edges[node], key=self.names.index):
                if state[nxt] == 1:
                    cycle = stack_path[stack_path.index(nxt):] + [nxt]
                    links = ", ".join(f"'{via[(a, b)]}'" for a, b in zip(cycle, cycle[1:]))
                    raise SystemError_(f"{where}: cycle without delay under Gauss-Seidel: {links}; "
                                       "put a delay or a component without direct feedthrough in the loop, "
                                       "or use algorithm = \"jacobi\"")
                if state[nxt] == 0:
                    visit(nxt)
            stack_path.pop()
            state[node] = 2
            order.append(node)

        for name in self.names:
            if state[name] == 0:
                visit(name)
        return order[::-1]

    def _record_indices(self, where: str):
        names = self.spec.record or [f"{n}.{o}" for n in self.names for o in self.components[n].outputs]
        indices = []
        for signal in names:
            comp, _, var = signal.partition(".")
            if comp not in self.components or var not in self.components[comp].outputs:
                raise SystemError_(f"{where}: recorded signal '{signal}' is not a component output")
            indices.append(self.offset[comp] + self.components[comp].outputs.index(var))
        return names, np.array(indices, dtype=int)

    def _read(self, name: str, into: np.ndarray | None = None) -> None:
        comp = self.components[name]
        start = self.offset[name]
        target = self.signals if into is None else into
        target[start:start + len(comp.outputs)] = comp.get_outputs()

    def _feed(self, name: str) -> None:
        targets = self.targets[name]
        if targets.size:
            comp = self.components[name]
            u = self._inputs[name]
            u[targets] = self.signals[self.sources[name]]
            comp.set_inputs(u)

    def run(self) -> RunResult:
        """Initialize, step over :func:`step_grid` from start to stop, record; stop early if the
        bicycle falls, a signal turns non-finite, an FMU fails a step or an FMU ends the
        simulation itself (``terminateSimulation``: the step is completed by the others and
        recorded). In each case the rows up to the last completed communication point are kept
        (``outcome.status`` says why the run ended: completed, terminated, fell, diverged, failed).

        Raises
        ------
        RunFailed
            If an FMU failed a step (fmi2Discard or worse); it carries the RunResult so far.
        """
        if self.coupling is not None:
            return self.coupling.run()
        spec = self.spec
        grid, data = self.recording_buffer()
        n_steps = len(grid) - 1
        record_names, record_idx = self.record
        multiples = {n: spec.components[n].step_multiple if n in spec.components else 1 for n in self.names}
        try:
            for comp in self.components.values():
                comp.setup(spec.start)
            self._inputs = {n: self.components[n].initial_inputs() for n in self.names}
            for name in self.names:
                self._read(name)
            if spec.initialize:  # propagate outputs to inputs (a few sweeps settle feedthrough chains)
                for _ in range(max(1, len(self.names))):
                    for name in self.order:
                        self._feed(name)
                        self._read(name)
            for comp in self.components.values():
                comp.end_initialization()
            for name in self.names:
                self._read(name)
            data[0, 0] = spec.start
            data[0, 1:] = self.signals[record_idx]
            outcome = Outcome("completed", spec.stop, complete_message(spec.stop, n_steps, grid))
            rows = n_steps + 1
            self._sampled = np.empty_like(self.signals)
            fast = (self._fast_run(data, grid, record_idx, multiples)
                    if self.use_fast_loop and self.algorithm.fast_code is not None else None)
            if fast is not None:
                outcome, rows = fast
                n_steps = 0  # done
                if isinstance(outcome, SimulationEnded):  # the C loop stopped inside step rows - 1
                    k = rows - 1
                    try:
                        self._communication_step(k, grid, multiples, resume=outcome)
                        outcome, rows = self._ended(outcome, k, grid, data, record_idx)
                    except StepFailed as exc:
                        outcome, rows = self._failed_outcome(exc.component, grid[k], str(exc)), k + 1
            for k in range(n_steps):
                if not k % 64:  # the reporter redraws at most 10 times a second; asking costs a call
                    _show_time(grid, k)
                try:
                    ended = self._communication_step(k, grid, multiples)
                except StepFailed as exc:
                    outcome, rows = self._failed_outcome(exc.component, grid[k], str(exc)), k + 1
                    break
                if ended is not None:
                    outcome, rows = self._ended(ended, k, grid, data, record_idx)
                    break
                self._record(data, k + 1, grid, record_idx)
                stop = self._check_outcome(grid[k + 1])
                if stop is not None:
                    outcome, rows = stop, k + 2
                    break
        finally:
            self._close_all()
            progress().clear()  # what the command prints next starts on a clean line
        return finished(data, rows, record_names, outcome)

    def _communication_step(self, k: int, grid: np.ndarray, multiples: dict[str, int],
                            resume: SimulationEnded | None = None) -> SimulationEnded | None:
        """Step every component due at base step ``k`` from ``grid[k]`` to its next point, read
        the outputs (and under after-transfer sampling the values to record, in ``_sampled``).

        ``resume``: the C loop (fastloop.c) stopped inside this step because that component
        asked to terminate; the components before it in the order (and it) have done their part,
        the others do theirs here.

        Returns
        -------
        SimulationEnded or None
            The first component that asked to terminate in this step (the step is completed by
            the others all the same, so the row at its end is consistent).
        """
        n_steps = len(grid) - 1
        t = grid[k]
        due = [n for n in self.order if k % multiples[n] == 0]
        done = set(self.order[:self.order.index(resume.component) + 1]) if resume is not None else set()
        ended = [resume] if resume is not None else []
        gauss_seidel = self.algorithm.sequential
        if not gauss_seidel and resume is None:  # (resumed: every input was set before the first step)
            for name in due:
                self._feed(name)
        for name in due:
            if name not in done:
                if gauss_seidel:
                    self._feed(name)
                try:
                    self.components[name].step(t, grid[min(k + multiples[name], n_steps)] - t)
                except SimulationEnded as end:  # the others still complete the step
                    ended.append(end)
            if gauss_seidel:
                self._read(name)
        if not gauss_seidel:
            for name in due:
                self._read(name)
        if self.spec.sampling == "after-transfer":
            # Record what the outputs are once the connected inputs took the new values
            # (direct feedthrough); the next step still transfers the after-step values.
            self._sampled[:] = self.signals
            for name in self.order:
                self._feed(name)
                self._read(name, into=self._sampled)
        return ended[0] if ended else None

    def _record(self, data: np.ndarray, row: int, grid: np.ndarray, record_idx: np.ndarray) -> None:
        sampled = self._sampled if self.spec.sampling == "after-transfer" else self.signals
        data[row, 0] = grid[row]
        data[row, 1:] = sampled[record_idx]

    def _ended(self, end: SimulationEnded, k: int, grid: np.ndarray, data: np.ndarray,
               record_idx: np.ndarray) -> tuple[Outcome, int]:
        """The outcome and row count of a run a component ended in base step ``k``: with the row at
        the step's end if the FMU got there, else (an FMU that stopped inside the step) the rows
        up to the step's start, the other components having gone on to its end."""
        reached = end.time
        if reached >= grid[k + 1] - 1e-9 * (grid[k + 1] - grid[k]):
            self._record(data, k + 1, grid, record_idx)
            return terminated(end.component, float(grid[k + 1])), k + 2
        outcome = terminated(end.component, reached)
        outcome.time = float(grid[k])
        outcome.message += f"; the result ends at the communication point before it, t = {grid[k]:g} s"
        return outcome, k + 1

    def recording_buffer(self) -> tuple[np.ndarray, np.ndarray]:
        """The communication points and an empty table for them (time, then the recorded
        signals), refused before anything runs if it would not fit in MAX_RECORD_BYTES."""
        spec = self.spec
        grid = step_grid(spec.start, spec.stop, spec.step)
        n_steps = len(grid) - 1
        recorded = len(self.record[1])
        size = (n_steps + 1) * (1 + recorded) * 8
        if size > MAX_RECORD_BYTES:
            raise SystemError_(f"{spec.path or spec.name}: recording {recorded} signals over {n_steps:,} "
                               f"steps would take {size / 1024**3:.1f} GiB; use a larger step or record fewer "
                               "signals ([system] record = [...])")
        return grid, self.allocate((n_steps + 1, 1 + recorded), self.record[0])

    @staticmethod
    def allocate(shape: tuple[int, int], names) -> np.ndarray:
        """The recording table: ``shape`` is (rows, 1 + recorded signals), ``names`` the recorded
        signals. An isolated run records into memory its caller can read after a crash
        (:mod:`cosim.cosimulation.isolated`)."""
        return np.empty(shape)

    def _close_all(self) -> None:
        """Close every component; the first error of a close is raised after all were closed."""
        error = None
        for comp in self.components.values():
            try:
                comp.close()
            except Exception as exc:  # keep closing the others
                error = error or exc
        if error is not None:
            raise error

    def _last_values(self) -> dict[str, float]:
        return {f"{n}.{o}": float(self.signals[self.offset[n] + j])
                for n in self.names for j, o in enumerate(self.components[n].outputs)}

    def _failed_outcome(self, component: str, t: float, text: str) -> Outcome:
        """The outcome of a run an FMU could not continue, naming the physical cause if the last
        communicated outputs show one (see :func:`cosim.fmu.simulate.physical_cause`)."""
        values = self._last_values()
        values.update(getattr(self.components[component], "last_outputs", {}) or {})  # nearer the failure
        cause = physical_cause(values)
        message = f"stopped at t = {t:g} s: {cause} ({text})" if cause else f"stopped at t = {t:g} s: {text}"
        return Outcome("failed", t, message)

    #: Step in C (fastloop.c) where every component is an FMU or a block with a native form;
    #: False: always the Python loop (the tests compare both).
    use_fast_loop = True

    def _natives(self, grid: np.ndarray, multiples: dict[str, int]) -> dict | None:
        """The native form of every Python block (registry.Native), or None if a component is
        neither an FMU nor a block that has one (then the Python loop steps the system)."""
        blocks = [n for n in self.names if not isinstance(self.components[n], FMUComponent)]
        if not all(callable(getattr(self.components[n], "native_form", None)) for n in blocks):
            return None
        if any(self.components[n].other_inputs or self.components[n].other_outputs
               for n in self.names if n not in blocks):  # the C loop sets and gets real values only
            return None
        n_steps = len(grid) - 1
        natives = {}
        for name in blocks:
            starts = np.arange(0, n_steps, multiples[name])
            steps = grid[np.minimum(starts + multiples[name], n_steps)] - grid[starts]  # as the loop steps
            natives[name] = self.components[name].native_form(steps)
            if natives[name] is None:
                return None
        return natives

    def _fast_run(self, data: np.ndarray, grid: np.ndarray, record_idx: np.ndarray, multiples: dict[str, int]):
        """Step in C when every component is an FMU or a native block; None where the Python loop
        must do it."""
        lib = fastloop.library()
        natives = self._natives(grid, multiples) if lib is not None else None
        if natives is None:
            return None
        try:
            return self._fast_steps(lib, natives, multiples, data, grid, record_idx)
        finally:
            for native in natives.values():
                if native.done is not None:
                    native.done()  # the block's own attributes get what the loop changed

    def _fast_steps(self, lib, natives: dict, multiples: dict, data: np.ndarray, grid: np.ndarray,
                    record_idx: np.ndarray):
        """``cosim_fast_run`` (fastloop.c) over the whole grid in :data:`CHUNKS` calls: (outcome, rows)."""
        from ctypes import byref, c_double, c_int, c_long, c_uint, c_void_p, pointer

        spec = self.spec
        n_steps = len(grid) - 1
        keep = []  # buffers the C structures point into
        comps = (FastComponent * len(self.names))()
        for j, name in enumerate(self.names):
            c = self.components[name]
            targets, sources = self.targets[name], self.sources[name]
            in_src = (c_int * max(1, len(targets)))(*[int(s) for s in sources])
            keep.append(in_src)
            if name in natives:
                in_target = (c_int * max(1, len(targets)))(*[int(t) for t in targets])
                block = fast_block(natives[name], self._inputs[name], keep)
                keep.append(in_target)
                comps[j] = FastComponent(n_in=len(targets), in_src=in_src, n_out=len(c.outputs),
                                         out_offset=self.offset[name], multiple=multiples[name],
                                         block=pointer(block), in_target=in_target)
                continue
            in_vr = (c_uint * max(1, len(targets)))(*[c._in_vr[t] for t in targets])
            in_buf = (c_double * max(1, len(targets)))()
            out_vr = (c_uint * max(1, len(c.outputs)))(*list(c._out_vr))
            keep += [in_vr, in_buf, out_vr]
            comps[j] = FastComponent(
                c._component, address(c._set_real), address(c._get_real), address(c._do_step),
                len(targets), in_vr, in_src, in_buf, len(c.outputs), out_vr, self.offset[name],
                multiples[name], now=c.now)
        order = (c_int * len(self.names))(*[self.names.index(n) for n in self.order])
        rec_idx = np.ascontiguousarray(record_idx, dtype=np.int32)
        times = np.ascontiguousarray(grid, dtype=float)
        steps_done, failed, fmi_status, failed_call = c_long(0), c_int(-1), c_int(0), c_int(1)
        failed_time = c_double(np.nan)
        fall = self.fall_index if self.fall_index is not None else -1

        def pointer_to(array: np.ndarray) -> c_void_p:  # (data_as costs ~2 us a call, five a run)
            return c_void_p(array.ctypes.data)

        # the grid in CHUNKS calls, so that the terminal shows how far the run is (a call costs µs)
        # (integers, strictly increasing as count <= n_steps; np.unique would import numpy.ma into a
        # matrix worker's first case)
        count = min(n_steps, CHUNKS)
        bounds = [n_steps * i // count for i in range(count + 1)] if count else [0]
        status = 0
        for first, last in zip(bounds[:-1], bounds[1:]):
            _show_time(grid, first)
            status = lib.cosim_fast_run(
                len(self.names), comps, order, self.algorithm.fast_code,
                int(spec.sampling == "after-transfer"), pointer_to(self.signals), pointer_to(self._sampled),
                len(self.signals), pointer_to(times), c_long(n_steps), c_long(first), c_long(last),
                len(rec_idx), pointer_to(rec_idx), pointer_to(data), fall, c_double(spec.fall_limit or 0.0),
                byref(steps_done), byref(failed), byref(fmi_status), byref(failed_call), byref(failed_time))
            if status != 0:
                break
        for j, name in enumerate(self.names):
            if name not in natives:
                self.components[name].now = comps[j].now  # as the Python loop leaves it
        t = float(grid[steps_done.value])
        rows = steps_done.value + 1
        if status == 0:
            return Outcome("completed", spec.stop, complete_message(spec.stop, n_steps, grid)), rows
        if status == 1:
            return Outcome("fell", t, f"fell at t = {t:.3f} s (|{spec.fall_signal}| > {spec.fall_limit:g})"), rows
        if status == 2:
            return self._check_outcome(t), rows
        name = self.names[failed.value]
        if status == 4:  # a bound of TransportDelay.native was wrong: a bug, not the user's
            raise RuntimeError(f"{name}: the native delay's sample ring is full at t = {t:g} s")
        component = self.components[name]
        what = component.calls[failed_call.value]
        h = grid[min(steps_done.value + multiples[name], n_steps)] - t
        reached = component.end_requested(what, t, h, fmi_status.value)
        if reached is not None:  # the model's own end: the caller completes the step
            component.now = reached
            return SimulationEnded(name, reached), rows
        error = component.failed(what, failed_time.value, fmi_status.value)
        return self._failed_outcome(name, t, str(error)), rows

    def _check_outcome(self, t: float) -> Outcome | None:
        if not np.all(np.isfinite(self.signals)):
            bad = int(np.flatnonzero(~np.isfinite(self.signals))[0])
            name = next(f"{n}.{self.components[n].outputs[bad - o]}" for n, o in self.offset.items()
                        if o <= bad < o + len(self.components[n].outputs))
            return Outcome("diverged", t, f"signal {name} is not finite at t = {t:g} s")
        if self.fall_index is not None and abs(self.signals[self.fall_index]) > self.spec.fall_limit:
            return Outcome("fell", t, f"fell at t = {t:.3f} s (|{self.spec.fall_signal}| > {self.spec.fall_limit:g})")
        return None


def assemble(spec: SystemSpec, components: dict[str, Component]) -> System:
    """Check the wiring and prepare the master (errors name the offending connection)."""
    return System(spec, components)


def run_components(spec: SystemSpec, components: dict[str, Component], allocate=None) -> RunResult:
    """Assemble and run; components are closed afterwards. ``allocate(shape)``, if given, makes the
    recording table (see :attr:`System.allocate`)."""
    try:
        system = assemble(spec, components)
    except Exception:
        for comp in components.values():
            comp.close()
        raise
    if allocate is not None:
        system.allocate = allocate
    return system.run()


__all__ = ["System", "RunResult", "RunFailed", "Outcome", "assemble", "run_components", "step_grid",
           "SimulationError"]
