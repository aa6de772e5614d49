"""Linearized Whipple bicycle of Meijaard, Papadopoulos, Ruina & Schwab (2007).

The model (Meijaard et al. 2007, eq. (3.1) and Appendix A) is

.. math::

    M \\ddot q + v C_1 \\dot q + (g K_0 + v^2 K_2) q = f,
    \\qquad q = [\\phi, \\delta]^T, \\quad f = [T_\\phi, T_\\delta]^T,

with roll angle :math:`\\phi` (rad, positive leaning right), steer angle
:math:`\\delta` (rad, positive steering right), forward speed ``v`` (m/s) and
the applied roll and steer torques (N m).  Parameters are the 26 symbols of
Meijaard's Table 1 (see :mod:`cosim.analytic.parameters`).

Astrom, Klein & Lennartsson (2005), eq. (24)-(25), write the same model as
``M q'' + C V q' + (K0 + K2 V^2) q = [0, T]`` with the steer angle positive to
the LEFT and g folded into K0; :func:`astrom_matrices` converts.

Functions
---------
matrices, astrom_matrices, state_matrices, state_space, eigenvalues,
characteristic_polynomial, weave_speed, capsize_speed, self_stable_interval,
asymptotic_eigenvalues.
"""
from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from cosim.analytic.parameters import validate_parameters

__all__ = [
    "STATES",
    "INPUTS",
    "matrices",
    "astrom_matrices",
    "state_matrices",
    "state_space",
    "eigenvalues",
    "characteristic_polynomial",
    "weave_speed",
    "weave_speed_of",
    "capsize_speed",
    "self_stable_interval",
    "asymptotic_eigenvalues",
]

#: State names of :func:`state_space`: roll (rad), steer (rad) and their rates (rad/s).
STATES: tuple[str, ...] = ("phi", "delta", "phi_dot", "delta_dot")
#: Input names of :func:`state_space`: roll torque and steer torque (N m).
INPUTS: tuple[str, ...] = ("T_phi", "T_delta")

#: Default speed scan of the stability-boundary searches (m/s).
DEFAULT_V_MAX = 30.0
DEFAULT_NUM = 3001

# IByy and IHyy do not enter M, C1, K0, K2: their only checks (triangle
# inequalities) are not model requirements, so the model functions skip them.
_MODEL_WAIVE = ("IByy", "IHyy")


def _checked(params: Mapping[str, float]) -> dict[str, float]:
    return validate_parameters(params, waive=_MODEL_WAIVE)


