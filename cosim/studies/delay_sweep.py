"""Rider delay against the unstable pole: the physical loop and the co-simulated loop, side by side.

The inverted-pendulum bicycle (1) (FMU ``Bicycle.Bicycles.InvertedPendulum``, unstable pole
``p = sqrt(m g h / J)``) is stabilized by steer-angle feedback ``delta = -k2 phi`` (5) acting
through a rider's neuromuscular delay ``tau``. Two loops are told apart:

* the *physical* loop: G_phi_delta (4) with ``delta(t) = -k2 phi(t - tau)``, whose stability is
  that of the exact delay equation (rightmost roots of ``det(s I - A - B K C exp(-s tau)) = 0``,
  :mod:`cosim.analytic.delay`);
* the *co-simulated* loop: bicycle FMU + exact transport delay + Python controller run by the
  master, whose Jacobi coupling adds a lag (:func:`coupling_delay`, 7.5 ms at the 5 ms step) to
  the rider's delay. Its prediction is the same delay equation with delay ``tau + lag``, and the
  growth rate observed in the co-simulation is compared with that prediction.

Near the stability boundary (``tau`` about 0.096 s for k2 = 1 at 5 m/s, :func:`stability_boundary`)
the lag decides: at ``tau = 0.09 s`` the physical loop is stable, the co-simulated one is not.

The paper's rule of thumb in the product ``p tau``: comfortable below 0.2, impossible above 2.

``python -m cosim.studies.delay_sweep`` prints the table (``--help`` for the options).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from cosim.analytic.delay import critical_delay, crossing_delays, feedback_matrices, spectral_abscissa
from cosim.cosimulation.system import system_from_dict
from cosim.errors import CosimError
from cosim.fmu.target import resolve_fmu

MODEL = "Bicycle.Bicycles.InvertedPendulum"
MARGIN = 0.02  # |max Re| below this (1/s) is marginal: too slow to classify from a finite co-simulation
DEFAULT_TAUS = (0.0, 0.06, 0.08, 0.09, 0.1, 0.8)  # s: the rows of the table in docs/cosimulation.md


@dataclass
class DelayCase:
    """One rider delay: the physical loop's exact verdict and the co-simulation's prediction and outcome."""

    tau: float  #: rider delay [s]
    p_tau: float  #: p tau [-]
    physical_max_real: float  #: largest real part of the roots of the physical loop (delay tau) [1/s]
    physical: str  #: stable, unstable (or marginal if the rightmost root is on the axis)
    lag: float  #: coupling lag of the master added to tau in the co-simulated loop [s]
    predicted_max_real: float  #: largest real part of the roots of the co-simulated loop (tau + lag) [1/s]
    predicted: str  #: stable, unstable, marginal (|max Re| < MARGIN)
    observed: str  #: stable, unstable, fell
    growth: float  #: observed exponential rate of |phi| [1/s]

    @property
    def agrees(self) -> bool:
        """The co-simulation behaves as its own prediction (the loop with delay ``tau + lag``) says."""
        return self.predicted == "marginal" or (self.predicted == "stable") == (self.observed == "stable")


@dataclass(frozen=True)
class StabilityBoundary:
    """The delay at which the physical loop loses stability, found two independent ways."""

    k2: float  #: steer-angle gain [rad/rad]
    V: float  #: speed [m/s]
    by_roots: float  #: delay where the rightmost characteristic root reaches the imaginary axis [s]
    by_crossing: float  #: phase margin / crossover frequency [s]
    frequency: float  #: gain-crossover frequency, the frequency of the oscillation at the boundary [rad/s]
    phase_margin: float  #: phase margin of the undelayed loop [rad]
    p: float  #: unstable pole [1/s]


def pendulum_pole(V: float) -> float:
    """The unstable pole p = sqrt(m g h / J), eq (2), of the model at speed V [1/s]."""
    # deferred: loads control, matplotlib, scipy, which importing this module does not
    from cosim.analytic.simple import pendulum_poles
    from cosim.analytic.twins import TWINS, bicycle

    return float(np.max(pendulum_poles(bicycle(TWINS[MODEL].parameters({"V": V})))))


def coupling_delay(tau: float, step: float) -> float:
    """Extra delay of the Jacobi loop [s]: half a step of zero-order hold plus one step for each
    direct-feedthrough block (the controller, and the delay block itself when tau < step)."""
    hops = 1 + (tau < step)
    return (hops + 0.5) * step


def loop(parameters: dict, k2: float):
    """``(A, B, C, K)`` of the physical loop: a state-space form of G_phi_delta (4) of the model
    (``delta`` [rad] -> ``phi`` [rad]) and the rider's feedback ``K = -k2`` of ``delta = K phi(t - tau)``."""
    import control

    # deferred: loads control, matplotlib, scipy, which importing this module does not
    from cosim.analytic.simple import roll_steer_tf
    from cosim.analytic.twins import TWINS, bicycle

    values = TWINS[MODEL].parameters(parameters)
    plant = control.ss(roll_steer_tf(bicycle(values), values["V"], frame="eq1"))
    return plant.A, plant.B, plant.C, -float(k2)


