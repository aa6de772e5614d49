"""Figures 5 and 15: the numbers their captions state, checked against the FMUs.

Figure 5 (``cosim.figures.fig5``): the speed V and torque T at which the self-stabilizing bicycle
(14) + (11) settles to the paper's phi = 0.14, delta = -0.14 rad are solved in closed form from the
static gains; checked here against the DC gain of the state-space model (relative 1e-10), as an
inverse (relative 1e-12), and by simulating the FMU ``Bicycle.Bicycles.SelfStabilizing`` for 10 s
(end values within 1e-5 rad of the analytic steady state, 2e-4 rad for the slower comparison case;
``cosim figures fig5`` reports 0.14 / -0.14 to two digits in ``fig5.json``).

Figure 15 (``cosim.figures.fig15``): its roller model (a roll-torque feedback on the linear Whipple
FMU) is the linearization of an exact toroidal rear wheel: the nonlinear Whipple FMU with crown
radius tR = R has the same lateral state matrix at several speeds (relative 1e-12) and, by an
independent root finder on its own linearizations, the figure's weave speeds to 5e-5 m/s. Its
adapted bicycle (cosim/params/adapted/fig15.toml, the app's crowned roller too) reproduces the
paper's statements: weave speed 3.9 m/s to the paper's digit (|v_w - 3.9| < 0.05 m/s) for both
radii, the FMU's weave speed equal to cosim.analytic.roller's (relative 1e-6), the capsize mode
stable at every speed (no real root crosses zero, exactly; none below 200 m/s in the FMU), and the
real parts inside Fig. 9's at every speed from 0 to 12 m/s.
"""
from __future__ import annotations

import json
import math
import os

import control
import numpy as np
import pytest
from conftest import run_cli
from scipy.optimize import brentq

from cosim.analytic import roller
from cosim.analytic import simple as S
from cosim.analytic import whipple as W
from cosim.compiler.build import build_model
from cosim.figures import fig5, fig15
from cosim.bicycle import stability as WP
from cosim.bicycle.linearize import steady_motion
from cosim.fmu.linearize import linearize
from cosim.nonlinear.model import MODEL as WHIPPLE
from cosim.nonlinear.model import speed_parameters

# the quick run (-m 'not slow') leaves this module out: its tests build, compile or run FMUs
pytestmark = pytest.mark.slow


def _build(model):
    return build_model(model, os.environ["COSIM_FMU_DIR"]).fmu  # conftest: a temporary or the developer's folder


@pytest.fixture(scope="module")
def self_stabilizing():
    return _build(fig5.MODEL)


@pytest.fixture(scope="module")
def whipple_linear():
    return _build(WP.MODEL)


@pytest.fixture(scope="module")
def whipple():
    return _build(WHIPPLE)


# --------------------------------------------------------------------------- Figure 5: analytic

TARGETS = {"paper 0.14/-0.14": (0.14, -0.14), "0.05/-0.02": (0.05, -0.02), "-0.3/0.1": (-0.3, 0.1)}


@pytest.mark.parametrize("phi, delta", TARGETS.values(), ids=TARGETS)
def test_operating_point_inverts_steady_state(phi, delta):
    V, T = fig5.operating_point(phi, delta)
    assert V > S.critical_velocity(S.SimpleBicycle())
    assert fig5.steady_state(V, T) == pytest.approx((phi, delta), rel=1e-12)


SPEEDS = {"2.5 m/s": 2.5, "paper's V": None, "4 m/s": 4.0, "8 m/s": 8.0}


@pytest.mark.parametrize("V", SPEEDS.values(), ids=SPEEDS)
def test_steady_state_is_dc_gain_of_the_model(V):
    """The closed-form static gains of (15) and (11) equal the DC gain of the state-space model of
    (14) + (11) (``cosim.analytic.simple.self_stabilizing_ss``, outputs phi and delta)."""
    V = V if V is not None else fig5.paper_operating_point()[0]
    T = 1.3
    dc = np.asarray(control.dcgain(S.self_stabilizing_ss(S.SimpleBicycle(), V))).ravel() * T
    assert fig5.steady_state(V, T) == pytest.approx(tuple(dc), rel=1e-10)


