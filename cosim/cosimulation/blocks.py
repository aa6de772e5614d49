"""Python components: signal sources, linear systems, transport and Padé delays.

Every block follows :class:`~cosim.cosimulation.component.Component`. Continuous-time linear
blocks are discretized exactly (zero-order hold on their inputs, as a Co-Simulation master
holds inputs over a step), so a Python block and the FMU of its Modelica twin agree to the
integration tolerance of the FMU.
"""
from __future__ import annotations

from collections import deque

import numpy as np
from scipy.linalg import expm

from ..errors import ParameterError
from .component import Component


def _positive(name: str, value: float) -> float:
    value = float(value)
    if not value > 0:
        raise ParameterError(f"parameter '{name}' must be positive, got {value:g}")
    return value


class Static(Component):
    """y = f(u) without memory: subclasses define ``evaluate``."""

    def __init__(self, name: str):
        super().__init__(name)
        self._u = np.zeros(len(self.inputs))
        self._y = np.zeros(len(self.outputs))

    def set_inputs(self, values):
        self._u[:] = values
        self._y[:] = self.evaluate(self._u)

    def get_outputs(self):
        return self._y

    def step(self, t, h):
        pass

    def get_state(self):
        return self._u.copy()

    def set_state(self, state):
        self.set_inputs(state)

    def evaluate(self, u: np.ndarray) -> np.ndarray:
        raise NotImplementedError


class Linear(Component):
    """x' = A x + B u, y = C x + D u, stepped exactly under a zero-order hold of u."""

    def __init__(self, name: str, A, B, C, D, inputs: list[str], outputs: list[str], x0=None):
        self.inputs, self.outputs = list(inputs), list(outputs)
        super().__init__(name)
        self.A, self.B = np.atleast_2d(A).astype(float), np.atleast_2d(B).astype(float)
        self.C, self.D = np.atleast_2d(C).astype(float), np.atleast_2d(D).astype(float)
        n = self.A.shape[0] if self.A.size else 0
        self.x = np.zeros(n) if x0 is None else np.asarray(x0, float).copy()
        self._u = np.zeros(len(self.inputs))
        self._y = np.zeros(len(self.outputs))
        self._discrete = {}
        self._no_feedthrough = {o for k, o in enumerate(self.outputs) if not np.any(self.D[k])}

    def feedthrough(self, output):
        return set() if output in self._no_feedthrough else set(self.inputs)

    def _update_outputs(self):
        self._y[:] = (self.C @ self.x if self.x.size else 0.0) + self.D @ self._u

    def set_inputs(self, values):
        self._u[:] = values
        self._update_outputs()

    def get_outputs(self):
        return self._y

    def step(self, t, h):
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

    def get_state(self):
        return self.x.copy(), self._u.copy()

    def set_state(self, state):
        self.x, u = state[0].copy(), state[1]
        self.set_inputs(u)


class TransportDelay(Component):
    """y(t) = u(t - tau), exact: the input history is buffered and interpolated linearly.

    Before ``t0 + tau`` the output is the initial input value. With ``tau`` at least one
    communication step the output does not depend on the current input (no feedthrough)."""

    inputs = ["u"]
    outputs = ["y"]

    def __init__(self, name: str, tau: float = 0.1):
        super().__init__(name)
        self.tau = float(tau)
        if self.tau < 0:
            raise ParameterError(f"parameter 'tau' must not be negative, got {tau:g}")
        self._times: deque = deque()
        self._values: deque = deque()
        self._t = 0.0
        self._u = 0.0
        self._y = np.zeros(1)
        self._min_step = np.inf

    def feedthrough(self, output):
        return set() if self.tau >= self._min_step else {"u"}

    def configure_step(self, h: float) -> None:
        """The master tells the smallest step it will take (for the feedthrough decision)."""
        self._min_step = h

    def setup(self, start_time):
        self._t = start_time
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

    def get_state(self):
        return self._t, self._u, list(self._times), list(self._values)

    def set_state(self, state):
        self._t, self._u = state[0], state[1]
        self._times, self._values = deque(state[2]), deque(state[3])
        self._y[0] = self._delayed(self._t)


def pade_delay(name: str, tau: float = 0.1, n: int = 2) -> Linear:
    """The [n/n] Padé approximation of ``exp(-s tau)`` as a linear block (python-control's ``pade``);
    the Python twin of ``Bicycle.Rider.PadeDelay``."""
    import control

    _positive("tau", tau)
    if int(n) != n or not 1 <= n <= 10:
        raise ParameterError(f"parameter 'n' (order) must be an integer from 1 to 10, got {n}")
    num, den = control.pade(tau, int(n))
    sys = control.ss(control.tf(num, den))
    return Linear(name, sys.A, sys.B, sys.C, sys.D, ["u"], ["y"])


class Pulse(Static):
    """A rectangular pulse ``amplitude`` on [start, start + duration), else 0 (a lateral push)."""

    inputs: list[str] = []
    outputs = ["y"]

    def __init__(self, name: str, amplitude: float = 1.0, start: float = 1.0, duration: float = 0.1):
        super().__init__(name)
        self.amplitude, self.start, self.duration = float(amplitude), float(start), _positive("duration", duration)
        self._t = 0.0

    def setup(self, start_time):
        self._t = start_time
        self._refresh()

    def _refresh(self):
        on = self.start <= self._t + 1e-12 and self._t + 1e-12 < self.start + self.duration
        self._y[0] = self.amplitude if on else 0.0

    def step(self, t, h):
        self._t = t + h
        self._refresh()

    def evaluate(self, u):
        return self._y

    def get_state(self):
        return self._t

    def set_state(self, state):
        self._t = state
        self._refresh()


class Step(Pulse):
    """``amplitude`` from ``start`` on."""

    def __init__(self, name: str, amplitude: float = 1.0, start: float = 0.0):
        super().__init__(name, amplitude, start, np.inf)
