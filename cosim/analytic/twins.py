"""Analytic twins of the exported bicycle models: python-control systems from :mod:`cosim.analytic.simple`.

Every model of ``Bicycle.Bicycles`` that ``cosim build`` exports has a twin here, built from the
closed-form equations of Åström, Klein & Lennartsson (2005).  A twin takes the model's top-level
parameter values (keyed by their Modelica names: ``m a h b c lambda J D V g k3 m_r J_r h_r R``)
and returns a :class:`control.StateSpace` whose input and output names are the FMU's top-level
inputs and outputs, in the FMU's order, with the same number of states as the FMU.  Transfer
functions, poles and zeros of the FMU's linearization (:func:`cosim.fmu.linearize.linearize`) must
equal the twin's to rounding (``cosim compare MODEL``).

How each model maps onto the paper (see ``simple.py`` for the ``frame`` option):

=================================  ========================  =====================================
model                              inputs -> outputs         analytic model
=================================  ========================  =====================================
``SelfStabilizing``                T -> phi delta psi eta    (14) + (11), ``frame="eq14"``
``SelfStabilizingGyro``            T -> phi delta psi eta    (14) + (11) with k3 ("Gyroscopic Effects")
``InvertedPendulum``               delta -> phi psi eta      (1)/(4), ``frame="eq1"``
``RearSteered``                    delta -> phi psi eta      (18): (4) at -V, the rider's signs
``LeaningRider``                   T theta -> phi delta      frame (14) + lean of (22) + (11), ``frame="eq14"``
                                   psi eta
``CrownedRoller``                  delta -> phi psi eta      (4) with the poles (27)
=================================  ========================  =====================================

The path (yaw psi, deviation eta) is ``der(psi) = V*delta_f/b``, ``der(eta) = V*psi`` with the
effective steer angle ``delta_f = delta*sin(lambda)`` (8) for the models with a head angle (as
``path_steer_tf(frame="eq14")``) and ``delta_f = delta`` for the models with a vertical steer axis
(``frame="eq1"``).  ``RearSteered`` takes its forward speed V > 0 with the rider's signs of phi,
delta, psi and eta; in these variables its twin is (18) as printed, ``rear_steer_roll_steer_tf(bike,
V)``, with the ordinary path (a negative V rides it backwards: (4) at -V).

The nonlinear bicycles have twins of their linearization about upright straight running
(:data:`cosim.bicycle.twins.STEADY_MOTION_TWINS`, on :func:`steady_lateral` here): the FMU's
linearization is reduced exactly to the lateral states ``phi, delta, u_phi, u_delta`` plus the
path ``psi, y`` (:func:`cosim.bicycle.linearize.steady_motion`) and compared with Meijaard et al.
(2007):

=================================  ========================  =====================================
``Whipple``                        T_delta T_phi -> phi      Meijaard M, C1, K0, K2 + path (A 9)
                                   delta u_phi u_delta psi y
``WhippleRider`` (hinge locked)    the same                  the same, upper body merged into the
                                                             rear frame (:func:`merged_rear_frame`)
=================================  ========================  =====================================

Their speed parameter is the initial rear wheel rate ``u_R0 = -v/rR``; crown radii ``tR``, ``tF``
and start values off upright straight running are refused. Their defaults are read from the
Modelica declarations; the simple models' defaults come from
``cosim/params/second-order/astrom2005.toml`` (as the Modelica records do).
"""
from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import control
import numpy as np

from cosim.analytic import simple, whipple
from cosim.analytic.parameters import PARAMETER_NAMES, load_parameters, load_second_order, merged_rear_frame
from cosim.analytic.simple import SimpleBicycle

__all__ = ["Twin", "TWINS", "LATERAL_OUTPUTS", "steady_lateral", "bicycle", "merged_rear_frame"]

#: Modelica parameter name -> :class:`SimpleBicycle` field (others are equal).
_FIELD = {"lambda": "lam"}

