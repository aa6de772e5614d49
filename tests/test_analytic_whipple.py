"""Linearized Whipple bicycle: Meijaard et al. (2007) benchmark and Astrom et al. (2005) eq (25).

Tolerances (stated per test):
* benchmark matrices vs Meijaard 2007 (14 printed decimals): rtol 1e-12, atol 1e-13;
* benchmark eigenvalues vs Meijaard 2007 Table 2 (14 decimals): atol 1e-12;
* weave / capsize speeds vs published 13-decimal values: rtol 1e-12 (>= 12 digits);
* Astrom eq (25) and the paper's stability figures: the printed precision, i.e.
  |computed - printed| <= half a unit of the last printed digit (+1e-12 for
  binary rounding).  Entries that miss it are listed in ``ASTROM_NOT_REPRODUCED``
  with the reason and run as strict xfails; ``test_astrom_discrepancies_are_table1_rounding``
  shows the reason holds.
"""
from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from scipy.optimize import least_squares, linear_sum_assignment

from reference import MEIJAARD_BENCHMARK
from cosim.analytic import parameters as P
from cosim.analytic import whipple as W

# --------------------------------------------------------------------------- Meijaard 2007 benchmark

BENCHMARK = MEIJAARD_BENCHMARK  # published Table 1 values (tests/reference.py)

PUBLISHED = {  # Meijaard et al. (2007), eq (5.3)-(5.6)
    "M": [[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]],
    "C1": [[0.0, 33.86641391492494], [-0.85035641456978, 1.68540397397560]],
    "K0": [[-80.95, -2.59951685249872], [-2.59951685249872, -0.80329488458618]],
    "K2": [[0.0, 76.59734589573222], [0.0, 2.65431523794604]],
}
V_WEAVE = 4.2923825363411  # Meijaard et al. (2007), section 5
V_CAPSIZE = 6.0242620153884

TABLE2 = {  # Meijaard et al. (2007), Table 2: eigenvalues at speed v [m/s]
    0.0: [-5.53094371765393, -3.13164324790656, 3.13164324790656, 5.53094371765393],
    4.0: [-12.15861426576447, -1.42944427361326, 0.41325331521125 - 3.07910818603206j,
          0.41325331521125 + 3.07910818603206j],
    5.0: [-14.07838969279822, -0.32286642900409, -0.77534188219585 - 4.46486771378823j,
          -0.77534188219585 + 4.46486771378823j],
    10.0: [-24.62459635017404, 0.16105338653172, -3.72016840437287 - 10.90681139476287j,
           -3.72016840437287 + 10.90681139476287j],
}


def test_bundled_names():
    assert {"benchmark", "astrom2005", "astrom2005-riderless"} <= set(P.bundled_parameter_sets())


def test_benchmark_file_matches_paper():
    assert P.load_parameters("benchmark") == BENCHMARK
    assert list(P.load_parameters("benchmark")) == list(P.PARAMETER_NAMES)


@pytest.mark.parametrize("name", ["M", "C1", "K0", "K2"])
def test_benchmark_matrices(name):
    """Tolerance rtol 1e-12, atol 1e-13 (published values carry 14 decimals)."""
    got = dict(zip(["M", "C1", "K0", "K2"], W.matrices(P.load_parameters("benchmark"))))[name]
    np.testing.assert_allclose(got, PUBLISHED[name], rtol=1e-12, atol=1e-13)


def test_benchmark_M11_exact():
    assert W.matrices(BENCHMARK)[0][0, 0] == pytest.approx(80.81722, rel=1e-15)


@pytest.mark.parametrize("v", sorted(TABLE2), ids=lambda v: f"v={v:g}")
def test_benchmark_eigenvalues_table2(v):
    """Tolerance atol 1e-12 (Table 2 carries 14 decimals)."""
    got = W.eigenvalues(BENCHMARK, v)
    want = np.array(TABLE2[v], dtype=complex)
    want = want[np.lexsort((want.imag, want.real))]
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


