"""The simple bicycle models of Åström, Klein & Lennartsson (2005) as FMUs, against their analytic
twins (:mod:`cosim.analytic.twins`, built on :mod:`cosim.analytic.simple`).

* each simple bicycle is exported and has a twin whose parameters, inputs and outputs are the FMU's;
* short simulations in Co-Simulation and Model Exchange equal the exact (matrix exponential)
  response of the twin;
* the FMU linearized at several speeds has the twin's poles, zeros and gain in every
  input -> output transfer function (relative error <= 1e-9);
* the paper's stability statements hold for the FMU linearizations: (6), (15)-(17), (19), (27);
* Figure 5: the inverse path response of the self-stabilizing bicycle to a steer-torque step.

Closed loops (the proportional steering delta = -k2 phi of (5), (6), (19)) are formed in Python
with ``control.feedback`` from the FMU's linearized open loop, restricted to the roll subsystem
(the path states psi and eta integrate the steer angle and do not act back on the roll dynamics,
which is checked; their two eigenvalues at the origin are not part of the paper's stability
statements).
"""
from __future__ import annotations

import json
import math
import os

import control
import numpy as np
import pytest
from scipy.linalg import expm

from conftest import run_cli
from reference import SELF_STABILIZING_DEFAULTS as PAPER
from cosim.analytic import simple
from cosim.analytic.compare import minimal_zpk, root_set_error as root_error
from cosim.fmu.linearize import linearize
from cosim.fmu.simulate import simulate
from cosim.analytic.twins import TWINS
from cosim.bicycle.twins import analytic_system

PKG = "Bicycle.Bicycles."

# Tolerances
LIN_RTOL = 1e-9  # poles, zeros, gains of linearization vs twin (exact Jacobians: rounding only)
CS_ATOL = 1e-8  # CS (own Dormand-Prince 5(4) at the model tolerance 1e-8), times the largest |signal|
ME_ATOL = 1e-5  # ME (FMPy's CVode), times the largest |signal|
SIM_STOP, SIM_STEP = 2.0, 0.01

V_C = simple.critical_velocity(simple.SimpleBicycle())  # (16), 1.89 m/s for the Table 1 bicycle

#: Speeds [m/s] of the linearization sweeps: below and above V_c, and negative (reversed).
SPEEDS = {
    "SelfStabilizing": [0.8, 1.5, 2.5, 4.0, 6.0, 10.0, -3.0],
    "SelfStabilizingGyro": [0.8, 1.5, 2.5, 4.0, 6.0, 10.0, -3.0],
    "LeaningRider": [0.8, 1.5, 2.5, 4.0, 6.0, 10.0, -3.0],
    # V = 0: the steer angle no longer drives the roll, but the pendulum still falls (the twin keeps
    # the roll states, so the eigenvalues of A compare)
    "InvertedPendulum": [0.0, 0.5, 1.0, 2.5, 5.0, 10.0, -4.0],
    "RearSteered": [0.0, 0.5, 1.0, 2.5, 5.0, 10.0, -4.0],
    "CrownedRoller": [0.0, 0.5, 1.0, 2.5, 5.0, 10.0],
}
#: Further parameter variations per model (each combined with every speed).
VARIANTS = {
    "SelfStabilizing": [{}, {"lambda": math.radians(80), "c": 0.05, "a": 0.3}],
    "SelfStabilizingGyro": [{}, {"k3": 0.0}, {"k3": 0.3}],
    "LeaningRider": [{}, {"m_r": 10.0, "J_r": 2.0, "h_r": 0.0}],
    "InvertedPendulum": [{}, {"h": 0.6, "J": 40.0, "D": 20.0}],
    "RearSteered": [{}],
    "CrownedRoller": [{}, {"R": 1.5}, {"R": 0.0}],
}
#: Constant inputs (from t = 0) and parameters of the simulation checks.
SIM_CASES = {
    "SelfStabilizing": ({"V": 6.0}, {"T": 1.0}),
    "SelfStabilizingGyro": ({"V": 4.0, "k3": 0.1}, {"T": 1.0}),
    "LeaningRider": ({"V": 6.0}, {"T": 0.5, "theta": 0.05}),
    "InvertedPendulum": ({"V": 5.0}, {"delta": 0.01}),
    "RearSteered": ({"V": 5.0}, {"delta": 0.01}),
    "CrownedRoller": ({"V": 3.0, "R": 1.3}, {"delta": 0.01}),
}
MODELS = [PKG + name for name in SPEEDS]  # the simple bicycles of the paper
IDS = list(SPEEDS)


