"""Rider and autopilot controllers as Python components.

Each has a Modelica twin in ``Bicycle.Control`` with the same parameter, input and output
names, so a system can swap the Python block for the FMU of its twin (e.g. for SSP export).
"""
from __future__ import annotations

import numpy as np

from ..errors import ParameterError
from .blocks import Static


class Proportional(Static):
    """The paper's rider: steer torque proportional to roll, ``T = -k * phi`` (k in N.m/rad)."""

    inputs = ["phi"]
    outputs = ["T"]

    def __init__(self, name: str, k: float = 10.0):
        super().__init__(name)
        self.k = float(k)

    def evaluate(self, u):
        return np.array([-self.k * u[0]])


class PD(Static):
    """``T = -kp * phi - kd * phi_dot`` (kp in N.m/rad, kd in N.m.s/rad)."""

    inputs = ["phi", "phi_dot"]
    outputs = ["T"]

    def __init__(self, name: str, kp: float = 10.0, kd: float = 1.0):
        super().__init__(name)
        self.kp, self.kd = float(kp), float(kd)

    def evaluate(self, u):
        return np.array([-self.kp * u[0] - self.kd * u[1]])


class SteerAngleFeedback(Static):
    """Steer-angle feedback for steer-angle-input models, ``delta = -k2 * phi`` (eq (5))."""

    inputs = ["phi"]
    outputs = ["delta"]

    def __init__(self, name: str, k2: float = 1.0):
        super().__init__(name)
        self.k2 = float(k2)

    def evaluate(self, u):
        return np.array([-self.k2 * u[0]])


class StateFeedback(Static):
    """``T = -(K1 phi + K2 delta + K3 phi_dot + K4 delta_dot)``: the LQR autopilot's control law.

    Use :func:`lqr_gains` to design ``K`` with python-control on the analytic linear Whipple
    model at the run speed."""

    inputs = ["phi", "delta", "phi_dot", "delta_dot"]
    outputs = ["T"]

    def __init__(self, name: str, K1: float = 0.0, K2: float = 0.0, K3: float = 0.0, K4: float = 0.0):
        super().__init__(name)
        self.K = np.array([K1, K2, K3, K4], dtype=float)

    def evaluate(self, u):
        return np.array([-self.K @ u])


def lqr_gains(params: str | dict, v: float, q_roll: float = 10.0, q_steer: float = 1.0,
              q_rates: float = 0.1, r: float = 0.1) -> dict:
    """LQR state-feedback gains for steer torque on the linear Whipple model (24).

    Parameters
    ----------
    params : str or dict
        Meijaard parameter set (bundled name, TOML path or dict).
    v : float
        Forward speed [m/s] the design is made for.
    q_roll, q_steer, q_rates, r : float
        Weights on roll [1/rad^2], steer [1/rad^2], both rates [s^2/rad^2] and torque [1/(N.m)^2].

    Returns
    -------
    dict
        ``{"K1": ..., "K2": ..., "K3": ..., "K4": ...}`` for :class:`StateFeedback`.
    """
    import control

    from ..analytic.parameters import load_parameters
    from ..analytic.whipple import state_matrices

    try:
        p = load_parameters(params) if isinstance(params, str) else params
        A, B = state_matrices(p, v)
    except FileNotFoundError:
        raise ParameterError(f"parameter 'params': no such bundled parameter set or file '{params}'") from None
    except ValueError as exc:  # an invalid parameter set, named by the analytic model
        raise ParameterError(f"parameter 'params': {exc}") from None
    if min(q_roll, q_steer, q_rates) < 0 or r <= 0:
        raise ParameterError("LQR weights must be non-negative and r positive")
    Q = np.diag([q_roll, q_steer, q_rates, q_rates])
    try:
        K, _, _ = control.lqr(A, B[:, [1]], Q, np.array([[r]]))
    except Exception as exc:  # python-control raises ControlArgument, LinAlgError, ValueError
        raise ParameterError(f"no LQR design for these weights at v = {v:g} m/s: {exc}") from None
    return {f"K{k + 1}": float(K[0, k]) for k in range(4)}


class LaneChange(Static):
    """Lane change by counter-steering (Meijaard conventions: y, psi, phi positive to the right).

    A cascade on steer torque: lateral error -> heading demand -> roll demand -> torque,
    ``T = kp (phi - phi_ref) + kd phi_dot`` with ``phi_ref = k_psi (k_y (y_cmd - y) - psi)`` and
    ``y_cmd`` stepping to ``y_ref`` at ``t_start``. To lean into the new lane the loop first steers
    away from it, so the path shows the inverse response of the right-half-plane zero. The default
    gains stabilize the benchmark bicycle at 5 m/s (slowest closed-loop pole -0.57 1/s)."""

    inputs = ["phi", "phi_dot", "psi", "y"]
    outputs = ["T"]

    def __init__(self, name: str, y_ref: float = 1.0, t_start: float = 1.0, k_y: float = 0.1,
                 k_psi: float = 1.0, kp: float = 20.0, kd: float = 10.0):
        super().__init__(name)
        self.y_ref, self.t_start = float(y_ref), float(t_start)
        self.k_y, self.k_psi, self.kp, self.kd = float(k_y), float(k_psi), float(kp), float(kd)
        self._t = 0.0

    def setup(self, start_time):
        self._t = start_time

    def evaluate(self, u):
        phi, phi_dot, psi, y = u
        y_cmd = self.y_ref if self._t >= self.t_start - 1e-12 else 0.0
        phi_ref = self.k_psi * (self.k_y * (y_cmd - y) - psi)
        return np.array([self.kp * (phi - phi_ref) + self.kd * phi_dot])

    def step(self, t, h):
        self._t = t + h
        self._y[:] = self.evaluate(self._u)

    def get_state(self):
        return self._t, self._u.copy()

    def set_state(self, state):
        self._t = state[0]
        self.set_inputs(state[1])


def lqr(name: str, params: str = "benchmark", v: float = 5.0, q_roll: float = 10.0, q_steer: float = 1.0,
        q_rates: float = 0.1, r: float = 0.1) -> StateFeedback:
    """The LQR autopilot: :class:`StateFeedback` with gains from :func:`lqr_gains`."""
    return StateFeedback(name, **lqr_gains(params, v, q_roll, q_steer, q_rates, r))


class LeanSteer(Static):
    """A rider who uses upper-body lean as a second input: ``T = -k phi - kd phi_dot`` on the
    handlebars and a lean angle ``theta = -k_lean phi`` of the upper body (paper conventions:
    lean to the left to right a bicycle that rolls to the right). For models with both inputs,
    e.g. ``Bicycle.Bicycles.LeaningRider`` (22)+(11)."""

    inputs = ["phi", "phi_dot"]
    outputs = ["T", "theta"]

    def __init__(self, name: str, k: float = 10.0, kd: float = 1.0, k_lean: float = 0.5):
        super().__init__(name)
        self.k, self.kd, self.k_lean = float(k), float(kd), float(k_lean)

    def evaluate(self, u):
        return np.array([-self.k * u[0] - self.kd * u[1], -self.k_lean * u[0]])