def test_benchmark_weave_and_capsize_speeds():
    """>= 12 significant digits (rtol 1e-12; the brief asks for >= 10)."""
    vw, vc = W.weave_speed(BENCHMARK), W.capsize_speed(BENCHMARK)
    assert vw == pytest.approx(V_WEAVE, rel=1e-12, abs=0)
    assert vc == pytest.approx(V_CAPSIZE, rel=1e-12, abs=0)
    lo, hi = W.self_stable_interval(BENCHMARK)
    assert lo == pytest.approx(vw, rel=1e-13) and hi == pytest.approx(vc, rel=1e-13)


@pytest.mark.parametrize("name", ["benchmark", "astrom2005", "astrom2005-riderless"])
def test_stability_boundaries_equal_an_iterative_root_finder(name):
    """The exact location of each boundary (a root of a0 * H3, the Routh-Hurwitz crossing
    polynomial in v) equals scipy's brentq on the eigenvalues' real parts to 1e-12 m/s."""
    from scipy.optimize import brentq

    p = P.load_parameters(name)
    mats = W.matrices(p)

    def largest(v, oscillatory):
        ev = np.linalg.eigvals(W.state_matrices(p, v)[0])
        pick = np.abs(ev.imag) > 1e-7 * np.maximum(1.0, np.abs(ev)) if oscillatory else np.abs(ev.imag) <= 1e-7
        return ev.real[pick].max()

    vw, vc = W.weave_speed(p), W.capsize_speed(p)
    assert vw == pytest.approx(brentq(lambda v: largest(v, True), vw - 0.05, vw + 0.05, xtol=1e-15), abs=1e-12)
    assert vc == pytest.approx(brentq(lambda v: largest(v, False), vc - 0.05, vc + 0.05, xtol=1e-15), abs=1e-12)
    assert W.self_stable_interval(p) == pytest.approx((vw, vc), abs=1e-12)
    assert abs(W._crossing_polynomial(p, mats)(vw)) <= 1e-9 * max(abs(c) for c in W._crossing_polynomial(p, mats).coef)


def test_capsize_speed_matches_closed_form():
    """det(g K0 + v^2 K2) = 0 is linear in v^2 (K2[:, 0] = 0); rtol 1e-12."""
    for name in ("benchmark", "astrom2005", "astrom2005-riderless"):
        p = P.load_parameters(name)
        M, C1, K0, K2 = W.matrices(p)
        vc2 = -p["g"] * np.linalg.det(K0) / (K0[0, 0] * K2[1, 1] - K0[1, 0] * K2[0, 1])
        assert W.capsize_speed(p) == pytest.approx(math.sqrt(vc2), rel=1e-12), name


def test_stability_boundaries_are_sign_changes():
    p = BENCHMARK
    for v, sign in [(V_WEAVE - 1e-6, 1), (V_WEAVE + 1e-6, -1), (V_CAPSIZE - 1e-6, -1), (V_CAPSIZE + 1e-6, 1)]:
        assert np.sign(W.eigenvalues(p, v).real.max()) == sign, v


def test_eigenvalues_vectorised_and_sorted():
    ev = W.eigenvalues(BENCHMARK, np.array([[0.0, 5.0], [4.0, 10.0]]))
    assert ev.shape == (2, 2, 4)
    np.testing.assert_allclose(ev[0, 1], W.eigenvalues(BENCHMARK, 5.0), rtol=0, atol=1e-13)
    assert np.all(np.diff(ev.real, axis=-1) >= 0)


def test_state_space_named_signals_and_poles():
    sys = W.state_space(BENCHMARK, 5.0)
    assert list(sys.state_labels) == ["phi", "delta", "phi_dot", "delta_dot"]
    assert list(sys.input_labels) == ["T_phi", "T_delta"]
    assert list(sys.output_labels) == ["phi", "delta", "phi_dot", "delta_dot"]
    poles = np.sort_complex(sys.poles())
    np.testing.assert_allclose(poles, np.sort_complex(W.eigenvalues(BENCHMARK, 5.0)), atol=1e-12)
    A, B = W.state_matrices(BENCHMARK, 5.0)
    M = W.matrices(BENCHMARK)[0]
    np.testing.assert_allclose(B[2:], np.linalg.inv(M), rtol=1e-14)
    np.testing.assert_array_equal(B[:2], 0.0)