def physical_max_real(parameters: dict, k2: float, tau: float) -> float:
    """Largest real part [1/s] of the roots of the physical loop with the rider's delay ``tau`` [s]
    (exact delay equation, no co-simulation lag)."""
    return spectral_abscissa(*feedback_matrices(*loop(parameters, k2)), tau)


def predicted_max_real(parameters: dict, k2: float, tau: float, step: float) -> float:
    """Largest real part [1/s] of the co-simulated loop: the physical loop with the delay ``tau``
    plus the master's coupling lag (:func:`coupling_delay`; none for ``step = 0``)."""
    lag = coupling_delay(tau, step) if step > 0 else 0.0
    return physical_max_real(parameters, k2, tau + lag)


def stability_boundary(k2: float = 1.0, V: float = 5.0) -> StabilityBoundary:
    """The rider delay at which the physical loop becomes unstable, two independent ways: the
    first delay where the rightmost root of the delay equation reaches the imaginary axis (scan
    and Brent's method), and the frequency-crossing formula ``phase margin / w_c``.

    Raises
    ------
    ValueError
        If ``k2`` does not stabilize the bicycle even without delay (``k2 <= b g / V^2``).
    """
    parameters = {"V": V}
    A, B, C, K = loop(parameters, k2)
    p = pendulum_pole(V)
    try:
        by_roots = critical_delay(*feedback_matrices(A, B, C, K), tau_max=2.0 / p)  # up to p tau = 2
    except ValueError:
        raise ValueError(f"k2 = {k2:g} does not stabilize the bicycle at V = {V:g} m/s even without delay") from None
    crossing = min(crossing_delays(A, B, C, K), key=lambda c: c.delay)
    return StabilityBoundary(float(k2), float(V), by_roots, crossing.delay, crossing.frequency,
                             crossing.phase_margin, p)


def _verdict(max_real: float, margin: float) -> str:
    return "marginal" if abs(max_real) < margin else ("stable" if max_real < 0 else "unstable")


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
    """Co-simulate one delay: returns (outcome, growth rate [1/s])."""
    # deferred: loads fmpy, which importing this module does not
    from cosim.cosimulation.factory import run_system

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
    """Every delay of ``taus`` [s]: the physical loop solved exactly, the co-simulated loop
    predicted and co-simulated (communication step ``step`` [s])."""
    parameters = {"V": V}
    p = pendulum_pole(V)
    cases = []
    for tau in taus:
        physical = physical_max_real(parameters, k2, tau)
        lag = coupling_delay(tau, step)
        predicted = physical_max_real(parameters, k2, tau + lag)
        observed, growth = run_case(fmu, parameters, k2, tau, step)
        cases.append(DelayCase(tau, p * tau, physical, _verdict(physical, 1e-9), lag, predicted,
                               _verdict(predicted, MARGIN), observed, growth))
    return cases


