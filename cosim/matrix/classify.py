"""Classification of a co-simulated run and its agreement with the prediction.

Observed class (of the observed signal x, usually the roll angle phi):

* ``fell``: the run stopped because |x| exceeded the fall limit; ``diverged``: a signal turned
  non-finite. Both count as unstable.
* otherwise the envelope of |x| in the last third of the run is compared with the middle third
  (the first third is left to the transients): ``sigma = ln(max_last / max_middle) / (T/3)``;
  ``stable`` if sigma < -observed_margin, ``unstable`` if sigma > +observed_margin, else
  ``marginal`` (inconclusive). A signal that decayed below 1e-12 of its peak is stable; one that
  never left 0 is ``unexcited`` (the case needs a perturbation: an initial state or a pulse).

The reported ``growth_rate`` [1/s] is a least-squares fit of ln(window maximum of |x|) against
time over the later part of the run (windows of a tenth of it), the quantity the analytic
``max_re`` predicts once the transients have died out.

Agreement: ``marginal`` if the prediction is marginal (|max Re| < margin; excluded from the
verdict) or the observation is and the prediction agrees it is near the boundary; ``agree`` if
predicted stable and observed stable, or predicted unstable and observed unstable/fell/diverged;
``disagree`` otherwise (an observation still inconclusive after the longer re-run disagrees with a
decisive prediction); ``failed`` if the case could not be run.
"""
from __future__ import annotations

import math

import numpy as np

UNSTABLE = ("unstable", "fell", "diverged")


def _window_max(t: np.ndarray, ax: np.ndarray, a: float, b: float) -> float:
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
    """Observed class, envelope growth rate, fitted growth rate, max |x| and settling time."""
    t = np.asarray(t, float)
    x = np.asarray(x, float)
    finite = np.isfinite(x)
    ax = np.abs(np.where(finite, x, np.nan))
    peak = float(np.nanmax(ax)) if finite.any() else math.nan
    out = {"class": None, "envelope_rate": None, "growth_rate": None, "max_roll": peak,
           "settling_time": None, "end_time": float(t[-1]) if t.size else 0.0}
    if status == "diverged" or not finite.all():
        out["class"] = "diverged"
        return out
    if status == "fell":
        out["class"] = "fell"
        # fit over the later half of the run before the fall (transients are gone by then)
        out["growth_rate"] = growth_rate(t, x, float(t[0] + (t[-1] - t[0]) / 2))
        return out
    if not peak > 0:
        out["class"] = "unexcited"
        return out
    T = float(t[-1] - t[0])
    third = T / 3
    m2 = _window_max(t, ax, t[0] + third, t[0] + 2 * third)
    m3 = _window_max(t, ax, t[0] + 2 * third, t[-1])
    if m3 <= 1e-12 * peak:
        sigma = -math.inf
    elif m2 <= 1e-12 * peak:
        sigma = math.inf
    else:
        sigma = math.log(m3 / m2) / third
    out["envelope_rate"] = sigma if math.isfinite(sigma) else (-1e9 if sigma < 0 else 1e9)
    out["growth_rate"] = growth_rate(t, x)
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


def is_stable(observed: str | None) -> bool:
    return observed == "stable"