def matrices(params: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Mass, damping-like and stiffness matrices of Meijaard et al. (2007).

    Closed-form expressions of Meijaard et al. (2007), Appendix A: total
    mass and centre of mass, inertia of the whole bicycle about the rear
    contact point (``T``), front assembly ``A = H + F`` and its inertia about
    the steer axis, ``mu = c cos(lam) / w``, gyrostatic coefficients
    ``SR = IRyy/rR``, ``SF = IFyy/rF``, ``ST = SR + SF`` and the static
    moment ``SA = mA uA + mu mT xT``.

    Parameters
    ----------
    params : mapping of str to float
        Meijaard parameter set (SI units), e.g. from
        :func:`cosim.analytic.parameters.load_parameters`.  Validated with
        :func:`~cosim.analytic.parameters.validate_parameters`, except the
        triangle inequalities of ``IByy``/``IHyy`` (these two inertias do not
        enter the linearized model).

    Returns
    -------
    M : ndarray, shape (2, 2)
        Mass matrix [kg m^2], symmetric positive definite.
    C1 : ndarray, shape (2, 2)
        Velocity-proportional matrix [kg m], multiplied by ``v`` [m/s]
        (``v C1`` in kg m^2/s).
    K0 : ndarray, shape (2, 2)
        Gravity stiffness [kg m], multiplied by ``g``.
    K2 : ndarray, shape (2, 2)
        Speed stiffness [kg], multiplied by ``v**2``.

    Raises
    ------
    ValueError
        Invalid parameters (message starts with the key), or a mass matrix
        that is not positive definite.
    """
    p = _checked(params)
    w, c, lam = p["w"], p["c"], p["lam"]
    rR, mR, IRxx, IRyy = p["rR"], p["mR"], p["IRxx"], p["IRyy"]
    xB, zB, mB, IBxx, IBxz, IBzz = p["xB"], p["zB"], p["mB"], p["IBxx"], p["IBxz"], p["IBzz"]
    xH, zH, mH, IHxx, IHxz, IHzz = p["xH"], p["zH"], p["mH"], p["IHxx"], p["IHxz"], p["IHzz"]
    rF, mF, IFxx, IFyy = p["rF"], p["mF"], p["IFxx"], p["IFyy"]
    IRzz, IFzz = IRxx, IFxx  # axisymmetric wheels
    sl, cl = math.sin(lam), math.cos(lam)

    # Whole bicycle: mass, centre of mass, inertia about the rear contact point (A1-A6).
    mT = mR + mB + mH + mF
    xT = (xB * mB + xH * mH + w * mF) / mT
    zT = (-rR * mR + zB * mB + zH * mH - rF * mF) / mT
    ITxx = IRxx + IBxx + IHxx + IFxx + mR * rR**2 + mB * zB**2 + mH * zH**2 + mF * rF**2
    ITxz = IBxz + IHxz - mB * xB * zB - mH * xH * zH + mF * w * rF
    ITzz = IRzz + IBzz + IHzz + IFzz + mB * xB**2 + mH * xH**2 + mF * w**2

    # Front assembly A = H + F (A7-A12).
    mA = mH + mF
    xA = (xH * mH + w * mF) / mA
    zA = (zH * mH - rF * mF) / mA
    IAxx = IHxx + IFxx + mH * (zH - zA) ** 2 + mF * (rF + zA) ** 2
    IAxz = IHxz - mH * (xH - xA) * (zH - zA) + mF * (w - xA) * (rF + zA)
    IAzz = IHzz + IFzz + mH * (xH - xA) ** 2 + mF * (w - xA) ** 2
    # Perpendicular distance of A's centre of mass from the steer axis, and the
    # front assembly's inertia about / products with the steer axis (A13-A16).
    uA = (xA - w - c) * cl - zA * sl
    IAll = mA * uA**2 + IAxx * sl**2 + 2.0 * IAxz * sl * cl + IAzz * cl**2
    IAlx = -mA * uA * zA + IAxx * sl + IAxz * cl
    IAlz = mA * uA * xA + IAxz * sl + IAzz * cl

    # Trail factor, gyrostatic coefficients and static moment (A17-A21).
    mu = c / w * cl
    SR = IRyy / rR
    SF = IFyy / rF
    ST = SR + SF
    SA = mA * uA + mu * mT * xT

    Mpd = IAlx + mu * ITxz
    M = np.array([[ITxx, Mpd],
                  [Mpd, IAll + 2.0 * mu * IAlz + mu**2 * ITzz]])
    K0 = np.array([[mT * zT, -SA],
                   [-SA, -SA * sl]])
    K2 = np.array([[0.0, (ST - mT * zT) * cl / w],
                   [0.0, (SA + SF * sl) * cl / w]])
    C1 = np.array([[0.0, mu * ST + SF * cl + ITxz * cl / w - mu * mT * zT],
                   [-(mu * ST + SF * cl), IAlz * cl / w + mu * (SA + ITzz * cl / w)]])
    if not (M[0, 0] > 0.0 and np.linalg.det(M) > 0.0):
        raise ValueError(f"mass matrix not positive definite: M = {M.tolist()}")
    return M, C1, K0, K2


def astrom_matrices(params: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Matrices in the conventions of Astrom, Klein & Lennartsson (2005), eq. (24)-(25).

    The paper writes ``M q'' + C V q' + (K0 + K2 V^2) q = [0, T]`` with
    ``q = [phi, delta]``, roll positive to the right (as Meijaard) but steer
    angle and steer torque positive to the LEFT (Meijaard: right), and g
    included in its K0.  With ``S = diag(1, -1)`` (``q_Meijaard = S q_Astrom``,
    premultiplied by ``S``)::

        M_A = S M S,  C_A = S C1 S,  K0_A = g S K0 S,  K2_A = S K2 S,

    i.e. the off-diagonal entries change sign, diagonals are unchanged.

    Parameters
    ----------
    params : mapping of str to float
        Meijaard parameter set (SI), e.g. ``load_parameters("astrom2005")``.

    Returns
    -------
    M : ndarray, shape (2, 2)
        [kg m^2].
    C : ndarray, shape (2, 2)
        [kg m], multiplied by V [m/s].
    K0 : ndarray, shape (2, 2)
        [N m/rad = kg m^2/s^2], gravity included.
    K2 : ndarray, shape (2, 2)
        [kg], multiplied by V**2.
    """
    M, C1, K0, K2 = matrices(params)
    S = np.diag([1.0, -1.0])
    g = float(params["g"])
    return S @ M @ S, S @ C1 @ S, g * (S @ K0 @ S), S @ K2 @ S


def state_matrices(params: Mapping[str, float], v: float) -> tuple[np.ndarray, np.ndarray]:
    """First-order form ``x' = A x + B u`` at forward speed ``v``.

    Parameters
    ----------
    params : mapping of str to float
        Meijaard parameter set (SI).
    v : float
        Forward speed [m/s] (negative: riding backwards).

    Returns
    -------
    A : ndarray, shape (4, 4)
        State matrix for ``x = [phi, delta, phi_dot, delta_dot]`` (rad, rad/s):
        ``[[0, I], [-M^-1 (g K0 + v^2 K2), -v M^-1 C1]]``.
    B : ndarray, shape (4, 2)
        Input matrix for ``u = [T_phi, T_delta]`` (N m): ``[[0], [M^-1]]``.
    """
    M, C1, K0, K2 = matrices(params)
    return assembled_state_matrices(np.linalg.inv(M), C1, K0, K2, float(params["g"]), float(v))


def assembled_state_matrices(Minv, C1, K0, K2, g: float, v: float) -> tuple[np.ndarray, np.ndarray]:
    """:func:`state_matrices` from ``M^-1`` [1/(kg m^2)], ``C1``, ``K0``, ``K2`` (:func:`matrices`),
    ``g`` [m/s^2] and ``v`` [m/s]: for callers that keep the speed-independent part."""
    A = np.zeros((4, 4))
    A[:2, 2:] = np.eye(2)
    A[2:, :2] = -Minv @ (g * K0 + v**2 * K2)
    A[2:, 2:] = -v * (Minv @ C1)
    B = np.zeros((4, 2))
    B[2:, :] = Minv
    return A, B


def state_space(params: Mapping[str, float], v: float):
    """python-control state-space model at forward speed ``v``.

    Parameters
    ----------
    params : mapping of str to float
        Meijaard parameter set (SI).
    v : float
        Forward speed [m/s].

    Returns
    -------
    control.StateSpace
        ``A, B`` from :func:`state_matrices`, ``C = I`` (outputs are the
        states), ``D = 0``; states and outputs named :data:`STATES`
        (``phi, delta`` [rad], ``phi_dot, delta_dot`` [rad/s]), inputs
        :data:`INPUTS` (``T_phi, T_delta`` [N m]); system name ``"whipple"``.
    """
    import control

    A, B = state_matrices(params, v)
    return control.ss(A, B, np.eye(4), np.zeros((4, 2)), states=list(STATES), inputs=list(INPUTS),
                      outputs=list(STATES), name="whipple")


def _sorted_eigs(ev: np.ndarray) -> np.ndarray:
    order = np.lexsort((ev.imag, ev.real), axis=-1)
    return np.take_along_axis(ev, order, axis=-1)


def _eigs(p: dict[str, float], mats, speeds: np.ndarray) -> np.ndarray:
    """Eigenvalues for an array of speeds, shape (n, 4), unsorted."""
    M, C1, K0, K2 = mats
    Minv = np.linalg.inv(M)
    speeds = np.asarray(speeds, dtype=float).reshape(-1)
    n = speeds.size
    A = np.zeros((n, 4, 4))
    A[:, 0, 2] = A[:, 1, 3] = 1.0
    A[:, 2:, :2] = -(Minv @ (p["g"] * K0))[None] - speeds[:, None, None] ** 2 * (Minv @ K2)[None]
    A[:, 2:, 2:] = -speeds[:, None, None] * (Minv @ C1)[None]
    return np.linalg.eigvals(A)


def eigenvalues(params: Mapping[str, float], v) -> np.ndarray:
    """Eigenvalues of the linearized bicycle at speed(s) ``v``.

    Parameters
    ----------
    params : mapping of str to float
        Meijaard parameter set (SI).
    v : float or array_like of float
        Forward speed(s) [m/s].

    Returns
    -------
    ndarray of complex
        Shape (4,) for scalar ``v``, otherwise ``v.shape + (4,)``: the
        eigenvalues [1/s] of :func:`state_matrices` ``A``, sorted by real
        part, then imaginary part.
    """
    p = _checked(params)
    mats = matrices(p)
    varr = np.asarray(v, dtype=float)
    ev = _sorted_eigs(_eigs(p, mats, varr))
    return ev[0] if varr.ndim == 0 else ev.reshape(varr.shape + (4,))


def characteristic_polynomial(params: Mapping[str, float], v: float) -> np.ndarray:
    """Coefficients of ``det(s^2 M + v s C1 + g K0 + v^2 K2)``.

    Parameters
    ----------
    params : mapping of str to float
        Meijaard parameter set (SI).
    v : float
        Forward speed [m/s].

    Returns
    -------
    ndarray, shape (5,)
        Coefficients, highest power of ``s`` first (``numpy.roots`` order);
        the leading one is ``det M``.  Its roots are the eigenvalues.
    """
    M, C1, K0, K2 = matrices(params)
    v = float(v)
    K = float(params["g"]) * K0 + v**2 * K2
    return _det_quadratic(M, v * C1, K)


def _det_quadratic(M: np.ndarray, C: np.ndarray, K: np.ndarray) -> np.ndarray:
    """Coefficients of det(s^2 M + s C + K) for 2x2 matrices, highest first (numbers, or
    polynomials in the speed: object arrays of numpy Polynomials)."""
    def entry(i, j):
        return np.array([M[i, j], C[i, j], K[i, j]])
    return np.polysub(np.polymul(entry(0, 0), entry(1, 1)), np.polymul(entry(0, 1), entry(1, 0)))


def _imag_tol(ev: np.ndarray) -> np.ndarray:
    # Eigenvalues with |Im| below this count as real (numerical noise of a
    # real pair is ~ sqrt(eps) * |lambda| only right at a double root).
    return 1e-7 * np.maximum(1.0, np.abs(ev))


def _weave_real(p, mats, v: float) -> float:
    """Largest real part among oscillatory eigenvalues (nan if none)."""
    ev = _eigs(p, mats, np.array([v]))[0]
    osc = ev[np.abs(ev.imag) > _imag_tol(ev)]
    return float(osc.real.max()) if osc.size else math.nan


def _real_mode_max(p, mats, v: float) -> float:
    """Largest real eigenvalue (nan if none)."""
    ev = _eigs(p, mats, np.array([v]))[0]
    real = ev[np.abs(ev.imag) <= _imag_tol(ev)]
    return float(real.real.max()) if real.size else math.nan


def _max_real(p, mats, v: float) -> float:
    return float(_eigs(p, mats, np.array([v]))[0].real.max())


def _crossing_polynomial(p, mats) -> np.polynomial.Polynomial:
    """``P(v) = a0(v) H3(v)``: zero wherever an eigenvalue crosses the imaginary axis.

    With ``det(s^2 M + s v C1 + g K0 + v^2 K2) = a4 s^4 + a3 s^3 + a2 s^2 + a1 s + a0`` (each
    ``a_k`` a polynomial in ``v``), a real eigenvalue crosses zero where ``a0(v) = 0`` and a
    complex pair crosses the imaginary axis where the Hurwitz determinant
    ``H3 = a1 a2 a3 - a4 a1^2 - a0 a3^2`` vanishes (Routh-Hurwitz for the quartic; ``H3 = 0``
    also at a real pair ``+-r``, which the sign test of :func:`_refine` tells apart).
    """
    V = np.polynomial.Polynomial
    M, C1, K0, K2 = mats
    v = V([0.0, 1.0])

    def matrix(entry):  # 2 x 2 of polynomials in v
        return np.array([[entry(i, j) for j in range(2)] for i in range(2)], dtype=object)

    a4, a3, a2, a1, a0 = _det_quadratic(matrix(lambda i, j: V([M[i, j]])), matrix(lambda i, j: C1[i, j] * v),
                                        matrix(lambda i, j: p["g"] * K0[i, j] + K2[i, j] * v**2))
    return a0 * (a1 * a2 * a3 - a4 * a1**2 - a0 * a3**2)


def _refine(f, a: float, b: float, polynomial: np.polynomial.Polynomial) -> float:
    """The speed in ``[a, b]`` where ``f`` (an eigenvalue's real part) changes sign.

    ``f`` changes sign only where an eigenvalue crosses the imaginary axis, i.e. at a real root
    of ``polynomial`` (:func:`_crossing_polynomial`): of its roots in the bracket (numpy's
    companion-matrix roots, each polished by one Newton step), the one across which ``f``
    changes sign. Exact up to rounding, and without an iterative root finder.
    """
    d = polynomial.deriv()
    found = []
    for r in polynomial.roots():
        if abs(r.imag) > 1e-9 * max(1.0, abs(r.real)):
            continue
        x = float(r.real)
        slope = float(d(x))
        if slope != 0.0:
            x -= float(polynomial(x)) / slope
        if a - 1e-12 <= x <= b + 1e-12:
            found.append(min(max(x, a), b))
    found = sorted(set(found))
    if len(found) == 1:
        return found[0]
    # several candidates in the bracket: the one with f on opposite sides just before and after
    fa = f(a)
    edges = [a, *((x + y) / 2 for x, y in zip(found, found[1:])), b]
    for x, after in zip(found, edges[1:]):
        if np.sign(f(after)) != np.sign(fa):
            return x
    raise ArithmeticError(f"no eigenvalue crosses the imaginary axis in [{a!r}, {b!r}] m/s although the "
                          "scan saw a sign change; refine the scan (num)")


def _scan(p, mats, v_min: float, v_max: float, num: int):
    if not (math.isfinite(v_min) and math.isfinite(v_max) and v_max > v_min and num >= 2):
        raise ValueError(f"bad speed scan: v_min={v_min!r}, v_max={v_max!r}, num={num!r}")
    speeds = np.linspace(v_min, v_max, int(num))
    return speeds, _eigs(p, mats, speeds)


def weave_speed(params: Mapping[str, float], *, v_min: float = 0.0, v_max: float = DEFAULT_V_MAX,
                num: int = DEFAULT_NUM) -> float | None:
    """Speed at which the weave (oscillatory) mode becomes stable.

    Method: eigenvalues are scanned on ``numpy.linspace(v_min, v_max, num)``;
    the oscillatory part of the spectrum is the eigenvalues with
    ``|Im| > 1e-7 max(1, |lambda|)``.  The first pair of neighbouring scan
    speeds, both with oscillatory eigenvalues, across which their largest
    real part changes sign from positive to non-positive brackets the root,
    which :func:`_refine` locates exactly: a root of the Routh-Hurwitz determinant of the
    characteristic polynomial (a polynomial in the speed).

    Parameters
    ----------
    params : mapping of str to float
        Meijaard parameter set (SI).
    v_min, v_max : float, optional
        Scanned speed range [m/s] (default 0 to 30).
    num : int, optional
        Number of scan speeds (default 3001, i.e. 0.01 m/s steps).

    Returns
    -------
    float or None
        Weave speed [m/s], or ``None`` if the weave mode does not become
        stable within the range.
    """
    p = _checked(params)
    return weave_speed_of(p, matrices(p), v_min=v_min, v_max=v_max, num=num)


def weave_speed_of(p: Mapping[str, float], mats, *, v_min: float = 0.0, v_max: float = DEFAULT_V_MAX,
                   num: int = DEFAULT_NUM) -> float | None:
    """:func:`weave_speed` of the bicycle ``M, C1, K0, K2 = mats`` (:func:`matrices`, or matrices
    changed from them, as :mod:`cosim.analytic.roller`'s) with the gravity ``p["g"]`` [m/s^2]."""
    speeds, ev = _scan(p, mats, v_min, v_max, num)
    osc = np.abs(ev.imag) > _imag_tol(ev)
    wr = np.where(osc, ev.real, -np.inf).max(axis=1)
    has = osc.any(axis=1)
    for i in range(len(speeds) - 1):
        if has[i] and has[i + 1] and wr[i] > 0.0 >= wr[i + 1]:
            if wr[i + 1] == 0.0:
                return float(speeds[i + 1])
            return _refine(lambda v: _weave_real(p, mats, v), speeds[i], speeds[i + 1],
                           _crossing_polynomial(p, mats))
    return None


def capsize_speed(params: Mapping[str, float], *, v_min: float | None = None, v_max: float = DEFAULT_V_MAX,
                  num: int = DEFAULT_NUM) -> float | None:
    """Speed at which the (real) capsize mode becomes unstable.

    Method: scan as in :func:`weave_speed`, starting at the weave speed if
    there is one (else at 0) unless ``v_min`` is given; the first sign change
    from negative to non-negative of the largest *real* eigenvalue
    (``|Im| <= 1e-7 max(1, |lambda|)``) is located exactly as in :func:`weave_speed`.  A real
    eigenvalue crosses zero exactly where ``det(g K0 + v^2 K2) = 0``;
    because ``K2`` has a zero first column this is linear in ``v^2``, so
    ``v_c^2 = -g det(K0) / (K0[0,0] K2[1,1] - K0[1,0] K2[0,1])`` (used in the
    tests as an independent check).

    Parameters
    ----------
    params : mapping of str to float
        Meijaard parameter set (SI).
    v_min : float, optional
        Start of the scan [m/s]; default: :func:`weave_speed` or 0.
    v_max : float, optional
        End of the scan [m/s] (default 30).
    num : int, optional
        Number of scan speeds (default 3001).

    Returns
    -------
    float or None
        Capsize speed [m/s], or ``None`` if there is no such crossing.
    """
    p = _checked(params)
    mats = matrices(p)
    if v_min is None:
        vw = weave_speed(p, v_max=v_max, num=num)
        v_min = 0.0 if vw is None else vw
    speeds, ev = _scan(p, mats, v_min, v_max, num)
    real = np.abs(ev.imag) <= _imag_tol(ev)
    rr = np.where(real, ev.real, -np.inf).max(axis=1)
    has = real.any(axis=1)
    for i in range(len(speeds) - 1):
        if has[i] and has[i + 1] and rr[i] < 0.0 <= rr[i + 1]:
            if rr[i + 1] == 0.0:
                return float(speeds[i + 1])
            return _refine(lambda v: _real_mode_max(p, mats, v), speeds[i], speeds[i + 1],
                           _crossing_polynomial(p, mats))
    return None


def self_stable_interval(params: Mapping[str, float], *, v_min: float = 0.0, v_max: float = DEFAULT_V_MAX,
                         num: int = DEFAULT_NUM) -> tuple[float, float] | None:
    """First speed interval in which all eigenvalues have negative real part.

    Method: the largest real part of all eigenvalues is scanned on
    ``numpy.linspace(v_min, v_max, num)``; both ends of the first run of
    negative values are located exactly as in :func:`weave_speed`.  For a bicycle like the benchmark this is
    ``(weave_speed, capsize_speed)``.

    Parameters
    ----------
    params : mapping of str to float
        Meijaard parameter set (SI).
    v_min, v_max : float, optional
        Scanned range [m/s] (default 0 to 30).
    num : int, optional
        Number of scan speeds (default 3001).

    Returns
    -------
    (float, float) or None
        ``(v_low, v_high)`` [m/s]; ``v_high = inf`` if still stable at
        ``v_max`` (stable up to the end of the scan, not proven beyond);
        ``None`` if no scanned speed is stable.
    """
    p = _checked(params)
    mats = matrices(p)
    speeds, ev = _scan(p, mats, v_min, v_max, num)
    mr = ev.real.max(axis=1)
    stable = np.flatnonzero(mr < 0.0)
    if stable.size == 0:
        return None
    i0 = int(stable[0])
    f = lambda v: _max_real(p, mats, v)  # noqa: E731
    crossing = _crossing_polynomial(p, mats)
    lo = float(speeds[0]) if i0 == 0 else _refine(f, speeds[i0 - 1], speeds[i0], crossing)
    unstable_after = np.flatnonzero(mr[i0:] >= 0.0)
    if unstable_after.size == 0:
        return lo, math.inf
    j = i0 + int(unstable_after[0])
    hi = float(speeds[j]) if mr[j] == 0.0 else _refine(f, speeds[j - 1], speeds[j], crossing)
    return lo, hi


def asymptotic_eigenvalues(params: Mapping[str, float]) -> np.ndarray:
    """High-speed limits ``lim_{v->inf} lambda / v`` of the eigenvalues.

    Method: with ``lambda = v sigma``,
    ``det(lambda^2 M + v lambda C1 + g K0 + v^2 K2)
    = v^4 det(sigma^2 M + sigma C1 + K2 + g K0 / v^2)``, so the limits are the
    roots of the quartic ``det(sigma^2 M + sigma C1 + K2)``, whose
    coefficients are formed exactly and solved with ``numpy.roots``.  Because
    the first column of ``K2`` is zero, its constant term is exactly 0 and
    one root is exactly ``sigma = 0`` (that eigenvalue grows more slowly than
    ``v``; Astrom et al. 2005: "one pole approaches zero").

    Parameters
    ----------
    params : mapping of str to float
        Meijaard parameter set (SI).

    Returns
    -------
    ndarray of complex, shape (4,)
        ``sigma`` [1/m] (eigenvalue per unit speed), sorted by real part then
        imaginary part; one entry is exactly 0.
    """
    M, C1, _K0, K2 = matrices(params)
    coeffs = _det_quadratic(M, C1, K2)
    roots = np.roots(coeffs).astype(complex)
    roots = np.concatenate([roots, np.zeros(4 - roots.size, dtype=complex)])
    return _sorted_eigs(roots)
