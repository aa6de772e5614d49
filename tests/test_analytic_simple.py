"""Tests of cosim.analytic.simple against the equations of Åström, Klein & Lennartsson (2005).

Tolerances: coefficients, poles and gains computed two ways agree to rtol = 1e-9
(REL) unless stated; boundary checks sit EPS = 1e-3 (relative) either side.
"""
from __future__ import annotations

import math

import control
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from cosim.analytic import simple as sm
from cosim.analytic.simple import SimpleBicycle
from reference import SELF_STABILIZING_DEFAULTS as PAPER

REL = 1e-9
EPS = 1e-3
BIKE = SimpleBicycle()
# b h < a c tan(lam): violates (17)
NO_TRAIL_COND = SimpleBicycle(a=0.9, c=0.5, lam=math.radians(80), h=0.8)
TALL = SimpleBicycle(h=1.2, J=92 * 1.2**2 + 4, D=92 * 0.5 * 1.2 + 1)
BIKES = [pytest.param(BIKE, id="table1"), pytest.param(TALL, id="tall"),
         pytest.param(SimpleBicycle.point_mass(), id="point-mass"),
         pytest.param(SimpleBicycle(lam=math.pi / 2, c=0.05), id="vertical-axis")]
SPEEDS = [pytest.param(V, id=f"V={V}") for V in (0.5, 2.5, 4.0, 6.0, 10.0)]
FRAMES = [pytest.param(f, id=f) for f in ("eq1", "eq14")]


def coeffs(G):
    """Numerator and (monic) denominator coefficient arrays of a SISO TF."""
    num, den = np.array(G.num[0][0], float), np.array(G.den[0][0], float)
    return np.trim_zeros(num / den[0], "f"), den / den[0]


def sorted_roots(r):
    r = np.asarray(r, complex)
    return r[np.lexsort((r.imag, r.real))]


def assert_roots(a, b, rtol=1e-7, atol=1e-9):
    np.testing.assert_allclose(sorted_roots(a), sorted_roots(b), rtol=rtol, atol=atol)


def stable(G):
    return bool(np.all(np.real(control.poles(G)) < 0))


# --------------------------------------------------------------------------- parameters

@pytest.mark.parametrize("name,value", [
    ("m", 0.0), ("m", -1.0), ("h", -0.1), ("b", 0.0), ("b", -1.0), ("lam", 0.0),
    ("lam", -0.1), ("lam", math.pi / 2 + 1e-9), ("lam", math.radians(120)), ("J", 0.0),
    ("J", -5.0), ("D", 0.0), ("a", -0.2), ("c", -0.01), ("g", 0.0), ("m_r", -1.0),
    ("J_r", -1.0), ("h_r", -0.1), ("R", -0.1), ("m", float("nan")), ("h", float("inf")),
    ("J", "12.5"),
], ids=lambda v: str(v))
def test_bad_parameter_raises_naming_it(name, value):
    with pytest.raises(ValueError, match=rf"\b{name}\b"):
        SimpleBicycle(**{name: value})


def test_defaults_and_valid_edges():
    assert (BIKE.m, BIKE.a, BIKE.h, BIKE.b, BIKE.c, BIKE.J, BIKE.D, BIKE.g) == tuple(
        PAPER[k] for k in ("m", "a", "h", "b", "c", "J", "D", "g"))
    assert BIKE.lam == pytest.approx(math.radians(70), rel=1e-15)
    SimpleBicycle(lam=math.pi / 2)  # 90 deg is allowed
    SimpleBicycle(c=0.0)            # neutral bicycle
    with pytest.raises(ValueError, match="frame"):
        sm.roll_steer_tf(BIKE, 3.0, frame="eq99")


def test_bike_is_frozen():
    with pytest.raises(AttributeError):
        BIKE.m = 1.0


# --------------------------------------------------------------------------- (2)-(4)

@pytest.mark.parametrize("bike", BIKES)
def test_pendulum_poles_eq2(bike):
    p = math.sqrt(bike.m * bike.g * bike.h / bike.J)
    np.testing.assert_allclose(sm.pendulum_poles(bike), [p, -p], rtol=REL)


