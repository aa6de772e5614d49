"""Figure 7: the saddle-node folds of the steady turns, checked against an independent solve.

`cosim figures fig7` searches the steady turns of the astrom2005 Whipple bicycle over
``|phi| < pi/2``, ``-pi < delta <= pi`` and lists the folds (speed extremal along a branch) per side
in ``fig7.json``, for knife-edge wheels and for toroidal ones (tR = tF = fig7.CROWN). Here every
listed fold is compared with a solve that shares no code with ``cosim.nonlinear.continuation``:
the steady-turn conditions ``du_phi/dt = du_delta/dt = 0`` are read from the FMU at a prescribed
forward speed ``V`` (the rear wheel rate that gives ``V`` is found from the FMU's own ``v`` output),
in the unknowns ``(phi, delta)``; the fold condition is that their finite-difference Jacobian in
``(phi, delta)`` is singular; ``scipy.optimize.root`` solves the three equations in
``(phi, delta, V)``. Across the fold speed the number of turns near the fold must change from 2 to 0.
"""
from __future__ import annotations

import json
import os

import numpy as np
import pytest
from scipy.optimize import root

from conftest import run_cli
from cosim.analytic.parameters import load_parameters
from cosim.figures import fig7
from cosim.nonlinear.model import MODEL, Bicycle, build

# the quick run (-m 'not slow') leaves this module out: its tests build, compile or run FMUs
pytestmark = pytest.mark.slow

VARIANTS = {"knife_edge": 0.0, "toroidal": fig7.CROWN}

# Rough start points (two digits) of the independent solve: (variant, V [m/s], phi, delta [rad]).
FOLDS = [
    pytest.param("knife_edge", 1.74, 0.23, -1.93, id="knife-edge-V1.74"),
    pytest.param("toroidal", 1.58, 0.22, -1.93, id="toroidal-V1.58"),
    pytest.param("toroidal", 3.57, 0.53, -2.63, id="toroidal-V3.57"),
    pytest.param("toroidal", 5.76, 0.76, -2.89, id="toroidal-V5.76"),
]


@pytest.fixture(scope="module")
def listed(tmp_path_factory) -> dict:
    """`cosim figures fig7` as a user runs it: the folds it lists in fig7.json."""
    out = tmp_path_factory.mktemp("fig7")
    r = run_cli("figures", "fig7", "-o", str(out))
    assert r.returncode == 0, r.stderr
    return json.loads((out / "fig7.json").read_text())


@pytest.fixture(scope="module")
def fmu():
    return build(MODEL, os.environ["COSIM_FMU_DIR"])


class TurnConditions:
    """The steady-turn conditions of the FMU at a prescribed forward speed, independent of
    cosim.nonlinear.continuation: unknowns (phi, delta) [rad] and the speed V [m/s]."""

    def __init__(self, bike: Bicycle):
        self.bike = bike
        ix = bike.index
        self.rows = [ix["u_phi"], ix["u_delta"]]

    def _set(self, phi, delta, u_R):
        self.bike.initialize({"phi0": phi, "delta0": delta, "u_R0": u_R, "u_phi0": 0.0, "u_delta0": 0.0})

    def wheel_rate(self, phi, delta, v) -> float:
        # The contact point's velocity is linear in the speeds (u_phi = u_delta = 0 here), so
        # one evaluation of the FMU's output v at u_R = -1 gives the rate for speed v.
        self._set(phi, delta, -1.0)
        return -v / float(self.bike.get(["v"])[0])

    def g(self, phi, delta, v) -> np.ndarray:
        """(du_phi/dt, du_delta/dt) [rad/s^2] of the turn (phi, delta) at speed v."""
        self._set(phi, delta, self.wheel_rate(phi, delta, v))
        return self.bike.derivatives()[self.rows]

    def jacobian(self, phi, delta, v, h: float = 1e-5) -> np.ndarray:
        """d g / d(phi, delta) at fixed speed, by central differences."""
        cols = [(self.g(phi + h, delta, v) - self.g(phi - h, delta, v)) / (2 * h),
                (self.g(phi, delta + h, v) - self.g(phi, delta - h, v)) / (2 * h)]
        return np.column_stack(cols)

    def fold(self, phi, delta, v) -> np.ndarray:
        """(phi, delta, V) of the fold near the start: g = 0 and det(dg/d(phi, delta)) = 0."""
        def equations(x):
            return np.concatenate([self.g(*x), [np.linalg.det(self.jacobian(*x))]])

        # The determinant of a central-difference Jacobian (h = 1e-5 on derivatives good to 1e-14)
        # is noisy: hybr stalls short of a relative step of 1e-13 on some FMUs of the same equations
        # (the sympy oracle's among them), and stops early at 1e-10 (g = 7e-9); at 1e-11 every one
        # converges with g below 1e-9.
        sol = root(equations, [phi, delta, v], method="hybr", options={"xtol": 1e-11})
        assert sol.success, sol.message
        assert np.abs(self.g(*sol.x)).max() < 1e-9
        return sol.x

    def turns_near(self, phi, delta, v, radius: float, starts: int = 5) -> list[np.ndarray]:
        """Distinct turns (phi, delta) at speed v within ``radius`` [rad] of (phi, delta)."""
        found = []
        for a in np.linspace(-radius, radius, starts):
            for b in np.linspace(-radius, radius, starts):
                sol = root(lambda x: self.g(x[0], x[1], v), [phi + a, delta + b], method="hybr",
                           options={"xtol": 1e-13})
                x = sol.x
                if (sol.success and np.abs(self.g(x[0], x[1], v)).max() < 1e-10
                        and np.abs(x - [phi, delta]).max() < radius
                        and not any(np.abs(x - f).max() < 1e-7 for f in found)):
                    found.append(x)
        return found