# ----------------------------------------------------------------------------
# helpers

def lin_ss(fmu, parameters: dict) -> control.StateSpace:
    """The FMU's linearization as a python-control StateSpace."""
    result = linearize(fmu, parameters)
    return result.to_statespace() if hasattr(result, "to_statespace") else result


def compare(found: control.StateSpace, expected: control.StateSpace) -> dict:
    """Errors of the eigenvalues of A and of every input -> output pair (poles, zeros, gain)."""
    errors = {"eigenvalues": root_error(np.linalg.eigvals(found.A), np.linalg.eigvals(expected.A))}
    for u in expected.input_labels:
        for y in expected.output_labels:
            i, o = list(found.input_labels).index(u), list(found.output_labels).index(y)
            ei, eo = list(expected.input_labels).index(u), list(expected.output_labels).index(y)
            z, p, k = minimal_zpk(found[o, i])
            ez, ep, ek = minimal_zpk(expected[eo, ei])
            gain = 0.0 if k == ek else abs(k - ek) / max(abs(ek), 1e-300)
            errors[f"{u}->{y}"] = max(root_error(p, ep), root_error(z, ez), gain)
    return errors


def roll_subsystem(sys: control.StateSpace) -> control.StateSpace:
    """The states other than path.psi, path.eta, with input/output names kept.

    Checks that the path states do not act on the roll dynamics or on phi and delta."""
    states = list(sys.state_labels)
    path = [k for k, s in enumerate(states) if s.startswith("path.")]
    roll = [k for k, s in enumerate(states) if not s.startswith("path.")]
    assert len(path) == 2 and len(roll) == 2, states
    assert np.all(sys.A[np.ix_(roll, path)] == 0)
    outputs = [k for k, y in enumerate(sys.output_labels) if y in ("phi", "delta")]
    assert np.all(sys.C[np.ix_(outputs, path)] == 0)
    return control.ss(sys.A[np.ix_(roll, roll)], sys.B[roll], sys.C[np.ix_(outputs, roll)], sys.D[outputs],
                      inputs=list(sys.input_labels), outputs=[sys.output_labels[k] for k in outputs],
                      states=[states[k] for k in roll])


def steer_feedback_poles(fmu, V: float, k2: float) -> np.ndarray:
    """Roll poles of the FMU's roll subsystem closed by delta = -k2 phi (5) (python-control feedback)."""
    roll = roll_subsystem(lin_ss(fmu, {"V": V}))
    closed = control.feedback(roll["phi", "delta"], k2)
    return np.linalg.eigvals(closed.A)


def step_response(sys: control.StateSpace, u: np.ndarray, times: np.ndarray) -> np.ndarray:
    """Exact response from rest to the constant input u: y(t) = C x(t) + D u (rows: times)."""
    n = sys.nstates
    M = np.zeros((n + 1, n + 1))
    M[:n, :n], M[:n, n] = sys.A, sys.B @ u
    out = []
    for t in times:
        x = (expm(M * t) @ np.r_[np.zeros(n), 1.0])[:n]
        out.append(sys.C @ x + sys.D @ u)
    return np.array(out)


# ----------------------------------------------------------------------------
# the twins and the FMUs' interfaces

