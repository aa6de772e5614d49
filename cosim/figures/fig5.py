"""Figure 5: the self-stabilizing bicycle (14) + (11) under a constant positive steer torque.

Simulated with the FMU of ``Bicycle.Bicycles.SelfStabilizing`` (Co-Simulation). The path
deviation eta first goes positive, then negative (the right-half-plane zero at sqrt(m g h / J) of
(21)); roll and steer settle with opposite signs."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from cosim.figures import pyplot, save

NAME = "fig5"
TITLE = "Constant positive steer torque: path deviation, roll and steer angle"
MODEL = "Bicycle.Bicycles.SelfStabilizing"
SPEED, TORQUE, STOP = 4.0, 1.0, 6.0  # m/s, N.m, s


def simulate_fig5(fmu: Path | None = None) -> np.ndarray:
    """eta, phi and delta [rad, m] of the FMU for the constant torque, sampled every 10 ms."""
    from cosim.compiler.build import DEFAULT_OUTPUT, build_model
    from cosim.fmu.simulate import simulate

    fmu = fmu or build_model(MODEL, DEFAULT_OUTPUT).fmu
    return simulate(fmu, STOP, 0.01, "cs", {"V": SPEED, "T": TORQUE}, outputs=["eta", "phi", "delta"])


def make(output: Path, fmu: Path | None = None) -> list[Path]:
    r = simulate_fig5(fmu)
    plt = pyplot()
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(6, 6))
    for ax, name, label in zip(axes, ("eta", "phi", "delta"), ("(a) eta [m]", "(b) phi [rad]", "(c) delta [rad]")):
        ax.plot(r["time"], r[name])
        ax.axhline(0.0, color="0.6", lw=0.8)
        ax.set_ylabel(label)
        ax.grid(True)
    early = r["time"] <= 1.5
    inset = axes[0].inset_axes([0.08, 0.12, 0.38, 0.5])  # the small positive start of eta
    inset.plot(r["time"][early], r["eta"][early])
    inset.axhline(0.0, color="0.6", lw=0.8)
    inset.set_title("first 1.5 s", fontsize=7)
    inset.tick_params(labelsize=6)
    axes[-1].set_xlabel("time [s]")
    turn = r["time"][np.argmax(r["eta"])]
    axes[0].set_title(f"{MODEL}, V = {SPEED} m/s, T = {TORQUE} N.m from t = 0\n"
                      f"eta peaks at t = {turn:.2f} s, then turns negative (inverse response)", fontsize=9)
    return [save(fig, Path(output) / "fig5.png")]
