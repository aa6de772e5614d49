"""The Modelica linear Whipple bicycle (Bicycle.Bicycles.WhippleLinear) against Meijaard et al. (2007)
and the independent analytic Python model (cosim.analytic.whipple).

The FMU is built once per module into a temporary folder; every linearization sets the
parameters at run time (no rebuild).

Tolerances (stated per test):
* calculated parameters M, C1, K0, K2 of the benchmark vs the published 14-decimal values:
  rtol 1e-12, atol 1e-13;
* FMU state matrices vs the analytic ones: rtol 1e-12, atol 1e-12 (scaled by the matrix norm);
* FMU eigenvalues vs analytic (``cosim.analytic.compare.root_set_error``, relative per root): 1e-10 for
  the benchmark, 1e-9 for the Astrom sets and for random bicycles;
* weave and capsize speeds by root finding on FMU linearizations vs published 13-decimal
  values: relative 1e-11 (>= 11 significant digits), vs the analytic model 1e-11.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from conftest import assert_plotted, assert_readable, calculated_parameters, png_pixels
from cosim.bicycle import stability as WP
from cosim.analytic import parameters as P
from cosim.analytic import whipple as W
from cosim.analytic.compare import root_set_error
from cosim.fmu.access import FMU

MODEL = "Bicycle.Bicycles.WhippleLinear"

PUBLISHED = {  # Meijaard et al. (2007), eq (5.3)-(5.6); FMU calculated-parameter names
    "M11": 80.81722, "M12": 2.31941332208709, "M21": 2.31941332208709, "M22": 0.29784188199686,
    "C1_12": 33.86641391492494, "C1_21": -0.85035641456978, "C1_22": 1.68540397397560,
    "K0_11": -80.95, "K0_12": -2.59951685249872, "K0_21": -2.59951685249872, "K0_22": -0.80329488458618,
    "K2_12": 76.59734589573222, "K2_22": 2.65431523794604,
}
V_WEAVE = 4.2923825363411  # Meijaard et al. (2007), section 5
V_CAPSIZE = 6.0242620153884

SETS = ("benchmark", "astrom2005", "astrom2005-riderless")
EIG_TOL = {"benchmark": 1e-10, "astrom2005": 1e-9, "astrom2005-riderless": 1e-9}
SPEEDS = [round(0.5 * k, 1) for k in range(21)]  # 0 ... 10 m/s


@pytest.fixture(scope="module")
def fmu(fmus):
    """The session's build (tests/conftest.py): the FMU is only read here."""
    return fmus[MODEL]


# --------------------------------------------------------------------------- interface

def test_interface(fmu):
    with FMU(fmu) as f:
        assert f.states == ["phi", "delta", "phi_dot", "delta_dot", "psi", "y"]
        assert f.names("input") == ["T_phi", "T_delta"]
        assert f.names("output") == ["phi", "delta", "phi_dot", "delta_dot", "psi", "y"]
        tunable = set(f.names("parameter"))
        assert set(P.PARAMETER_NAMES) | {"v"} <= tunable
        assert set(PUBLISHED) <= set(f.names("calculatedParameter"))
        units = {n: f.variables[n].unit for n in ("M11", "C1_12", "K0_11", "K2_12", "v", "lam", "T_phi")}
    assert units == {"M11": "kg.m2", "C1_12": "kg.m", "K0_11": "kg.m", "K2_12": "kg", "v": "m/s",
                     "lam": "rad", "T_phi": "N.m"}


def test_defaults_are_the_benchmark(fmu):
    with FMU(fmu) as f:
        defaults = {n: float(f.variables[n].start) for n in P.PARAMETER_NAMES}
    assert defaults == P.load_parameters("benchmark")


@pytest.mark.parametrize("name", SETS, ids=SETS)
def test_parameters_for_model_is_identity(name):
    assert WP.parameters_for_model(name) == P.load_parameters(name)


def test_parameters_for_model_rejects_bad_sets(tmp_path):
    from cosim.errors import ParameterError

    with pytest.raises(ParameterError, match="unknown bundled parameter set"):
        WP.parameters_for_model("no-such-set")
    bad = tmp_path / "bad.toml"
    bad.write_text("\n".join(f"{k} = {v!r}" for k, v in {**P.load_parameters("benchmark"), "w": -1.0}.items()))
    with pytest.raises(ParameterError, match=r"w: must be positive"):
        WP.parameters_for_model(bad)
    with pytest.raises(FileNotFoundError):
        WP.parameters_for_model(tmp_path / "missing.toml")


# --------------------------------------------------------------------------- benchmark matrices

@pytest.mark.parametrize("name", list(PUBLISHED), ids=list(PUBLISHED))
def test_benchmark_calculated_parameters(fmu, name):
    """Calculated parameter of the FMU (default = benchmark) vs Meijaard (2007): rtol 1e-12, atol 1e-13."""
    got = calculated_parameters(fmu, [name])[name]
    assert got == pytest.approx(PUBLISHED[name], rel=1e-12, abs=1e-13)


