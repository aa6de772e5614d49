"""Coupling error of the fixed-step master: Jacobi and Gauss-Seidel converge to the solution of
the same loop inside one FMU as the communication step shrinks; the observed order is the slope
of log(error) over log(step)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cosim.cosimulation import algorithms
from cosim.cosimulation.system import system_from_dict
from cosim.fmu.simulate import simulate

REFERENCE = "Bicycle.Examples.WhippleLinearRiderP"  # bicycle and rider in one model
BIKE = "Bicycle.Bicycles.WhippleLinear"
K, V, PHI0, STOP = 2.0, 5.0, 0.05, 5.0


@dataclass
class ConvergenceRow:
    algorithm: str
    step: float
    error: float  # max |phi| deviation from the single-FMU solution [rad]
    order: float | None  # log2(error(2h) / error(h))


def reference_solution(fmu, times: np.ndarray) -> np.ndarray:
    """phi(t) of the single FMU, Co-Simulation at tolerance 1e-12 on the sample times."""
    step = float(times[1] - times[0])
    result = simulate(fmu, float(times[-1]), step, "cs", {"k": K}, relative_tolerance=1e-12, outputs=["phi"])
    return np.interp(times, result["time"], result["phi"])


def coupled_solution(bike_fmu, algorithm: str, step: float) -> np.ndarray:
    # deferred: loads fmpy, which importing this module does not
    from cosim.cosimulation.factory import run_system

    spec = system_from_dict({
        "system": {"stop": STOP, "step": step, "algorithm": algorithm},
        "components": {
            "bike": {"fmu": str(bike_fmu), "parameters": {"v": V, "phi0": PHI0}},
            "rider": {"python": "Proportional", "parameters": {"k": K}},
        },
        "connections": ["bike.phi -> rider.phi", "rider.T -> bike.T_delta"],
    })
    return run_system(spec).data


def held_input_algorithms() -> list[str]:
    """The registered coupling algorithms that hold the inputs over a communication step (all
    but the one-ODE ones): their coupling error is of order one in the step."""
    return [a.name for a in algorithms.algorithms(one_ode=False)]


def convergence(bike_fmu, reference_fmu, steps=(0.04, 0.02, 0.01, 0.005)) -> list[ConvergenceRow]:
    """Error against the single-FMU solution for each algorithm and step (steps halving)."""
    rows = []
    for algorithm in held_input_algorithms():
        previous = None
        for h in steps:
            data = coupled_solution(bike_fmu, algorithm, h)
            error = float(np.max(np.abs(data["bike.phi"] - reference_solution(reference_fmu, data["time"]))))
            order = None if previous is None else float(np.log(previous / error) / np.log(2.0))
            rows.append(ConvergenceRow(algorithm, h, error, order))
            previous = error
    return rows


def format_rows(rows: list[ConvergenceRow]) -> str:
    lines = [f"{'algorithm':<13} {'step [s]':>9} {'max |phi error| [rad]':>22} {'observed order':>15}"]
    for r in rows:
        order = f"{r.order:15.3f}" if r.order is not None else f"{'':>15}"
        lines.append(f"{r.algorithm:<13} {r.step:9.4f} {r.error:22.3e} {order}")
    return "\n".join(lines)