@pytest.mark.parametrize("name", ["benchmark", "astrom2005", "astrom2005-riderless"])
def test_asymptotic_eigenvalues(name):
    """lambda(v)/v -> roots of det(s^2 M + s C1 + K2); at v = 1e5 within 1e-4 (error O(1/v))."""
    p = P.load_parameters(name)
    sig = W.asymptotic_eigenvalues(p)
    assert np.count_nonzero(sig == 0) == 1  # exact zero root (K2[:, 0] = 0)
    v = 1e5
    lam_v = W.eigenvalues(p, v) / v
    cost = np.abs(sig[:, None] - lam_v[None, :])
    r, c = linear_sum_assignment(cost)
    assert cost[r, c].max() < 1e-4


# --------------------------------------------------------------------------- Astrom et al. (2005), eq (25)

# Paper Table 1 (its axes: x forward, y left, z UP) -> Meijaard keys (z DOWN).
TABLE1 = {
    "rider": dict(m=87.0, x=0.492, z=1.028, Jxx=3.28, Jxz=-0.603, Jyy=3.880, Jzz=0.566),
    "riderless": dict(m=12.0, x=0.439, z=0.579, Jxx=0.476, Jxz=-0.274, Jyy=1.033, Jzz=0.527),
}


def astrom_table1_converted(rear: dict) -> dict:
    front = dict(m=2.0, x=0.866, z=0.676, Jxx=0.08, Jxz=0.02, Jyy=0.07, Jzz=0.02)
    wheel = dict(m=1.5, Jxx=0.07, Jyy=0.14)
    out = {"w": 1.00, "c": 0.08, "lam": math.radians(90 - 70), "g": 9.81,
           "rR": 0.35, "mR": wheel["m"], "IRxx": wheel["Jxx"], "IRyy": wheel["Jyy"],
           "rF": 0.35, "mF": wheel["m"], "IFxx": wheel["Jxx"], "IFyy": wheel["Jyy"]}
    for b, d in (("B", rear), ("H", front)):
        out.update({f"x{b}": d["x"], f"z{b}": -d["z"], f"m{b}": d["m"], f"I{b}xx": d["Jxx"],
                    f"I{b}xz": -d["Jxz"], f"I{b}yy": d["Jyy"], f"I{b}zz": d["Jzz"]})
    return out


@pytest.mark.parametrize("name,rear", [("astrom2005", "rider"), ("astrom2005-riderless", "riderless")])
def test_astrom_files_are_table1_converted(name, rear):
    got = P.load_parameters(name)
    want = astrom_table1_converted(TABLE1[rear])
    assert got.keys() == want.keys()
    for k in want:
        assert got[k] == pytest.approx(want[k], rel=1e-15, abs=0), k


