"""How a co-simulation run ended, and its recorded rows: shared by both couplings
(:mod:`cosim.cosimulation.master` for the stepped algorithms, :mod:`cosim.cosimulation.model_exchange`
for one ODE), so neither imports the other's results."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cosim.errors import SimulationError

#: How a run can end: completed (the stop time), terminated (an FMU ended the run itself by
#: terminateSimulation, without an error), fell (the fall criterion), diverged (a non-finite
#: signal), failed (an FMU could not continue).
STATUSES = ("completed", "terminated", "fell", "diverged", "failed")


@dataclass
class Outcome:
    """How a run ended.

    Attributes
    ----------
    status : str
        One of :data:`STATUSES`.
    time : float
        When the run ended [s]: the stop time, or the last recorded time.
    message : str
        One line saying so.
    component : str or None
        The component that ended the run (``terminated``, ``failed``), where one did.
    """

    status: str
    time: float
    message: str
    component: str | None = None

    @property
    def complete(self) -> bool:
        """True if the run reached the stop time or ended by a criterion of the model: a fall, or an
        FMU that ended the simulation itself (terminateSimulation)."""
        return self.status in ("completed", "terminated", "fell")


@dataclass
class RunResult:
    """Recorded signals (``time`` first) and the outcome; ``steps`` communication steps were
    taken (the last one shorter if ``step`` does not divide the span, see
    :func:`cosim.cosimulation.master.step_grid`)."""

    data: np.ndarray
    outcome: Outcome
    steps: int


class RunFailed(SimulationError):
    """An FMU could not continue the run; ``result`` holds the rows up to the last completed
    communication point (``result.outcome.status == "failed"``, the message names the cause)."""

    def __init__(self, result: RunResult):
        super().__init__(result.outcome.message)
        self.result = result

    def __reduce__(self):  # pickled from an isolated worker with its rows
        return type(self), (self.result,)


def complete_message(t: float, steps: int, grid: np.ndarray) -> str:
    """The message of a run that reached its stop time ``t`` [s] after ``steps`` steps on ``grid``."""
    text = f"completed at t = {t:g} s after {steps} step{'s' if steps != 1 else ''}"
    if steps >= 2 and grid[-1] - grid[-2] < 0.999999 * (grid[1] - grid[0]):
        text += f" (the last one {grid[-1] - grid[-2]:.6g} s, to end on stop)"
    return text


def terminated(component: str, t: float) -> Outcome:
    """The outcome of a run that component ``component`` ended at ``t`` [s] by terminateSimulation."""
    return Outcome("terminated", t, f"component '{component}' ended the run at t = {t:g} s (terminateSimulation)",
                   component)


def finished(data: np.ndarray, rows: int, record_names, outcome: Outcome) -> RunResult:
    """The result of a run: the first ``rows`` rows of ``data`` (time, then the recorded signals) as
    a named table with its outcome; a failed run is raised as :class:`RunFailed` carrying it."""
    dtype = [("time", float)] + [(n, float) for n in record_names]
    table = np.empty(rows, dtype=dtype)
    for j, name in enumerate(["time"] + list(record_names)):
        table[name] = data[:rows, j]
    result = RunResult(table, outcome, rows - 1)
    if outcome.status == "failed":
        raise RunFailed(result)
    return result


__all__ = ["Outcome", "RunResult", "RunFailed", "STATUSES", "complete_message", "finished", "terminated"]
