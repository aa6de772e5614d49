"""Glue between the Meijaard parameter sets and the FMU of ``Bicycle.Bicycles.WhippleLinear``.

The Modelica model names its top-level parameters exactly as the symbols of Meijaard et al.
(2007), Table 1 (``w c lam g rR mR IRxx IRyy xB zB mB IBxx IBxz IByy IBzz xH zH mH IHxx IHxz
IHyy IHzz rF mF IFxx IFyy``), so a parameter set of :mod:`cosim.analytic.parameters` (a bundled
name such as ``benchmark``, ``astrom2005``, ``astrom2005-riderless`` or a TOML file) maps onto the
FMU by identity after validation (:func:`cosim.analytic.parameters.parameters_for_model`); the
forward speed is the FMU parameter ``v``.

FMU analysis helpers (all from :func:`cosim.fmu.linearize.linearize` of the FMU, never from the
analytic Python model):

* :func:`whipple_fmu` builds the model (incrementally) and returns the FMU path;
* :func:`state_matrix` / :func:`eigenvalues`: the 4x4 state matrix of ``[phi, delta, phi_dot,
  delta_dot]`` (the FMU's heading ``psi`` and lateral position ``y`` are integrators that do not
  feed back, so they are dropped) and its eigenvalues at one speed;
* :func:`weave_speed` / :func:`capsize_speed`: the stability boundaries by root finding
  (``scipy.optimize.brentq``) on FMU-linearization eigenvalues.

Sign conventions are Meijaard's: roll positive leaning right, steer positive to the right.
"""
from __future__ import annotations

import math
import os
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from cosim.analytic.parameters import parameters_for_model
from cosim.errors import SimulationError
from cosim.bicycle.linearize import linearize_speeds
from cosim.fmu.linearize import ParameterLinearizer, linearize
from cosim.compiler.library import load_library

__all__ = [
    "MODEL",
    "WHIPPLE_STATES",
    "SPEED",
    "parameters_for_model",
    "speed_sweep",
    "whipple_fmu",
    "linearization",
    "INPUTS",
    "state_space",
    "state_spaces",
    "closed_loop",
    "state_matrix",
    "sorted_eigenvalues",
    "eigenvalues",
    "oscillatory",
    "weave_speed",
    "capsize_speed",
]

#: The exported linear Whipple bicycle.
MODEL = "Bicycle.Bicycles.WhippleLinear"
#: The dynamic states of the model, in the FMU's state order (psi and y follow them).
WHIPPLE_STATES: tuple[str, ...] = ("phi", "delta", "phi_dot", "delta_dot")
#: The FMU parameter that holds the forward speed [m/s].
SPEED = "v"
#: The inputs of the model: roll torque and steer torque [N m].
INPUTS: tuple[str, ...] = ("T_phi", "T_delta")


def whipple_fmu(output: str | Path | None = None) -> Path:
    """The FMU of :data:`MODEL`, built into ``output`` (default: the project's ``fmus/``) if needed.

    The build is incremental (nothing is compiled when the FMU is up to date), so this is cheap
    to call repeatedly.
    """
    # the compiler imports pymoca and CasADi: only for a build
    # deferred: loads casadi, which importing this module does not
    from cosim.compiler.build import DEFAULT_OUTPUT, build_model

    return build_model(MODEL, output or DEFAULT_OUTPUT, load_library()).fmu


def linearization(fmu: str | Path, params: Mapping[str, float], v: float):
    """:func:`cosim.fmu.linearize.linearize` of the FMU at speed ``v`` (FMU parameter names)."""
    return linearize(fmu, {**{k: float(x) for k, x in params.items()}, SPEED: float(v)})


def state_space(fmu: str | Path, params: Mapping[str, float], v: float) -> tuple[np.ndarray, np.ndarray]:
    """``A`` (4x4) and ``B`` (4x2) of ``[phi, delta, phi_dot, delta_dot]`` from an FMU linearization.

    ``B``'s columns are the inputs ``T_phi`` and ``T_delta`` [N m]. A root finder asks for one
    speed after another with the same parameters: an FMU built here is then linearized on one
    instance per parameter set (:class:`cosim.fmu.linearize.ParameterLinearizer`, the same numbers
    as :func:`linearization`), the last :data:`KEPT_INSTANCES` sets kept.

    Raises
    ------
    ValueError
        If the FMU lacks one of the states or inputs, or the remaining states (``psi``, ``y``)
        feed back into them (which would make the 4x4 block's eigenvalues not the bicycle's).
    """
    params = {k: float(x) for k, x in params.items()}
    key = _linearizer(fmu, params)
    if key is None:
        system = linearization(fmu, params, v).system
        return _bicycle_blocks(fmu, system.states, system.inputs, [system.A], [system.B])[0]
    linearizer = _LINEARIZERS[key]
    try:
        A, B = linearizer.state_space(float(v))
    except SimulationError:  # a fresh instance for the next call
        _LINEARIZERS.pop(key).close()
        raise
    st = linearizer.structure
    return _bicycle_blocks(fmu, st.states, st.inputs, [A], [B])[0]