# (set, matrix, i, j, printed value, decimals printed)
EQ25 = [
    (s, n, i, j, val, dec)
    for s, entries in {
        "astrom2005": [("M", 0, 0, 96.8, 1), ("M", 0, 1, -3.57, 2), ("M", 1, 0, -3.57, 2), ("M", 1, 1, 0.258, 3),
                       ("C", 0, 0, 0.0, 12), ("C", 0, 1, -50.8, 1), ("C", 1, 0, 0.436, 3), ("C", 1, 1, 2.20, 2),
                       ("K0", 0, 0, -901.0, 1), ("K0", 0, 1, 35.17, 2), ("K0", 1, 0, 35.17, 2),
                       ("K0", 1, 1, -12.03, 2),
                       ("K2", 0, 0, 0.0, 12), ("K2", 0, 1, -87.06, 2), ("K2", 1, 0, 0.0, 12), ("K2", 1, 1, 3.50, 2)],
        "astrom2005-riderless": [("M", 0, 0, 6.00, 2), ("M", 0, 1, -0.472, 3), ("M", 1, 0, -0.472, 3),
                                 ("M", 1, 1, 0.152, 3),
                                 ("C", 0, 0, 0.0, 12), ("C", 0, 1, -5.84, 2), ("C", 1, 0, 0.436, 3),
                                 ("C", 1, 1, 0.666, 3),
                                 ("K0", 0, 0, -91.72, 2), ("K0", 0, 1, 7.51, 2), ("K0", 1, 0, 7.51, 2),
                                 ("K0", 1, 1, -2.57, 2),
                                 ("K2", 0, 0, 0.0, 12), ("K2", 0, 1, -9.54, 2), ("K2", 1, 0, 0.0, 12),
                                 ("K2", 1, 1, 0.848, 3)],
    }.items()
    for n, i, j, val, dec in entries
]

_ROUNDING = ("Consistent with Table 1 (rider) being printed rounded while (25) was computed "
             "from unrounded data: test_astrom_discrepancies_are_table1_rounding finds one parameter set within the "
             "rounding of every Table 1 entry that reproduces all printed (25) and stability numbers")

#: Printed numbers NOT reproduced from Table 1 as printed: id -> (computed, reason).
ASTROM_NOT_REPRODUCED = {
    "astrom2005-M11": "96.7217 -> 96.7, printed 96.8. " + _ROUNDING,
    "astrom2005-M12": "-3.5758 -> -3.58, printed -3.57. " + _ROUNDING,
    "astrom2005-M21": "-3.5758 -> -3.58, printed -3.57. " + _ROUNDING,
    "astrom2005-M22": "0.25859 -> 0.259, printed 0.258. " + _ROUNDING,
    "astrom2005-C22": "2.2054 -> 2.21, printed 2.20. " + _ROUNDING,
    "astrom2005-K011": "-900.931 -> -900.9, printed -901.0. " + _ROUNDING,
    "astrom2005-K012": "35.196 -> 35.20, printed 35.17. " + _ROUNDING,
    "astrom2005-K021": "35.196 -> 35.20, printed 35.17. " + _ROUNDING,
    "astrom2005-K022": "-12.0378 -> -12.04, printed -12.03. " + _ROUNDING,
    "astrom2005-K212": "-87.0512 -> -87.05, printed -87.06. " + _ROUNDING,
    "astrom-v0-pole-9.18": "9.18676 -> 9.19, printed 9.18. " + _ROUNDING,
    "astrom-weave-5.96": "5.95478 -> 5.95, printed 5.96. " + _ROUNDING,
    "astrom-capsize-10.36": "10.36823 -> 10.37, printed 10.36. " + _ROUNDING,
    "astrom-asymptote-imag-1.33": "1.33609 -> 1.34, printed 1.33. " + _ROUNDING,
}


def _id(s, n, i, j):
    return f"{s}-{n}{i + 1}{j + 1}"


def _mark(case_id):
    if case_id in ASTROM_NOT_REPRODUCED:
        return [pytest.mark.xfail(strict=True, reason=ASTROM_NOT_REPRODUCED[case_id])]
    return []


def _within_printed(value, printed, decimals):
    return abs(value - printed) <= 0.5 * 10.0**-decimals + 1e-12


@pytest.mark.parametrize(
    "name,mat,i,j,printed,decimals",
    [pytest.param(*e, id=_id(*e[:4]), marks=_mark(_id(*e[:4]))) for e in EQ25],
)
def test_astrom_eq25(name, mat, i, j, printed, decimals):
    """Printed precision: |computed - printed| <= 0.5e-decimals (+1e-12)."""
    M, C, K0, K2 = W.astrom_matrices(P.load_parameters(name))
    value = {"M": M, "C": C, "K0": K0, "K2": K2}[mat][i, j]
    assert _within_printed(value, printed, decimals), f"computed {value!r}, printed {printed}"