def test_paper_operating_point():
    """The stated V, T of Figure 5 give the paper's values: by the DC gain of the state-space model
    (independent of the closed form) and to the two digits the paper prints."""
    V, T = fig5.paper_operating_point()
    assert S.critical_velocity(S.SimpleBicycle()) < V < 10.0 and 0.0 < T < 10.0
    dc = np.asarray(control.dcgain(S.self_stabilizing_ss(S.SimpleBicycle(), V))).ravel() * T
    assert tuple(dc) == pytest.approx((fig5.PAPER_PHI, fig5.PAPER_DELTA), rel=1e-10)
    phi, delta = fig5.steady_state(V, T)
    assert (round(phi, 2), round(delta, 2)) == (0.14, -0.14)


BAD = {
    "phi zero": ((0.0, -0.1), "phi != 0"),
    "same signs": ((0.14, 0.14), "opposite sign"),
    "below V_c": ((0.01, -1.0), "no stable steady state"),
    "not finite": ((math.nan, -0.1), "must be finite"),
}


@pytest.mark.parametrize("target, message", BAD.values(), ids=BAD)
def test_operating_point_refuses(target, message):
    with pytest.raises(ValueError, match=message):
        fig5.operating_point(*target)


def test_steady_state_refuses_unstable_speed():
    with pytest.raises(ValueError, match="V_c"):
        fig5.steady_state(1.5, 1.0)


# --------------------------------------------------------------------------- Figure 5: FMU

CASES = {"paper's V, T": (None, None, 1e-5), "V = 4, T = 1": (fig5.COMPARISON_SPEED, fig5.COMPARISON_TORQUE, 2e-4)}


@pytest.mark.parametrize("V, T, tol", CASES.values(), ids=CASES)
def test_fmu_settles_to_analytic_steady_state(self_stabilizing, V, T, tol):
    """The figure's simulation (the FMU's Co-Simulation) ends at the analytic steady state; the
    tolerance covers the transient left after 10 s (decay rates 1.06 and 0.76 1/s)."""
    if V is None:
        V, T = fig5.paper_operating_point()
    r = fig5.simulate_fig5(self_stabilizing, V, T)
    assert r["time"][-1] == pytest.approx(fig5.STOP)
    expected = fig5.steady_state(V, T)
    for name, value in zip(("phi", "delta"), expected):
        assert abs(r[name][-1] - value) <= tol, f"{name}: {r[name][-1]!r} vs {value!r}"
        late = r[name][r["time"] >= fig5.STOP - 2.0]
        assert np.ptp(late) <= 10 * tol, f"{name} has not settled in the last 2 s"
    assert r["eta"][:100].max() > 0.0 > r["eta"][-1]  # the inverse response


def test_fig5_command_reports_paper_values(tmp_path):
    result = run_cli("figures", "fig5", "-o", str(tmp_path))
    assert result.returncode == 0, result.stderr
    assert f"wrote {tmp_path / 'fig5.json'}" in result.stdout
    data = json.loads((tmp_path / "fig5.json").read_text())
    case = data["cases"][0]
    V, T = fig5.paper_operating_point()
    assert case["speed_m_s"] == pytest.approx(V, rel=1e-12) and case["torque_N_m"] == pytest.approx(T, rel=1e-12)
    settled = case["settled_rad"]
    assert (f"{settled['phi']:.2f}", f"{settled['delta']:.2f}") == ("0.14", "-0.14")
    for name, value in zip(("phi", "delta"), fig5.steady_state(V, T)):
        assert case["steady_state_rad"][name] == pytest.approx(value, rel=1e-12)
        assert abs(settled[name] - value) <= 1e-5


# --------------------------------------------------------------------------- Figure 15