def test_pendulum_pole_value_table1():
    # Table 1 bicycle with rider: the paper's fourth-order model has +-3.05 at V = 0
    assert sm.pendulum_poles(BIKE)[0] == pytest.approx(3.05, abs=0.01)


@pytest.mark.parametrize("bike", BIKES)
@pytest.mark.parametrize("V", SPEEDS)
def test_G_phi_delta_poles_and_zero_eq2_eq3_eq4(bike, V):
    G = sm.roll_steer_tf(bike, V)
    assert_roots(control.poles(G), sm.pendulum_poles(bike))
    assert_roots(control.zeros(G), [sm.steer_roll_zero(bike, V)])
    assert sm.steer_roll_zero(bike, V) == pytest.approx(-bike.m * V * bike.h / bike.D, rel=REL)
    # (4): V D/(b J) (s + m V h / D) / (s^2 - m g h / J)
    num, den = coeffs(G)
    k = V * bike.D / (bike.b * bike.J)
    np.testing.assert_allclose(num, [k, k * bike.m * V * bike.h / bike.D], rtol=REL)
    np.testing.assert_allclose(den, [1, 0, -bike.m * bike.g * bike.h / bike.J], rtol=REL, atol=1e-12)


@pytest.mark.parametrize("V", SPEEDS)
def test_G_phi_delta_point_mass_approximation_eq4(V):
    bike = SimpleBicycle.point_mass(m=80, a=0.4, h=1.1)
    num, den = coeffs(sm.roll_steer_tf(bike, V))
    a, b, h, g = bike.a, bike.b, bike.h, bike.g
    np.testing.assert_allclose(num, [a * V / (b * h), a * V / (b * h) * V / a], rtol=REL)
    np.testing.assert_allclose(den, [1, 0, -g / h], rtol=REL, atol=1e-12)


@pytest.mark.parametrize("V", SPEEDS)
def test_G_phi_delta_eq14_frame(V):
    s = math.sin(BIKE.lam)
    num, _ = coeffs(sm.roll_steer_tf(BIKE, V, frame="eq14"))
    m, a, c, g, h, b, D, J = BIKE.m, BIKE.a, BIKE.c, BIKE.g, BIKE.h, BIKE.b, BIKE.D, BIKE.J
    np.testing.assert_allclose(num, [D * V * s / (b * J), m * (V**2 * h - a * c * g) * s / (b * J)], rtol=REL)


# --------------------------------------------------------------------------- (5), (6)

@pytest.mark.parametrize("bike", BIKES)
@pytest.mark.parametrize("V", SPEEDS)
@pytest.mark.parametrize("side", [pytest.param(1 + EPS, id="above"), pytest.param(1 - EPS, id="below")])
def test_closed_loop_eq6_stable_iff_k2_above_bg_over_V2(bike, V, side):
    k2 = side * bike.b * bike.g / V**2
    assert sm.critical_steer_gain(bike, V) == pytest.approx(bike.b * bike.g / V**2, rel=REL)
    G = sm.steer_feedback_closed_loop(bike, V, k2)
    # characteristic polynomial of (6) (with d(phi)/dt in the damping term)
    J, D, b, m, h, g = bike.J, bike.D, bike.b, bike.m, bike.h, bike.g
    _, den = coeffs(G)
    np.testing.assert_allclose(den, [1, D * V * k2 / (b * J), (m * V**2 * h * k2 / b - m * g * h) / J],
                               rtol=1e-7, atol=1e-9)
    assert stable(G) == (side > 1) == sm.steer_feedback_is_stable(bike, V, k2)


# --------------------------------------------------------------------------- (18), (19)

@pytest.mark.parametrize("bike", BIKES)
@pytest.mark.parametrize("V", SPEEDS)
def test_rear_steering_eq18(bike, V):
    G = sm.rear_steer_roll_steer_tf(bike, V)
    num, den = coeffs(G)
    k = V * bike.D / (bike.b * bike.J)
    np.testing.assert_allclose(num, [-k, k * bike.m * V * bike.h / bike.D], rtol=REL)
    z, p = control.zeros(G).real, sm.pendulum_poles(bike)[0]
    assert z == pytest.approx([bike.m * V * bike.h / bike.D], rel=1e-9)  # right-half-plane zero
    assert max(control.poles(G).real) == pytest.approx(p, rel=1e-9)      # right-half-plane pole
    assert sm.rear_steer_zero_pole_ratio(bike, V) == pytest.approx(z[0] / p, rel=1e-9)