def test_astrom_convention_is_meijaard_with_steer_flipped():
    """Steer positive left: S = diag(1, -1) flips off-diagonal signs; g folded into K0."""
    p = P.load_parameters("astrom2005")
    M, C1, K0, K2 = W.matrices(p)
    Ma, Ca, K0a, K2a = W.astrom_matrices(p)
    flip = np.array([[1, -1], [-1, 1]])
    np.testing.assert_array_equal(Ma, M * flip)
    np.testing.assert_array_equal(Ca, C1 * flip)
    np.testing.assert_allclose(K0a, p["g"] * K0 * flip, rtol=1e-15)
    np.testing.assert_array_equal(K2a, K2 * flip)


def _astrom_claims(p):
    """The paper's stability figures for the rider bicycle: (id, computed, printed, decimals)."""
    ev0 = np.sort(np.abs(W.eigenvalues(p, 0.0).real))
    lo, hi = W.self_stable_interval(p, v_min=4.0, v_max=12.0, num=81)
    sig = W.asymptotic_eigenvalues(p)
    real = sig[(sig.imag == 0) & (sig != 0)].real
    cplx = sig[sig.imag > 0]
    assert real.size == 1 and cplx.size == 1
    return [
        ("astrom-v0-pole-3.05", ev0[0], 3.05, 2),
        ("astrom-v0-pole-9.18", ev0[2], 9.18, 2),
        ("astrom-weave-5.96", lo, 5.96, 2),
        ("astrom-capsize-10.36", hi, 10.36, 2),
        ("astrom-asymptote-real--1.40", real[0], -1.40, 2),
        ("astrom-asymptote-cplx-real--0.65", cplx[0].real, -0.65, 2),
        ("astrom-asymptote-imag-1.33", cplx[0].imag, 1.33, 2),
    ]


_CLAIM_IDS = [c[0] for c in _astrom_claims(P.load_parameters("astrom2005"))]


@pytest.mark.parametrize("claim", [pytest.param(c, id=c, marks=_mark(c)) for c in _CLAIM_IDS])
def test_astrom_stability_claims(claim):
    """Poles +-3.05, +-9.18 at v = 0; self-stable 5.96-10.36 m/s; asymptotes -1.40 v, (-0.65 +- 1.33i) v."""
    p = P.load_parameters("astrom2005")
    _, value, printed, decimals = next(c for c in _astrom_claims(p) if c[0] == claim)
    assert _within_printed(value, printed, decimals), f"computed {value!r}, printed {printed}"


def test_astrom_weave_and_capsize_are_the_stability_interval():
    p = P.load_parameters("astrom2005")
    lo, hi = W.self_stable_interval(p)
    assert W.weave_speed(p) == pytest.approx(lo, rel=1e-13)
    assert W.capsize_speed(p) == pytest.approx(hi, rel=1e-13)


def test_astrom_self_alignment_speed():
    """Paper: V_sa = sqrt(7.51/2.57) = 1.74 m/s.  1.74 is sqrt(-K0_22/K2_22) of the RIDERLESS (25)
    (front-fork equation alone); the printed formula evaluates to 1.709 (a misprint)."""
    M, C, K0, K2 = W.astrom_matrices(P.load_parameters("astrom2005-riderless"))
    assert _within_printed(math.sqrt(-K0[1, 1] / K2[1, 1]), 1.74, 2)
    assert not _within_printed(math.sqrt(7.51 / 2.57), 1.74, 2)


# Half-unit of the last printed digit of every Table 1 / text entry that enters the model.
_TABLE1_HALF_UNIT = dict(
    w=0.005, c=0.005, lam=math.radians(0.5), rR=0.005, rF=0.005, mR=0.05, mF=0.05,
    IRxx=0.005, IFxx=0.005, IRyy=0.005, IFyy=0.005,
    mB=0.5, xB=0.0005, zB=0.0005, IBxx=0.005, IBxz=0.0005, IBzz=0.0005,
    mH=0.5, xH=0.0005, zH=0.0005, IHxx=0.005, IHxz=0.005, IHzz=0.005,
)