#: The Table 1 bicycle of the simple models, from ``cosim/params/second-order/astrom2005.toml``
#: (the defaults the Modelica models declare; ``tests/test_simple_models.py`` checks they agree).
_SECOND_ORDER = load_second_order("astrom2005")
_PAPER = {k: _SECOND_ORDER[k] for k in ("m", "a", "h", "b", "c", "lambda", "J", "D", "V", "g")}
_PENDULUM = {k: _PAPER[k] for k in ("m", "h", "b", "J", "D", "V", "g")}


@dataclass(frozen=True)
class Twin:
    """The analytic counterpart of one exported model.

    Attributes
    ----------
    model : str
        Full Modelica name, e.g. ``"Bicycle.Bicycles.SelfStabilizing"``.
    build : callable
        ``build(parameters, V) -> control.StateSpace``; ``parameters`` holds every name of
        ``defaults`` (Modelica names), ``V`` the speed [m/s].
    defaults : dict
        The model's top-level parameters with their Modelica default values (SI units).
    inputs, outputs : tuple of str
        The FMU's top-level inputs and outputs, in modelDescription order.
    speed : str
        Name of the speed parameter.
    equations : str
        Where the model comes from in the paper.
    """

    model: str
    build: Callable[[Mapping[str, float], float], control.StateSpace]
    defaults: dict = field(default_factory=dict)
    inputs: tuple[str, ...] = ()
    outputs: tuple[str, ...] = ()
    speed: str = "V"
    equations: str = ""

    def default_values(self) -> dict[str, float]:
        """The model's top-level parameters with their default values (SI units)."""
        return dict(self.defaults)

    def reduce(self, linearization) -> control.StateSpace:
        """The FMU's linearization (:class:`cosim.fmu.linearize.Linearization`) as the system
        compared with :meth:`system`: here the whole of it."""
        return linearization.to_statespace()

    def parameters(self, values: Mapping[str, float] | None = None) -> dict[str, float]:
        """The defaults updated with ``values``; unknown names raise ``ValueError``.

        Names with a dot (FMU-internal variables such as ``solver.fixedStepSize``) are ignored.
        """
        values = dict(values or {})
        defaults = self.default_values()
        unknown = sorted(k for k in values if "." not in k and k not in defaults)
        if unknown:
            raise ValueError(f"{self.model}: unknown parameter(s) {', '.join(unknown)}; "
                             f"parameters are: {', '.join(defaults)}")
        merged = dict(defaults)
        for k, v in values.items():
            if "." in k:
                continue
            v = float(v)
            if not math.isfinite(v):
                raise ValueError(f"{self.model}: parameter {k} must be finite, got {v!r}")
            merged[k] = v
        return merged

    def system(self, values: Mapping[str, float] | None = None) -> control.StateSpace:
        """The analytic state-space model at the given parameter values (defaults elsewhere)."""
        p = self.parameters(values)
        sys = self.build(p, p[self.speed])
        if tuple(sys.input_labels) != self.inputs or tuple(sys.output_labels) != self.outputs:
            raise RuntimeError(f"{self.model}: twin signals {sys.input_labels} -> {sys.output_labels} differ "
                               f"from the model's {self.inputs} -> {self.outputs}")
        return sys


def bicycle(parameters: Mapping[str, float]) -> SimpleBicycle:
    """A :class:`SimpleBicycle` from Modelica parameter names (missing fields keep their defaults).

    Parameters that are not fields of :class:`SimpleBicycle` (``V``, ``k3``) are skipped.
    Raises ``ValueError`` naming the parameter if a value is out of range.
    """
    fields = set(SimpleBicycle.__dataclass_fields__)
    kwargs = {}
    for name, value in parameters.items():
        key = _FIELD.get(name, name)
        if key in fields:
            kwargs[key] = float(value)
    return SimpleBicycle(**kwargs)


# ----------------------------------------------------------------------------
# building blocks

