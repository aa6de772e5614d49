"""A co-simulation with foreign FMUs, run where their binaries cannot take the caller down.

The whole run (set-up, steps, clean-up) happens in a guarded worker process
(:func:`cosim.fmu.isolation.run_isolated`). The master records each communication point into a
table in memory shared with the caller (an unlinked temporary file mapped by both), so that when
a binary crashes, calls ``exit`` or hangs, the caller still has every row up to the last completed
step and reports the run as failed there (:class:`~cosim.cosimulation.outcome.RunFailed`, exit 4).
A completed row is one whose time is written: the master writes a row only after every
component finished its step, and the time column starts as NaN.
"""
from __future__ import annotations

import os
import tempfile

import numpy as np

from cosim.cosimulation.component import Component
from cosim.cosimulation.master import run_components
from cosim.cosimulation.outcome import Outcome, RunResult, finished
from cosim.cosimulation.system import SystemSpec
from cosim.fmu.isolation import DEFAULT_TIMEOUT, FMUProcessError, run_isolated

__all__ = ["run_isolated_system"]


class _SharedTable:
    """The recording table in an unlinked temporary file: nothing is left behind, whatever ends
    the processes."""

    def __init__(self):
        handle, path = tempfile.mkstemp(prefix="cosim-run-", suffix=".bin")
        os.unlink(path)
        self.fd, self.shape, self.names, self.view, self.rows = handle, None, None, None, 0

    def allocate(self, shape) -> np.ndarray:
        """In the worker: the table, its time column NaN until a row is written."""
        os.ftruncate(self.fd, int(np.prod(shape)) * 8 or 8)
        table = np.memmap(os.fdopen(os.dup(self.fd), "r+b"), dtype=float, mode="r+", shape=tuple(shape))
        table[:, 0] = np.nan
        return table

    def attach(self, shape, names) -> None:
        """In the caller: map the table the worker made."""
        self.shape, self.names = tuple(shape), list(names)
        self.view = np.memmap(os.fdopen(os.dup(self.fd), "rb"), dtype=float, mode="r", shape=self.shape)

    def count(self) -> bool:
        """Update the number of completed rows; True if it grew."""
        if self.view is None:
            return False
        times = self.view[self.rows:, 0]
        unwritten = np.flatnonzero(np.isnan(times))
        grown = int(unwritten[0]) if len(unwritten) else len(times)
        self.rows += grown
        return grown > 0

    def close(self) -> None:
        self.view = None
        os.close(self.fd)


def run_isolated_system(spec: SystemSpec, components: dict[str, Component], foreign: list[str],
                        timeout: float | None = DEFAULT_TIMEOUT) -> RunResult:
    """Run the system in a guarded worker (see the module docstring).

    Parameters
    ----------
    spec, components
        As for :func:`cosim.cosimulation.master.run_components` (created, not yet set up: their
        binaries are loaded in the worker only).
    foreign : list of str
        The components whose FMUs were not built here (named in messages).
    timeout : float or None
        Longest time [s] without a completed communication step; None: no limit.

    Raises
    ------
    RunFailed
        An FMU failed a step, or the worker ended abnormally or stopped answering; carries the rows
        up to the last completed communication point.
    """
    table = _SharedTable()

    def work(worker):
        def allocate(shape, names):
            data = table.allocate(shape)
            worker.send("table", (shape, list(names)))
            worker.doing("the set-up and initialization of the components")
            return data

        worker.doing("assembling the system")
        return run_components(spec, components, allocate=allocate)

    def on_message(kind, payload):
        if kind == "table":
            table.attach(*payload)

    where = f"{spec.path or spec.name} (foreign FMUs: {', '.join(foreign)})"
    try:
        return run_isolated(work, what=where, timeout=timeout, on_message=on_message, progress=table.count)
    except FMUProcessError as exc:
        table.count()
        if table.view is None or table.rows == 0:
            raise
        rows = table.rows
        data = np.array(table.view[:rows])
        t = float(data[rows - 1, 0])
        message = (f"stopped at t = {t:g} s: the FMU of {', '.join(foreign)} {exc.what} during the "
                   f"communication step from t = {t:g} s")
        return finished(data, rows, table.names, Outcome("failed", t, message))
    finally:
        table.close()
        for comp in components.values():  # the caller's copies were never set up
            try:
                comp.close()
            except Exception:
                pass
