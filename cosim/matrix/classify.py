"""Classification of a co-simulated run and its agreement with the prediction.

Observed class (of the observed signal x, usually the roll angle phi):

* ``fell``: the run stopped because |x| exceeded the fall limit; ``diverged``: a signal turned
  non-finite. Both count as unstable.
* otherwise the class follows from the observed growth rate ``sigma`` [1/s]: ``stable`` if
  sigma < -observed_margin, ``unstable`` if sigma > +observed_margin, else ``marginal``
  (inconclusive; a decisive prediction then re-runs the case longer). A signal that never left 0
  is ``unexcited`` (the case needs a perturbation: an initial state or a pulse).

How sigma is estimated, and why it does not depend on the stop time
--------------------------------------------------------------------
A linear system's free response is a sum of damped oscillations ``sum_m a_m exp(lambda_m t)``
and its verdict is the largest Re(lambda_m) present. The **modal estimate** identifies those
exponents from the recorded samples by the matrix pencil method (Hua & Sarkar, IEEE Trans. ASSP
38(5), 1990; :func:`modal_fit`): the rank of the Hankel matrix of the samples gives the number
of modes, its shift invariance their exponents, a least-squares fit their amplitudes, and the
fit's residual says whether the signal really is such a sum. Noise-free co-simulation data are
fitted to ~1e-7 and the exponents recovered to four digits from any window with a few dozen
samples per mode -- in particular a slow mode whose growth is still hidden in the first seconds
by a larger decaying transient, or a slow oscillation of which the run covers less than a period
(the rear-steered bicycle at 10 m/s: 0.31 +- 0.29j 1/s, a 22 s period, seen in an 8 s run).

The former verdict compared the envelope of the last third of the run with the middle third.
That needs the run to outlast the transients *and* a period of the slowest oscillation: at 8 s
the example above fell in a zero crossing and was called ``stable``. The alternatives were worse
for a user who wants a trustworthy observation: taking the exponent of the linear prediction for
short runs makes the observation copy the prediction it is meant to test, and refusing stop
times shorter than a few periods of the predicted slowest mode needs a prediction
(``predict = false`` has none) and refuses runs that hold all the information needed.

When the modal fit is not accepted (a nonlinear, clipped, noisy or piecewise signal: the
residual exceeds :data:`MODAL_RESIDUAL` or more than :data:`MODAL_MAX_ORDER` modes are needed,
also after dropping the first third of the run), sigma is the envelope comparison
``ln(max_last / max_middle) / (T/3)`` of the later two thirds as before (a signal that decayed
below 1e-12 of its peak is stable). ``growth_method`` in the observation says which was used.

The reported ``growth_rate`` [1/s] is the modal sigma, or without an accepted modal fit a
least-squares fit of ln(window maximum of |x|) against time over the later part of the run
(windows of a tenth of it, :func:`growth_rate`), the quantity the analytic ``max_re`` predicts
once the transients have died out.

Agreement: ``marginal`` if the prediction is marginal (|max Re| < margin; excluded from the
verdict) or the observation is and the prediction agrees it is near the boundary; ``agree`` if
predicted stable and observed stable, or predicted unstable and observed unstable/fell/diverged;
``disagree`` otherwise (an observation still inconclusive after the longer re-run disagrees with a
decisive prediction); ``failed`` if the case could not be run.
"""
from __future__ import annotations

import math

import numpy as np

from cosim.matrix.pencil import MODAL_SIGNIFICANT, SMALL_ORDER, SMALL_PENCIL, ModalFit
from cosim.matrix.pencil import native as native_pencil

UNSTABLE = ("unstable", "fell", "diverged")

#: A modal fit is accepted when ||x - fit|| / ||x|| is at most this (co-simulations: ~1e-7).
MODAL_RESIDUAL = 1e-4
#: ... and needs at most this many modes (more: the signal is not a sum of a few exponentials).
MODAL_MAX_ORDER = 30
#: Samples used by the fit (longer runs are decimated; Re(lambda) = ln|z| / h is alias-free): the
#: pencil's cost grows with their cube and more do not identify better (docs/benchmarks.md).
MODAL_SAMPLES = 200