def _path(bike: SimpleBicycle, V: float, effective: bool) -> control.StateSpace:
    """delta -> (psi, eta): der(psi) = V*delta_f/b, der(eta) = V*psi (delta_f = delta*sin(lam) if effective)."""
    gain = V / bike.b * (math.sin(bike.lam) if effective else 1.0)
    return control.ss([[0.0, 0.0], [V, 0.0]], [[gain], [0.0]], np.eye(2), np.zeros((2, 1)),
                      states=["psi", "eta"], inputs=["delta"], outputs=["psi", "eta"])


def _with_path(sys: control.StateSpace, C_delta, D_delta, path: control.StateSpace,
               outputs: list[str]) -> control.StateSpace:
    """Append the path states of ``path`` driven by delta = C_delta x + D_delta u of ``sys``.

    The outputs are ``sys``'s followed by psi and eta, renamed to ``outputs``.
    """
    n, m = sys.nstates, sys.ninputs
    C_delta = np.atleast_2d(np.asarray(C_delta, float)).reshape(1, n)
    D_delta = np.atleast_2d(np.asarray(D_delta, float)).reshape(1, m)
    A = np.block([[sys.A, np.zeros((n, 2))], [path.B @ C_delta, path.A]])
    B = np.vstack([sys.B, path.B @ D_delta])
    C = np.block([[sys.C, np.zeros((sys.noutputs, 2))], [np.zeros((2, n)), path.C]])
    D = np.vstack([sys.D, np.zeros((2, m))])
    return control.ss(A, B, C, D, states=list(sys.state_labels) + ["psi", "eta"],
                      inputs=list(sys.input_labels), outputs=outputs)