def format_cases(cases: list[DelayCase], boundary: StabilityBoundary | None = None) -> str:
    """The table: the physical loop (delay tau) and the co-simulated loop (tau + coupling lag)."""
    lines = [f"{'':16}{'physical loop (tau)':^20}  {'co-simulated loop (tau + coupling lag)':^52}".rstrip(),
             (f"{'tau [s]':>8} {'p*tau':>7} {'max Re [1/s]':>12} {'verdict':>9}  {'lag [s]':>7} "
              f"{'max Re [1/s]':>12} {'predicted':>9} {'observed':>9} {'growth [1/s]':>12}  rule of thumb")]
    for c in cases:
        rule = "comfortable" if c.p_tau < 0.2 else ("impossible" if c.p_tau > 2 else "demanding")
        lines.append(f"{c.tau:8.3f} {c.p_tau:7.3f} {c.physical_max_real:12.4f} {c.physical:>9}  {c.lag:7.4f} "
                     f"{c.predicted_max_real:12.4f} {c.predicted:>9} {c.observed:>9} {c.growth:12.4f}  {rule}")
    if boundary is not None:
        lines.append(f"physical loop stable for tau < {boundary.by_roots:.5f} s (p tau < "
                     f"{boundary.p * boundary.by_roots:.4f}): delay of the first root on the imaginary axis;")
        lines.append(f"frequency crossing: phase margin / crossover = {math.degrees(boundary.phase_margin):.2f} deg / "
                     f"{boundary.frequency:.4f} rad/s = {boundary.by_crossing:.5f} s")
    return "\n".join(lines)


def largest_stabilizable_p_tau(gains, V: float = 5.0) -> float:
    """The largest p*tau for which some gain of ``gains`` still stabilizes the physical loop
    (exact delay equation, no co-simulation lag): the practical limit of steer-angle feedback,
    to compare with the paper's p*tau < 2. Gains that do not stabilize without delay are skipped."""
    parameters = {"V": V}
    p = pendulum_pole(V)
    best = 0.0
    for k2 in gains:
        A, E = feedback_matrices(*loop(parameters, k2))
        if spectral_abscissa(A, E, 0.0) >= 0:
            continue
        best = max(best, critical_delay(A, E, tau_max=2.0 / p))  # inf if stable up to p tau = 2
    return p * best


def main(argv: list[str] | None = None) -> int:
    """``python -m cosim.studies.delay_sweep``: print the table and the stability boundary."""
    import argparse
    import sys

    parser = argparse.ArgumentParser(
        prog="python -m cosim.studies.delay_sweep",
        description="Rider delay: the physical loop (exact delay equation) and the co-simulated loop "
                    "(rider delay + the master's coupling lag, predicted and co-simulated).")
    parser.add_argument("--k2", type=float, default=1.0, help="steer-angle gain of delta = -k2 phi [rad/rad]")
    parser.add_argument("--speed", type=float, default=5.0, help="forward speed V [m/s]")
    parser.add_argument("--step", type=float, default=0.005, help="communication step of the co-simulation [s]")
    parser.add_argument("--taus", type=float, nargs="+", default=list(DEFAULT_TAUS), metavar="TAU",
                        help="rider delays [s] (default: %(default)s)")
    parser.add_argument("--fmu", default=None, help=f"FMU of {MODEL} (default: built into $COSIM_FMU_DIR or ./fmus)")
    args = parser.parse_args(argv)
    if not (math.isfinite(args.step) and args.step > 0):
        parser.error(f"--step must be a positive time in s, got {args.step:g}")
    if not (math.isfinite(args.speed) and args.speed > 0):
        parser.error(f"--speed must be a positive speed in m/s, got {args.speed:g}")
    if not all(math.isfinite(t) and t >= 0 for t in args.taus):
        parser.error(f"--taus must be delays >= 0 s, got {' '.join(f'{t:g}' for t in args.taus)}")
    try:
        boundary = stability_boundary(args.k2, args.speed)
    except ValueError as exc:
        parser.error(str(exc))

    try:
        fmu = resolve_fmu(args.fmu or MODEL)
        cases = sweep(fmu, args.taus, k2=args.k2, V=args.speed, step=args.step)
    except CosimError as exc:
        print(f"{parser.prog}: error: {exc}", file=sys.stderr)
        return 2
    print(format_cases(cases, boundary))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