def test_astrom_discrepancies_are_table1_rounding():
    """Search (bounded least squares) for one parameter set, each entry within half a unit of
    Table 1's last printed digit, that reproduces ALL printed rider numbers of (25) and of the
    stability discussion at printed precision.  Existence shows the misses above are explained
    by the rounding of Table 1.  Tolerance: every number within half a printed unit (exactly)."""
    base = P.load_parameters("astrom2005")
    keys = list(_TABLE1_HALF_UNIT)
    entries = [e for e in EQ25 if e[0] == "astrom2005"]

    def perturbed(x):
        p = dict(base)
        for k, xi in zip(keys, x):
            p[k] = base[k] + xi * _TABLE1_HALF_UNIT[k]
        p["IRyy"] = min(p["IRyy"], 2 * p["IRxx"])  # stay a physical disc
        p["IFyy"] = min(p["IFyy"], 2 * p["IFxx"])
        return p

    def quantities(p):
        M, C, K0, K2 = W.astrom_matrices(p)
        mats = {"M": M, "C": C, "K0": K0, "K2": K2}
        out = [(mats[n][i, j], val, dec) for _, n, i, j, val, dec in entries]
        return out + [(v, pr, dec) for _, v, pr, dec in _astrom_claims(p)]

    def residuals(x, target=1.0):
        # excess over `target` half-units of the last printed digit (0 inside)
        return np.array([max(0.0, abs(v - pr) / (0.5 * 10.0**-d) - target)
                         for v, pr, d in quantities(perturbed(x))])

    assert residuals(np.zeros(len(keys))).max() > 0.0  # the printed table alone misses some
    # Aim at 0.8 half-units so that the optimum lies strictly inside the printed intervals.
    sol = least_squares(residuals, np.zeros(len(keys)), bounds=(-1.0, 1.0), args=(0.8,),
                        xtol=1e-15, ftol=1e-15, gtol=1e-15)
    assert np.all(np.abs(sol.x) <= 1.0)
    assert residuals(sol.x).max() == 0.0


def test_astrom_table1_inertias_violate_triangle_inequality():
    """Documented data quirk: the printed frame inertias are not physical; IByy/IHyy are waived."""
    for rear in TABLE1.values():
        p = astrom_table1_converted(rear)
        with pytest.raises(ValueError, match=r"^IByy: triangle inequality"):
            P.validate_parameters(p)
        with pytest.raises(ValueError, match=r"^IHyy: triangle inequality"):
            P.validate_parameters(p, waive=("IByy",))
        P.validate_parameters(p, waive=("IByy", "IHyy"))
        W.matrices(p)  # IByy, IHyy do not enter the model


def test_astrom_copy_loaded_by_path_carries_its_waiver(tmp_path):
    """The waiver is in the file: a copy loads as the bundled set, the same values without the
    waiver lines are refused unless the caller waives the checks."""
    src = Path(P.__file__).resolve().parents[1] / "params" / "astrom2005.toml"
    copy = tmp_path / "mine.toml"
    shutil.copy(src, copy)
    assert P.load_parameters(copy) == P.load_parameters(src) == P.load_parameters("astrom2005")
    stripped = tmp_path / "stripped.toml"
    stripped.write_text("".join(line for line in src.read_text().splitlines(True)
                                if not line.startswith((P.WAIVER_KEY, P.REASON_KEY))))
    with pytest.raises(ValueError, match=r"^IByy:"):
        P.load_parameters(stripped)
    assert P.load_parameters(stripped, waive=["IByy", "IHyy"]) == P.load_parameters("astrom2005")


# --------------------------------------------------------------------------- property test

