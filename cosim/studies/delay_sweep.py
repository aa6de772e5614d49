"""Rider delay against the unstable pole: co-simulated stability versus the analytic prediction.

The inverted-pendulum bicycle (1) (FMU ``Bicycle.Bicycles.InvertedPendulum``, unstable pole
``p = sqrt(m g h / J)``) is stabilized by steer-angle feedback ``delta = -k2 phi`` (5) acting
through a rider's neuromuscular delay ``tau``. For each ``tau`` the closed loop is

* co-simulated by the master: bicycle FMU + exact transport delay + Python controller, and
* predicted by python-control: G_phi_delta (4) with ``-k2`` and a Padé approximation of the
  delay (plus the communication step the Jacobi loop adds, and half a step of zero-order hold).

The paper's rule of thumb in the product ``p tau``: comfortable below 0.2, impossible above 2.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MODEL = "Bicycle.Bicycles.InvertedPendulum"
PADE_ORDER = 6
MARGIN = 0.02  # |max Re| below this (1/s) is marginal: too slow to classify from a finite run


@dataclass
class DelayCase:
    tau: float
    p_tau: float
    predicted_max_real: float
    predicted: str  # stable, unstable, marginal
    observed: str  # stable, unstable, fell
    growth: float  # observed exponential rate of |phi| (1/s)

    @property
    def agrees(self) -> bool:
        return self.predicted == "marginal" or (self.predicted == "stable") == (self.observed == "stable")


def pendulum_pole(V: float) -> float:
    """The unstable pole p = sqrt(m g h / J), eq (2), of the model at speed V [1/s]."""
    from cosim.analytic.simple import pendulum_poles
    from cosim.analytic.twins import TWINS, bicycle

    return float(np.max(pendulum_poles(bicycle(TWINS[MODEL].parameters({"V": V})))))


def coupling_delay(tau: float, step: float) -> float:
    """Extra delay of the Jacobi loop: half a step of zero-order hold plus one step for each
    direct-feedthrough block (the controller, and the delay block itself when tau < step)."""
    hops = 1 + (tau < step)
    return (hops + 0.5) * step


def predicted_max_real(parameters: dict, k2: float, tau: float, step: float) -> float:
    """Largest real part of the analytic closed loop with a Padé delay of ``tau`` plus the
    coupling delay of the co-simulation (:func:`coupling_delay`)."""
    import control

    from cosim.analytic.simple import roll_steer_tf
    from cosim.analytic.twins import TWINS, bicycle

    values = TWINS[MODEL].parameters(parameters)
    roll = roll_steer_tf(bicycle(values), values["V"], frame="eq1")  # G_phi_delta (4)
    delay = tau + (coupling_delay(tau, step) if step > 0 else 0.0)
    num, den = control.pade(delay, PADE_ORDER) if delay > 0 else ([1.0], [1.0])
    loop = control.feedback(roll * control.tf(num, den) * k2, 1)
    return float(np.max(np.real(loop.poles())))


def observed_growth(time: np.ndarray, phi: np.ndarray, window: float = 2.0) -> float:
    """Exponential growth rate of |phi| (1/s): slope of log(max |phi| per window) over the last
    60 % of the run; a window (2 s) spans at least one oscillation of the loop."""
    t0 = time[0] + 0.4 * (time[-1] - time[0])
    edges = np.arange(t0, time[-1] + 1e-12, window)
    centres, peaks = [], []
    for a, b in zip(edges, edges[1:]):
        inside = (time >= a) & (time < b)
        peak = np.max(np.abs(phi[inside])) if inside.any() else 0.0
        if peak > 1e-300:
            centres.append(0.5 * (a + b))
            peaks.append(np.log(peak))
    return float(np.polyfit(centres, peaks, 1)[0]) if len(peaks) >= 2 else float("nan")


def run_case(fmu, parameters: dict, k2: float, tau: float, step: float = 0.005, stop: float = 20.0,
             phi0: float = 0.02) -> tuple[str, float]:
    """Co-simulate one delay: returns (outcome, growth rate)."""
    from cosim.cosimulation.factory import run_system
    from cosim.cosimulation.system import system_from_dict

    spec = system_from_dict({
        "system": {"stop": stop, "step": step, "fall": {"signal": "bike.phi", "limit": 1.0}},
        "components": {
            "bike": {"fmu": str(fmu), "parameters": {**parameters, "frame.phi": phi0}},
            "delay": {"python": "TransportDelay", "parameters": {"tau": tau}},
            "rider": {"python": "SteerAngleFeedback", "parameters": {"k2": k2}},
        },
        "connections": ["bike.phi -> rider.phi", "rider.delta -> delay.u", "delay.y -> bike.delta"],
    })
    result = run_system(spec)
    if result.outcome.status == "fell":
        return "fell", float("inf")
    growth = observed_growth(result.data["time"], result.data["bike.phi"])
    return ("stable" if growth < 0 else "unstable"), growth


def sweep(fmu, taus, k2: float = 1.0, V: float = 5.0, step: float = 0.005) -> list[DelayCase]:
    """Every delay of ``taus`` co-simulated and predicted."""
    parameters = {"V": V}
    p = pendulum_pole(V)
    cases = []
    for tau in taus:
        re = predicted_max_real(parameters, k2, tau, step)
        predicted = "marginal" if abs(re) < MARGIN else ("stable" if re < 0 else "unstable")
        observed, growth = run_case(fmu, parameters, k2, tau, step)
        cases.append(DelayCase(tau, p * tau, re, predicted, observed, growth))
    return cases


def format_cases(cases: list[DelayCase]) -> str:
    lines = [f"{'tau [s]':>8} {'p*tau':>7} {'predicted max Re':>17} {'predicted':>10} {'observed':>9} "
             f"{'growth [1/s]':>12}  rule of thumb"]
    for c in cases:
        rule = "comfortable" if c.p_tau < 0.2 else ("impossible" if c.p_tau > 2 else "demanding")
        lines.append(f"{c.tau:8.3f} {c.p_tau:7.3f} {c.predicted_max_real:17.4f} {c.predicted:>10} "
                     f"{c.observed:>9} {c.growth:12.4f}  {rule}")
    return "\n".join(lines)


def largest_stabilizable_p_tau(gains, V: float = 5.0) -> float:
    """The largest p*tau for which some gain of ``gains`` still stabilizes the loop (analytic,
    no co-simulation step): the practical limit of steer-angle feedback, to compare with the
    paper's p*tau < 2."""
    from scipy.optimize import brentq

    parameters = {"V": V}
    p = pendulum_pole(V)
    best = 0.0
    for k2 in gains:
        def margin(tau):
            return predicted_max_real(parameters, k2, tau, 0.0)

        if margin(0.0) >= 0:
            continue
        hi = 0.05
        while margin(hi) < 0 and hi < 10:
            hi *= 2
        if margin(hi) < 0:
            continue
        best = max(best, brentq(margin, 0.0, hi, xtol=1e-6))
    return p * best
