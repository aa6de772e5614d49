"""Figure 5: the self-stabilizing bicycle (14) + (11) under a constant positive steer torque.

Simulated with the FMU of ``Bicycle.Bicycles.SelfStabilizing`` (Co-Simulation). The path
deviation eta first goes positive, then negative (the right-half-plane zero at sqrt(m g h / J) of
(21)); roll and steer settle with opposite signs.

Speed and torque
----------------
The paper says that phi settles to 0.14 rad and delta to -0.14 rad but states neither the speed V
nor the torque T. Both follow from the static gains of the model (the ``s = 0`` values of (15)
and of (11)); with the ``m, a, h, b, c, lambda, g`` of the model (Table 1 bicycle with rider)::

    phi / T   = b (V^2 h - a c g) / (a c m g^2 (b h cos(lambda) - a c sin(lambda)))    [(15), s = 0]
    delta     = k1(V) T - k2(V) phi                                                    [(11)]
    delta/phi = -g h b / ((V^2 h - a c g) sin(lambda))                                 [both]

so the ratio delta/phi fixes V alone, and then phi fixes T (:func:`operating_point`): the paper's
0.14 / -0.14 need V = 3.2912 m/s and T = 1.4458 N m (J and D only shape the transient). The
figure is simulated there (solid) and, for comparison, at V = 4 m/s, T = 1 N m (dashed; settles
to phi = 0.145, delta = -0.097). ``fig5.json`` lists V, T, the analytic steady state and the
FMU's values at the end of the run.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from cosim.figures import pyplot, save
from cosim.plotting import place_legend
from cosim.outputs import write_text
from cosim.fmu.simulate import simulate

NAME = "fig5"
MODEL = "Bicycle.Bicycles.SelfStabilizing"
PAPER_PHI, PAPER_DELTA = 0.14, -0.14  # rad: the steady values the paper's text quotes for Figure 5
COMPARISON_SPEED, COMPARISON_TORQUE = 4.0, 1.0  # m/s, N m: a second operating point, drawn dashed
STOP, STEP = 10.0, 0.01  # s: the slower comparison transient decays as exp(-0.76 t)


def steady_state(V: float, T: float, bike=None) -> tuple[float, float]:
    """Steady roll and steer angle [rad] of (14) + (11) under a constant steer torque.

    Parameters
    ----------
    V : float
        Forward speed [m/s], above the critical speed V_c = sqrt(b g cot(lambda)) (16), where the
        steady state is reached (below it the bicycle falls over).
    T : float
        Constant steer torque [N m].
    bike : cosim.analytic.simple.SimpleBicycle, optional
        The parameters (default: the model's, the Table 1 bicycle with rider).

    Returns
    -------
    (phi, delta) : tuple of float
        ``phi = G(V) T`` with G the static gain of (15), ``delta = k1(V) T - k2(V) phi`` (11).

    Raises
    ------
    ValueError
        If V is not above V_c or condition (17) fails (no stable steady state).
    """
    # deferred: loads control, matplotlib, scipy, which importing this module does not
    from cosim.analytic import simple as S

    bike = bike or S.SimpleBicycle()
    _check_stable(bike, V)
    m, a, h, b, c, g, lam = bike.m, bike.a, bike.h, bike.b, bike.c, bike.g, bike.lam
    gain = b * (V**2 * h - a * c * g) / (a * c * m * g**2 * (b * h * math.cos(lam) - a * c * math.sin(lam)))
    phi = gain * T
    return phi, S.fork_gain_k1(bike, V) * T - S.fork_gain_k2(bike, V) * phi


def operating_point(phi: float, delta: float, bike=None) -> tuple[float, float]:
    """The speed V [m/s] and constant steer torque T [N m] at which (14) + (11) settle to
    ``phi``, ``delta`` [rad] (inverse of :func:`steady_state`, in closed form).

    The static gains give ``delta/phi = -g h b / ((V^2 h - a c g) sin(lambda))``, so
    ``V^2 = (g h b / (rho sin(lambda)) + a c g) / h`` with ``rho = -delta/phi``, and then
    ``T = phi / G(V)`` with G the static gain of (15).

    Raises
    ------
    ValueError
        If phi is zero, delta does not have the opposite sign of phi (no speed above V_c
        gives that), or the speed that gives the ratio is not above V_c (not a stable
        steady state).
    """
    # deferred: loads control, matplotlib, scipy, which importing this module does not
    from cosim.analytic import simple as S

    bike = bike or S.SimpleBicycle()
    if not (math.isfinite(phi) and math.isfinite(delta)) or phi == 0.0:
        raise ValueError(f"phi and delta must be finite with phi != 0, got phi = {phi!r}, delta = {delta!r}")
    rho = -delta / phi
    if not rho > 0.0:
        raise ValueError(f"delta = {delta!r} rad must have the opposite sign of phi = {phi!r} rad: above V_c the "
                         "steady roll and steer angles of (14) + (11) always have opposite signs")
    V = math.sqrt((bike.g * bike.h * bike.b / (rho * math.sin(bike.lam)) + bike.a * bike.c * bike.g) / bike.h)
    _check_stable(bike, V)
    phi_per_torque = steady_state(V, 1.0, bike)[0]
    return V, phi / phi_per_torque


def _check_stable(bike, V: float) -> None:
    # deferred: loads control, matplotlib, scipy, which importing this module does not
    from cosim.analytic import simple as S

    if not S.is_self_stabilizing(bike, V):
        raise ValueError(f"V = {V:.6g} m/s: (14) + (11) has no stable steady state there (needs V > V_c = "
                         f"{S.critical_velocity(bike):.6g} m/s and b h > a c tan(lambda), (16)-(17))")


def paper_operating_point() -> tuple[float, float]:
    """V [m/s] and T [N m] that give the paper's phi = 0.14, delta = -0.14 rad (:func:`operating_point`)."""
    return operating_point(PAPER_PHI, PAPER_DELTA)


def simulate_fig5(fmu: Path | None = None, speed: float | None = None, torque: float | None = None) -> np.ndarray:
    """eta [m], phi and delta [rad] of the FMU under the constant torque from t = 0, every 10 ms.

    ``speed`` [m/s] and ``torque`` [N m] default to :func:`paper_operating_point`.
    """
    # deferred: loads casadi, which importing this module does not
    from cosim.compiler.build import DEFAULT_OUTPUT, build_model

    if speed is None or torque is None:
        speed, torque = paper_operating_point()
    fmu = fmu or build_model(MODEL, DEFAULT_OUTPUT).fmu
    return simulate(fmu, STOP, STEP, "cs", {"V": speed, "T": torque}, outputs=["eta", "phi", "delta"])


def _case(label: str, V: float, T: float, fmu) -> dict:
    r = simulate_fig5(fmu, V, T)
    phi, delta = steady_state(V, T)
    return {"label": label, "speed_m_s": V, "torque_N_m": T, "result": r,
            "steady_state_rad": {"phi": phi, "delta": delta},
            "settled_rad": {"phi": float(r["phi"][-1]), "delta": float(r["delta"][-1])},
            "settled_at_s": float(r["time"][-1]),
            "eta_peak": {"time_s": float(r["time"][np.argmax(r["eta"])]), "eta_m": float(r["eta"].max())}}


def make(output: Path, fmu: Path | None = None) -> list[Path]:
    V, T = paper_operating_point()
    cases = [_case("speed and torque giving the paper's phi = 0.14, delta = -0.14 rad", V, T, fmu),
             _case("comparison: another speed and torque", COMPARISON_SPEED, COMPARISON_TORQUE, fmu)]
    plt = pyplot()
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(6, 6.4))
    styles = ({"color": "C0", "lw": 1.5}, {"color": "0.45", "lw": 1.0, "ls": "--"})
    for case, style in zip(cases, styles):
        r, s = case["result"], case["settled_rad"]
        label = (f"V = {case['speed_m_s']:.4g} m/s, T = {case['torque_N_m']:.4g} N m: "
                 f"phi -> {s['phi']:.3f}, delta -> {s['delta']:.3f} rad")
        for ax, name in zip(axes, ("eta", "phi", "delta")):
            ax.plot(r["time"], r[name], label=label, **style)
    for ax, label in zip(axes, ("(a) eta [m]", "(b) phi [rad]", "(c) delta [rad]")):
        ax.axhline(0.0, color="0.6", lw=0.8)
        ax.set_ylabel(label)
        ax.grid(True)
    for ax, name in zip(axes[1:], ("phi", "delta")):  # the paper's steady values
        ax.axhline(cases[0]["steady_state_rad"][name], color="C3", lw=0.8, ls=":")
    r = cases[0]["result"]
    early = r["time"] <= 1.5
    inset = axes[0].inset_axes([0.08, 0.12, 0.38, 0.5])  # the small positive start of eta
    inset.plot(r["time"][early], r["eta"][early], color="C0")
    inset.axhline(0.0, color="0.6", lw=0.8)
    inset.set_title("first 1.5 s (solid)", fontsize=7)
    inset.tick_params(labelsize=6)
    axes[-1].set_xlabel("time [s]")
    place_legend(axes[1], fontsize=6.5)
    s = cases[0]["settled_rad"]
    axes[0].set_title(
        f"{MODEL}, T from t = 0; solid: V = {V:.4f} m/s, T = {T:.4f} N m, solved from the static\n"
        f"gains of (15), (11) for the paper's phi = 0.14, delta = -0.14 rad; settles to phi = {s['phi']:.2f}, "
        f"delta = {s['delta']:.2f} rad\n"
        f"eta peaks at t = {cases[0]['eta_peak']['time_s']:.2f} s, then turns negative (inverse response); "
        f"dotted red: the paper's values", fontsize=8)
    out = Path(output)
    out.mkdir(parents=True, exist_ok=True)
    summary = {
        "model": MODEL,
        "paper_steady_state_rad": {"phi": PAPER_PHI, "delta": PAPER_DELTA},
        "how": "V and T solved in closed form from the static gains of (15) and (11) for the paper's steady "
               "phi and delta (cosim.figures.fig5.operating_point); settled_rad are the FMU's values at the "
               "end of the run, steady_state_rad the analytic static gains times T",
        "cases": [{k: v for k, v in case.items() if k != "result"} for case in cases],
    }
    json_path = out / f"{NAME}.json"
    write_text(json_path, json.dumps(summary, indent=2) + "\n", "figure data")
    return [save(fig, out / f"{NAME}.png"), json_path]