#: Parameter sets whose FMU instance :func:`state_space` keeps (a figure's root finders go
#: through one set after another).
KEPT_INSTANCES = 2
_LINEARIZERS: dict[tuple, ParameterLinearizer] = {}  # (FMU file version, parameters) -> instance


def _linearizer(fmu, params: dict) -> tuple | None:
    """The key in :data:`_LINEARIZERS` of the kept instance for ``fmu`` and ``params`` (made now
    if new); None for an FMU that :func:`linearization` runs otherwise (not built here, no
    directional derivatives) or with ``v`` among ``params``."""
    path = Path(fmu)
    try:
        status = path.stat()
    except OSError:
        return None  # linearization() names the problem
    key = (str(path.resolve()), status.st_size, status.st_mtime_ns, os.getpid(), tuple(params.items()))
    if key not in _LINEARIZERS:
        if SPEED in params or not ParameterLinearizer.usable(path):
            return None
        while len(_LINEARIZERS) >= KEPT_INSTANCES:
            _LINEARIZERS.pop(next(iter(_LINEARIZERS))).close()
        _LINEARIZERS[key] = ParameterLinearizer(path, SPEED, params)
    return key


def state_spaces(fmu: str | Path, params: Mapping[str, float], speeds) -> list[tuple[np.ndarray, np.ndarray]]:
    """:func:`state_space` at each of ``speeds`` [m/s] from one speed sweep
    (:func:`cosim.bicycle.linearize.linearize_speeds`: one FMU instance, the same matrices as one
    :func:`linearization` per speed); ValueError as :func:`state_space`."""
    sweep = linearize_speeds(fmu, [float(v) for v in speeds], {k: float(x) for k, x in params.items()})
    first = sweep.systems[0]
    return _bicycle_blocks(fmu, first.states, first.inputs, [s.A for s in sweep.systems],
                           [s.B for s in sweep.systems])


def _bicycle_blocks(fmu, states: list[str], inputs: list[str], As, Bs) -> list[tuple[np.ndarray, np.ndarray]]:
    """The (phi, delta, phi_dot, delta_dot) blocks of each (A, B) with the columns of ``INPUTS``;
    ValueError if a state or input is missing or another state feeds back into them."""
    missing = [s for s in WHIPPLE_STATES if s not in states] + [u for u in INPUTS if u not in inputs]
    if missing:
        raise ValueError(f"{fmu}: {', '.join(missing)} not found (states: {', '.join(states)}; "
                         f"inputs: {', '.join(inputs)})")
    idx = [states.index(s) for s in WHIPPLE_STATES]
    rest = [k for k in range(len(states)) if k not in idx]
    if rest and any(np.any(A[np.ix_(idx, rest)] != 0.0) for A in As):
        raise ValueError(f"{fmu}: states {', '.join(states[k] for k in rest)} feed back into the bicycle")
    columns = [inputs.index(u) for u in INPUTS]
    return [(A[np.ix_(idx, idx)], B[np.ix_(idx, columns)]) for A, B in zip(As, Bs)]


def closed_loop(A: np.ndarray, B: np.ndarray, roll_stiffness: float = 0.0) -> np.ndarray:
    """State matrix with the roll-torque feedback ``T_phi = -roll_stiffness * phi`` [N m/rad].

    A positive ``roll_stiffness`` is an extra restoring roll moment, e.g. of a crowned roller
    (see :mod:`cosim.figures.fig15`); it adds ``roll_stiffness / g`` to ``K0[0, 0]``.
    """
    if roll_stiffness == 0.0:
        return A
    return A - roll_stiffness * np.outer(B[:, 0], [1.0, 0.0, 0.0, 0.0])


def state_matrix(fmu: str | Path, params: Mapping[str, float], v: float, roll_stiffness: float = 0.0) -> np.ndarray:
    """The 4x4 state matrix of ``[phi, delta, phi_dot, delta_dot]`` from an FMU linearization
    (with the optional roll-torque feedback of :func:`closed_loop`)."""
    return closed_loop(*state_space(fmu, params, v), roll_stiffness)


def sorted_eigenvalues(A: np.ndarray) -> np.ndarray:
    """Eigenvalues of ``A`` sorted by real part, then imaginary part."""
    ev = np.linalg.eigvals(A)
    return ev[np.lexsort((ev.imag, ev.real))]


def eigenvalues(fmu: str | Path, params: Mapping[str, float], v: float, roll_stiffness: float = 0.0) -> np.ndarray:
    """Eigenvalues [1/s] of :func:`state_matrix`, sorted by real part, then imaginary part."""
    return sorted_eigenvalues(state_matrix(fmu, params, v, roll_stiffness))


def oscillatory(ev: np.ndarray) -> np.ndarray:
    """Mask of the eigenvalues that count as complex: ``|Im| > 1e-7 max(1, |lambda|)``.

    The same criterion as :mod:`cosim.analytic.whipple` (a real pair split by rounding right at
    a double root has ``|Im| ~ sqrt(eps) |lambda|``, far below it only away from it).
    """
    ev = np.asarray(ev)
    return np.abs(ev.imag) > 1e-7 * np.maximum(1.0, np.abs(ev))


