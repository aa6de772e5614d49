"""Rider and autopilot controllers as Python blocks.

Each has a Modelica twin in ``Bicycle.Control`` with the same parameter, input and output
names, so a system can swap the Python block for the FMU of its twin (e.g. for SSP export).
Each is one class (see :mod:`cosim.cosimulation.registry`): its gain matrix (or state-space
matrices) is at once its Python stepping, its native form for the C stepping loop and its linear
model.
"""
from __future__ import annotations

import numpy as np

from cosim.errors import ParameterError
from cosim.cosimulation.blocks import Affine, Linear
from cosim.cosimulation.registry import Window
from cosim.analytic.parameters import load_parameters
from cosim.analytic.whipple import state_matrices


class Proportional(Affine):
    """The paper's rider: steer torque proportional to roll, T = -k phi (k in N.m/rad)."""

    inputs = ["phi"]
    outputs = ["T"]
    twin = "Bicycle.Control.Proportional"

    def __init__(self, name: str, k: float = 10.0):
        super().__init__(name)
        self.k = float(k)

    def gain(self):
        return [[-self.k]]


class PD(Affine):
    """Proportional-derivative rider: T = -kp phi - kd phi_dot (kp in N.m/rad, kd in N.m.s/rad)."""

    inputs = ["phi", "phi_dot"]
    outputs = ["T"]
    twin = "Bicycle.Control.PD"

    def __init__(self, name: str, kp: float = 10.0, kd: float = 1.0):
        super().__init__(name)
        self.kp, self.kd = float(kp), float(kd)

    def gain(self):
        return [[-self.kp, -self.kd]]


class PID(Linear):
    """PID rider: T = -kp phi - ki (integral of phi) - kd phi_dot (kp in N.m/rad, ki in N.m/(rad.s), kd in N.m.s/rad).

    The derivative term reads the roll rate the bicycle outputs (no filtered derivative needed);
    the integral starts at 0."""

    inputs = ["phi", "phi_dot"]
    outputs = ["T"]
    twin = "Bicycle.Control.PID"

    def __init__(self, name: str, kp: float = 10.0, ki: float = 1.0, kd: float = 1.0):
        self.kp, self.ki, self.kd = float(kp), float(ki), float(kd)
        # state: the integral of phi
        super().__init__(name, A=[[0.0]], B=[[1.0, 0.0]], C=[[-self.ki]], D=[[-self.kp, -self.kd]])


class SteerAngleFeedback(Affine):
    """Steer-angle feedback for steer-angle-input models, delta = -k2 phi (eq (5), k2 dimensionless)."""

    inputs = ["phi"]
    outputs = ["delta"]
    twin = "Bicycle.Control.SteerAngleFeedback"

    def __init__(self, name: str, k2: float = 1.0):
        super().__init__(name)
        self.k2 = float(k2)

    def gain(self):
        return [[-self.k2]]


class StateFeedback(Affine):
    """State feedback on steer torque: T = -(K1 phi + K2 delta + K3 phi_dot + K4 delta_dot).

    K1, K2 in N.m/rad, K3, K4 in N.m.s/rad; :class:`LQR` designs them."""

    inputs = ["phi", "delta", "phi_dot", "delta_dot"]
    outputs = ["T"]
    twin = "Bicycle.Control.StateFeedback"

    def __init__(self, name: str, K1: float = 0.0, K2: float = 0.0, K3: float = 0.0, K4: float = 0.0):
        super().__init__(name)
        self.K = np.array([K1, K2, K3, K4], dtype=float)

    def gain(self):
        return -self.K.reshape(1, 4)


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

    Raises
    ------
    ParameterError
        For an unknown or invalid parameter set, negative weights, or no stabilizing design.
    """
    import control

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


class LQR(StateFeedback):
    """The LQR autopilot: state feedback with gains designed by python-control on the analytic
    linear Whipple model of ``params`` at speed v (m/s), weights as in :func:`lqr_gains`."""

    twin_same_parameters = False  # the twin (StateFeedback) takes the designed gains

    def __init__(self, name: str, params: str = "benchmark", v: float = 5.0, q_roll: float = 10.0,
                 q_steer: float = 1.0, q_rates: float = 0.1, r: float = 0.1):
        self.gains = lqr_gains(params, v, q_roll, q_steer, q_rates, r)
        super().__init__(name, **self.gains)

    def twin_parameters(self):
        return dict(self.gains)


class LaneChange(Affine):
    """Lane change by counter-steering (Meijaard conventions: y, psi, phi positive to the right).

    A cascade on steer torque: lateral error -> heading demand -> roll demand -> torque,
    ``T = kp (phi - phi_ref) + kd phi_dot`` with ``phi_ref = k_psi (k_y (y_cmd - y) - psi)`` and
    ``y_cmd`` stepping to ``y_ref`` [m] at ``t_start`` [s] (k_y in rad/m, k_psi dimensionless,
    kp in N.m/rad, kd in N.m.s/rad). To lean into the new lane the loop first steers away from it,
    so the path shows the inverse response of the right-half-plane zero. The default gains
    stabilize the benchmark bicycle at 5 m/s (slowest closed-loop pole -0.57 1/s)."""

    inputs = ["phi", "phi_dot", "psi", "y"]
    outputs = ["T"]
    twin = "Bicycle.Control.LaneChange"

    def __init__(self, name: str, y_ref: float = 1.0, t_start: float = 1.0, k_y: float = 0.1,
                 k_psi: float = 1.0, kp: float = 20.0, kd: float = 10.0):
        super().__init__(name)
        self.y_ref, self.t_start = float(y_ref), float(t_start)
        self.k_y, self.k_psi, self.kp, self.kd = float(k_y), float(k_psi), float(kp), float(kd)

    def gain(self):
        kp, kpsi = self.kp, self.kp * self.k_psi
        return [[kp, self.kd, kpsi, kpsi * self.k_y]]

    def window(self):
        # The command enters as -kp k_psi k_y y_cmd, y_cmd = y_ref from t >= t_start - 1e-12 s (as
        # in Bicycle.Control.LaneChange) on, else 0.
        def command(y_cmd):
            return (-self.kp * self.k_psi * self.k_y * y_cmd,)

        return Window(self.t_start - 1e-12, np.inf, 0.0, command(self.y_ref), command(0.0))


class LeanSteer(Affine):
    """Rider using steer torque and upper-body lean: T = -k phi - kd phi_dot, theta = -k_lean phi.

    k in N.m/rad, kd in N.m.s/rad, k_lean dimensionless (paper conventions: lean to the left to
    right a bicycle that rolls to the right). For models with both inputs, e.g.
    ``Bicycle.Bicycles.LeaningRider`` (22)+(11)."""

    inputs = ["phi", "phi_dot"]
    outputs = ["T", "theta"]
    twin = "Bicycle.Control.LeanSteer"

    def __init__(self, name: str, k: float = 10.0, kd: float = 1.0, k_lean: float = 0.5):
        super().__init__(name)
        self.k, self.kd, self.k_lean = float(k), float(kd), float(k_lean)

    def gain(self):
        return [[-self.k, -self.kd], [-self.k_lean, 0.0]]
