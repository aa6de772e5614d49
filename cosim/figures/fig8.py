"""Figure 8 of Astrom, Klein & Lennartsson (2005): root locus of the bicycle with rider over speed.

The poles of the linear fourth-order model (24) with the parameters of Table 1 (bicycle with
rider, ``cosim/params/astrom2005.toml``) for forward speeds 0 <= v <= 15 m/s, each the
eigenvalues of an FMU linearization of ``Bicycle.Bicycles.WhippleLinear`` at that speed (the
4x4 block of ``phi, delta, phi_dot, delta_dot``; heading and path states do not feed back).
The poles at v = 0 are marked with red circles; the speeds where the weave pair crosses the
imaginary axis (v_w) and where the capsize pole does (v_c) are found by root finding on FMU
linearizations and marked. Paper: poles at v = 0 at +-3.05 and +-9.18, v_w = 5.96 m/s,
v_c = 10.36 m/s.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from cosim.figures import pyplot, save
from cosim.plotting import place_legend

NAME = "fig8"
PARAMS = "astrom2005"
SPEEDS = np.linspace(0.0, 15.0, 151)


def compute(fmu=None):
    """Speeds, eigenvalues (len(SPEEDS) x 4), weave and capsize speeds, all from the FMU."""
    # deferred: loads fmpy, which importing this module does not
    from cosim.bicycle import stability as WP

    fmu, params, ev, vw, vc = WP.speed_sweep(fmu, PARAMS, SPEEDS)
    marks = {v: WP.eigenvalues(fmu, params, v) for v in (vw, vc) if v is not None}
    return SPEEDS, ev, vw, vc, marks


def make(output: Path) -> list[Path]:
    plt = pyplot()
    speeds, ev, vw, vc, marks = compute()
    fig, ax = plt.subplots(figsize=(7.0, 5.0))
    vv = np.repeat(speeds, ev.shape[1])
    sc = ax.scatter(ev.real.ravel(), ev.imag.ravel(), c=vv, cmap="viridis", s=6, zorder=2)
    fig.colorbar(sc, ax=ax, label="forward speed v [m/s]")
    ax.plot(ev[0].real, ev[0].imag, "o", mfc="none", mec="red", ms=9, mew=1.5, zorder=3, label="v = 0")
    # The paper's names: p1, p2 = -+ pendulum poles, p3, p4 = -+ front-fork poles.
    for label, p in zip(("p3", "p1", "p2", "p4"), sorted(ev[0].real)):
        ax.annotate(label, (p, 0), textcoords="offset points", xytext=(0, 10), ha="center", color="red",
                    fontsize=8)
    for v, label, color in ((vw, "v_w", "tab:orange"), (vc, "v_c", "tab:purple")):
        if v is None:
            continue
        e = marks[v]
        crossing = e[np.argmin(np.abs(e.real))]
        ax.plot([crossing.real] * (2 if abs(crossing.imag) > 0 else 1),
                [crossing.imag, -crossing.imag] if abs(crossing.imag) > 0 else [0.0], "s", mfc="none",
                mec=color, ms=8, zorder=4, label=f"{label} = {v:.2f} m/s (crossing)")
    ax.axhline(0, color="0.6", lw=0.6, zorder=1)
    ax.axvline(0, color="0.6", lw=0.6, zorder=1)
    ax.set_xlabel("Re p [1/s]")
    ax.set_ylabel("Im p [1/s]")
    ax.set_title("Fig. 8: root locus over speed, bicycle with rider\n"
                 "(astrom2005, 0 <= v <= 15 m/s, FMU linearizations of WhippleLinear)", fontsize=10)
    ax.grid(True, lw=0.3)
    place_legend(ax, fontsize=8)
    Path(output).mkdir(parents=True, exist_ok=True)
    return [save(fig, Path(output) / f"{NAME}.png")]
