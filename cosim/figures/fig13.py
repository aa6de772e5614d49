"""Figure 13 of Astrom, Klein & Lennartsson (2005): critical speeds versus wheel inertia.

Riderless bicycle (Table 1 values in parentheses, ``cosim/params/astrom2005-riderless.toml``).
The paper varies "the moments of inertia of the wheels ... from 0 to 0.184 kg m^2,
corresponding to the case in which all of the mass is located at the perimeter of the wheel"
(0.184 = m R^2 = 1.5 kg * (0.35 m)^2, the spin inertia of a rim of the wheel's mass), and plots
the speed at which the bicycle becomes stable (weave speed, solid) and at which the capsize mode
becomes unstable (dashed), on logarithmic scales.

Choices made here (the paper's text and caption differ: the text says "the wheels", the
caption "the front wheel"):

* ``I`` is the **spin** inertia ``Iyy``; the diametral inertia follows as ``Ixx = Iyy/2``
  (perpendicular-axis theorem for a flat wheel, as in Table 1: 0.07 = 0.14/2), the wheel mass
  is unchanged. ``I`` runs over 1e-3 ... 0.184 kg m^2 (log scale: 0 itself cannot be shown).
* Black: **both wheels** get ``I`` (IRyy = IFyy = I). This reproduces the features the paper
  describes: the capsize speed grows without bound as I -> 0, as I^(-1/2) (the coefficient
  that multiplies v^2 in det(g K0 + v^2 K2) vanishes with the gyroscopic terms; the paper says
  "inversely proportional to the square", the log-log slope is -1/2), and the ratio of the two
  speeds tends to a constant.
* Grey: **front wheel only** (rear wheel as in Table 1). Here the capsize mode stays stable at
  every speed once I_F is below about 0.05 kg m^2, so its curve ends there.

Every speed is a root (``brentq``, 1e-6 m/s) of eigenvalues of FMU linearizations of
``Bicycle.Bicycles.WhippleLinear`` (see :mod:`cosim.bicycle.stability`).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from cosim.figures import pyplot, save
from cosim.plotting import place_legend

NAME = "fig13"
PARAMS = "astrom2005-riderless"
INERTIAS = np.geomspace(1e-3, 0.184, 16)
XTOL = 1e-6  # m/s, root-finding tolerance (far below what the plot resolves)
WHEELS = ("RF", "F")  # the wheels given the inertia: both, the front one only


def _with_inertia(params: dict, inertia: float, wheels: str) -> dict:
    p = dict(params)
    for w in wheels:
        p[f"I{w}yy"] = inertia
        p[f"I{w}xx"] = inertia / 2.0
    return p


def critical_speeds(fmu, params: dict, wheels: str, inertias=INERTIAS) -> tuple[np.ndarray, np.ndarray]:
    """Weave and capsize speeds [m/s] (nan where none below 200 m/s) for each inertia.

    The inertias are processed from large to small with the previous weave speed as the
    bracket guess (the weave speed grows as the inertia shrinks)."""
    # deferred: loads fmpy, which importing this module does not
    from cosim.bicycle import stability as WP

    weave = np.full(len(inertias), np.nan)
    capsize = np.full(len(inertias), np.nan)
    guess = None
    for k in np.argsort(inertias)[::-1]:
        p = _with_inertia(params, float(inertias[k]), wheels)
        vw = WP.weave_speed(fmu, p, bracket=guess, xtol=XTOL)
        vc = WP.capsize_speed(fmu, p, v_start=vw if vw is not None else 0.0, xtol=XTOL)
        if vw is not None:
            weave[k] = vw
            guess = (0.9 * vw, 1.6 * vw)
        if vc is not None:
            capsize[k] = vc
    return weave, capsize


def parts() -> list[tuple]:
    """Both wheels and the front wheel only as ``(critical_speeds, args)``: independent of each
    other, computed in parallel by :func:`cosim.figures.make_figures`."""
    # deferred: loads fmpy, which importing this module does not
    from cosim.bicycle import stability as WP

    fmu, params = WP.whipple_fmu(), WP.parameters_for_model(PARAMS)
    return [(critical_speeds, (fmu, params, wheels)) for wheels in WHEELS]


def make(output: Path, computed: list | None = None) -> list[Path]:
    """Draw the figure; ``computed``: the results of :func:`parts` (in that order), computed
    here if not given."""
    plt = pyplot()
    results = dict(zip(WHEELS, computed if computed is not None else [f(*args) for f, args in parts()]))
    fig, ax = plt.subplots(figsize=(7.0, 5.0))
    for wheels, color, label in (("RF", "k", "both wheels"), ("F", "0.6", "front wheel only")):
        weave, capsize = results[wheels]
        ax.loglog(INERTIAS, weave, "-", color=color, lw=1.6, marker=".", label=f"weave speed v_w ({label})")
        ax.loglog(INERTIAS, capsize, "--", color=color, lw=1.6, marker=".",
                  label=f"capsize speed v_c ({label})")
    weave, capsize = results["RF"]
    ok = np.isfinite(capsize) & (INERTIAS <= 0.02)
    if ok.sum() >= 2:
        slope = np.polyfit(np.log(INERTIAS[ok]), np.log(capsize[ok]), 1)[0]
        ax.text(0.03, 0.05, f"both wheels, I <= 0.02: v_c ~ I^({slope:.2f})", transform=ax.transAxes, fontsize=8)
    ax.axvline(0.14, color="tab:blue", lw=0.8, ls=":", label="Table 1: I = 0.14 kg m²")
    ax.set_xlabel("wheel spin inertia I = Iyy [kg m²]  (Ixx = I/2)")
    ax.set_ylabel("critical speed [m/s]")
    ax.set_title("Fig. 13: critical speeds vs wheel inertia, riderless bicycle (astrom2005-riderless)\n"
                 "solid: weave speed (becomes stable), dashed: capsize speed; FMU linearizations\n"
                 "black: both wheels (the paper's text), grey: front wheel only (its caption); only both wheels\n"
                 "show what the paper describes (capsize speed growing as I -> 0)", fontsize=9)
    from matplotlib.ticker import FuncFormatter

    plain = FuncFormatter(lambda y, _: f"{y:g}")
    ax.yaxis.set_major_formatter(plain)
    ax.yaxis.set_minor_formatter(FuncFormatter(lambda y, _: f"{y:g}" if str(round(y))[0] in "2357" else ""))
    ax.grid(True, which="both", lw=0.3)
    place_legend(ax, fontsize=8)
    Path(output).mkdir(parents=True, exist_ok=True)
    return [save(fig, Path(output) / f"{NAME}.png")]
