"""The adapted bicycle of Figure 15 of Astrom, Klein & Lennartsson (2005) on a crowned rear roller.

One definition for ``cosim figures fig15`` (:mod:`cosim.figures.fig15`) and the app's
"crowned roller" bicycle (:mod:`cosim.app.bicycles`): the parameter set
``cosim/params/adapted/fig15.toml`` (:data:`ADAPTED`, our choice: the paper gives no data; see
that file and docs/figures/README.md) and the roller's lateral radii :data:`RADII`.

The roller in the linearized model
----------------------------------
A toroidal rear wheel of crown (lateral) radius R that rolls by phi moves its ground contact
point sideways by R phi relative to the frame, towards the lean. The rear normal force
``N_R = g mT (1 - xT/w)`` (static load of the rear wheel; mT the total mass, xT its distance in
front of the rear contact) then acts with the lever R phi about the roll axis: a restoring roll
moment ``-k phi`` with ``k = g mT (1 - xT/w) R`` [N m/rad], i.e. Meijaard's ``K0[0, 0]`` becomes
``mT zT + mT (1 - xT/w) R`` (:func:`matrices`). This is the paper's eq (27) (m g h -> m g (h - R))
for a roller on the rear wheel only, and exactly the linearization of the nonlinear Whipple model
with a toroidal rear wheel (tests/test_fig5_fig15.py compares the state matrices to 1e-12).
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from cosim.analytic import whipple
from cosim.analytic.parameters import load_parameter_set, validate_parameters

__all__ = ["ADAPTED", "ADAPTED_NAME", "RADII", "CENTRE_OF_MASS_HEIGHT", "adapted_parameters", "roller_stiffness",
           "matrices", "eigenvalues", "weave_speed", "capsize_speed"]

#: The adapted bicycle's parameter file (Meijaard symbols, SI) and its name (``--params adapted/fig15``).
ADAPTED_NAME = "adapted/fig15"
ADAPTED = Path(__file__).resolve().parents[1] / "params" / f"{ADAPTED_NAME}.toml"
#: Lateral radii of the crowned rear roller [m]: the caption of Figure 15 (0.3) and its text (0.4).
RADII = (0.3, 0.4)
#: Height of the centre of mass of bicycle and rider above the ground [m] (the paper's text).
CENTRE_OF_MASS_HEIGHT = 0.4


def adapted_parameters() -> dict[str, float]:
    """The adapted bicycle with rider of Figure 15 (:data:`ADAPTED`), validated, by Meijaard symbol [SI]."""
    return validate_parameters(load_parameter_set(ADAPTED_NAME).values)


def _totals(p: Mapping[str, float]) -> tuple[float, float]:
    mT = p["mR"] + p["mB"] + p["mH"] + p["mF"]
    xT = (p["xB"] * p["mB"] + p["xH"] * p["mH"] + p["w"] * p["mF"]) / mT
    return mT, xT


def roller_stiffness(params: Mapping[str, float], radius: float) -> float:
    """``k = g mT (1 - xT/w) R`` [N m/rad]: the rear normal force times the contact's lateral shift
    per roll angle, for a rear roller of lateral radius ``radius`` [m] (0: a knife edge)."""
    mT, xT = _totals(params)
    return params["g"] * mT * (1.0 - xT / params["w"]) * radius


def matrices(params: Mapping[str, float], radius: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Meijaard's ``M, C1, K0, K2`` (:func:`cosim.analytic.whipple.matrices`) with the rear roller of
    lateral radius ``radius`` [m] in ``K0[0, 0]`` (module docstring)."""
    M, C1, K0, K2 = whipple.matrices(params)
    K0 = K0.copy()
    K0[0, 0] += roller_stiffness(params, radius) / params["g"]
    return M, C1, K0, K2


def eigenvalues(params: Mapping[str, float], radius: float, speeds) -> np.ndarray:
    """Eigenvalues [1/s] at each of ``speeds`` [m/s], shape ``(len(speeds), 4)``, sorted by real part."""
    p = validate_parameters(params, waive=("IByy", "IHyy"))
    ev = whipple._eigs(p, matrices(p, radius), np.asarray(speeds, dtype=float))
    return np.sort_complex(ev)


def weave_speed(params: Mapping[str, float], radius: float, v_max: float = 30.0) -> float | None:
    """Speed [m/s] at which the weave (oscillatory) mode becomes stable on the rear roller
    (:func:`cosim.analytic.whipple.weave_speed_of` of :func:`matrices`: a 0.01 m/s scan, the crossing
    located exactly); None if it stays unstable up to ``v_max``."""
    p = validate_parameters(params, waive=("IByy", "IHyy"))
    return whipple.weave_speed_of(p, matrices(p, radius), v_max=v_max, num=int(round(v_max / 0.01)) + 1)


def capsize_speed(params: Mapping[str, float], radius: float) -> float | None:
    """Speed [m/s] at which a real eigenvalue crosses zero (the capsize mode turns unstable), or None
    if there is none at any speed.

    Exact: a real root crosses zero where ``det(g K0 + v^2 K2) = 0``, which is linear in ``v^2``
    (the first column of ``K2`` is zero): ``v^2 = -g det(K0) / (K0[0,0] K2[1,1] - K0[1,0] K2[0,1])``;
    no positive solution means no crossing at any speed."""
    p = validate_parameters(params, waive=("IByy", "IHyy"))
    _, _, K0, K2 = matrices(p, radius)
    denominator = K0[0, 0] * K2[1, 1] - K0[1, 0] * K2[0, 1]
    if denominator == 0.0:
        return None
    v2 = -p["g"] * np.linalg.det(K0) / denominator
    return math.sqrt(v2) if v2 > 0.0 else None