def _weave_real(fmu, params, v: float, k: float = 0.0) -> float:
    ev = eigenvalues(fmu, params, v, k)
    osc = ev[oscillatory(ev)]
    return float(osc.real.max()) if osc.size else math.nan


def _brentq(f, a: float, b: float, xtol: float) -> float:
    from scipy.optimize import brentq

    return float(brentq(f, a, b, xtol=xtol, rtol=4 * np.finfo(float).eps, maxiter=200))


def weave_speed(fmu: str | Path, params: Mapping[str, float], *, bracket: tuple[float, float] | None = None,
                v_start: float = 0.25, v_max: float = 200.0, growth: float = 1.25,
                xtol: float = 1e-13, roll_stiffness: float = 0.0) -> float | None:
    """Speed [m/s] at which the weave (oscillatory) mode becomes stable, from FMU linearizations.

    ``f(v)`` = the largest real part of the oscillatory eigenvalues (:func:`oscillatory`) of the
    FMU's state matrix at speed ``v``. A bracket ``[a, b]`` with ``f(a) > 0 >= f(b)`` is taken
    from ``bracket`` if it holds there, else found on the geometric speed grid
    ``v_start * growth**k`` up to ``v_max`` (first pair of neighbours with oscillatory
    eigenvalues across which ``f`` turns non-positive); ``brentq`` refines it to ``xtol``.

    ``roll_stiffness`` [N m/rad] closes the loop ``T_phi = -roll_stiffness * phi`` first
    (:func:`closed_loop`). Returns None if the weave mode does not become stable below ``v_max``.
    """
    f = lambda v: _weave_real(fmu, params, v, roll_stiffness)
    if bracket is not None:
        a, b = map(float, bracket)
        fa, fb = f(a), f(b)
        if fa > 0.0 >= fb:
            return b if fb == 0.0 else _brentq(f, a, b, xtol)
    prev_v, prev_f = None, math.nan
    v = float(v_start)
    while v <= v_max * growth:
        fv = f(min(v, v_max))
        if prev_f > 0.0 and fv <= 0.0:
            return min(v, v_max) if fv == 0.0 else _brentq(f, prev_v, min(v, v_max), xtol)
        prev_v, prev_f = min(v, v_max), fv
        if v >= v_max:
            break
        v *= growth
    return None


def _det(fmu, params, v: float, k: float = 0.0) -> float:
    return float(np.linalg.det(state_matrix(fmu, params, v, k)))


def capsize_speed(fmu: str | Path, params: Mapping[str, float], *, v_start: float | None = None,
                  v_max: float = 200.0, growth: float = 1.25, xtol: float = 1e-13,
                  roll_stiffness: float = 0.0) -> float | None:
    """Speed [m/s] above which the real capsize mode is unstable, from FMU linearizations.

    A real eigenvalue crosses zero exactly where ``det A`` (the product of the eigenvalues)
    changes sign. Starting at ``v_start`` (default: :func:`weave_speed`, or 0 without one),
    ``det A`` of the FMU's state matrix is evaluated on the geometric grid
    ``v_start * growth**k`` up to ``v_max``; the first sign change is refined by ``brentq``
    (``det A`` is a polynomial in ``v``, so convergence is fast). The crossing counts only if
    the largest real eigenvalue at the upper end of its bracket is non-negative (a mode
    becoming unstable).

    ``roll_stiffness`` as in :func:`weave_speed`. Returns None if there is no such crossing
    below ``v_max``.
    """
    if v_start is None:
        vw = weave_speed(fmu, params, v_max=v_max, xtol=xtol, roll_stiffness=roll_stiffness)
        v_start = 0.0 if vw is None else vw
    f = lambda v: _det(fmu, params, v, roll_stiffness)
    a = float(v_start)
    fa = f(a)
    step = max(a, 0.25) * (growth - 1.0)
    while a < v_max:
        b = min(v_max, a + step)
        fb = f(b)
        if fa == 0.0 or fa * fb < 0.0 or fb == 0.0:
            # The crossing counts if a real eigenvalue is non-negative at the bracket's upper end.
            above = eigenvalues(fmu, params, b, roll_stiffness)
            real = above[~oscillatory(above)]
            if real.size and real.real.max() >= 0.0:
                return a if fa == 0.0 else (b if fb == 0.0 else _brentq(f, a, b, xtol))
        a, fa = b, fb
        step *= growth
    return None


def speed_sweep(fmu, parameter_set: str, speeds):
    """Eigenvalues at each speed (FMU linearizations) and the weave and capsize speeds.

    Returns ``(fmu, params, eigenvalues (len(speeds) x 4), weave speed, capsize speed)``."""
    fmu = fmu or whipple_fmu()
    params = parameters_for_model(parameter_set)
    ev = np.array([sorted_eigenvalues(A) for A, _ in state_spaces(fmu, params, speeds)])
    vw = weave_speed(fmu, params)
    return fmu, params, ev, vw, capsize_speed(fmu, params, v_start=vw)