def _median(a: np.ndarray) -> float:
    """``np.median`` of a non-empty 1-D array without NaN, bit for bit, at a third of its cost (a
    case calls it twice, and numpy's checks and dispatch cost more than the partition)."""
    n = a.size
    k = n // 2
    if n % 2:
        return float(np.partition(a, k)[k])
    part = np.partition(a, (k - 1, k))
    return float((part[k - 1] + part[k]) / 2)


def _uniform_prefix(t: np.ndarray) -> int:
    """Length of the longest prefix of ``t`` on one uniform grid (a last short step is dropped)."""
    if t.size < 3:
        return t.size
    dt = np.diff(t)
    h = _median(dt)
    if not h > 0:
        return 0
    bad = np.flatnonzero(np.abs(dt - h) > 1e-6 * h)
    return int(bad[0]) + 1 if bad.size else t.size


def hankel(x: np.ndarray, pencil: int) -> np.ndarray:
    """The Hankel matrix ``Y[i, j] = x[i + j]`` of ``n - pencil`` rows and ``pencil + 1`` columns
    (``scipy.linalg.hankel(x[:n - pencil], x[n - pencil - 1:])``, without importing scipy)."""
    return np.lib.stride_tricks.sliding_window_view(x, pencil + 1)  # a view: the QR copies it once