def test_rear_steer_ratio_point_mass_approximation():
    bike = SimpleBicycle.point_mass(a=0.6, h=0.9)
    for V in (1.0, 5.0, 12.0):
        assert sm.rear_steer_zero_pole_ratio(bike, V) == pytest.approx(V / bike.a * math.sqrt(bike.h / bike.g), rel=REL)


@pytest.mark.parametrize("bike", BIKES)
@pytest.mark.parametrize("V", [0.1, 1.0, 3.0, 6.0, 15.0, 50.0])
@pytest.mark.parametrize("k2", [1e-3, 0.1, 1.0, 3.0, 30.0, 1e3])
def test_rear_steering_closed_loop_eq19_always_unstable(bike, V, k2):
    G = sm.rear_steer_closed_loop(bike, V, k2)
    _, den = coeffs(G)
    assert den[1] == pytest.approx(-bike.D * V * k2 / (bike.b * bike.J), rel=1e-9)  # negative damping
    assert not stable(G)
    assert not sm.steer_feedback_is_stable(bike, -V, k2)


# --------------------------------------------------------------------------- (9)-(13), (16), (17)

def test_self_alignment_velocity_eq10_value():
    assert sm.self_alignment_velocity(BIKE) == pytest.approx(1.89, abs=0.005)  # quoted after (25)
    assert sm.critical_velocity(BIKE) == sm.self_alignment_velocity(BIKE)
    assert sm.self_alignment_velocity(SimpleBicycle(lam=math.pi / 2)) == pytest.approx(0.0, abs=1e-7)


@pytest.mark.parametrize("bike", BIKES[:3])
@pytest.mark.parametrize("V", SPEEDS)
def test_fork_gains_solve_torque_balance_eq9(bike, V):
    k1, k2 = sm.fork_gain_k1(bike, V), sm.fork_gain_k2(bike, V)
    m, a, b, c, g, lam = bike.m, bike.a, bike.b, bike.c, bike.g, bike.lam
    for T, phi in [(1.0, 0.0), (0.0, 0.1), (-2.0, 0.05)]:
        delta = k1 * T - k2 * phi  # (11)
        residual = (T - a * c * m * g * math.sin(lam) / b * phi
                    - a * c * m * math.sin(lam) / b**2 * (V**2 * math.sin(lam) - b * g * math.cos(lam)) * delta)
        assert residual == pytest.approx(0.0, abs=1e-10)
    assert (k2 > 0) == (V > sm.self_alignment_velocity(bike))
    assert sm.manual_steer_gain(bike, V, 7.0) == pytest.approx(7.0 * k1 + k2, rel=REL)


def test_fork_singular_cases_raise():
    with pytest.raises(ValueError, match="self-alignment"):
        sm.fork_gain_k1(BIKE, sm.self_alignment_velocity(BIKE))
    with pytest.raises(ValueError, match="c = 0"):
        sm.fork_gain_k2(SimpleBicycle(c=0.0), 5.0)


@pytest.mark.parametrize("bike,expected", [
    pytest.param(BIKE, True, id="table1"),
    pytest.param(NO_TRAIL_COND, False, id="large-trail"),
    pytest.param(SimpleBicycle(lam=math.pi / 2), False, id="vertical-axis"),
])
def test_trail_condition_eq17(bike, expected):
    assert sm.trail_condition(bike) is expected
    assert (bike.b * bike.h > bike.a * bike.c * math.tan(bike.lam)) is expected


# --------------------------------------------------------------------------- (14), (11), (15)