def test_every_simple_bicycle_is_exported_and_has_a_twin(fmus):
    assert set(MODELS) <= set(fmus) and set(MODELS) <= set(TWINS)
    assert set(TWINS) <= set(fmus)


@pytest.mark.parametrize("model", MODELS, ids=IDS)
def test_twin_matches_fmu_interface(fmus, model):
    """Twin defaults, inputs and outputs are the FMU's top-level parameters, inputs and outputs."""
    from fmpy import read_model_description

    md = read_model_description(str(fmus[model]))
    variables = [v for v in md.modelVariables if "." not in v.name]
    parameters = {v.name: float(v.start) for v in variables if v.causality == "parameter"}
    assert parameters == TWINS[model].defaults
    assert tuple(v.name for v in variables if v.causality == "input") == TWINS[model].inputs
    assert tuple(v.name for v in variables if v.causality == "output") == TWINS[model].outputs
    sys = analytic_system(model, {})
    assert tuple(sys.input_labels) == TWINS[model].inputs
    assert tuple(sys.output_labels) == TWINS[model].outputs
    assert sys.nstates == len([v for v in md.modelVariables if v.derivative is not None])


@pytest.mark.parametrize("model", MODELS, ids=IDS)
def test_parameters_are_bounded(fmus, model):
    """Every top-level parameter except the speed and an initial value carries a minimum; lambda is
    at most 90 deg; no speed has a bound (negative: ridden backwards, the rear-steered bicycle too)."""
    from fmpy import read_model_description

    md = read_model_description(str(fmus[model]))
    params = {v.name: v for v in md.modelVariables if v.causality == "parameter" and "." not in v.name}
    for name, v in params.items():
        if name in ("V", "phi0"):
            continue
        assert v.min is not None and float(v.min) >= 0, f"{model}.{name} has no minimum"
    for name in ("m", "a", "h", "b", "c", "J", "D", "g", "m_r", "J_r"):
        if name in params:
            assert float(params[name].min) > 0, f"{model}.{name} must be strictly positive"
    if "lambda" in params:
        assert float(params["lambda"].max) == pytest.approx(math.pi / 2, rel=1e-15)
    assert params["V"].min is None and params["V"].max is None, f"{model}.V is bounded"


@pytest.mark.parametrize("model,name,value,word", [
    (PKG + "SelfStabilizing", "b", "0", "minimum"),
    (PKG + "SelfStabilizing", "lambda", "2", "maximum"),
    (PKG + "RearSteered", "D", "0", "minimum"),
    (PKG + "CrownedRoller", "R", "-0.1", "minimum"),
    (PKG + "LeaningRider", "J_r", "0", "minimum"),
], ids=["b=0", "lambda=2", "rear-D=0", "R<0", "J_r=0"])
def test_cli_refuses_out_of_range_parameters(fmus, tmp_path, model, name, value, word):
    result = run_cli("simulate", str(fmus[model]), "--stop-time", "0.1", "--param", f"{name}={value}",
                     "-o", str(tmp_path / "out.csv"))
    assert result.returncode != 0
    assert f"'{name}'" in result.stderr and word in result.stderr, result.stderr
    assert not (tmp_path / "out.csv").exists()


def _at(points, G1, G2):
    return max(abs(G1(s) - G2(s)) / abs(G2(s)) for s in points)