@pytest.mark.parametrize("name", SETS, ids=SETS)
def test_calculated_matrices_match_analytic(fmu, name):
    """M, C1, K0, K2 from the FMU (parameters set at run time) vs cosim.analytic.whipple: rtol 1e-12, atol 1e-13."""
    params = WP.parameters_for_model(name)
    got = calculated_parameters(fmu, list(PUBLISHED), params)
    M, C1, K0, K2 = W.matrices(params)
    expected = {"M11": M[0, 0], "M12": M[0, 1], "M21": M[1, 0], "M22": M[1, 1],
                "C1_12": C1[0, 1], "C1_21": C1[1, 0], "C1_22": C1[1, 1],
                "K0_11": K0[0, 0], "K0_12": K0[0, 1], "K0_21": K0[1, 0], "K0_22": K0[1, 1],
                "K2_12": K2[0, 1], "K2_22": K2[1, 1]}
    assert C1[0, 0] == K2[0, 0] == K2[1, 0] == 0.0  # the structural zeros the model does not declare
    for key, value in expected.items():
        assert got[key] == pytest.approx(value, rel=1e-12, abs=1e-13), key


# --------------------------------------------------------------------------- linearization

@pytest.mark.parametrize("name", SETS, ids=SETS)
@pytest.mark.parametrize("v", [-4.0, 0.0, 5.0], ids=lambda v: f"v={v:g}")
def test_state_space_matches_analytic(fmu, name, v):
    """A, B of the 4 bicycle states from the FMU vs cosim.analytic.whipple.state_matrices:
    |difference| <= 1e-12 * (1 + |analytic|) elementwise."""
    params = WP.parameters_for_model(name)
    A, B = WP.state_space(fmu, params, v)
    A_ref, B_ref = W.state_matrices(params, v)
    np.testing.assert_allclose(A, A_ref, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(B, B_ref, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("v", [-3.0, 0.0, 4.6], ids=lambda v: f"v={v:g}")
def test_heading_and_path_kinematics(fmu, v):
    """der(psi) = (v delta + c der(delta)) cos(lam)/w, der(y) = v psi; psi, y do not feed back. Exact to 1e-14."""
    p = WP.parameters_for_model("benchmark")
    lin = WP.linearization(fmu, p, v).system
    i = {s: k for k, s in enumerate(lin.states)}
    A = lin.A
    k = math.cos(p["lam"]) / p["w"]
    expected_psi = np.zeros(6)
    expected_psi[i["delta"]] = v * k
    expected_psi[i["delta_dot"]] = p["c"] * k
    expected_y = np.zeros(6)
    expected_y[i["psi"]] = v
    np.testing.assert_allclose(A[i["psi"]], expected_psi, rtol=1e-14, atol=1e-14)
    np.testing.assert_allclose(A[i["y"]], expected_y, rtol=1e-14, atol=1e-14)
    assert np.all(A[:4, 4:] == 0.0)
    np.testing.assert_array_equal(lin.B[4:], 0.0)


@pytest.mark.parametrize("name", SETS, ids=SETS)
@pytest.mark.parametrize("v", SPEEDS, ids=[f"v={v:g}" for v in SPEEDS])
def test_eigenvalues_match_analytic(fmu, name, v):
    """FMU-linearized eigenvalues vs cosim.analytic.whipple.eigenvalues (root_set_error, relative):
    <= 1e-10 for the benchmark, <= 1e-9 for the Astrom sets."""
    params = WP.parameters_for_model(name)
    err = root_set_error(WP.eigenvalues(fmu, params, v), W.eigenvalues(params, v))
    assert err <= EIG_TOL[name]


def test_full_linearization_has_two_zero_eigenvalues(fmu):
    """Heading and lateral position add two eigenvalues at exactly zero to the bicycle's four."""
    p = WP.parameters_for_model("benchmark")
    lin = WP.linearization(fmu, p, 5.0)
    ev = lin.eigenvalues
    assert np.sum(ev == 0.0) == 2
    assert root_set_error(ev[ev != 0.0], W.eigenvalues(p, 5.0)) <= 1e-10


# --------------------------------------------------------------------------- stability boundaries

def test_benchmark_weave_and_capsize_speeds_from_fmu(fmu):
    """Root finding on FMU linearizations vs Meijaard (2007): relative 1e-11 (>= 11 digits)."""
    params = WP.parameters_for_model("benchmark")
    vw = WP.weave_speed(fmu, params)
    vc = WP.capsize_speed(fmu, params, v_start=vw)
    assert vw == pytest.approx(V_WEAVE, rel=1e-11)
    assert vc == pytest.approx(V_CAPSIZE, rel=1e-11)


@pytest.mark.parametrize("name", SETS[1:], ids=SETS[1:])
def test_astrom_weave_and_capsize_speeds_from_fmu(fmu, name):
    """FMU root finding vs the analytic model: relative 1e-11; and the paper's values for the rider
    set (5.96 and 10.36 m/s, printed to 0.01 m/s from rounded Table 1 data: within 0.01 m/s)."""
    params = WP.parameters_for_model(name)
    vw = WP.weave_speed(fmu, params)
    vc = WP.capsize_speed(fmu, params, v_start=vw)
    assert vw == pytest.approx(W.weave_speed(params), rel=1e-11)
    assert vc == pytest.approx(W.capsize_speed(params), rel=1e-11)
    if name == "astrom2005":
        assert abs(vw - 5.96) <= 0.01 and abs(vc - 10.36) <= 0.01


@pytest.mark.parametrize("name", SETS[:2], ids=SETS[:2])
@pytest.mark.parametrize("v", [-0.5, -1.0, -2.0, -4.0, -6.0, -8.0, -10.0], ids=lambda v: f"v={v:g}")
def test_rear_steered_is_unstable(fmu, name, v):
    """Negative speed (riding backwards = rear-steered, Fig 9): the FMU linearizes, matches the
    analytic eigenvalues (root_set_error <= 1e-9) and some pole has a positive real part."""
    params = WP.parameters_for_model(name)
    ev = WP.eigenvalues(fmu, params, v)
    assert root_set_error(ev, W.eigenvalues(params, v)) <= 1e-9
    assert ev.real.max() > 0.0


def test_roll_stiffness_is_a_K0_11_change(fmu):
    """closed_loop(A, B, k) equals the model with K0[0, 0] + k/g (analytic), to 1e-12."""
    params = WP.parameters_for_model("astrom2005")
    k, v = 250.0, 4.0
    A_cl = WP.state_matrix(fmu, params, v, roll_stiffness=k)
    M, C1, K0, K2 = W.matrices(params)
    K0 = K0.copy()
    K0[0, 0] += k / params["g"]
    Minv = np.linalg.inv(M)
    A = np.zeros((4, 4))
    A[:2, 2:] = np.eye(2)
    A[2:, :2] = -Minv @ (params["g"] * K0 + v**2 * K2)
    A[2:, 2:] = -v * Minv @ C1
    np.testing.assert_allclose(A_cl, A, rtol=1e-12, atol=1e-12)


# --------------------------------------------------------------------------- property test

FACTOR = st.floats(0.8, 1.2)


@st.composite
def perturbed_benchmarks(draw):
    """Every benchmark parameter times a factor in [0.8, 1.2] (signed ones and g included); the
    benchmark's wheels are thin discs (Iyy = 2 Ixx) and its rear frame is near the triangle
    inequality, so Iyy of the wheels and frames is then clipped into the physical range
    (wheels: Iyy <= 2 Ixx; frames: sqrt((Ixx-Izz)^2 + 4 Ixz^2) <= Iyy <= Ixx + Izz)."""
    p = {k: v * draw(FACTOR) for k, v in P.load_parameters("benchmark").items()}
    for w in "RF":
        p[f"I{w}yy"] = min(p[f"I{w}yy"], 2.0 * p[f"I{w}xx"])
    for b in "BH":
        ixx, ixz, izz = p[f"I{b}xx"], p[f"I{b}xz"], p[f"I{b}zz"]
        p[f"I{b}yy"] = min(max(p[f"I{b}yy"], math.hypot(ixx - izz, 2.0 * ixz)), ixx + izz)
    return p


@settings(max_examples=30, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(p=perturbed_benchmarks(), v=st.floats(-10.0, 15.0))
def test_random_bicycles_fmu_equals_analytic(fmu, p, v):
    """Random physically plausible bicycles (benchmark +-20%, kept if validate_parameters accepts
    them): FMU eigenvalues vs analytic, root_set_error <= 1e-9."""
    try:
        p = P.validate_parameters(p)
        W.matrices(p)
    except ValueError:
        assume(False)
    err = root_set_error(WP.eigenvalues(fmu, p, v), W.eigenvalues(p, v))
    assert err <= 1e-9


# --------------------------------------------------------------------------- figures

FIGURES = ["fig8", "fig9", "fig13", "fig15"]


@pytest.mark.parametrize("name", FIGURES, ids=FIGURES)
def test_figure_is_written(fmu, name, tmp_path, monkeypatch, drawn_figures):
    """`cosim figures NAME` (cosim.figures.make_figures) writes NAME.png, using this module's FMU:
    every axes of the figure shows finite, varying data with a unit on its axes and no legend
    over it, and the PNG is that drawing."""
    from cosim.figures import make_figures, registry

    monkeypatch.setattr(WP, "whipple_fmu", lambda *a, **k: fmu)
    assert name in registry()
    written = make_figures([name], tmp_path)
    assert written == [tmp_path / f"{name}.png"]
    assert len(drawn_figures) == 1
    assert_plotted(drawn_figures[0][1])
    assert_readable(drawn_figures[0])
    pixels = png_pixels(written[0])
    assert min(pixels.shape[:2]) >= 300, f"{pixels.shape[1]} x {pixels.shape[0]} pixels"
    assert (pixels.min(axis=-1) < 0.5).mean() > 0.005, "the image is (almost) blank"
