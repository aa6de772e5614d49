"""Figure 9 of Astrom, Klein & Lennartsson (2005): real parts of the poles versus speed.

Bicycle with rider (Table 1, ``cosim/params/astrom2005.toml``), forward speeds -10 <= v <= 15
m/s; negative speeds are the rear-steered bicycle (riding backwards), for which the paper notes
that some pole is unstable at every speed. Every point is an eigenvalue of an FMU linearization
of ``Bicycle.Bicycles.WhippleLinear`` at that speed. As in the paper: real poles are dots,
complex poles open circles, unstable poles (Re >= 0) red, stable ones blue. The self-stable
range v_w < v < v_c (paper: 5.96 m/s <= V <= 10.36 m/s) is found by root finding on FMU
linearizations and shaded.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from cosim.figures import pyplot, save
from cosim.plotting import place_legend

NAME = "fig9"
PARAMS = "astrom2005"
SPEEDS = np.linspace(-10.0, 15.0, 201)


def plot_real_parts(ax, speeds, ev, vw=None, vc=None, shade=True, no_capsize_note: str | None = None) -> None:
    """The paper's style: dot = real pole, o = complex pole; red = unstable, blue = stable."""
    # deferred: loads fmpy, which importing this module does not
    from cosim.bicycle.stability import oscillatory

    vv = np.repeat(speeds, ev.shape[1])
    e = ev.ravel()
    osc = oscillatory(e)
    unstable = e.real >= 0.0
    for mask, kw in ((~osc & ~unstable, dict(marker=".", color="tab:blue", ms=4, ls="none")),
                     (~osc & unstable, dict(marker=".", color="tab:red", ms=4, ls="none")),
                     (osc & ~unstable, dict(marker="o", mfc="none", mec="tab:blue", ms=4, ls="none", mew=0.8)),
                     (osc & unstable, dict(marker="o", mfc="none", mec="tab:red", ms=4, ls="none", mew=0.8))):
        ax.plot(vv[mask], e.real[mask], **kw)
    ax.axhline(0.0, color="k", lw=0.6)
    ax.axvline(0.0, color="0.6", lw=0.6)
    if shade and vw is not None and vc is not None and vw < vc:
        ax.axvspan(vw, vc, color="tab:green", alpha=0.12, lw=0,
                   label=f"self-stable {vw:.2f} < v < {vc:.2f} m/s")
    elif shade and vw is not None:
        ax.axvspan(vw, speeds.max(), color="tab:green", alpha=0.12, lw=0,
                   label=f"self-stable for v > {vw:.2f} m/s ({no_capsize_note or 'no capsize in the plotted range'})")
    # legend proxies
    ax.plot([], [], ".", color="k", label="real pole")
    ax.plot([], [], "o", mfc="none", mec="k", label="complex pole")
    ax.plot([], [], "s", color="tab:red", label="unstable (Re >= 0)")
    ax.plot([], [], "s", color="tab:blue", label="stable")
    ax.set_xlabel("forward speed v [m/s]  (v < 0: rear-steered)")
    ax.set_ylabel("Re p [1/s]")
    ax.grid(True, lw=0.3)


def compute(fmu=None):
    # deferred: loads fmpy, which importing this module does not
    from cosim.bicycle import stability as WP

    _, _, ev, vw, vc = WP.speed_sweep(fmu, PARAMS, SPEEDS)
    return SPEEDS, ev, vw, vc


def make(output: Path) -> list[Path]:
    plt = pyplot()
    speeds, ev, vw, vc = compute()
    fig, ax = plt.subplots(figsize=(7.0, 5.0))
    plot_real_parts(ax, speeds, ev, vw, vc)
    ax.set_ylim(-16, 16)
    ax.set_title("Fig. 9: real parts of the poles, bicycle with rider (astrom2005)\n"
                 "dot real, o complex; red unstable, blue stable; FMU linearizations of WhippleLinear",
                 fontsize=10)
    place_legend(ax, fontsize=8)
    Path(output).mkdir(parents=True, exist_ok=True)
    return [save(fig, Path(output) / f"{NAME}.png")]