@pytest.mark.parametrize("V", [0.8, 3.0, 6.0], ids=lambda v: f"V={v}")
def test_twins_are_the_papers_transfer_functions(V):
    """The twins' transfer functions are those of simple.py: (4), G_eta_delta, (15), (21), (27)."""
    points = [0.3, 1.1j, -2 + 0.7j, 5 + 5j]
    bike = simple.SimpleBicycle()
    ip = analytic_system(PKG + "InvertedPendulum", {"V": V})
    assert _at(points, ip["phi", "delta"], simple.roll_steer_tf(bike, V, "eq1")) < 1e-12
    assert _at(points, ip["eta", "delta"], simple.path_steer_tf(bike, V, "eq1")) < 1e-12
    rs = analytic_system(PKG + "RearSteered", {"V": V})  # (18) at the forward speed V, the rider's signs
    assert _at(points, rs["phi", "delta"], simple.rear_steer_roll_steer_tf(bike, V)) < 1e-12
    assert _at(points, rs["eta", "delta"], simple.path_steer_tf(bike, V, "eq1")) < 1e-12
    ss = analytic_system(PKG + "SelfStabilizing", {"V": V})
    assert _at(points, ss["phi", "T"], simple.self_stabilizing_tf(bike, V)) < 1e-12
    assert _at(points, ss["delta", "T"], simple.steer_torque_tf(bike, V, "eq14")) < 1e-12
    assert _at(points, ss["eta", "T"], simple.path_torque_tf(bike, V, "eq14")) < 1e-12
    gy = analytic_system(PKG + "SelfStabilizingGyro", {"V": V, "k3": 0.2})
    assert _at(points, gy["phi", "T"], simple.self_stabilizing_tf(bike, V, k3=0.2)) < 1e-12
    cr = analytic_system(PKG + "CrownedRoller", {"V": V, "R": 0.4})
    poles = simple.crowned_roller_poles(simple.SimpleBicycle(R=0.4))
    assert root_error(minimal_zpk(cr["phi", "delta"])[1], poles) < 1e-12


def test_twin_rejects_bad_parameters():
    with pytest.raises(ValueError, match="unknown parameter"):
        analytic_system(PKG + "SelfStabilizing", {"speed": 3.0})
    with pytest.raises(ValueError, match="b must be > 0"):
        analytic_system(PKG + "InvertedPendulum", {"b": 0.0})
    with pytest.raises(ValueError, match="self-alignment"):
        analytic_system(PKG + "SelfStabilizing", {"V": V_C})
    with pytest.raises(KeyError, match="no analytic twin"):
        analytic_system("Bicycle.Bicycles.Unicycle", {})


# ----------------------------------------------------------------------------
# simulation against the twin

@pytest.mark.parametrize("kind,atol", [("cs", CS_ATOL), ("me", ME_ATOL)], ids=["cs", "me"])
@pytest.mark.parametrize("model", MODELS, ids=IDS)
def test_simulation_matches_twin(fmus, model, kind, atol):
    """Constant inputs from rest for 2 s: every output equals the twin's exact response to
    atol times the largest |value| of that output (CS 1e-8 at tolerance 1e-8; ME 1e-5)."""
    params, inputs = SIM_CASES[model.removeprefix(PKG)]
    twin = analytic_system(model, params)
    result = simulate(fmus[model], SIM_STOP, SIM_STEP, kind, {**params, **inputs},
                      outputs=list(twin.output_labels))
    u = np.array([inputs[n] for n in twin.input_labels])
    expected = step_response(twin, u, result["time"])
    for k, name in enumerate(twin.output_labels):
        scale = max(np.max(np.abs(expected[:, k])), 1e-12)
        np.testing.assert_allclose(result[name], expected[:, k], rtol=0, atol=atol * scale, err_msg=name)


# ----------------------------------------------------------------------------
# linearization against the twin

LIN_CASES = [(PKG + name, V, variant)
             for name, speeds in SPEEDS.items() for variant in VARIANTS[name] for V in speeds]


def _lin_id(case):
    model, V, variant = case
    extra = ",".join(f"{k}={v:g}" for k, v in variant.items())
    return f"{model.removeprefix(PKG)}-V={V:g}" + (f"-{extra}" if extra else "")