def _conditions(fmu, variant):
    crown = VARIANTS[variant]
    return Bicycle(fmu, {**load_parameters(fig7.PARAMS), "tR": crown, "tF": crown})


@pytest.mark.parametrize("variant", list(VARIANTS), ids=["knife-edge", "toroidal"])
def test_folds_listed_on_both_sides(listed, variant):
    """At least one fold per side; the phi < 0 list is the mirror (-phi, -delta) of phi > 0; every
    fold has the steer beyond 90 degrees, opposite to the lean."""
    rows = listed[variant]["folds"]
    right = sorted((r for r in rows if r["side"] == "phi>0"), key=lambda r: r["v_m_s"])
    left = sorted((r for r in rows if r["side"] != "phi>0"), key=lambda r: r["v_m_s"])
    assert len(right) >= 1 and len(left) == len(right)
    for a, b in zip(right, left):
        assert (b["v_m_s"], b["phi_rad"], b["delta_rad"]) == (a["v_m_s"], -a["phi_rad"], -a["delta_rad"])
        assert a["phi_rad"] > 0 and a["delta_rad"] < -np.pi / 2
        assert a["residual_rad_s2"] < 1e-9
    assert f"{len(right)} saddle-node fold(s) per side" in listed[variant]["model_shows"]


@pytest.mark.parametrize("variant, v, phi, delta", FOLDS)
def test_fold_equals_independent_solve(listed, fmu, variant, v, phi, delta):
    """The independent fold solve from a rough start lands on a fold listed by `cosim figures
    fig7` (both sides: the conditions are odd under (phi, delta) -> (-phi, -delta))."""
    with _conditions(fmu, variant) as bike:
        c = TurnConditions(bike)
        phi_f, delta_f, v_f = c.fold(phi, delta, v)
        g = c.g(phi_f, delta_f, v_f)
        assert np.allclose(c.g(-phi_f, -delta_f, v_f), -g, rtol=0.0, atol=1e-12)
        # the Jacobian in (phi, delta) is singular: one singular value vanishes, the other not
        s = np.linalg.svd(c.jacobian(phi_f, delta_f, v_f), compute_uv=False)
        assert s[1] < 1e-6 * s[0]
    rows = listed[variant]["folds"]
    for sign, side in ((1.0, "phi>0"), (-1.0, "phi<0 (mirror)")):
        match = [r for r in rows if r["side"] == side and abs(r["v_m_s"] - v_f) < 1e-7 * v_f]
        assert len(match) == 1, f"no listed fold at V = {v_f:.8f} m/s on side {side}: {rows}"
        assert match[0]["phi_rad"] == pytest.approx(sign * phi_f, abs=1e-6)
        assert match[0]["delta_rad"] == pytest.approx(sign * delta_f, abs=1e-6)


@pytest.mark.parametrize("variant, v, phi, delta", FOLDS)
def test_two_turns_merge_and_vanish_at_the_fold(listed, fmu, variant, v, phi, delta):
    """Near a listed fold there are two turns at speeds on one side of it (the side its `kind`
    says) and none on the other."""
    rows = [r for r in listed[variant]["folds"] if r["side"] == "phi>0"]
    fold = min(rows, key=lambda r: abs(r["v_m_s"] - v))
    v_f, dv = fold["v_m_s"], 2e-3
    with _conditions(fmu, variant) as bike:
        c = TurnConditions(bike)
        counts = {s: len(c.turns_near(fold["phi_rad"], fold["delta_rad"], v_f + s * dv, radius=0.05))
                  for s in (-1, 1)}
    assert counts == ({-1: 0, 1: 2} if fold["kind"] == "min" else {-1: 2, 1: 0})


def test_knife_edge_fold_to_four_digits(listed):
    """The knife-edge fold where an independent check found it: V = 1.7371 m/s,
    phi = 0.2345 rad; its delta = -1.9335 rad was a point of the curve next to the fold (at
    V = 1.73714 the two turns have delta = -1.9332 and -1.9342), the fold itself is at -1.9337."""
    right = [r for r in listed["knife_edge"]["folds"] if r["side"] == "phi>0"]
    assert len(right) == 1
    assert right[0]["v_m_s"] == pytest.approx(1.7371, abs=5e-5)
    assert right[0]["phi_rad"] == pytest.approx(0.2345, abs=5e-5)
    assert right[0]["delta_rad"] == pytest.approx(-1.9335, abs=3e-4)