def _frame(draw, ixx_max):
    ixx = draw(st.floats(0.01, ixx_max))
    izz = draw(st.floats(0.01, ixx_max))
    rho = draw(st.floats(-0.95, 0.95))
    ixz = rho * math.sqrt(ixx * izz)
    spread = math.hypot(ixx - izz, 2 * ixz)
    iyy = spread + draw(st.floats(0.0, 1.0)) * (ixx + izz - spread)
    return ixx, ixz, iyy, izz


@st.composite
def bicycles(draw):
    w = draw(st.floats(0.5, 1.6))
    p = {"w": w, "c": draw(st.floats(-0.2, 0.3)) * w, "lam": draw(st.floats(-0.5, 0.8)),
         "g": draw(st.floats(1.0, 20.0))}
    for wh in ("R", "F"):
        r, m = draw(st.floats(0.15, 0.5)), draw(st.floats(0.3, 6.0))
        ixx = m * r**2 * draw(st.floats(0.2, 0.6))
        p.update({f"r{wh}": r, f"m{wh}": m, f"I{wh}xx": ixx, f"I{wh}yy": ixx * draw(st.floats(1.0, 2.0))})
    for b, mmax, imax, xr in (("B", 120.0, 15.0, (-0.3, 1.0)), ("H", 10.0, 0.3, (0.5, 1.3))):
        ixx, ixz, iyy, izz = _frame(draw, imax)
        p.update({f"x{b}": draw(st.floats(*xr)) * w, f"z{b}": -draw(st.floats(0.2, 1.5)),
                  f"m{b}": draw(st.floats(0.5, mmax)),
                  f"I{b}xx": ixx, f"I{b}xz": ixz, f"I{b}yy": iyy, f"I{b}zz": izz})
    return p


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(p=bicycles(), v=st.floats(-10.0, 20.0))
def test_state_space_eigenvalues_are_roots_of_det(p, v):
    """Eigenvalues of state_space(p, v).A vs roots of det(s^2 M + v s C1 + g K0 + v^2 K2).

    Tolerances: (1) relative backward error |det P(lam)| / (|lam|^2 |M| + |lam| |v C1| + |K|)^2
    <= 1e-10 for every eigenvalue; (2) matched root distance <= 1e-6 (1 + max |lam|): a
    double root (e.g. where the weave pair forms) is only determined to ~sqrt(eps)."""
    try:
        p = P.validate_parameters(p)
    except ValueError:
        assume(False)
    M, C1, K0, K2 = W.matrices(p)
    K = p["g"] * K0 + v**2 * K2
    ev = np.asarray(W.state_space(p, v).poles(), dtype=complex)
    assert ev.shape == (4,)
    norm = np.linalg.norm
    for lam in ev:
        P_l = lam**2 * M + lam * v * C1 + K
        scale = (abs(lam) ** 2 * norm(M, 2) + abs(lam) * abs(v) * norm(C1, 2) + norm(K, 2)) ** 2
        assert abs(np.linalg.det(P_l)) <= 1e-10 * scale
    roots = np.roots(W.characteristic_polynomial(p, v)).astype(complex)
    roots = np.concatenate([roots, np.zeros(4 - roots.size, complex)])
    cost = np.abs(ev[:, None] - roots[None, :])
    r, c = linear_sum_assignment(cost)
    assert cost[r, c].max() <= 1e-6 * (1 + np.abs(ev).max())
    np.testing.assert_allclose(np.sort_complex(W.eigenvalues(p, v)), np.sort_complex(ev),
                               atol=1e-6 * (1 + np.abs(ev).max()))


# --------------------------------------------------------------------------- bad parameters

def _with(**changes):
    p = dict(BENCHMARK)
    for k, v in changes.items():
        if v is _DROP:
            del p[k]
        else:
            p[k] = v
    return p


_DROP = object()

