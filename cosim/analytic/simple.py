"""Simple second-order bicycle models of Åström, Klein & Lennartsson (2005).

Every formula of the sections "Simple Second-Order Models" to "Effects of Rider
Lean" of *Bicycle Dynamics and Control* (IEEE Control Systems Magazine 25(4),
2005), plus the crowned-roller pole (27) and the :math:`p\\tau` rule, as numbers
or python-control systems.  Equation numbers in the docstrings are the paper's.

Conventions (ISO 8855, as in the paper): roll angle φ positive leaning to the
right, steer angle δ positive steering to the left, steer torque T positive
counter-clockwise seen from above, path deviation η along the inertial η axis
(to the left).  Angles in rad, V in m/s, T in N m, time in s.

Two frame models appear in the paper and both are offered through the ``frame``
argument of the functions that combine a frame with the static front fork (11):

``"eq1"``
    the inverted-pendulum frame (1), written for λ = 90°, c = 0.  The paper
    uses it for (20), (21) and (22)/(23), so those are reproduced *as printed*
    with ``frame="eq1"``.
``"eq14"``
    the frame (14), where δ is replaced by the effective steer angle δ sin λ (8)
    and the trail adds the torque -mgac sin λ δ / b.  This is the model of the
    self-stabilizing bicycle (15) and of the Modelica model
    ``Bicycle.Bicycles.SelfStabilizing``; use it to compare with that FMU.

Inconsistencies found in the printed equations (the code follows what the
governing equations imply and says so where it matters):

* (6) and (19) print ``dδ/dt`` in the damping term; it is ``dφ/dt`` (δ = -k2 φ
  has been substituted).  (19) also calls the gain "k" in the text; it is k2.
* (15) prints the damping term as ``DVg / (V² sin λ - bg cos λ)``; inserting
  (11) into (14) gives ``DVg sin λ / (V² sin λ - bg cos λ)``.  Stability is
  unaffected (sin λ > 0).
* (21) contains ``V_c``.  (21) equals G_ηδ · (20) only if ``V_c² = bg/k2(V) =
  V² sin λ - bg cos λ``, i.e. the critical speed of (6) for the gain k2(V), not
  the critical speed (16).
* (23) prints the steer-torque term as ``m V² k1 T / b``; inserting (11) in (22)
  gives ``m V² h k1 T / b`` (the height h is missing).
* With the frame (1) and the fork (11) the closed loop (20) is stable for every
  V > V_sa (λ < 90°), condition (17) plays no role; (17) comes from the trail
  term -acg of (14).  With λ = 90° the fork gain k2 = bg/V² sits exactly on
  the stability boundary of (6): the loop (1)+(11) is then only marginally stable.
* Figure 5 quotes steady values φ = 0.14 rad, δ = -0.14 rad but not the speed
  or torque.  The steady ratio is φ/δ = -V²/(bg) for (1)+(11) and
  -(V²h - acg) sin λ/(bgh) for (14)+(11), so |φ| = |δ| needs V ≈ 3.1 m/s
  resp. 3.29 m/s for the Table 1 bicycle: ``cosim.figures.fig5.operating_point``
  solves for V and T and the figure is drawn there (tests/test_fig5_fig15.py).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import control
import numpy as np

from cosim.analytic.parameters import load_second_order

#: The bicycle of Astrom, Klein & Lennartsson (2005) for the simple models (``lambda`` is the head angle).
_PAPER = load_second_order("astrom2005")

__all__ = [
    "SimpleBicycle",
    "pendulum_poles",
    "steer_roll_zero",
    "roll_steer_tf",
    "rear_steer_roll_steer_tf",
    "critical_steer_gain",
    "steer_feedback_closed_loop",
    "steer_feedback_is_stable",
    "rear_steer_closed_loop",
    "rear_steer_zero_pole_ratio",
    "self_alignment_velocity",
    "critical_velocity",
    "trail_condition",
    "is_self_stabilizing",
    "fork_gain_k1",
    "fork_gain_k2",
    "manual_steer_gain",
    "self_stabilizing_tf",
    "self_stabilizing_ss",
    "steer_torque_tf",
    "path_steer_tf",
    "path_torque_tf",
    "leaning_rider_ss",
    "crowned_roller_poles",
    "crowned_roller_is_stable",
    "manual_control_rating",
]

Frame = Literal["eq1", "eq14"]


@dataclass(frozen=True)
class SimpleBicycle:
    """Parameters of the simple bicycle models (rider lumped into the frame).

    Defaults: the Table 1 bicycle with rider as one rigid body, identical to the
    Modelica model ``Bicycle.Bicycles.SelfStabilizing``.

    Parameters
    ----------
    m : float
        Total mass of bicycle and rider [kg], > 0.
    a : float
        Horizontal distance from the rear contact point P1 to the centre of
        mass [m], > 0.
    h : float
        Height of the centre of mass above the ground [m], > 0.
    b : float
        Wheel base [m], > 0.
    c : float
        Trail [m], >= 0 (c = 0 is the neutral bicycle; the static fork (11) is
        then undefined).
    lam : float
        Head angle λ [rad], in (0, π/2]; π/2 is a vertical steer axis.
    J : float
        Moment of inertia about the x axis [kg m²], > 0.
    D : float
        Inertia product D = -Jxz [kg m²], > 0 (≈ m a h).
    g : float
        Gravitational acceleration [m/s²], > 0.
    m_r : float
        Mass of the rider's upper body [kg], >= 0 (only used by (22)/(23)).
    J_r : float
        Moment of inertia of the upper body about its lean axis [kg m²], >= 0.
    h_r : float
        Distance from the upper body's centre of mass to its lean axis [m], >= 0.
    R : float
        Lateral (rocking) radius of crowned rollers [m], >= 0; only used by
        (27).  R = 0 is an ordinary thin tyre.

    Raises
    ------
    ValueError
        Naming the parameter, if a value is not finite or out of range.
    """

    # Defaults: the paper's bicycle, cosim/params/second-order/astrom2005.toml (the one source of the values).
    m: float = _PAPER["m"]
    a: float = _PAPER["a"]
    h: float = _PAPER["h"]
    b: float = _PAPER["b"]
    c: float = _PAPER["c"]
    lam: float = _PAPER["lambda"]
    J: float = _PAPER["J"]
    D: float = _PAPER["D"]
    g: float = _PAPER["g"]
    m_r: float = 0.0
    J_r: float = 0.0
    h_r: float = 0.0
    R: float = 0.0

    def __post_init__(self) -> None:
        self.validate()

    def validate(self) -> None:
        """Raise ``ValueError`` naming the first invalid parameter."""
        positive = ("m", "a", "h", "b", "J", "D", "g")
        nonnegative = ("c", "m_r", "J_r", "h_r", "R")
        for name in ("lam", *positive, *nonnegative):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
                raise ValueError(f"{name} must be a real number, got {value!r}")
            if not math.isfinite(value):
                raise ValueError(f"{name} must be finite, got {value!r}")
        for name in positive:
            if getattr(self, name) <= 0:
                raise ValueError(f"{name} must be > 0, got {getattr(self, name)!r}")
        for name in nonnegative:
            if getattr(self, name) < 0:
                raise ValueError(f"{name} must be >= 0, got {getattr(self, name)!r}")
        if not 0.0 < self.lam <= math.pi / 2:
            raise ValueError(f"lam (head angle) must be in (0, pi/2] rad, i.e. (0, 90] deg, got {self.lam!r}")

    @classmethod
    def point_mass(cls, m: float = _PAPER["m"], a: float = _PAPER["a"], h: float = _PAPER["h"],
                   **kw) -> "SimpleBicycle":
        """Bicycle with the approximations J ≈ m h², D ≈ m a h used after (1)."""
        return cls(m=m, a=a, h=h, J=m * h**2, D=m * a * h, **kw)


# ----------------------------------------------------------------------------
# helpers

def _tf(num, den) -> control.TransferFunction:
    """Transfer function normalised to a monic denominator."""
    den = np.atleast_1d(np.asarray(den, dtype=float))
    num = np.atleast_1d(np.asarray(num, dtype=float))
    return control.tf(num / den[0], den / den[0])


def _speed(V: float) -> float:
    V = float(V)
    if not math.isfinite(V):
        raise ValueError(f"V must be finite, got {V!r}")
    return V


def _frame_coefficients(bike: SimpleBicycle, V: float, frame: Frame) -> tuple[float, float]:
    """Coefficients (e, f) of the frame torque e·dδ/dt + f·δ in (1) or (14) [N m s, N m]."""
    if frame == "eq1":
        return bike.D * V / bike.b, bike.m * V**2 * bike.h / bike.b
    if frame == "eq14":
        s = math.sin(bike.lam)
        return (bike.D * V * s / bike.b,
                bike.m * (V**2 * bike.h - bike.a * bike.c * bike.g) * s / bike.b)
    raise ValueError(f"frame must be 'eq1' or 'eq14', got {frame!r}")


def _fork_denominator(bike: SimpleBicycle, V: float) -> float:
    """V² sin λ - b g cos λ [m²/s²]; zero at the self-alignment speed (10)."""
    if bike.c == 0:
        raise ValueError("c = 0: the static front fork (9)-(13) is singular for a neutral bicycle")
    w = V**2 * math.sin(bike.lam) - bike.b * bike.g * math.cos(bike.lam)
    if abs(w) <= 1e-12 * (V**2 + bike.b * bike.g):
        raise ValueError(f"V = {V!r} equals the self-alignment velocity (10): k1, k2 are infinite")
    return w


# ----------------------------------------------------------------------------
# steer angle as input: (2)-(6), (18), (19)

def pendulum_poles(bike: SimpleBicycle) -> np.ndarray:
    """Poles of the inverted-pendulum model (1), eq. (2).

    Returns
    -------
    numpy.ndarray
        ``[+p, -p]`` with p = sqrt(m g h / J) [rad/s] (≈ sqrt(g/h)).
    """
    p = math.sqrt(bike.m * bike.g * bike.h / bike.J)
    return np.array([p, -p])


def steer_roll_zero(bike: SimpleBicycle, V: float) -> float:
    """Zero of G_φδ, eq. (3): z = -m V h / D [rad/s] (≈ -V/a).

    For V < 0 (rear-wheel steering, (18)) the zero is in the right half plane.
    """
    return -bike.m * _speed(V) * bike.h / bike.D


def roll_steer_tf(bike: SimpleBicycle, V: float, frame: Frame = "eq1") -> control.TransferFunction:
    """Transfer function from steer angle δ to roll angle φ, eq. (4) [rad/rad].

    G_φδ(s) = V (D s + m V h) / (b (J s² - m g h)).  A negative V gives the
    rear-wheel-steered bicycle (18).

    Parameters
    ----------
    bike : SimpleBicycle
    V : float
        Forward speed [m/s].
    frame : {"eq1", "eq14"}
        ``"eq1"`` is (4) as printed; ``"eq14"`` is the same input-output map of
        the frame (14): (D V sin λ s + m (V² h - a c g) sin λ) / (b (J s² - m g h)).
    """
    e, f = _frame_coefficients(bike, _speed(V), frame)
    return _tf([e, f], roll_polynomial(bike))


def roll_polynomial(bike: SimpleBicycle) -> np.ndarray:
    """``J s² - m g h``: the denominator of (4) and (18), the falling pendulum [kg m²] (also at
    V = 0, where the transfer function itself is 0 and keeps no denominator)."""
    return np.array([bike.J, 0.0, -bike.m * bike.g * bike.h])


def rear_steer_roll_steer_tf(bike: SimpleBicycle, V: float) -> control.TransferFunction:
    """Rear-wheel-steered bicycle, eq. (18): G_φδ of (4) with V replaced by -V.

    G(s) = (-V D s + m V² h) / (b (J s² - m g h)); for V > 0 it has the pole
    +sqrt(mgh/J) and the zero +m V h / D in the right half plane.

    V is the rear-steered bicycle's forward speed [m/s] and φ, δ are the rider's (φ positive
    leaning to the rider's right, δ positive steering the bicycle to the left): the
    ``delta -> phi`` map of ``Bicycle.Bicycles.RearSteered`` at its ``V``.  Turning the axes of
    model (1) half a revolution about the vertical changes the signs of both φ and δ, so G is
    (4) at -V in either set of axes.
    """
    return roll_steer_tf(bike, -_speed(V))


def critical_steer_gain(bike: SimpleBicycle, V: float) -> float:
    """Smallest stabilizing gain of δ = -k2 φ (5) for V > 0, from (6): b g / V² [rad/rad]."""
    V = _speed(V)
    if V == 0:
        return math.inf
    return bike.b * bike.g / V**2


def steer_feedback_closed_loop(bike: SimpleBicycle, V: float, k2: float) -> control.TransferFunction:
    """Closed loop (6) of (4) with the proportional steering δ = -k2 φ + δ_ref (5).

    The characteristic polynomial is J s² + (D V k2 / b) s + m V² h k2 / b - m g h
    (the paper prints dδ/dt in (6); it is dφ/dt).  Negative V gives (19).

    Returns
    -------
    control.TransferFunction
        From the steer reference δ_ref [rad] to φ [rad].
    """
    return control.feedback(roll_steer_tf(bike, V), float(k2))


def steer_feedback_is_stable(bike: SimpleBicycle, V: float, k2: float) -> bool:
    """Routh test of (6): D V k2 > 0 and m V² h k2 / b > m g h.

    For V > 0 this is the paper's condition k2 > b g / V² (D > 0 by validation).
    For V < 0 it is the rear-steered loop (19): never stable for k2 > 0.
    """
    V = _speed(V)
    damping = bike.D * V * k2 / bike.b
    stiffness = bike.m * V**2 * bike.h * k2 / bike.b - bike.m * bike.g * bike.h
    return damping > 0 and stiffness > 0


def rear_steer_closed_loop(bike: SimpleBicycle, V: float, k2: float) -> control.TransferFunction:
    """Rear-wheel steering with δ = -k2 φ (+ δ_ref), eq. (19).

    J φ'' - (D V k2 / b) φ' + (m V² h k2 / b - m g h) φ = 0: for V > 0 and
    k2 > 0 the damping is negative, so the loop is unstable.
    """
    return steer_feedback_closed_loop(bike, -_speed(V), k2)


def rear_steer_zero_pole_ratio(bike: SimpleBicycle, V: float) -> float:
    """Ratio of the right-half-plane zero and pole of (18), after (19) [-].

    z/p = (m V h / D) sqrt(J / (m g h)) ≈ (V/a) sqrt(h/g); robust control needs
    it large.
    """
    return bike.m * _speed(V) * bike.h / bike.D * math.sqrt(bike.J / (bike.m * bike.g * bike.h))


# ----------------------------------------------------------------------------
# the static front fork: (9)-(17)

def self_alignment_velocity(bike: SimpleBicycle) -> float:
    """Self-alignment velocity, eq. (10): V_sa = sqrt(b g cot λ) [m/s]."""
    return math.sqrt(bike.b * bike.g * math.cos(bike.lam) / math.sin(bike.lam))


def critical_velocity(bike: SimpleBicycle) -> float:
    """Critical velocity of the self-stabilizing bicycle (15), eq. (16) [m/s].

    V_c = sqrt(b g cot λ), equal to V_sa (10) for the static fork.
    """
    return self_alignment_velocity(bike)


def trail_condition(bike: SimpleBicycle) -> bool:
    """Condition (17): b h > a c tan λ (evaluated as b h cos λ > a c sin λ).

    False for λ = 90° with c > 0; for c = 0 and λ = 90° both sides vanish.
    """
    return bike.b * bike.h * math.cos(bike.lam) > bike.a * bike.c * math.sin(bike.lam)


def is_self_stabilizing(bike: SimpleBicycle, V: float) -> bool:
    """Whether (15) is asymptotically stable: V > V_c (16) and (17).

    The paper states "stable if"; for V > 0 and D > 0 the Routh test of (15)
    shows it is also "only if".
    """
    return _speed(V) > critical_velocity(bike) and trail_condition(bike)


def fork_gain_k1(bike: SimpleBicycle, V: float) -> float:
    """Steer-torque gain of the static fork (11), eq. (12) [rad/(N m)].

    k1 = b² / ((V² sin λ - b g cos λ) m a c sin λ); negative below V_sa.
    """
    w = _fork_denominator(bike, _speed(V))
    return bike.b**2 / (w * bike.m * bike.a * bike.c * math.sin(bike.lam))


def fork_gain_k2(bike: SimpleBicycle, V: float) -> float:
    """Roll-to-steer gain of the static fork (11), eq. (13) [rad/rad].

    k2 = b g / (V² sin λ - b g cos λ); negative below V_sa.
    """
    return bike.b * bike.g / _fork_denominator(bike, _speed(V))


def manual_steer_gain(bike: SimpleBicycle, V: float, k: float) -> float:
    """Effective roll feedback with the rider torque T = -k φ ("Manual Control").

    δ = -(k k1(V) + k2(V)) φ; returns k k1 + k2 [rad/rad] (k in N m/rad).
    """
    return k * fork_gain_k1(bike, V) + fork_gain_k2(bike, V)


def _frame_fork_ss(bike: SimpleBicycle, V: float, frame: Frame, k3: float) -> control.StateSpace:
    """Frame ((1) or (14), rider lean as in (22)) closed by the fork (11) + k3 term.

    States x = [χ, L] with χ = φ + (J_r/J) θ and L = J χ' - e δ (momentum form),
    inputs u = [T, θ], outputs y = [φ, δ].
    """
    V = _speed(V)
    e, f = _frame_coefficients(bike, V, frame)
    k1, k2 = fork_gain_k1(bike, V), fork_gain_k2(bike, V)
    J, mgh = bike.J, bike.m * bike.g * bike.h
    r = bike.J_r / J
    if k3 != 0 and r != 0:
        raise ValueError("k3 != 0 with a leaning rider (J_r > 0) makes δ depend on dθ/dt (improper)")
    if J + k3 * e == 0:
        raise ValueError(f"k3 = {k3!r}: J + k3 e vanishes (e = coefficient of d(delta)/dt)")
    kappa = J / (J + k3 * e)
    # δ = κ (k1 T - k2 φ - k3 φ'), φ = χ - r θ, φ' = (L + e δ)/J when r = 0
    d_x = kappa * np.array([-k2, -k3 / J])
    d_u = kappa * np.array([k1, k2 * r])
    A = np.vstack([np.array([0.0, 1.0 / J]) + e * d_x / J,
                   np.array([mgh, 0.0]) + f * d_x])
    B = np.vstack([e * d_u / J,
                   np.array([0.0, -mgh * r + bike.m_r * bike.g * bike.h_r]) + f * d_u])
    C = np.vstack([[1.0, 0.0], d_x])
    Dm = np.vstack([[0.0, -r], d_u])
    return control.ss(A, B, C, Dm, states=["chi", "L"], inputs=["T", "theta"], outputs=["phi", "delta"])


def self_stabilizing_ss(bike: SimpleBicycle, V: float, k3: float = 0.0,
                        frame: Frame = "eq14") -> control.StateSpace:
    """Self-stabilizing bicycle (14) + (11) (or + gyroscopic fork) as a state-space model.

    States in momentum form, as in the Modelica model ``SelfStabilizing``::

        x = [φ, L],  L = J dφ/dt - (D V sin λ / b) δ      [rad, kg m²/s]
        dφ/dt = (L + D V sin λ δ / b) / J
        dL/dt = m g h φ + m (V² h - a c g) sin λ δ / b
        δ = k1 T - k2 φ - k3 dφ/dt

    Parameters
    ----------
    bike : SimpleBicycle
    V : float
        Forward speed [m/s], not equal to V_sa.
    k3 : float
        Gain [s] of the gyroscopic derivative term of the fork ("Gyroscopic
        Effects"); the paper gives no formula, only k3 ∝ V.  0 gives (11).
    frame : {"eq14", "eq1"}
        ``"eq1"`` uses (1) instead of (14) (no sin λ, no trail torque);
        L is then J dφ/dt - D V δ / b.

    Returns
    -------
    control.StateSpace
        Input T [N m]; outputs φ [rad] and δ [rad] (δ has a feedthrough k1 T).
    """
    sys = _frame_fork_ss(bike, V, frame, float(k3))
    return control.ss(sys.A, sys.B[:, :1], sys.C, sys.D[:, :1],
                      states=["phi", "L"], inputs=["T"], outputs=["phi", "delta"])


def self_stabilizing_tf(bike: SimpleBicycle, V: float, k3: float = 0.0, frame: Frame = "eq14",
                        as_printed: bool = False) -> control.TransferFunction:
    """Transfer function from steer torque T to roll φ, eq. (15) [rad/(N m)].

    From (14) + (11) (or δ = k1 T - k2 φ - k3 φ')::

        ((J + e k3) s² + (e k2 + f k3) s + f k2 - m g h) φ = k1 (e s + f) T

    with e = D V sin λ / b and f = m (V² h - a c g) sin λ / b.  For k3 = 0 this
    is (15) with the damping term D V g sin λ / (V² sin λ - b g cos λ).

    Parameters
    ----------
    as_printed : bool
        Use the damping term of (15) exactly as printed, D V g / (V² sin λ -
        b g cos λ), i.e. without sin λ (only with frame="eq14" and k3 = 0).
    """
    V = _speed(V)
    e, f = _frame_coefficients(bike, V, frame)
    k1, k2 = fork_gain_k1(bike, V), fork_gain_k2(bike, V)
    mgh = bike.m * bike.g * bike.h
    den = [bike.J + e * k3, e * k2 + f * k3, f * k2 - mgh]
    if as_printed:
        if frame != "eq14" or k3 != 0:
            raise ValueError("as_printed applies to eq. (15) only: frame='eq14', k3=0")
        den[1] = bike.D * V * bike.g / _fork_denominator(bike, V)
    return _tf([k1 * e, k1 * f], den)


# ----------------------------------------------------------------------------
# maneuvering: (20), (21)

def steer_torque_tf(bike: SimpleBicycle, V: float, frame: Frame = "eq1",
                    k3: float = 0.0) -> control.TransferFunction:
    """Transfer function from steer torque T to steer angle δ, eq. (20) [rad/(N m)].

    G_δT = k1 / (1 + k2 G_φδ) = k1 (s² - m g h / J) / (s² + k2 D V s/(b J) +
    k2 V² m h/(b J) - m g h/J) as printed (``frame="eq1"``: frame (1), as the
    paper does).  ``frame="eq14"`` gives the consistent version for (14) + (11),
    whose poles are those of (15).  The zeros ±sqrt(m g h / J) are the pendulum
    poles (2) in both cases (also with k3).
    """
    V = _speed(V)
    e, f = _frame_coefficients(bike, V, frame)
    k1, k2 = fork_gain_k1(bike, V), fork_gain_k2(bike, V)
    mgh = bike.m * bike.g * bike.h
    return _tf([k1 * bike.J, 0.0, -k1 * mgh], [bike.J + e * k3, e * k2 + f * k3, f * k2 - mgh])


def path_steer_tf(bike: SimpleBicycle, V: float, frame: Frame = "eq1") -> control.TransferFunction:
    """Transfer function from steer angle δ to path deviation η [m/rad].

    From dη/dt = V ψ, dψ/dt = V δ / b: G_ηδ = V² / (b s²) (``frame="eq1"``, as
    printed).  ``frame="eq14"`` uses the effective steer angle δ sin λ (8), as
    the frame (14) does: G_ηδ = V² sin λ / (b s²).
    """
    V = _speed(V)
    _frame_coefficients(bike, V, frame)  # validates ``frame``
    gain = V**2 / bike.b * (math.sin(bike.lam) if frame == "eq14" else 1.0)
    return _tf([gain], [1.0, 0.0, 0.0])


def path_torque_tf(bike: SimpleBicycle, V: float, frame: Frame = "eq1",
                   k3: float = 0.0) -> control.TransferFunction:
    """Transfer function from steer torque T to path deviation η, eq. (21) [m/(N m)].

    G_ηT = G_ηδ G_δT = (k1 V² / b) (s² - m g h / J) /
    (s² (s² + k2 V D s/(b J) + (m g h / J)(V² / V_c² - 1))).

    With ``frame="eq1"`` this is (21) as printed, where V_c² must be read as
    b g / k2(V) = V² sin λ - b g cos λ (the critical speed of (6) for the gain
    k2(V)), *not* (16).  ``frame="eq14"`` is the consistent version for
    (14) + (11) (denominator of (15), yaw from δ sin λ).  Either way the zero
    +sqrt(m g h / J) gives the inverse response of Figure 5.
    """
    G_eta_delta = path_steer_tf(bike, V, frame)
    G_delta_T = steer_torque_tf(bike, V, frame, k3)
    return _tf(np.polymul(G_eta_delta.num[0][0], G_delta_T.num[0][0]),
               np.polymul(G_eta_delta.den[0][0], G_delta_T.den[0][0]))


# ----------------------------------------------------------------------------
# rider lean: (22), (23)

def leaning_rider_ss(bike: SimpleBicycle, V: float, frame: Frame = "eq1") -> control.StateSpace:
    """Bicycle with a leaning rider, (22) + (11) = (23), as a two-input state-space model.

    (22): J φ'' + J_r θ'' = m g h φ + m_r g h_r θ + (D V / b) δ' + (m V² h / b) δ
    with θ the upper-body lean relative to the frame (same sense as φ) and the
    fork δ = k1 T - k2 φ.  (The paper writes the same symbol for φ and θ; and
    (23) as printed lacks the factor h in m V² h k1 T / b.)  ``frame="eq14"``
    replaces the frame terms by those of (14).

    Since θ'' enters, the states are x = [χ, L] with χ = φ + (J_r/J) θ and
    L = J χ' - (D V / b) δ the total roll angular momentum [kg m²/s].

    Returns
    -------
    control.StateSpace
        Inputs T [N m] and θ [rad]; outputs φ [rad] and δ [rad].
    """
    return _frame_fork_ss(bike, V, frame, 0.0)


# ----------------------------------------------------------------------------
# crowned rollers (27) and the p·τ rule

def crowned_roller_poles(bike: SimpleBicycle) -> np.ndarray:
    """Roll poles of a bicycle on crowned rollers of lateral radius R, eq. (27).

    The gravity term m g h of (1) becomes m g (h - R): poles ±sqrt(m g (h - R) / J)
    [rad/s] (≈ ±sqrt((1 - R/h) g / h)), real for R < h, imaginary for R > h.

    Returns
    -------
    numpy.ndarray
        Complex array ``[+p, -p]``.
    """
    p = np.sqrt(complex(bike.m * bike.g * (bike.h - bike.R) / bike.J))
    return np.array([p, -p])


def crowned_roller_is_stable(bike: SimpleBicycle) -> bool:
    """(27): stable (poles on the imaginary axis, no damping) iff R > h."""
    return bike.R > bike.h


def manual_control_rating(pole: complex, tau: float) -> str:
    """Difficulty of stabilizing an unstable pole by hand with neural delay τ.

    Uses p τ with p the real part of the pole [rad/s] and τ [s]: ``"comfortable"``
    for p τ < 0.2, ``"impossible"`` for p τ > 2, otherwise ``"difficult"``.
    A stable pole (p <= 0) is ``"comfortable"``.  The paper's example: τ = 0.2 s
    allows p < 1 rad/s.
    """
    tau = float(tau)
    if not math.isfinite(tau) or tau < 0:
        raise ValueError(f"tau must be a finite delay >= 0 s, got {tau!r}")
    p_tau = complex(pole).real * tau
    if p_tau < 0.2:
        return "comfortable"
    if p_tau > 2.0:
        return "impossible"
    return "difficult"
