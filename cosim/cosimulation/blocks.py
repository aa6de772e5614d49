"""Python blocks: the shared kinds (affine without memory, linear with states), signal sources and delays.

Every block is a :class:`~cosim.cosimulation.registry.Block` and registers itself by class name.
Continuous-time linear blocks are discretized exactly (zero-order hold on their inputs, as a
Co-Simulation master holds inputs over a step), so a Python block and the FMU of its Modelica
twin agree to the integration tolerance of the FMU.

Each kind also has its native form (:meth:`~cosim.cosimulation.registry.Block.native`): the master's
C stepping loop then steps it, with the same operations in the same order, so its results are
bit-identical to the Python loop's. For that the products of a matrix and a vector are
:func:`matvec` (a fixed order of additions) and not ``@``, whose order BLAS chooses per CPU.
"""
from __future__ import annotations

from collections import deque

import numpy as np
from scipy.linalg import expm

from cosim.errors import ParameterError
from cosim.cosimulation.registry import Block, Native, Window
from cosim.statespace import StateSpace


def matvec(M: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``M @ v`` summed in a fixed order, ``(M[:, 0] v[0] + M[:, 1] v[1]) + ...`` (0 without columns).

    BLAS sums a product of more than one row in an order of its own (and with fused multiply-adds
    on CPUs that have them); this order is the one ``fastloop.c`` uses, so both loops agree bit
    for bit."""
    if M.shape[1] == 0:
        return np.zeros(M.shape[0])
    out = M[:, 0] * v[0]
    for j in range(1, M.shape[1]):
        out = out + M[:, j] * v[j]
    return out


def _positive(name: str, value: float) -> float:
    value = float(value)
    if not value > 0:
        raise ParameterError(f"parameter '{name}' must be positive, got {value:g}")
    return value


class Affine(Block, register=False):
    """``y = D u + r(t)`` without memory: subclasses define :meth:`gain` (D) and, for sources and
    references, :meth:`window` (r). The same two methods give the Python stepping, the native form
    and the linear model, so the block's equations are written once."""

    native_methods = Block.native_methods + ("_refresh", "_parameters")

    def __init__(self, name: str):
        super().__init__(name)
        self._u = np.zeros(len(self.inputs))
        self._y = np.zeros(len(self.outputs))
        self._D = None
        self._window = None

    def gain(self) -> np.ndarray:
        """The matrix D (outputs x inputs) from the block's parameters."""
        raise NotImplementedError

    def window(self) -> Window | None:
        """The exogenous part r(t) (sources, references) as a :class:`Window`; None (default): 0."""
        return None

    def exogenous(self, t):
        window = self.window() if self._D is None else self._window  # set with D (_parameters)
        return np.zeros(len(self.outputs)) if window is None else window.value(t)

    def _parameters(self) -> None:
        if self._D is None:  # parameters are fixed once the block exists
            self._window = self.window()
            self._D = np.asarray(self.gain(), float).reshape(len(self.outputs), len(self.inputs))

    def _refresh(self) -> None:
        self._parameters()
        self._y[:] = matvec(self._D, self._u) + self.exogenous(self._t)

    def setup(self, start_time):
        super().setup(start_time)
        self._refresh()

    def set_inputs(self, values):
        self._u[:] = values
        self._refresh()

    def get_outputs(self):
        return self._y

    def step(self, t, h):
        self._t = t + h
        self._refresh()

    def native(self, steps):
        self._parameters()
        t = np.array([self._t])

        def done():
            self._t = float(t[0])

        return Native("affine", self._u, self._y, t, D=self._D, window=self._window, done=done)

    def linear(self, settings):
        D = self.gain()
        return StateSpace.of(np.zeros((0, 0)), np.zeros((0, len(self.inputs))), np.zeros((len(self.outputs), 0)),
                             D, self.inputs, self.outputs)


class Linear(Block, register=False):
    """``x' = A x + B u``, ``y = C x + D u``, stepped exactly under a zero-order hold of u;
    subclasses pass their matrices to ``__init__``, which are also their linear model (and, with
    the discrete matrices of each step, their native form)."""

    native_methods = Block.native_methods + ("_update_outputs", "_discretized")

    def __init__(self, name: str, A, B, C, D, x0=None):
        super().__init__(name)
        self.A, self.B = np.atleast_2d(A).astype(float), np.atleast_2d(B).astype(float)
        self.C, self.D = np.atleast_2d(C).astype(float), np.atleast_2d(D).astype(float)
        n = self.A.shape[0] if self.A.size else 0
        self.x0 = np.zeros(n) if x0 is None else np.asarray(x0, float).copy()
        self.x = self.x0.copy()
        self._u = np.zeros(len(self.inputs))
        self._y = np.zeros(len(self.outputs))
        self._discrete = {}
        self._no_feedthrough = {o for k, o in enumerate(self.outputs) if not np.any(self.D[k])}

    def feedthrough(self, output):
        return set() if output in self._no_feedthrough else set(self.inputs)

    def _update_outputs(self):
        self._y[:] = (matvec(self.C, self.x) if self.x.size else 0.0) + matvec(self.D, self._u)

    def setup(self, start_time):
        super().setup(start_time)
        self.x = self.x0.copy()
        self._update_outputs()

    def set_inputs(self, values):
        self._u[:] = values
        self._update_outputs()

    def get_outputs(self):
        return self._y

    def _discretized(self, h: float) -> tuple[np.ndarray, np.ndarray]:
        """Ad, Bd for a step of ``h`` [s]; steps that differ by round-off (1e-15 s) share the pair
        computed for the first of them."""
        key = round(h, 15)
        found = self._discrete.get(key)
        if found is None:  # exp([[A, B], [0, 0]] h) gives Ad and Bd at once
            n, m = self.A.shape[0], self.B.shape[1]
            M = np.zeros((n + m, n + m))
            M[:n, :n], M[:n, n:] = self.A, self.B
            E = expm(M * h)
            found = self._discrete[key] = (np.ascontiguousarray(E[:n, :n]), np.ascontiguousarray(E[:n, n:]))
        return found

    def step(self, t, h):
        self._t = t + h
        if not self.x.size:
            return
        Ad, Bd = self._discretized(h)
        self.x = matvec(Ad, self.x) + matvec(Bd, self._u)
        self._update_outputs()

    def native(self, steps):
        n = self.x.size
        # The pairs in the order the Python stepping computes them: the first of each group of
        # steps that share a pair is the one it is computed for (see _discretized).
        lengths, first, inverse = np.unique(np.asarray(steps, float), return_index=True, return_inverse=True)
        pairs, index, slot = [], {}, np.empty(len(lengths), dtype=np.int32)
        for j in np.argsort(first, kind="stable") if n else ():
            pair = self._discretized(float(lengths[j]))
            if id(pair) not in index:
                index[id(pair)] = len(pairs)
                pairs.append(pair)
            slot[j] = index[id(pair)]
        which = np.ascontiguousarray(slot[inverse] if n else np.zeros(0), dtype=np.int32)
        Ad = np.array([p[0] for p in pairs], dtype=float).reshape(len(pairs), n, n)
        Bd = np.array([p[1] for p in pairs], dtype=float).reshape(len(pairs), n, len(self.inputs))
        t = np.array([self._t])

        def done():
            self._t = float(t[0])

        return Native("linear", self._u, self._y, t, D=np.ascontiguousarray(self.D), x=self.x,
                      C=np.ascontiguousarray(self.C), Ad=Ad, Bd=Bd, which=which, done=done)

    def linear(self, settings):
        n = self.x.size
        return StateSpace.of(self.A if n else np.zeros((0, 0)), self.B if n else np.zeros((0, len(self.inputs))),
                             self.C if n else np.zeros((len(self.outputs), 0)), self.D, self.inputs, self.outputs)


def _pade_matrices(tau: float, n: int):
    """A, B, C, D of the [n/n] Pade approximation of exp(-s tau) (python-control's ``pade``)."""
    import control

    if tau == 0:
        return np.zeros((0, 0)), np.zeros((0, 1)), np.zeros((1, 0)), np.ones((1, 1))
    num, den = control.pade(tau, int(n))
    sys = control.ss(control.tf(num, den))
    return sys.A, sys.B, sys.C, sys.D


class PadeDelay(Linear):
    """The rider's delay exp(-s tau) as its [n/n] Pade approximation (tau in s, n the order)."""

    inputs = ["u"]
    outputs = ["y"]
    twin = "Bicycle.Rider.PadeDelay"

    def __init__(self, name: str, tau: float = 0.1, n: int = 2):
        _positive("tau", tau)
        if int(n) != n or not 1 <= n <= 10:
            raise ParameterError(f"parameter 'n' (order) must be an integer from 1 to 10, got {n}")
        self.tau, self.n = float(tau), int(n)
        super().__init__(name, *_pade_matrices(self.tau, self.n))

    def twin_parameters(self):
        if self.n != 2:  # n sets the number of states: it is fixed when the FMU is built
            raise ParameterError(f"the Modelica twin {self.twin} is built with n = 2")
        return {"tau": self.tau}


class TransportDelay(Block):
    """The exact delay y(t) = u(t - tau) (tau in s), the input history buffered and interpolated linearly.

    Before ``t0 + tau`` the output is the initial input value. With ``tau`` at least one
    communication step the output does not depend on the current input (no feedthrough). The
    exact delay has no Modelica form the compiler accepts (no ``delay()``): its twin and its
    linear model are Pade approximations."""

    inputs = ["u"]
    outputs = ["y"]
    twin = "Bicycle.Rider.PadeDelay"
    twin_same_parameters = False
    twin_approximation = "exact delay -> Pade approximation, n = 2"
    interpolates = True
    native_methods = Block.native_methods + ("_delayed",)

    def __init__(self, name: str, tau: float = 0.1):
        super().__init__(name)
        self.tau = float(tau)
        if self.tau < 0:
            raise ParameterError(f"parameter 'tau' must not be negative, got {tau:g}")
        self._times: deque = deque()
        self._values: deque = deque()
        self._u = 0.0
        self._y = np.zeros(1)
        self._min_step = np.inf

    def feedthrough(self, output):
        return set() if self.tau >= self._min_step else {"u"}

    def configure_step(self, h: float) -> None:
        self._min_step = h

    def setup(self, start_time):
        super().setup(start_time)
        self._times.clear()
        self._values.clear()

    def set_inputs(self, values):
        self._u = float(values[0])
        # The sample at the current time is replaced, so re-setting an input is idempotent.
        if self._times and self._times[-1] == self._t:
            self._values[-1] = self._u
        else:
            self._times.append(self._t)
            self._values.append(self._u)
        self._y[0] = self._delayed(self._t)

    def _delayed(self, t):
        target = t - self.tau
        times, values = self._times, self._values
        if not times or target <= times[0]:
            return values[0] if values else self._u
        if target >= times[-1]:
            return values[-1]
        # Samples arrive in time order: search from the old end (few samples are older than tau).
        k = 1
        while times[k] < target:
            k += 1
        t0, t1 = times[k - 1], times[k]
        v0, v1 = values[k - 1], values[k]
        return v1 if t1 == t0 else v0 + (v1 - v0) * (target - t0) / (t1 - t0)

    def get_outputs(self):
        return self._y

    def step(self, t, h):
        self._t = t + h
        # Forget what can no longer be reached (keep one sample before the horizon).
        horizon = self._t - self.tau
        while len(self._times) > 2 and self._times[1] <= horizon:
            self._times.popleft()
            self._values.popleft()
        self._y[0] = self._delayed(self._t)

    def native(self, steps):
        steps = np.asarray(steps, float)
        # Samples the ring must hold: those within tau of the block's time, spaced by its steps
        # (the last step may be shorter), the one before them, one appended before the next step
        # forgets, and margin for round-off; never more than one new sample per step. fastloop.c
        # checks it all the same.
        count = len(self._times)
        regular = steps[:-1].min() if len(steps) > 1 else np.inf
        bound = count + len(steps) + 2
        capacity = max(count + 2, int(min(bound, self.tau / regular + 8)))
        ring_t, ring_v = np.zeros(capacity), np.zeros(capacity)
        ring_t[:count], ring_v[:count] = self._times, self._values
        ring = np.array([0, count], dtype=np.int64)
        u, t = np.array([self._u]), np.array([self._t])

        def done():
            self._t, self._u = float(t[0]), float(u[0])
            first, size = int(ring[0]), int(ring[1])
            live = (first + np.arange(size)) % capacity
            self._times, self._values = deque(ring_t[live].tolist()), deque(ring_v[live].tolist())

        return Native("delay", u, self._y, t, tau=self.tau, ring_t=ring_t, ring_v=ring_v, ring=ring, done=done)

    def twin_parameters(self):
        return {"tau": self.tau}

    def linear(self, settings):
        order = int(settings.get("pade_order", 2))
        return StateSpace.of(*_pade_matrices(self.tau, order), ["u"], ["y"])


class Pulse(Affine):
    """A rectangular pulse: amplitude on [start, start + duration), else 0 (start, duration in s; a lateral push)."""

    inputs: list[str] = []
    outputs = ["y"]
    twin = "Bicycle.Sources.TorquePulse"

    def __init__(self, name: str, amplitude: float = 1.0, start: float = 1.0, duration: float = 0.1):
        super().__init__(name)
        self.amplitude, self.start, self.duration = float(amplitude), float(start), _positive("duration", duration)

    def gain(self):
        return np.zeros((1, 0))

    def window(self):
        # 1e-12 s: a jump on a communication point counts as reached despite round-off in t.
        return Window(self.start, self.start + self.duration, 1e-12, (self.amplitude,), (0.0,))


class Step(Pulse):
    """A step: amplitude from start on, else 0 (start in s; a steady push)."""

    twin = "Bicycle.Sources.TorqueStep"

    def __init__(self, name: str, amplitude: float = 1.0, start: float = 0.0):
        super().__init__(name, amplitude, start, np.inf)
