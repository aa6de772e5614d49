"""Python blocks: the shared kinds (affine without memory, linear with states), signal sources and delays.

Every block is a :class:`~cosim.cosimulation.registry.Block` and registers itself by class name.
Continuous-time linear blocks are discretized exactly (zero-order hold on their inputs, as a
Co-Simulation master holds inputs over a step), so a Python block and the FMU of its Modelica
twin agree to the integration tolerance of the FMU.
"""
from __future__ import annotations

from collections import deque

import numpy as np
from scipy.linalg import expm

from cosim.errors import ParameterError
from cosim.cosimulation.registry import Block, LinearModel


def _positive(name: str, value: float) -> float:
    value = float(value)
    if not value > 0:
        raise ParameterError(f"parameter '{name}' must be positive, got {value:g}")
    return value


class Affine(Block, register=False):
    """``y = D u + r(t)`` without memory: subclasses define :meth:`gain` (D) and, for sources and
    references, :meth:`~cosim.cosimulation.registry.Block.exogenous` (r). The same two methods
    give the Python stepping and the linear model, so the block's equations are written once."""

    def __init__(self, name: str):
        super().__init__(name)
        self._u = np.zeros(len(self.inputs))
        self._y = np.zeros(len(self.outputs))
        self._D = None

    def gain(self) -> np.ndarray:
        """The matrix D (outputs x inputs) from the block's parameters."""
        raise NotImplementedError

    def _refresh(self) -> None:
        if self._D is None:  # parameters are fixed once the block exists
            self._D = np.asarray(self.gain(), float).reshape(len(self.outputs), len(self.inputs))
        self._y[:] = self._D @ self._u + self.exogenous(self._t)

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

    def linear(self, settings):
        D = self.gain()
        return LinearModel(np.zeros((0, 0)), np.zeros((0, len(self.inputs))), np.zeros((len(self.outputs), 0)),
                           D, list(self.inputs), list(self.outputs))


class Linear(Block, register=False):
    """``x' = A x + B u``, ``y = C x + D u``, stepped exactly under a zero-order hold of u;
    subclasses pass their matrices to ``__init__``, which are also their linear model."""

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
        self._y[:] = (self.C @ self.x if self.x.size else 0.0) + self.D @ self._u

    def setup(self, start_time):
        super().setup(start_time)
        self.x = self.x0.copy()
        self._update_outputs()

    def set_inputs(self, values):
        self._u[:] = values
        self._update_outputs()

    def get_outputs(self):
        return self._y

    def step(self, t, h):
        self._t = t + h
        if not self.x.size:
            return
        key = round(h, 15)
        if key not in self._discrete:  # exp([[A, B], [0, 0]] h) gives Ad and Bd at once
            n, m = self.A.shape[0], self.B.shape[1]
            M = np.zeros((n + m, n + m))
            M[:n, :n], M[:n, n:] = self.A, self.B
            E = expm(M * h)
            self._discrete[key] = (E[:n, :n], E[:n, n:])
        Ad, Bd = self._discrete[key]
        self.x = Ad @ self.x + Bd @ self._u
        self._update_outputs()

    def linear(self, settings):
        n = self.x.size
        return LinearModel(self.A if n else np.zeros((0, 0)), self.B if n else np.zeros((0, len(self.inputs))),
                           self.C if n else np.zeros((len(self.outputs), 0)), self.D,
                           list(self.inputs), list(self.outputs))


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

    def twin_parameters(self):
        return {"tau": self.tau}

    def linear(self, settings):
        order = int(settings.get("pade_order", 2))
        return LinearModel(*_pade_matrices(self.tau, order), ["u"], ["y"], interpolates=True)


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

    def exogenous(self, t):
        # 1e-12 s: a jump on a communication point counts as reached despite round-off in t.
        on = self.start <= t + 1e-12 and t + 1e-12 < self.start + self.duration
        return np.array([self.amplitude if on else 0.0])


class Step(Pulse):
    """A step: amplitude from start on, else 0 (start in s; a steady push)."""

    twin = "Bicycle.Sources.TorqueStep"

    def __init__(self, name: str, amplitude: float = 1.0, start: float = 0.0):
        super().__init__(name, amplitude, start, np.inf)