@pytest.mark.parametrize("case", LIN_CASES, ids=[_lin_id(c) for c in LIN_CASES])
def test_linearization_matches_twin(fmus, case):
    """Poles, zeros and gain of every input -> output transfer function (minimal realizations)
    and the eigenvalues of A agree with the twin to 1e-9 relative."""
    model, V, variant = case
    params = {**variant, "V": V}
    found, expected = lin_ss(fmus[model], params), analytic_system(model, params)
    assert tuple(found.input_labels) == tuple(expected.input_labels)
    assert tuple(found.output_labels) == tuple(expected.output_labels)
    errors = compare(found, expected)
    worst = max(errors, key=errors.get)
    assert errors[worst] <= LIN_RTOL, f"{worst}: relative error {errors[worst]:.2e} ({errors})"


@pytest.mark.parametrize("model", ["InvertedPendulum", "RearSteered", "CrownedRoller"])
def test_compare_at_standstill(fmus, model):
    """`cosim compare` at V = 0, where the transfer functions from the steer angle vanish: the
    eigenvalues of A (the falling pendulum and the path's integrators) still agree."""
    result = run_cli("compare", PKG + model, "--speeds", "0,2", "--json")
    assert result.returncode == 0, result.stderr
    errors = [row["eigenvalue_error"] for row in json.loads(result.stdout)["comparisons"]]
    assert len(errors) == 2 and max(errors) <= LIN_RTOL, errors


# ----------------------------------------------------------------------------
# stability statements of the paper, from FMU linearizations

@pytest.mark.parametrize("V", [1.5, 3.0, 5.0, 8.0], ids=lambda v: f"V={v}")
def test_eq6_proportional_steering(fmus, V):
    """(6): the inverted pendulum (1) with delta = -k2 phi is stable iff k2 > b g / V^2."""
    k_crit = simple.critical_steer_gain(simple.SimpleBicycle(), V)
    for factor in (0.0, 0.5, 0.9, 0.99, 1.01, 1.1, 2.0, 10.0):
        poles = steer_feedback_poles(fmus[PKG + "InvertedPendulum"], V, factor * k_crit)
        assert (np.max(poles.real) < 0) == (factor > 1), (factor, poles)


def test_eq15_to_17_self_stabilization(fmus):
    """(15) is stable iff V > V_c (16) and b h > a c tan(lambda) (17)."""
    fmu = fmus[PKG + "SelfStabilizing"]
    for V in (-3.0, 0.3, 1.0, 1.5, 0.99 * V_C, 1.01 * V_C, 2.5, 4.0, 6.0, 10.0, 20.0):
        poles = np.linalg.eigvals(roll_subsystem(lin_ss(fmu, {"V": V})).A)
        assert (np.max(poles.real) < 0) == (V > V_C), (V, poles)
    # (17): b h = a c tan(lambda) at lambda_17 = atan(b h / (a c)) = 87.7 deg for the Table 1 bicycle.
    lambda_17 = math.atan(1.0 * 1.0 / (0.5 * 0.08))
    for lam, stable in ((lambda_17 - math.radians(0.5), True), (lambda_17 + math.radians(0.5), False)):
        bike = simple.SimpleBicycle(lam=lam)
        assert simple.trail_condition(bike) == stable
        for V in (2.0, 6.0, 20.0):
            assert V > simple.critical_velocity(bike)
            poles = np.linalg.eigvals(roll_subsystem(lin_ss(fmu, {"V": V, "lambda": lam})).A)
            assert (np.max(poles.real) < 0) == stable, (lam, V, poles)


def test_eq19_rear_steering_is_unstable(fmus):
    """(19): the rear-steered bicycle with delta = -k2 phi is unstable for every k2 > 0 at every
    forward speed V > 0 (the model's own V)."""
    fmu = fmus[PKG + "RearSteered"]
    for speed in (0.5, 2.0, 5.0, 10.0, 20.0):
        for k2 in np.logspace(-3, 3, 13):
            poles = steer_feedback_poles(fmu, speed, k2)
            assert np.max(poles.real) > 0, (speed, k2, poles)