RADII = {f"R = {R:g} m": R for R in fig15.ROLLER_RADII}


def _torus_lateral_matrix(fmu, params, radius, v):
    sm = steady_motion(linearize(fmu, speed_parameters({**params, "tR": radius, "tF": 0.0}, v)))
    assert sm.system.states == ["phi", "delta", "u_phi", "u_delta"]
    return sm.system.A


def _torus_weave_speed(fmu, params, radius):
    """Root of the largest real part of the oscillatory eigenvalues of the torus FMU's lateral
    dynamics: first sign change + -> - on a 0.25 m/s grid from 0.5 to 15 m/s, then brentq."""
    def weave_real(v):
        ev = np.linalg.eigvals(_torus_lateral_matrix(fmu, params, radius, v))
        osc = ev[WP.oscillatory(ev)]
        return float(osc.real.max()) if osc.size else math.nan

    grid = np.arange(0.5, 15.0 + 1e-9, 0.25)
    values = [weave_real(v) for v in grid]
    for a, b, fa, fb in zip(grid, grid[1:], values, values[1:]):
        if fa > 0.0 >= fb:
            return brentq(weave_real, a, b, xtol=1e-10)
    raise AssertionError(f"no weave speed on the grid: {values}")


@pytest.mark.parametrize("radius", RADII.values(), ids=RADII)
def test_torus_rear_wheel_has_the_roller_state_matrix(whipple, whipple_linear, radius):
    """Both blocks of A are polynomials in v (constant and v^2; v): equal at four speeds means
    equal M, C1, K0, K2."""
    p = fig15.adapted_parameters()
    k = fig15.roller_stiffness(p, radius)
    for v in (0.0, 2.0, 5.0, 8.0):
        roller = WP.state_matrix(whipple_linear, p, v, k)
        torus = _torus_lateral_matrix(whipple, p, radius, v)
        assert np.abs(torus - roller).max() <= 1e-12 * np.abs(roller).max(), f"v = {v} m/s"


@pytest.mark.parametrize("radius", RADII.values(), ids=RADII)
def test_torus_rear_wheel_reproduces_fig15_weave_speeds(whipple, whipple_linear, radius):
    p = fig15.adapted_parameters()
    figure, _ = fig15.critical_speeds(whipple_linear, p, radius)
    torus = _torus_weave_speed(whipple, p, radius)
    assert round(torus, 4) == round(figure, 4) and abs(torus - figure) <= 5e-5, (torus, figure)
    knife_edge, _ = fig15.critical_speeds(whipple_linear, p, 0.0)
    assert abs(torus - knife_edge) > 0.1  # the crown radius matters: the comparison can fail


PAPER_WEAVE, WEAVE_DIGIT = 3.9, 0.05  # m/s: "the weave mode becomes stable at 3.9 m/s", to its digit


@pytest.mark.parametrize("radius", RADII.values(), ids=RADII)
def test_adapted_bicycle_reproduces_the_papers_statements(whipple_linear, radius):
    p = fig15.adapted_parameters()
    assert p == roller.adapted_parameters()  # one bicycle for the figure and the app
    weave, capsize = fig15.critical_speeds(whipple_linear, p, radius)
    assert weave == pytest.approx(roller.weave_speed(p, radius), rel=1e-6)
    assert abs(weave - PAPER_WEAVE) < WEAVE_DIGIT, weave
    assert capsize is None and roller.capsize_speed(p, radius) is None
    assert roller.capsize_speed(p, 0.0) is not None  # the knife edge capsizes: the check can fail
    speeds = np.linspace(0.0, 12.0, 241)
    ours, fig9 = roller.eigenvalues(p, radius, speeds).real, W.eigenvalues(fig15.parameters_for_model(fig15.FIG9), speeds).real
    assert np.all(ours.max(axis=1) < fig9.max(axis=1)) and np.all(ours.min(axis=1) > fig9.min(axis=1))