def _canonical(num, den) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(A, B, C, D) of the controllable canonical form of the proper SISO transfer function
    ``num/den`` (coefficients, highest power first), with a state for every root of ``den`` also
    where ``num`` is 0: at V = 0 the steer angle no longer drives the roll, but the pendulum still
    falls (python-control's ``ss`` of that transfer function has no states, so its A could not be
    compared with the FMU's)."""
    num = np.atleast_1d(np.asarray(num, float))
    den = np.trim_zeros(np.atleast_1d(np.asarray(den, float)), "f")
    n = den.size - 1
    num = np.concatenate([np.zeros(max(0, n + 1 - num.size)), num])[-(n + 1):] / den[0]
    den = den / den[0]
    d = num[0]  # feedthrough
    A = np.zeros((n, n))
    A[:-1, 1:] = np.eye(n - 1)
    A[-1, :] = -den[:0:-1]                           # x_n' = -a_0 x_1 - ... - a_{n-1} x_n + u
    B = np.zeros((n, 1))
    B[-1, 0] = 1.0
    C = (num[1:] - d * den[1:])[::-1].reshape(1, n)  # y = b_0 x_1 + ... + b_{n-1} x_n + d u
    return A, B, C, np.array([[d]])


def _steer_angle_model(G: control.TransferFunction, den, bike: SimpleBicycle, V: float) -> control.StateSpace:
    """Roll transfer function G_phi_delta (numerator over the monic ``den``, the roll dynamics'
    characteristic polynomial) plus the path of a vertical steer axis: delta -> phi, psi, eta."""
    den = np.asarray(den, float)
    A, B, C, D = _canonical(G.num[0][0], den / den[0])
    roll = control.ss(A, B, C, D, inputs=["delta"], outputs=["phi"], states=[f"x{k}" for k in range(A.shape[0])])
    return _with_path(roll, np.zeros(roll.nstates), [1.0], _path(bike, V, effective=False),
                      ["phi", "psi", "eta"])


def _torque_model(sys: control.StateSpace, bike: SimpleBicycle, V: float) -> control.StateSpace:
    """A frame + fork model with outputs (phi, delta) plus the path with delta_f = delta*sin(lam)."""
    k = list(sys.output_labels).index("delta")
    return _with_path(sys, sys.C[k], sys.D[k], _path(bike, V, effective=True),
                      ["phi", "delta", "psi", "eta"])


# ----------------------------------------------------------------------------
# the twins

def _self_stabilizing(p: Mapping[str, float], V: float) -> control.StateSpace:
    bike = bicycle(p)
    return _torque_model(simple.self_stabilizing_ss(bike, V, k3=0.0, frame="eq14"), bike, V)


def _self_stabilizing_gyro(p: Mapping[str, float], V: float) -> control.StateSpace:
    bike = bicycle(p)
    return _torque_model(simple.self_stabilizing_ss(bike, V, k3=p["k3"], frame="eq14"), bike, V)


def _inverted_pendulum(p: Mapping[str, float], V: float) -> control.StateSpace:
    bike = bicycle(p)
    return _steer_angle_model(simple.roll_steer_tf(bike, V, frame="eq1"), simple.roll_polynomial(bike), bike, V)


def _rear_steered(p: Mapping[str, float], V: float) -> control.StateSpace:
    """(18) at the forward speed V in the rider's variables: model (1) at -V turned half a
    revolution about the vertical (phi, delta and eta change sign), so the roll transfer function is
    (4) at -V and the path is the ordinary der(psi) = V delta / b, der(eta) = V psi."""
    bike = bicycle(p)
    return _steer_angle_model(simple.rear_steer_roll_steer_tf(bike, V), simple.roll_polynomial(bike), bike, V)


def _leaning_rider(p: Mapping[str, float], V: float) -> control.StateSpace:
    bike = bicycle(p)
    return _torque_model(simple.leaning_rider_ss(bike, V, frame="eq14"), bike, V)


def _crowned_roller(p: Mapping[str, float], V: float) -> control.StateSpace:
    bike = bicycle(p)
    G = simple.roll_steer_tf(bike, V, frame="eq1")  # monic denominator s^2 - m g h / J
    den = np.real(np.poly(simple.crowned_roller_poles(bike)))  # s^2 - m g (h - R) / J, eq (27)
    return _steer_angle_model(control.tf(G.num[0][0], den), den, bike, V)


def _whipple_linear(p: Mapping[str, float], v: float) -> control.StateSpace:
    """Meijaard et al. (2007) in :mod:`cosim.analytic.whipple` plus the linearized heading and
    path (Meijaard eq. (A 9)): der(psi) = (v delta + c delta_dot) cos(lam) / w, der(y) = v psi."""
    params = {k: p[k] for k in PARAMETER_NAMES}
    A4, B4 = whipple.state_matrices(params, v)
    A = np.zeros((6, 6))
    A[:4, :4] = A4
    A[4, 1], A[4, 3] = v * math.cos(p["lam"]) / p["w"], p["c"] * math.cos(p["lam"]) / p["w"]
    A[5, 4] = v
    B = np.zeros((6, 2))
    B[:4] = B4
    names = ["phi", "delta", "phi_dot", "delta_dot", "psi", "y"]
    return control.ss(A, B, np.eye(6), np.zeros((6, 2)), states=names, inputs=["T_phi", "T_delta"],
                      outputs=names)


def _meijaard_defaults() -> dict:
    return {**load_parameters("benchmark"), "v": 5.0, "phi0": 0.0, "delta0": 0.0, "phi_dot0": 0.0,
            "delta_dot0": 0.0}


_TORQUE_OUT = ("phi", "delta", "psi", "eta")
_ANGLE_OUT = ("phi", "psi", "eta")

TWINS: dict[str, Twin] = {t.model: t for t in (
    Twin("Bicycle.Bicycles.SelfStabilizing", _self_stabilizing, dict(_PAPER), ("T",), _TORQUE_OUT,
         equations="(14) + (11); path with delta*sin(lambda)"),
    Twin("Bicycle.Bicycles.SelfStabilizingGyro", _self_stabilizing_gyro, {**_PAPER, "k3": _SECOND_ORDER["k3"]}, ("T",),
         _TORQUE_OUT, equations="(14) + (11) with delta = k1 T - k2 phi - k3 dphi/dt"),
    Twin("Bicycle.Bicycles.InvertedPendulum", _inverted_pendulum, dict(_PENDULUM), ("delta",), _ANGLE_OUT,
         equations="(1), (4); path der(psi) = V delta / b, der(eta) = V psi"),
    Twin("Bicycle.Bicycles.RearSteered", _rear_steered, {**_PENDULUM, "phi0": 0.0}, ("delta",), _ANGLE_OUT,
         equations="(18) at forward speed V, the rider's signs; path der(psi) = V delta / b, der(eta) = V psi"),
    Twin("Bicycle.Bicycles.LeaningRider", _leaning_rider,
         {**_PAPER, **{k: _SECOND_ORDER[k] for k in ("m_r", "J_r", "h_r")}}, ("T", "theta"), _TORQUE_OUT,
         equations="frame (14) with the lean terms of (22), + (11) (not (23) as printed: its frame is (1))"),
    Twin("Bicycle.Bicycles.CrownedRoller", _crowned_roller, {**_PENDULUM, "R": _SECOND_ORDER["R"]}, ("delta",), _ANGLE_OUT,
         equations="(1) with m g (h - R), poles (27)"),
    Twin("Bicycle.Bicycles.WhippleLinear", _whipple_linear, _meijaard_defaults(), ("T_phi", "T_delta"),
         ("phi", "delta", "phi_dot", "delta_dot", "psi", "y"), speed="v",
         equations="(24) with Meijaard et al. (2007) M, C1, K0, K2"),
)}


# ----------------------------------------------------------------------------
# the nonlinear bicycles' linearization about upright straight running (their twins, which reduce an
# FMU's linearization first, are cosim.bicycle.twins.STEADY_MOTION_TWINS)

#: The states of :func:`steady_lateral`, the outputs of the nonlinear bicycles' twins.
LATERAL_OUTPUTS = ("phi", "delta", "u_phi", "u_delta", "psi", "y")
#: Initial values that must be zero for the steady motion the twin describes (the others -- x0,
#: y0, thetaR0, thetaF0, the Newton start theta_guess -- do not change the linearization).
_STEADY_STARTS = ("psi0", "phi0", "delta0", "u_phi0", "u_delta0", "beta0", "u_beta0")


def steady_lateral(p: Mapping[str, float], u_R0: float, rider: bool) -> control.StateSpace:
    """Meijaard et al. (2007) about upright straight running at v = -u_R0 rR, on the nonlinear
    bicycle's names: states (:data:`LATERAL_OUTPUTS`), inputs (T_delta, T_phi); ``u_R0`` [rad/s] the
    rear wheel rate, ``rider`` whether ``p`` holds an upper body to merge into the rear frame.
    ValueError for crowned wheels or start values off upright straight running (named)."""
    crowned = [k for k in ("tR", "tF") if p.get(k, 0.0) != 0.0]
    if crowned:
        raise ValueError(f"{', '.join(crowned)}: the analytic model has knife-edge wheels (crown radius 0)")
    moving = [k for k in _STEADY_STARTS if p.get(k, 0.0) != 0.0]
    if moving:
        raise ValueError(f"{', '.join(moving)}: the analytic model is about upright straight running along x "
                         "(these start values must be 0)")
    params = merged_rear_frame(p) if rider else {k: p[k] for k in PARAMETER_NAMES}
    v = -float(u_R0) * float(p["rR"])
    sys = _whipple_linear({**p, **params}, v)
    names = list(LATERAL_OUTPUTS)
    order = [1, 0]  # the FMU's inputs are (T_delta, T_phi)
    return control.ss(sys.A, sys.B[:, order], np.eye(6), np.zeros((6, 2)), states=names,
                      inputs=["T_delta", "T_phi"], outputs=names)