@pytest.mark.parametrize("bike", BIKES[:3])
@pytest.mark.parametrize("V", SPEEDS)
def test_eq15_as_printed_vs_derived(bike, V):
    """Numerator and stiffness are as printed in (15); the damping differs by sin(lam)."""
    m, a, b, c, g, h, J, D, lam = bike.m, bike.a, bike.b, bike.c, bike.g, bike.h, bike.J, bike.D, bike.lam
    W = V**2 * math.sin(lam) - b * g * math.cos(lam)
    printed_num = [D * V * b / (a * c * m * W), b * (V**2 * h - a * c * g) / (a * c * W)]
    printed_den = [J, D * V * g / W, m * g**2 * (b * h * math.cos(lam) - a * c * math.sin(lam)) / W]
    num, den = coeffs(sm.self_stabilizing_tf(bike, V))
    np.testing.assert_allclose(num, np.array(printed_num) / J, rtol=1e-9)
    np.testing.assert_allclose(den[[0, 2]], np.array(printed_den)[[0, 2]] / J, rtol=1e-9)
    assert den[1] == pytest.approx(printed_den[1] * math.sin(lam) / J, rel=1e-9)
    num_p, den_p = coeffs(sm.self_stabilizing_tf(bike, V, as_printed=True))
    np.testing.assert_allclose(den_p, np.array(printed_den) / J, rtol=1e-9)
    assert stable(sm.self_stabilizing_tf(bike, V)) == stable(sm.self_stabilizing_tf(bike, V, as_printed=True))


@pytest.mark.parametrize("bike", BIKES)
@pytest.mark.parametrize("V", SPEEDS)
@pytest.mark.parametrize("frame", FRAMES)
@pytest.mark.parametrize("k3", [pytest.param(0.0, id="k3=0"), pytest.param(0.05, id="k3=0.05")])
def test_state_space_agrees_with_transfer_functions(bike, V, frame, k3):
    S = sm.self_stabilizing_ss(bike, V, k3=k3, frame=frame)
    G_phi = sm.self_stabilizing_tf(bike, V, k3=k3, frame=frame)
    G_delta = sm.steer_torque_tf(bike, V, frame=frame, k3=k3)
    assert S.state_labels == ["phi", "L"] and S.output_labels == ["phi", "delta"]
    assert_roots(np.linalg.eigvals(S.A), control.poles(G_phi))
    assert_roots(np.linalg.eigvals(S.A), control.poles(G_delta))
    for i, G in enumerate((G_phi, G_delta)):
        Si = control.ss2tf(S[i, 0])
        assert_roots(control.zeros(Si), control.zeros(G), rtol=1e-6)
        if abs(coeffs(G)[1][-1]) > 1e-9:  # frame (1) with lam = 90 deg: pole at 0 (k2 = bg/V^2 exactly)
            assert control.dcgain(S[i, 0]) == pytest.approx(control.dcgain(G), rel=1e-8)
        # same high-frequency (feedthrough) gain
        assert Si(1e7) == pytest.approx(G(1e7), rel=1e-6, abs=1e-12)
    assert_roots(control.zeros(G_delta), sm.pendulum_poles(bike))  # zeros of (20) = poles (2)