@pytest.mark.parametrize("V", [1.0, 3.0, 5.0, 9.0], ids=lambda v: f"V={v}")
def test_eq18_rear_steering_in_the_riders_signs(fmus, V):
    """(18) from the FMU at the forward speed V > 0, with the numbers written out from the paper's
    formulas: the right-half-plane pole sqrt(m g h / J) = 3.055 1/s and zero m V h / D, the gain
    -V D / (b J) (a left steer step first rolls the bicycle to the rider's left), the ratio z/p
    printed after (19); the path turns to the rider's left: G_psi_delta = V / (b s),
    G_eta_delta = V^2 / (b s^2)."""
    m, h, b, J, D, g = (PAPER[k] for k in ("m", "h", "b", "J", "D", "g"))
    lin = lin_ss(fmus[PKG + "RearSteered"], {"V": V})
    z, p, k = minimal_zpk(lin["phi", "delta"])
    pole, zero = math.sqrt(m * g * h / J), m * V * h / D
    assert pole == pytest.approx(3.055, abs=5e-4)
    assert root_error(p, [pole, -pole]) < 1e-12 and root_error(z, [zero]) < 1e-12
    assert k == pytest.approx(-V * D / (b * J), rel=1e-12)
    assert zero / pole == pytest.approx(simple.rear_steer_zero_pole_ratio(simple.SimpleBicycle(), V), rel=1e-12)
    for name, order, gain in (("psi", 1, V / b), ("eta", 2, V**2 / b)):
        z, p, k = minimal_zpk(lin[name, "delta"])
        assert len(z) == 0 and len(p) == order and np.all(np.abs(p) < 1e-12), (name, z, p)
        assert k == pytest.approx(gain, rel=1e-12), name


@pytest.mark.parametrize("V", [2.0, 5.0], ids=lambda v: f"V={v}")
def test_rear_steered_ridden_backwards_is_model_1(fmus, V):
    """Reversing the velocity once more: the rear-steered bicycle at V < 0 rolls as the front-steered
    bicycle (1) at -V (InvertedPendulum FMU), FMU against FMU; its forward speed is what makes it hard."""
    rear = minimal_zpk(lin_ss(fmus[PKG + "RearSteered"], {"V": -V})["phi", "delta"])
    front = minimal_zpk(lin_ss(fmus[PKG + "InvertedPendulum"], {"V": V})["phi", "delta"])
    assert root_error(rear[0], front[0]) < 1e-12 and root_error(rear[1], front[1]) < 1e-12
    assert rear[2] == pytest.approx(front[2], rel=1e-12) and front[0][0] < 0  # zero -m V h / D (3)


@pytest.mark.parametrize("h", [1.0, 0.4], ids=["h=1", "h=0.4"])
def test_eq27_crowned_rollers(fmus, h):
    """(27): with the steer angle held, the roll poles are +-sqrt(m g (h - R) / J): one unstable
    real pole for R < h, an undamped (imaginary) pair for R > h."""
    fmu = fmus[PKG + "CrownedRoller"]
    J = PAPER["J"] if h == 1.0 else 30.0
    for R in (0.0, 0.5 * h, 0.9 * h, 0.999 * h, 1.001 * h, 1.2 * h, 2.0 * h, 5.0 * h):
        roll = roll_subsystem(lin_ss(fmu, {"V": 3.0, "h": h, "J": J, "R": R}))
        poles = np.linalg.eigvals(roll.A)
        expected = simple.crowned_roller_poles(simple.SimpleBicycle(h=h, J=J, R=R))
        assert root_error(poles, expected) < 1e-12
        if R < h:
            assert np.max(poles.real) > 0 and not simple.crowned_roller_is_stable(simple.SimpleBicycle(h=h, R=R))
        else:
            assert np.all(np.abs(poles.real) <= 1e-12 * np.abs(poles)), poles
            assert simple.crowned_roller_is_stable(simple.SimpleBicycle(h=h, R=R))


# ----------------------------------------------------------------------------
# Figure 5

