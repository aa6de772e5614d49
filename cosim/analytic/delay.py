"""Characteristic roots of a linear system with one delayed feedback (a retarded delay equation).

The loop ``x'(t) = A x(t) + E x(t - tau)`` (time in s, ``A`` and ``E`` in 1/s) has the
characteristic function

    f(s) = det(s I - A - E exp(-s tau)),

an entire function with infinitely many zeros; for ``tau > 0`` only finitely many lie to the right
of any vertical line (retarded type), so the rightmost roots decide stability. For a plant
``x' = A x + B u, y = C x`` with the rider's delayed output feedback ``u(t) = K y(t - tau)``,
``E = B K C``.

Roots are found in three steps (:func:`characteristic_roots`):

1. *Estimates*: eigenvalues of the Chebyshev pseudospectral discretization of the infinitesimal
   generator of the delay equation (Breda, Maset & Vermiglio, SIAM J. Sci. Comput. 27(2), 2005),
   which converge spectrally to the rightmost roots.
2. *Refinement*: Newton's method on the exact ``f``, with ``f'/f = tr(M(s)^-1 M'(s))``.
3. *Certificate*: every root with ``Re s >= sigma`` satisfies ``|s| <= ||A|| + ||E|| exp(-sigma tau)``
   (``s`` is an eigenvalue of ``A + E exp(-s tau)``), so the half plane holds its roots in a known
   rectangle; the argument principle on that rectangle counts them, and the count must equal the
   number of roots found, else :class:`DelayRootError`.

For a single-input single-output loop the delays at which a root crosses the imaginary axis also
follow from the frequency response (:func:`crossing_delays`): at a gain-crossover frequency
``w_c`` (``|L(i w_c)| = 1``, ``L = -K G``) the loop has a root ``i w_c`` for
``tau = (phase margin + 2 pi m) / w_c``. The two methods are independent and check each other.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = [
    "CrossingDelay",
    "DelayRootError",
    "characteristic_function",
    "characteristic_roots",
    "critical_delay",
    "crossing_delays",
    "feedback_matrices",
    "first_crossing_delay",
    "largest_pd_delay",
    "spectral_abscissa",
    "stable_delay_intervals",
]


class DelayRootError(ArithmeticError):
    """The roots of a delay equation could not be found or certified (the message says why)."""


def _matrices(A, E) -> tuple[np.ndarray, np.ndarray]:
    A = np.atleast_2d(np.asarray(A, dtype=float))
    E = np.atleast_2d(np.asarray(E, dtype=float))
    if A.ndim != 2 or A.shape[0] != A.shape[1]:
        raise ValueError(f"A must be a square matrix, got shape {A.shape}")
    if E.shape != A.shape:
        raise ValueError(f"E must have the shape of A {A.shape}, got {E.shape}")
    if not (np.all(np.isfinite(A)) and np.all(np.isfinite(E))):
        raise ValueError("A and E must be finite")
    return A, E


def _delay(tau) -> float:
    tau = float(tau)
    if not math.isfinite(tau) or tau < 0:
        raise ValueError(f"tau must be a finite delay >= 0 s, got {tau!r}")
    return tau


def feedback_matrices(A, B, C, K) -> tuple[np.ndarray, np.ndarray]:
    """``(A, E = B K C)`` of the plant ``x' = A x + B u, y = C x`` under ``u(t) = K y(t - tau)``.

    Parameters
    ----------
    A, B, C : array_like
        State-space matrices of a strictly proper plant (``D = 0``; a feedthrough would make the
        delay equation of neutral type, which this module does not treat).
    K : float or array_like
        Feedback gain (inputs x outputs), in the units of ``u`` per unit of ``y``.
    """
    A = np.atleast_2d(np.asarray(A, dtype=float))
    B = np.asarray(B, dtype=float).reshape(A.shape[0], -1)
    C = np.asarray(C, dtype=float).reshape(-1, A.shape[0])
    K = np.asarray(K, dtype=float).reshape(B.shape[1], C.shape[0])
    return A, B @ K @ C


def _matrix(A, E, tau, s) -> np.ndarray:
    """M(s) = s I - A - E exp(-s tau) for an array of ``s`` (stacked along the first axes)."""
    s = np.asarray(s, dtype=complex)
    eye = np.eye(A.shape[0])
    return s[..., None, None] * eye - A - E * np.exp(-s * tau)[..., None, None]


def characteristic_function(A, E, tau, s) -> np.ndarray:
    """``f(s) = det(s I - A - E exp(-s tau))`` at ``s`` (scalar or array, 1/s)."""
    A, E = _matrices(A, E)
    return np.linalg.det(_matrix(A, E, _delay(tau), s))


def _chebyshev(N: int) -> tuple[np.ndarray, np.ndarray]:
    """Chebyshev points x_j = cos(j pi / N) and the differentiation matrix (Trefethen 2000, cheb)."""
    x = np.cos(np.pi * np.arange(N + 1) / N)
    c = np.ones(N + 1)
    c[0] = c[-1] = 2.0
    c *= (-1.0) ** np.arange(N + 1)
    dx = x[:, None] - x[None, :]
    D = np.outer(c, 1.0 / c) / (dx + np.eye(N + 1))
    D -= np.diag(D.sum(axis=1))
    return x, D


def _estimates(A, E, tau, N) -> np.ndarray:
    """Eigenvalues of the pseudospectral generator on N + 1 Chebyshev nodes of [-tau, 0]."""
    n = A.shape[0]
    _, D = _chebyshev(N)  # nodes theta_j = tau (x_j - 1) / 2: theta_0 = 0, theta_N = -tau
    G = np.kron((2.0 / tau) * D, np.eye(n))
    G[:n, :] = 0.0  # the row of theta = 0 is the delay equation itself
    G[:n, :n] = A
    G[:n, -n:] = E
    return np.linalg.eigvals(G)


def _newton(A, E, tau, s, iterations=60) -> complex | None:
    eye = np.eye(A.shape[0])
    for _ in range(iterations):
        M = _matrix(A, E, tau, s)
        dM = eye + tau * E * np.exp(-s * tau)
        try:
            ratio = np.trace(np.linalg.solve(M, dM))  # f'/f
        except np.linalg.LinAlgError:
            return complex(s)  # M singular: s is a root to machine precision
        if ratio == 0 or not np.isfinite(ratio):
            return None
        step = 1.0 / ratio
        s = s - step
        if abs(step) <= 1e-13 * (1.0 + abs(s)):
            return complex(s)
    return None


def _phase(A, E, tau, s) -> np.ndarray:
    sign, _ = np.linalg.slogdet(_matrix(A, E, tau, s))
    return np.angle(sign)


def _winding(A, E, tau, corners, points: int, depth: int = 30) -> int:
    """Zeros of f inside the closed polygon ``corners`` (counter-clockwise), argument principle.

    Each edge is sampled ``points`` times; an interval over which the phase of f turns by more
    than pi/4 is bisected until it does not (a zero on the contour would need endless bisection:
    :class:`DelayRootError`)."""
    total = 0.0
    for a, b in zip(corners, corners[1:] + corners[:1]):
        t = np.linspace(0.0, 1.0, points + 1)
        for _ in range(depth):
            phase = _phase(A, E, tau, a + (b - a) * t)
            turn = np.angle(np.exp(1j * np.diff(phase)))
            coarse = np.abs(turn) > np.pi / 4
            if not coarse.any():
                break
            t = np.sort(np.concatenate([t, 0.5 * (t[:-1] + t[1:])[coarse]]))
        else:
            raise DelayRootError(f"a characteristic root lies on or next to the contour edge {a:.6g} -> {b:.6g}")
        total += turn.sum()
    return round(total / (2.0 * np.pi))


def _distinct(roots, tolerance=1e-7) -> list[complex]:
    kept: list[complex] = []
    for r in sorted(roots, key=lambda z: (-z.real, z.imag)):
        if all(abs(r - k) > tolerance * (1.0 + abs(k)) for k in kept):
            kept.append(r)
    return kept


def characteristic_roots(A, E, tau, sigma: float | None = None, width: float = 1.0) -> np.ndarray:
    """Every characteristic root with ``Re s >= sigma`` of ``x' = A x + E x(t - tau)``, certified.

    Parameters
    ----------
    A, E : array_like
        Square matrices of the same shape [1/s].
    tau : float
        Delay [s], >= 0. For ``tau = 0`` the roots are the eigenvalues of ``A + E`` (all of them).
    sigma : float, optional
        Left edge of the half plane searched [1/s]; by default ``width`` to the left of the
        rightmost root (so the rightmost roots are certified, whatever lies further left).
    width : float
        Default distance of ``sigma`` to the left of the rightmost root [1/s].

    Returns
    -------
    ndarray of complex
        The roots [1/s], rightmost first; conjugate pairs both listed.

    Raises
    ------
    DelayRootError
        If the argument principle counts a different number of roots in the half plane than were
        found, even with a fine discretization, or a root sits on the contour.
    """
    A, E = _matrices(A, E)
    tau = _delay(tau)
    if tau == 0.0:
        roots = np.linalg.eigvals(A + E)
        roots = roots if sigma is None else roots[roots.real >= sigma]
        return np.array(sorted(roots, key=lambda z: (-z.real, z.imag)), dtype=complex)
    norm_A, norm_E = np.linalg.norm(A, 2), np.linalg.norm(E, 2)
    N, count, roots, left = 24, None, [], sigma
    for _ in range(6):
        estimates = _estimates(A, E, tau, N)
        rightmost = float(np.max(estimates.real))
        left = (rightmost - width) if sigma is None else float(sigma)
        # |s| <= ||A|| + ||E|| exp(-Re(s) tau) for every root: a bound on the rectangle to search.
        radius = norm_A + norm_E * math.exp(-left * tau) + 1.0
        if radius * tau > 0.5 * N:  # seeds good enough for Newton up to |s| tau ~ N / 2
            N = min(int(2 * radius * tau) + 16, 2000)
            if N == 2000:
                raise DelayRootError(f"the roots of Re s >= {left:.4g} extend to |s| ~ {radius:.4g} 1/s: "
                                     f"too many to resolve for tau = {tau:g} s")
            continue
        seeds = estimates[(estimates.real >= left - 1.0) & (np.abs(estimates) <= radius + 1.0)]
        refined = [_newton(A, E, tau, complex(z)) for z in seeds]
        roots = _distinct([r for r in refined if r is not None and r.real >= left and abs(r) <= radius])
        # Keep the contour off every root: move its left edge away from roots next to it.
        while any(abs(r.real - left) < 1e-6 * (1.0 + abs(r)) for r in roots):
            left -= 1e-3
        roots = [r for r in roots if r.real >= left]
        corners = [complex(left, -radius), complex(radius, -radius), complex(radius, radius),
                   complex(left, radius)]
        count = _winding(A, E, tau, corners, points=max(400, int(40 * radius * tau)))
        if count == len(roots):
            return np.array(roots, dtype=complex)
        N *= 2
    raise DelayRootError(f"the argument principle counts {count} roots with Re s >= {left:.4g} for "
                         f"tau = {tau:g} s, Newton found {len(roots)}")


def spectral_abscissa(A, E, tau) -> float:
    """Largest real part of the characteristic roots [1/s] (< 0: the loop is asymptotically stable).

    Raises
    ------
    DelayRootError
        If no root can be certified (see :func:`characteristic_roots`).
    """
    for width in (1.0, 4.0, 16.0):  # a wider strip if the rightmost estimate was spurious
        roots = characteristic_roots(A, E, tau, width=width)
        if len(roots):
            return float(roots[0].real)
    raise DelayRootError(f"no characteristic root found near the rightmost estimate for tau = {float(tau):g} s")


def critical_delay(A, E, tau_max: float, grid: int = 64, xtol: float = 1e-10) -> float:
    """Smallest delay [s] in ``(0, tau_max]`` at which the rightmost root reaches the imaginary axis.

    The spectral abscissa (continuous in ``tau`` for a retarded equation) is scanned on ``grid``
    delays; its first sign change is refined by Brent's method. Returns ``inf`` if it keeps its
    sign at ``tau = 0`` over the whole interval.

    Raises
    ------
    ValueError
        If the loop without delay is not stable (there is no stable delay to leave).
    """
    A, E = _matrices(A, E)
    from scipy.optimize import brentq

    if spectral_abscissa(A, E, 0.0) >= 0:
        raise ValueError("the loop is not stable without delay: no critical delay")
    taus = np.linspace(0.0, float(tau_max), grid + 1)[1:]
    previous = 0.0
    for tau in taus:
        if spectral_abscissa(A, E, tau) >= 0:
            return float(brentq(lambda t: spectral_abscissa(A, E, t), previous, tau, xtol=xtol))
        previous = tau
    return math.inf


@dataclass(frozen=True)
class CrossingDelay:
    """A gain crossover of a single-loop system and the delay that puts a root on it."""

    frequency: float  #: crossover frequency w_c with |L(i w_c)| = 1 [rad/s]
    phase_margin: float  #: 180 deg + arg L(i w_c), in [0, 2 pi) [rad]
    delay: float  #: phase_margin / w_c: the smallest delay with a root at i w_c [s]


def crossing_delays(A, B, C, K) -> list[CrossingDelay]:
    """Gain crossovers of the loop gain ``L(s) = -K C (s I - A)^-1 B`` and their critical delays.

    With ``u(t) = K y(t - tau)`` the characteristic equation is ``1 + L(s) exp(-s tau) = 0``, so
    ``i w`` is a root iff ``|L(i w)| = 1`` and ``w tau = 180 deg + arg L(i w) (mod 2 pi)``.
    ``|L(i w)|^2 = 1`` is the polynomial ``n(s) n(-s) = d(s) d(-s)`` on ``s = i w``, with
    ``d = det(s I - A)`` and ``n = det(s I - A - B K C) - d``.

    Parameters
    ----------
    A, B, C : array_like
        Single-input single-output plant, strictly proper.
    K : float
        Feedback gain.

    Returns
    -------
    list of CrossingDelay
        One entry per positive crossover frequency, by increasing frequency.
    """
    A, E = feedback_matrices(A, B, C, K)
    if np.linalg.matrix_rank(E) > 1 or np.asarray(B).size != A.shape[0] or np.asarray(C).size != A.shape[0]:
        raise ValueError("crossing_delays needs a single-input single-output loop")
    d = np.poly(A)
    n = np.poly(A + E) - d  # d(s) (1 + L(s)) = det(s I - A - E)
    mirror = (-1.0) ** np.arange(len(d) - 1, -1, -1)  # p(-s) has coefficients p_k (-1)^k
    P = np.polysub(np.polymul(n, n * mirror), np.polymul(d, d * mirror))
    P = np.trim_zeros(P, "f")
    crossings = []
    for root in np.roots(P) if len(P) > 1 else []:
        w = root.imag
        if w <= 0 or abs(root.real) > 1e-6 * (1.0 + abs(root)):
            continue

        def h(w):  # |n(iw)|^2 - |d(iw)|^2, real on the imaginary axis
            return abs(np.polyval(n, 1j * w)) ** 2 - abs(np.polyval(d, 1j * w)) ** 2

        for _ in range(50):  # Newton (central difference) to polish the polynomial root
            dw = 1e-7 * (1.0 + w)
            slope = (h(w + dw) - h(w - dw)) / (2 * dw)
            if slope == 0:
                break
            step = h(w) / slope
            w -= step
            if abs(step) < 1e-15 * (1.0 + w):
                break
        L = np.polyval(n, 1j * w) / np.polyval(d, 1j * w)
        margin = (np.angle(L) + np.pi) % (2.0 * np.pi)
        crossings.append(CrossingDelay(float(w), float(margin), float(margin / w)))
    return sorted(_unique_crossings(crossings), key=lambda c: c.frequency)


def _unique_crossings(crossings):
    kept = []
    for c in sorted(crossings, key=lambda c: c.frequency):
        if not kept or abs(c.frequency - kept[-1].frequency) > 1e-8 * (1.0 + c.frequency):
            kept.append(c)
    return kept


def first_crossing_delay(A, B, C, K) -> float:
    """Smallest delay [s] that puts a root on the imaginary axis, ``min(phase margin / w_c)``.

    For a loop that is stable without delay this is where stability is first lost as the delay
    grows (roots cannot cross at ``s = 0``: ``f(0)`` does not depend on the delay). ``inf`` if
    ``|L(i w)|`` never equals 1.
    """
    delays = [c.delay for c in crossing_delays(A, B, C, K)]
    return min(delays) if delays else math.inf


def stable_delay_intervals(A, B, C, K, tau_max: float) -> list[tuple[float, float]]:
    """The delays ``tau`` in ``[0, tau_max]`` [s] at which the single loop ``u(t) = K y(t - tau)``
    is asymptotically stable, as a list of intervals ``(start, end)``.

    Exact for the retarded delay equation: roots cross the imaginary axis only at the gain
    crossovers ``i w_c`` of :func:`crossing_delays`, at the delays ``(phase margin + 2 pi m) / w_c``
    (m = 0, 1, ...), and always in the same direction at one crossover: to the right as the delay
    grows iff ``|d(i w)|^2 - |n(i w)|^2`` increases with ``w`` there (Cooke & van den Driessche,
    Funkcial. Ekvac. 29, 1986). Starting from the number of right-half-plane roots without delay
    (the eigenvalues of ``A + B K C``), each crossing adds or removes a pair; the loop is stable
    where that count is zero. A loop whose gain never crosses 1 keeps its stability at every delay.

    Parameters
    ----------
    A, B, C : array_like
        Single-input single-output plant, strictly proper (as :func:`crossing_delays`).
    K : float
        Feedback gain.
    tau_max : float
        Largest delay of interest [s].

    Returns
    -------
    list of (float, float)
        Disjoint intervals by increasing delay; an ``end`` of ``inf`` means stable beyond
        ``tau_max``.
    """
    tau_max = _delay(tau_max)
    A, E = feedback_matrices(A, B, C, K)
    unstable = int(np.count_nonzero(np.linalg.eigvals(A + E).real > 0))
    d = np.poly(A)
    n = np.poly(A + E) - d

    def gap(w):  # |d(iw)|^2 - |n(iw)|^2
        return abs(np.polyval(d, 1j * w)) ** 2 - abs(np.polyval(n, 1j * w)) ** 2

    events = []
    for c in crossing_delays(A, B, C, K):
        dw = 1e-6 * (1.0 + c.frequency)
        direction = 1 if gap(c.frequency + dw) > gap(c.frequency - dw) else -1
        m = 0
        while (tau := (c.phase_margin + 2.0 * math.pi * m) / c.frequency) <= tau_max:
            events.append((tau, 2 * direction))
            m += 1
    intervals, start = [], (0.0 if unstable == 0 else None)
    for tau, change in sorted(events):
        unstable += change
        if unstable == 0 and start is None:
            start = tau
        elif unstable != 0 and start is not None:
            intervals.append((start, tau))
            start = None
    if start is not None:
        intervals.append((start, math.inf))
    return intervals


def largest_pd_delay(A, B, c_p, c_d, tau_max: float = 5.0, grid: int = 30) -> tuple[float, float, float]:
    """The largest delay [s] at which some rider ``u(t) = -(kp c_p + kd c_d) x(t - tau)`` (a
    proportional-derivative rider on the outputs ``c_p x`` and ``c_d x``) keeps the loop stable, and
    gains ``kp``, ``kd`` that come closest.

    For given gains the stable delays are exact (:func:`stable_delay_intervals`); the largest of them
    is maximised over the gains by a search: both signs of ``kp`` and ``kd`` on a logarithmic grid of
    ``grid`` magnitudes from 0.1 to 1000 each, then Nelder-Mead from the best point (a numerical
    supremum: the stable interval of the best gains shrinks to that delay).

    Parameters
    ----------
    A : array_like
        State matrix (n x n) [1/s].
    B : array_like
        Input column (n) of the rider's input.
    c_p, c_d : array_like
        Rows (n) giving the rider's proportional and derivative outputs.
    tau_max : float, optional
        Largest delay considered [s]; the result is ``inf`` if some gains stay stable beyond it.
    grid : int, optional
        Magnitudes per sign and gain in the first search.

    Returns
    -------
    (float, float, float)
        ``(tau, kp, kd)``: the delay [s] and the gains (0 delay and NaN gains if no gains of the
        grid stabilise the loop at any delay).
    """
    from scipy.optimize import minimize  # deferred: scipy is heavy

    A = np.atleast_2d(np.asarray(A, dtype=float))
    b = np.asarray(B, dtype=float).reshape(-1, 1)
    c_p, c_d = np.asarray(c_p, dtype=float).ravel(), np.asarray(c_d, dtype=float).ravel()

    def longest(gains) -> float:
        C = (gains[0] * c_p + gains[1] * c_d).reshape(1, -1)
        return max((end for _, end in stable_delay_intervals(A, b, C, -1.0, tau_max)), default=0.0)

    magnitudes = np.geomspace(0.1, 1000.0, int(grid))
    values = np.concatenate([-magnitudes[::-1], magnitudes])
    score, kp, kd = max((longest((kp, kd)), kp, kd) for kp in values for kd in values)
    if score == 0.0:
        return 0.0, math.nan, math.nan
    if math.isinf(score):
        return math.inf, float(kp), float(kd)
    result = minimize(lambda g: -longest(g), (kp, kd), method="Nelder-Mead",
                      options={"xatol": 1e-6, "fatol": 1e-9, "maxiter": 3000})
    if -result.fun > score:
        score, (kp, kd) = -result.fun, result.x
    return float(score), float(kp), float(kd)