@pytest.mark.parametrize("V", SPEEDS)
def test_state_space_matches_modelica_equations(V):
    """SelfStabilizing.mo: omega = (L + D V sin(lam) delta / b)/J, der(L) = m g h phi + m(V^2 h - a c g) sin(lam)/b delta."""
    b_ = BIKE
    S = sm.self_stabilizing_ss(b_, V)
    k1, k2, s = sm.fork_gain_k1(b_, V), sm.fork_gain_k2(b_, V), math.sin(b_.lam)
    rng = np.random.default_rng(1)
    for phi, L, T in rng.normal(size=(5, 3)):
        delta = k1 * T - k2 * phi
        dx = S.A @ [phi, L] + S.B[:, 0] * T
        y = S.C @ [phi, L] + S.D[:, 0] * T
        assert dx[0] == pytest.approx((L + b_.D * V * s * delta / b_.b) / b_.J, rel=1e-9, abs=1e-12)
        assert dx[1] == pytest.approx(b_.m * b_.g * b_.h * phi + b_.m * (V**2 * b_.h - b_.a * b_.c * b_.g) * s / b_.b * delta,
                                      rel=1e-9, abs=1e-9)
        np.testing.assert_allclose(y, [phi, delta], rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("bike", [pytest.param(BIKE, id="table1"), pytest.param(NO_TRAIL_COND, id="large-trail"),
                                  pytest.param(SimpleBicycle(lam=math.radians(45)), id="lam45")])
@pytest.mark.parametrize("side", [pytest.param(1 + EPS, id="above-Vc"), pytest.param(1 - EPS, id="below-Vc"),
                                  pytest.param(0.5, id="half-Vc"), pytest.param(3.0, id="3xVc")])
def test_self_stabilization_boundary_eq16_eq17(bike, side):
    V = side * sm.critical_velocity(bike)
    expected = side > 1 and sm.trail_condition(bike)
    assert sm.is_self_stabilizing(bike, V) is expected
    assert stable(sm.self_stabilizing_tf(bike, V)) is expected
    assert bool(np.all(np.linalg.eigvals(sm.self_stabilizing_ss(bike, V).A).real < 0)) is expected


@settings(max_examples=60, deadline=None)
@given(m=st.floats(10, 200), a=st.floats(0.1, 1.2), h=st.floats(0.3, 1.5), b=st.floats(0.6, 1.5),
       c=st.floats(0.005, 0.3), lam_deg=st.floats(45, 89.5), V_factor=st.floats(0.05, 6.0))
def test_self_stabilization_property(m, a, h, b, c, lam_deg, V_factor):
    """(15) is stable iff V > V_c and (17), for random bicycles (J = m h^2, D = m a h)."""
    bike = SimpleBicycle.point_mass(m=m, a=a, h=h, b=b, c=c, lam=math.radians(lam_deg))
    margin = abs(b * h * math.cos(bike.lam) - a * c * math.sin(bike.lam)) / (b * h)
    assume(abs(V_factor - 1) > 1e-2 and margin > 1e-6)  # too close to a boundary to decide numerically
    V = V_factor * sm.critical_velocity(bike)
    poles = np.linalg.eigvals(sm.self_stabilizing_ss(bike, V).A)
    assert bool(np.all(poles.real < 0)) is sm.is_self_stabilizing(bike, V)


def test_gyroscopic_term_k3_reduces_and_adds_damping():
    V = 6.0
    np.testing.assert_allclose(sm.self_stabilizing_ss(BIKE, V, k3=0.0).A, sm.self_stabilizing_ss(BIKE, V).A)
    _, den0 = coeffs(sm.self_stabilizing_tf(BIKE, V))
    _, den1 = coeffs(sm.self_stabilizing_tf(BIKE, V, k3=0.1))
    assert den1[1] > den0[1]  # derivative feedback increases the damping (V^2 h > a c g)


# --------------------------------------------------------------------------- (20), (21), Figure 5

@pytest.mark.parametrize("bike", [pytest.param(BIKE, id="table1"), pytest.param(NO_TRAIL_COND, id="large-trail")])
@pytest.mark.parametrize("side", [pytest.param(1 + EPS, id="above-Vsa"), pytest.param(1 - EPS, id="below-Vsa")])
def test_frame_eq1_with_fork_stable_iff_above_Vsa(bike, side):
    """(1)+(11), the model of (20): stable iff V > V_sa; condition (17) plays no role."""
    V = side * sm.self_alignment_velocity(bike)
    assert stable(sm.steer_torque_tf(bike, V, frame="eq1")) is (side > 1)


@pytest.mark.parametrize("bike", BIKES[:3])
@pytest.mark.parametrize("V", [2.5, 4.0, 6.0, 10.0])
@pytest.mark.parametrize("frame", FRAMES)
def test_G_delta_T_eq20_equals_k1_over_1_plus_k2_G(bike, V, frame):
    k1, k2 = sm.fork_gain_k1(bike, V), sm.fork_gain_k2(bike, V)
    G = sm.roll_steer_tf(bike, V, frame=frame)
    ref = k1 * control.feedback(1, k2 * G)
    H = sm.steer_torque_tf(bike, V, frame=frame)
    assert_roots(control.poles(H), control.poles(control.minreal(ref, verbose=False)))
    assert control.dcgain(H) == pytest.approx(control.dcgain(ref), rel=1e-8)
    if frame == "eq1":  # (20) as printed
        J, D, b, m, h, g = bike.J, bike.D, bike.b, bike.m, bike.h, bike.g
        num, den = coeffs(H)
        np.testing.assert_allclose(num, [k1, 0, -k1 * m * g * h / J], rtol=1e-9, atol=1e-14)
        np.testing.assert_allclose(den, [1, k2 * D * V / (b * J), k2 * V**2 * m * h / (b * J) - m * g * h / J],
                                   rtol=1e-9)
    else:  # consistent version: poles of (15)
        assert_roots(control.poles(H), control.poles(sm.self_stabilizing_tf(bike, V)))


@pytest.mark.parametrize("V", [2.5, 6.0, 10.0])
def test_G_eta_T_eq21_as_printed(V):
    """(21) = G_eta_delta (20) when V_c^2 is read as b g / k2(V); not with V_c of (16)."""
    bike = BIKE
    k1, k2 = sm.fork_gain_k1(bike, V), sm.fork_gain_k2(bike, V)
    J, D, b, m, h, g = bike.J, bike.D, bike.b, bike.m, bike.h, bike.g
    num, den = coeffs(sm.path_torque_tf(bike, V))

    def printed_den(Vc2):
        return [1, k2 * V * D / (b * J), m * g * h / J * (V**2 / Vc2 - 1), 0, 0]
    np.testing.assert_allclose(num, [k1 * V**2 / b, 0, -k1 * V**2 / b * m * g * h / J], rtol=1e-9, atol=1e-14)
    np.testing.assert_allclose(den, printed_den(b * g / k2), rtol=1e-9, atol=1e-12)
    assert not np.allclose(den, printed_den(sm.critical_velocity(bike) ** 2), rtol=1e-3)


@pytest.mark.parametrize("bike", BIKES[:3])
@pytest.mark.parametrize("V", [2.5, 4.0, 6.0, 10.0])
@pytest.mark.parametrize("frame", FRAMES)
def test_figure5_inverse_response(bike, V, frame):
    """Positive torque step: eta first positive then negative; steady phi > 0, delta < 0."""
    G_eta = sm.path_torque_tf(bike, V, frame=frame)
    z = sm.pendulum_poles(bike)[0]
    assert max(control.zeros(G_eta).real) == pytest.approx(z, rel=1e-7)  # RHP zero sqrt(mgh/J)
    t = np.linspace(0, 20, 4001)
    _, eta = control.step_response(G_eta, t)
    assert eta[40] > 0          # t = 0.2 s
    assert eta[-1] < 0
    assert np.argmax(eta) < np.argmin(eta)
    S = sm.self_stabilizing_ss(bike, V, frame=frame)
    phi_ss, delta_ss = np.ravel(control.dcgain(S))
    assert phi_ss > 0 > delta_ss


def test_figure5_steady_state_table1_V6():
    """Modelica example SelfStabilizingTorqueStep: V = 6 m/s, T = 1 N m (model (14)+(11))."""
    phi, delta = np.ravel(control.dcgain(sm.self_stabilizing_ss(BIKE, 6.0)))
    m, a, b, c, g, h, lam = BIKE.m, BIKE.a, BIKE.b, BIKE.c, BIKE.g, BIKE.h, BIKE.lam
    bracket = b * h * math.cos(lam) - a * c * math.sin(lam)
    assert delta == pytest.approx(-b**2 * h / (m * a * c * g * math.sin(lam) * bracket), rel=1e-9)
    assert phi == pytest.approx(b * (36 * h - a * c * g) / (a * c * m * g**2 * bracket), rel=1e-9)


# --------------------------------------------------------------------------- (22), (23)

RIDER = SimpleBicycle(h=1.2, J=140.0, D=55.0, m_r=40.0, J_r=3.0, h_r=0.35)


@pytest.mark.parametrize("V", [2.5, 6.0, 10.0])
def test_leaning_rider_eq23(V):
    bike = RIDER
    S = sm.leaning_rider_ss(bike, V)
    assert S.input_labels == ["T", "theta"] and S.output_labels == ["phi", "delta"]
    k1, k2 = sm.fork_gain_k1(bike, V), sm.fork_gain_k2(bike, V)
    J, D, b, m, h, g = bike.J, bike.D, bike.b, bike.m, bike.h, bike.g
    den = [J, D * V * k2 / b, m * V**2 * h * k2 / b - m * g * h]
    num_T = [D * V * k1 / b, m * V**2 * h * k1 / b]      # (23) prints m V^2 k1 / b (no h)
    num_theta = [-bike.J_r, 0.0, bike.m_r * g * bike.h_r]
    for j, num in enumerate((num_T, num_theta)):
        G = sm._tf(num, den)
        Sj = S[0, j]
        assert_roots(np.linalg.eigvals(S.A), control.poles(G))
        assert control.dcgain(Sj) == pytest.approx(control.dcgain(G), rel=1e-8)
        assert control.ss2tf(Sj)(2.0 + 1.0j) == pytest.approx(G(2.0 + 1.0j), rel=1e-8)
    printed_T = sm._tf([D * V * k1 / b, m * V**2 * k1 / b], den)
    assert control.dcgain(printed_T) != pytest.approx(control.dcgain(S[0, 0]), rel=1e-3)
    # two actuators: B has full rank n = 2, so (sidebar) no invariant zeros from [T, theta]
    assert np.linalg.matrix_rank(S.B) == 2


@pytest.mark.parametrize("frame", FRAMES)
def test_leaning_rider_without_rider_is_self_stabilizing_model(frame):
    S2 = sm.leaning_rider_ss(BIKE, 6.0, frame=frame)
    S1 = sm.self_stabilizing_ss(BIKE, 6.0, frame=frame)
    np.testing.assert_allclose(S2.A, S1.A)
    np.testing.assert_allclose(S2.B[:, :1], S1.B)
    np.testing.assert_allclose(S2.B[:, 1], 0.0)


def test_k3_with_leaning_rider_rejected():
    with pytest.raises(ValueError, match="k3"):
        sm._frame_fork_ss(RIDER, 6.0, "eq1", 0.1)


# --------------------------------------------------------------------------- (27), p tau

@pytest.mark.parametrize("R", [pytest.param(R, id=f"R={R}") for R in (0.0, 0.2, 0.39, 0.41, 0.6, 2.0)])
def test_crowned_roller_eq27(R):
    bike = SimpleBicycle.point_mass(h=0.4, R=R)
    poles = sm.crowned_roller_poles(bike)
    expected = np.sqrt(complex(bike.m * bike.g * (bike.h - R) / bike.J))
    np.testing.assert_allclose(poles, [expected, -expected], rtol=REL)
    np.testing.assert_allclose(poles[0], np.sqrt(complex((1 - R / bike.h) * bike.g / bike.h)), rtol=REL)
    assert sm.crowned_roller_is_stable(bike) is (R > bike.h)
    assert bool(np.max(poles.real) <= 0) is (R > bike.h)
    if R == 0:
        np.testing.assert_allclose(poles.real, sm.pendulum_poles(bike), rtol=REL)


@pytest.mark.parametrize("pole,tau,rating", [
    (0.5, 0.2, "comfortable"), (0.99, 0.2, "comfortable"), (1.0, 0.2, "difficult"), (5.0, 0.2, "difficult"),
    (10.0, 0.2, "difficult"), (10.5, 0.2, "impossible"), (-3.0, 0.2, "comfortable"),
    (0.5 + 4j, 0.2, "comfortable"), (3.05, 0.2, "difficult"), (3.05, 1.0, "impossible"),
], ids=lambda v: str(v))
def test_manual_control_rating(pole, tau, rating):
    assert sm.manual_control_rating(pole, tau) == rating


@pytest.mark.parametrize("tau", [-0.1, float("nan")])
def test_manual_control_rating_bad_delay(tau):
    with pytest.raises(ValueError, match="tau"):
        sm.manual_control_rating(1.0, tau)


@pytest.mark.parametrize("V", [2.5, 3.13, 6.0, 10.0])
@pytest.mark.parametrize("frame", FRAMES)
def test_steady_roll_steer_ratio(V, frame):
    """phi/delta at steady state: -V^2/(bg) for (1)+(11), -(V^2 h - acg) sin(lam)/(bgh) for (14)+(11)."""
    b_ = BIKE
    phi, delta = np.ravel(control.dcgain(sm.self_stabilizing_ss(b_, V, frame=frame)))
    if frame == "eq1":
        expected = -V**2 / (b_.b * b_.g)
    else:
        expected = -(V**2 * b_.h - b_.a * b_.c * b_.g) * math.sin(b_.lam) / (b_.b * b_.g * b_.h)
    assert phi / delta == pytest.approx(expected, rel=1e-9)