@pytest.mark.parametrize("V", [4.0, 6.0], ids=lambda v: f"V={v}")
def test_figure5_inverse_path_response(fmus, V):
    """A constant positive steer torque: eta first positive then negative; roll and steer settle
    to the twin's steady state, roll positive and steer negative (opposite signs)."""
    fmu = fmus[PKG + "SelfStabilizing"]
    result = simulate(fmu, 30.0, 0.01, "cs", {"V": V, "T": 1.0}, outputs=["phi", "delta", "eta"])
    t, eta = result["time"], result["eta"]
    first = np.argmax(np.abs(eta) > 1e-9)
    assert eta[first] > 0, "eta must start positive"
    assert np.max(eta) > 0 and eta[-1] < 0
    crossing = t[np.argmax((t > t[first]) & (eta < 0))]
    assert 0 < crossing < 5.0
    bike = simple.SimpleBicycle()  # steady state of (15) and of G_delta_T, per unit torque
    dc = np.array([control.dcgain(simple.self_stabilizing_tf(bike, V)),
                   control.dcgain(simple.steer_torque_tf(bike, V, "eq14"))])
    assert dc[0] > 0 > dc[1]
    np.testing.assert_allclose([result["phi"][-1], result["delta"][-1]], dc, rtol=2e-2)
    assert result["phi"][-1] > 0 > result["delta"][-1]


# ----------------------------------------------------------------------------
# the examples run what their documentation says

EXAMPLES = ["SelfStabilizingTorqueStep", "SelfStabilizingGyroRecovery", "InvertedPendulumSteerFeedback",
            "RearSteeredSteerFeedback", "LeaningRiderLean", "CrownedRollerRocking"]


@pytest.fixture(scope="module")
def example_runs():
    """Each example built (into the session's FMU folder, so a kept COSIM_TEST_FMU_DIR reuses
    them) and run over its experiment (CS): name -> result."""
    from cosim.compiler.build import build

    results = build([f"Bicycle.Examples.{n}" for n in EXAMPLES], output=os.environ["COSIM_FMU_DIR"], jobs=2)
    signals = ["bicycle.phi", "bicycle.psi", "bicycle.eta"]
    return {r.model.removeprefix("Bicycle.Examples."): simulate(r.fmu, fmi_type="cs", outputs=signals)
            for r in results}


def _tail(result, name, seconds):
    return result[name][result["time"] >= result["time"][-1] - seconds]


@pytest.mark.parametrize("example", EXAMPLES)
def test_example(example_runs, example):
    r = example_runs[example]
    phi = r["bicycle.phi"]
    if example == "SelfStabilizingTorqueStep":  # Figure 5 at 6 m/s, T = 1 N m
        assert np.max(r["bicycle.eta"]) > 0 > r["bicycle.eta"][-1] and phi[-1] > 0
    elif example in ("SelfStabilizingGyroRecovery", "InvertedPendulumSteerFeedback"):  # lean 0.05 rad decays
        assert phi[0] == 0.05 and np.max(np.abs(_tail(r, "bicycle.phi", 1.0))) < 0.05 * 0.05
    elif example == "RearSteeredSteerFeedback":  # (19): lean 0.01 rad grows
        assert phi[0] == 0.01 and np.max(np.abs(_tail(r, "bicycle.phi", 1.0))) > 10 * 0.01
    elif example == "LeaningRiderLean":  # frame rolls against the upper body, then turns right
        assert phi[0] == pytest.approx(-16.0 * 0.05 / PAPER["J"], rel=1e-12)
        assert phi[-1] > 0 and r["bicycle.psi"][-1] < 0
    elif example == "CrownedRollerRocking":  # (27), R = 1.2 > h: undamped, period 2 pi / 1.37 s
        omega = math.sqrt(PAPER["m"] * PAPER["g"] * 0.2 / PAPER["J"])
        np.testing.assert_allclose(phi, 0.05 * np.cos(omega * r["time"]), rtol=0, atol=1e-8)