BAD = [
    pytest.param(_with(IBxz=_DROP), "IBxz", id="missing-IBxz"),
    pytest.param(_with(foo=1.0), "foo", id="unknown-foo"),
    pytest.param(_with(IRzz=0.0603), "IRzz", id="unknown-IRzz"),
    pytest.param(_with(mB=-1.0), "mB", id="negative-mass"),
    pytest.param(_with(mR=-0.1), "mR", id="negative-wheel-mass"),
    pytest.param(_with(mH=0.0, mF=0.0), "mH", id="massless-front-assembly"),
    pytest.param(_with(rR=0.0), "rR", id="zero-rear-radius"),
    pytest.param(_with(rF=-0.35), "rF", id="negative-front-radius"),
    pytest.param(_with(w=0.0), "w", id="zero-wheelbase"),
    pytest.param(_with(c=1.5), "c", id="trail-exceeds-wheelbase"),
    pytest.param(_with(g=0.0), "g", id="zero-gravity"),
    pytest.param(_with(lam=math.pi / 2), "lam", id="lam-pi/2"),
    pytest.param(_with(lam=-2.0), "lam", id="lam-below"),
    pytest.param(_with(zB=0.1), "zB", id="rear-frame-below-ground"),
    pytest.param(_with(zH=0.0), "zH", id="front-frame-on-ground"),
    pytest.param(_with(IBxx=-9.2), "IBxx", id="negative-moment"),
    pytest.param(_with(IFxx=-0.1), "IFxx", id="negative-wheel-moment"),
    pytest.param(_with(IBxz=6.0), "IBxz", id="not-positive-definite"),
    pytest.param(_with(IByy=12.5), "IByy", id="triangle-Iyy-too-big"),
    pytest.param(_with(IHyy=0.001), "IHyy", id="triangle-Iyy-too-small"),
    pytest.param(_with(IRyy=0.2), "IRyy", id="wheel-triangle"),
    pytest.param(_with(mB="85"), "mB", id="string-value"),
    pytest.param(_with(mB=True), "mB", id="bool-value"),
    pytest.param(_with(xH=float("nan")), "xH", id="nan"),
    pytest.param(_with(IHzz=float("inf")), "IHzz", id="inf"),
]


@pytest.mark.parametrize("params,key", BAD)
def test_bad_parameters_raise_naming_key(params, key):
    with pytest.raises(ValueError, match=rf"^{key}:"):
        P.validate_parameters(params)


@pytest.mark.parametrize("params,key", [b for b in BAD if b.id not in ("triangle-Iyy-too-big",
                                                                        "triangle-Iyy-too-small")])
def test_bad_parameters_rejected_by_model(params, key):
    """The model functions validate too (all checks except the unused IByy/IHyy triangles)."""
    with pytest.raises(ValueError, match=rf"^{key}:"):
        W.matrices(params)


def _toml(params):
    lines = []
    for k, v in params.items():
        if isinstance(v, str):
            lines.append(f'{k} = "{v}"')
        elif isinstance(v, bool):
            lines.append(f"{k} = {str(v).lower()}")
        elif isinstance(v, float) and not math.isfinite(v):
            lines.append(f"{k} = {'nan' if math.isnan(v) else ('inf' if v > 0 else '-inf')}")
        else:
            lines.append(f"{k} = {v!r}")
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("params,key", BAD)
def test_bad_parameter_files_raise_naming_key(tmp_path, params, key):
    f = tmp_path / "bad.toml"
    f.write_text(_toml(params))
    with pytest.raises(ValueError, match=rf"^{key}:"):
        P.load_parameters(f)


def test_good_file_roundtrip(tmp_path):
    f = tmp_path / "bench.toml"
    f.write_text(_toml(BENCHMARK))
    assert P.load_parameters(str(f)) == BENCHMARK


def test_unknown_bundled_name_and_missing_file(tmp_path):
    with pytest.raises(ValueError, match="unknown bundled parameter set"):
        P.load_parameters("no-such-bicycle")
    with pytest.raises(FileNotFoundError):
        P.load_parameters(tmp_path / "absent.toml")


def test_waive_only_triangle_checks():
    with pytest.raises(ValueError, match=r"^mB:"):
        P.validate_parameters(BENCHMARK, waive=["mB"])