def singular_values_right(Y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Singular values and right singular vectors (rows of ``vh``) of a matrix with more rows than columns.

    The SVD of the triangular factor R of ``Y = Q R``: the same values and vectors, bit for bit,
    as ``np.linalg.svd(Y, full_matrices=False)``, whose LAPACK driver (``gesdd``) takes the same
    QR path for a tall matrix -- but without forming the left singular vectors U (m x n), which
    the pencil does not use and which cost about as much as the rest (tests/test_matrix_pool.py
    compares the two bit for bit)."""
    if Y.shape[0] <= Y.shape[1]:
        _, s, vh = np.linalg.svd(Y, full_matrices=False)
        return s, vh
    R = np.linalg.qr(Y, mode="r")
    _, s, vh = np.linalg.svd(R, full_matrices=False)
    return s, vh


def _signal_subspace(x: np.ndarray, pencil: int):
    """(order, right singular vectors) of the Hankel matrix of ``x`` with ``pencil + 1`` columns, or None.

    The order is the numerical rank: singular values above the errors of the data, i.e. above 1e-7
    of the largest (co-simulated signals carry solver errors of about that order) and well above
    the noise floor (the median of the lower half of the spectrum: ~1e-16 for clean signals)."""
    try:
        s, vh = singular_values_right(hankel(x, pencil))
    except np.linalg.LinAlgError:
        return None
    if not s[0] > 0:
        return None
    floor = _median(s[s.size // 2:])
    return int(np.sum(s > max(1e-7 * s[0], 30.0 * floor))), vh


def _pencil(x: np.ndarray, h: float, max_order: int, small: bool = True):
    """Matrix pencil fit of uniform samples ``x`` (step ``h``): (lambda, contributions, residual)
    or None when the signal needs more than ``max_order`` modes or the algebra fails.

    The pencil parameter is ``n // 3`` (between N/3 and N/2: least noise-sensitive), or with
    ``small`` first :data:`SMALL_PENCIL`, kept when it finds at most :data:`SMALL_ORDER` modes
    (then its lower half of the spectrum is still the noise floor)."""
    n = x.size
    found = None
    if small and SMALL_PENCIL < n // 3:
        found = _signal_subspace(x, SMALL_PENCIL)
        if found is not None and found[0] > SMALL_ORDER:
            found = None
    if found is None:
        found = _signal_subspace(x, n // 3)
        if found is None:
            return None
    order, vh = found
    if order > max_order:
        return None
    v = vh[:order].conj().T
    try:
        z = np.linalg.eigvals(np.linalg.pinv(v[:-1]) @ v[1:])
    except np.linalg.LinAlgError:
        return None
    z = z[np.abs(z) > 0]
    if not z.size:
        return None
    # columns z^(k - k0), anchored at the end for growing modes: no overflow, and |coefficient|
    # is then the mode's largest contribution over the window
    k = np.arange(n)[:, None]
    anchor = np.where(np.abs(z) > 1.0, n - 1, 0)[None, :]
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        Z = z[None, :] ** (k - anchor)
    if not np.isfinite(Z).all():
        return None
    coef, *_ = np.linalg.lstsq(Z, x.astype(complex), rcond=None)
    fit = (Z @ coef).real
    residual = float(np.linalg.norm(x - fit) / np.linalg.norm(x))
    lam = np.log(z.astype(complex)) / h
    return lam, np.abs(coef), residual, float(np.linalg.norm(x - fit) / math.sqrt(n))


def modal_fit(t, x, *, max_samples: int = MODAL_SAMPLES, max_order: int = MODAL_MAX_ORDER,
              max_residual: float = MODAL_RESIDUAL, small: bool = True, native: bool = True) -> ModalFit | None:
    """The exponents of a signal that is a sum of damped oscillations (matrix pencil method).

    Parameters
    ----------
    t : array of float
        Sample times [s] (a uniform grid; samples after the first irregular step are dropped).
    x : array of float
        The signal (finite).
    max_samples, max_order, max_residual
        Decimation target, largest number of modes and largest relative residual accepted.
    small : bool
        Try the small pencil (:data:`SMALL_PENCIL`) first.
    native : bool
        Fit in C (:mod:`cosim.matrix.pencil`: the same steps with the same LAPACK routines, a
        third of the cost) where it can be had; False: always with numpy, as below.

    Returns
    -------
    ModalFit or None
        None when the samples are too few or irregular, or the signal is not such a sum
        (more than ``max_order`` modes, or a residual above ``max_residual``) over the whole run
        and over its later two thirds (where the response to a pulse has become free).
    """
    if native:
        fitter = native_pencil()
        if fitter is not None:
            return fitter.modal_fit(t, x, max_samples, max_order, max_residual, small)
    t = np.asarray(t, float)
    x = np.asarray(x, float)
    n = _uniform_prefix(t)
    t, x = t[:n], x[:n]
    if n < 30 or not np.isfinite(x).all():
        return None
    for first in (0, n // 3):
        tw, xw = t[first:], x[first:]
        stride = max(1, math.ceil(tw.size / max_samples))
        tw, xw = tw[::stride], xw[::stride]
        peak = float(np.abs(xw).max())
        if tw.size < 30 or not peak > 0:
            continue
        h = float(tw[1] - tw[0])
        found = _pencil(xw / peak, h, max_order, small)  # scaled: the thresholds are relative
        if found is None:
            continue
        lam, contrib, residual, rms = found
        if residual > max_residual:
            continue
        significant = contrib >= max(MODAL_SIGNIFICANT, 100.0 * rms)
        if not significant.any():
            continue
        lam, contrib = lam[significant], contrib[significant]
        order = np.argsort(-lam.real)
        lam, contrib = lam[order], contrib[order]
        return ModalFit(rate=float(lam[0].real), modes=[complex(v) for v in lam],
                        contributions=[float(c) for c in contrib], residual=residual, order=int(lam.size),
                        start=float(tw[0]))
    return None


def _window_max(t: np.ndarray, ax: np.ndarray, a: float, b: float, increasing: bool = False) -> float:
    """max |x| over the samples with a - 1e-12 <= t <= b + 1e-12 (0 if none); on an ``increasing``
    grid those are one slice, found by bisection instead of two masks over the whole run."""
    if increasing:
        lo = int(t.searchsorted(a - 1e-12, side="left"))
        hi = int(t.searchsorted(b + 1e-12, side="right"))
        return float(ax[lo:hi].max()) if hi > lo else 0.0
    sel = (t >= a - 1e-12) & (t <= b + 1e-12)
    return float(ax[sel].max()) if sel.any() else 0.0


def growth_rate(t: np.ndarray, x: np.ndarray, start: float | None = None) -> float | None:
    """Slope of ln(window max |x|) over [start, end] (default: the later two thirds)."""
    ax = np.abs(x)
    if t.size < 8:
        return None
    t0, t1 = float(t[0]), float(t[-1])
    start = t0 + (t1 - t0) / 3 if start is None else start
    if t1 - start <= 0:
        return None
    n = 10
    edges = np.linspace(start, t1, n + 1)
    centers, logs = [], []
    peak = float(ax.max())
    for a, b in zip(edges[:-1], edges[1:]):
        m = _window_max(t, ax, a, b)
        if m > 1e-12 * peak and m > 0:
            sel = (t >= a - 1e-12) & (t <= b + 1e-12)
            k = int(np.argmax(ax[sel]))
            centers.append(float(t[sel][k]))
            logs.append(math.log(m))
    if len(centers) < 3:
        return None
    slope = np.polyfit(np.asarray(centers), np.asarray(logs), 1)[0]
    return float(slope)


def observe(t: np.ndarray, x: np.ndarray, status: str, observed_margin: float, settle_fraction: float = 0.02) -> dict:
    """Observed class, growth rate, envelope rate, max |x| and settling time of a run.

    Parameters
    ----------
    t, x : arrays of float
        Sample times [s] and the observed signal.
    status : str
        Outcome of the run (``completed``, ``fell``, ``diverged``).
    observed_margin : float
        |growth rate| [1/s] below which the observation is ``marginal`` (inconclusive).
    settle_fraction : float
        Band (fraction of the peak) of the settling time.

    Returns
    -------
    dict
        ``class``; ``growth_rate`` [1/s] and ``growth_method`` (``modal`` or ``envelope``, see the
        module docstring); ``modes`` (dominant identified exponents [re, im] in 1/s, modal only);
        ``envelope_rate`` [1/s] (last third vs middle third); ``max_roll``; ``settling_time`` [s]
        (stable runs); ``end_time`` [s].
    """
    t = np.asarray(t, float)
    x = np.asarray(x, float)
    finite = np.isfinite(x)
    if finite.all():  # every run that did not diverge: no NaN to mask
        ax = np.abs(x)
        peak = float(ax.max()) if ax.size else math.nan
    else:
        ax = np.abs(np.where(finite, x, np.nan))
        peak = float(np.nanmax(ax)) if finite.any() else math.nan
    out = {"class": None, "envelope_rate": None, "growth_rate": None, "growth_method": None, "modes": None,
           "max_roll": peak, "settling_time": None, "end_time": float(t[-1]) if t.size else 0.0}
    if status == "diverged" or not finite.all():
        out["class"] = "diverged"
        return out
    fit = modal_fit(t, x, small=status != "fell") if peak > 0 else None
    if fit is not None:
        out["growth_rate"], out["growth_method"] = fit.rate, "modal"
        # the dominant exponents [1/s] as [re, im] (upper half plane), for the report
        out["modes"] = [[v.real, v.imag] for v in fit.modes if v.imag >= 0][:4]
    if status == "fell":
        out["class"] = "fell"
        if fit is None:  # fit over the later half of the run before the fall (transients are gone by then)
            out["growth_rate"], out["growth_method"] = growth_rate(t, x, float(t[0] + (t[-1] - t[0]) / 2)), "envelope"
        return out
    if not peak > 0:
        out["class"] = "unexcited"
        return out
    T = float(t[-1] - t[0])
    third = T / 3
    increasing = bool((t[1:] > t[:-1]).all())  # a run's time grid: the windows are slices
    m2 = _window_max(t, ax, t[0] + third, t[0] + 2 * third, increasing)
    m3 = _window_max(t, ax, t[0] + 2 * third, t[-1], increasing)
    if m3 <= 1e-12 * peak:
        sigma = -math.inf
    elif m2 <= 1e-12 * peak:
        sigma = math.inf
    else:
        sigma = math.log(m3 / m2) / third
    out["envelope_rate"] = sigma if math.isfinite(sigma) else (-1e9 if sigma < 0 else 1e9)
    if fit is None:
        out["growth_rate"], out["growth_method"] = growth_rate(t, x), "envelope"
    else:
        sigma = fit.rate  # independent of the stop time (see the module docstring)
    if sigma < -observed_margin:
        out["class"] = "stable"
    elif sigma > observed_margin:
        out["class"] = "unstable"
    else:
        out["class"] = "marginal"
    if out["class"] == "stable":
        band = settle_fraction * peak
        outside = np.flatnonzero(ax > band)
        out["settling_time"] = float(t[outside[-1] + 1] - t[0]) if outside.size and outside[-1] + 1 < t.size else 0.0
    return out


def agreement(predicted: str | None, observed: str | None) -> str:
    """agree, disagree or marginal (see the module docstring)."""
    if predicted is None or observed is None:
        return "failed"
    if observed == "unexcited":
        return "failed"
    if predicted == "marginal":
        return "marginal"
    if predicted == "stable":
        return "agree" if observed == "stable" else "disagree"
    return "agree" if observed in UNSTABLE else "disagree"
