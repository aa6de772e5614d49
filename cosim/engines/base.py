"""The interface of a co-simulation engine, and the registry that finds engines by name.

An engine is one class: a subclass of :class:`Engine` with its ``name`` and what it can run
(FMI versions, single FMUs, SSP archives), decorated with :func:`register`. Every engine returns
its results alike: a NumPy structured array with ``time`` [s] first and one float column per
recorded variable, one row after each communication step (no row at the start time).
"""
from __future__ import annotations

from pathlib import Path
from typing import ClassVar

import numpy as np

from cosim.errors import CosimError, SimulationError


class EngineUnavailable(CosimError, ImportError):
    """An engine cannot be loaded here; the message says what is missing."""


class EngineUnsupported(CosimError, ValueError):
    """An FMU or SSP the engine cannot run (libcosim and FMI 3.0, an engine without SSP support);
    the message names the file and what runs it instead."""


class UnknownEngine(CosimError, KeyError):
    """No engine of that name is registered; the message lists the registered ones."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""


class Engine:
    """A co-simulation engine; subclasses set the class attributes, override :meth:`load` and
    what they run (:meth:`run_fmu`, :meth:`run_ssp`), and register with :func:`register`."""

    #: Its name in the registry, test ids and messages.
    name: ClassVar[str] = ""
    #: The Python module it runs on (what :meth:`load` returns).
    module: ClassVar[str] = ""
    #: The FMI versions of the Co-Simulation FMUs it runs.
    fmi_versions: ClassVar[tuple[str, ...]] = ("2.0", "3.0")
    #: When it records the outputs of a system of several FMUs: ``"after-step"`` (right after
    #: the step) or ``"after-transfer"`` (once the connected inputs took the new values), the
    #: ``sampling`` of our master that records alike.
    sampling: ClassVar[str] = "after-step"
    #: Code of another project: its results check ours.
    independent: ClassVar[bool] = False
    #: The engine the results of the others on single FMUs are compared with.
    reference: ClassVar[bool] = False
    #: The pytest marker of the tests that run it (they are skipped, with the reason, where it
    #: cannot be loaded); None: it loads wherever this package runs.
    marker: ClassVar[str | None] = None

    def load(self):
        """The module the engine runs on, loaded.

        Raises
        ------
        EngineUnavailable
            If it cannot be loaded here, naming what is missing.
        """
        raise NotImplementedError

    def run_fmu(self, fmu: str | Path, stop_time: float, step: float, start_values: dict | None = None,
                outputs: list[str] | None = None) -> np.ndarray:
        """Simulate one Co-Simulation FMU from 0 to ``stop_time`` [s] with the fixed
        communication step ``step`` [s] and the ``start_values`` (parameters and inputs, held
        from the start); returns ``time`` and the ``outputs`` columns (default: every output)
        after each step.

        Raises
        ------
        EngineUnsupported
            If the engine does not run single FMUs, or not this FMU's FMI version.
        """
        raise EngineUnsupported(f"{fmu}: the engine {self.name} does not run single FMUs")

    def run_ssp(self, ssp: str | Path, signals: list[str], stop_time: float | None = None,
                step: float | None = None) -> np.ndarray:
        """Run an SSP archive and record ``signals`` ("component.variable") after each step;
        ``stop_time`` [s] and ``step`` [s] default to the archive's own.

        Raises
        ------
        EngineUnsupported
            If the engine does not run SSP archives, or not this one's FMI versions.
        """
        raise EngineUnsupported(f"{ssp}: the engine {self.name} does not run SSP archives")

    @property
    def runs_fmu(self) -> bool:
        """True if the engine runs single FMUs."""
        return type(self).run_fmu is not Engine.run_fmu

    @property
    def runs_ssp(self) -> bool:
        """True if the engine runs SSP archives."""
        return type(self).run_ssp is not Engine.run_ssp

    def runs(self, what: str, fmi_version: str = "2.0") -> bool:
        """True if the engine runs ``what`` ("fmu" or "ssp") with FMUs of ``fmi_version``."""
        kinds = {"fmu": self.runs_fmu, "ssp": self.runs_ssp}
        if what not in kinds:
            raise ValueError(f"what an engine runs is 'fmu' or 'ssp', got {what!r}")
        return kinds[what] and fmi_version in self.fmi_versions

    def __repr__(self) -> str:
        return f"<engine {self.name!r}>"


_REGISTERED: dict[str, Engine] = {}


def register(cls: type[Engine]) -> type[Engine]:
    """Class decorator: make the engine ``cls`` known by its ``name`` (after those registered
    before it).

    Raises
    ------
    ValueError
        If the name is empty or taken by another class.
    """
    if not cls.name:
        raise ValueError(f"{cls.__qualname__}: an engine needs a name")
    if cls.name in _REGISTERED and type(_REGISTERED[cls.name]) is not cls:
        raise ValueError(f"{cls.__qualname__}: the engine name {cls.name!r} is taken by "
                         f"{type(_REGISTERED[cls.name]).__qualname__}")
    _REGISTERED[cls.name] = cls()
    return cls


def unregister(name: str) -> None:
    """Forget the engine ``name`` (nothing if it is not registered)."""
    _REGISTERED.pop(name, None)


def engine(name: str) -> Engine:
    """The registered engine called ``name``.

    Raises
    ------
    UnknownEngine
        If none is, naming the registered ones.
    """
    if name not in _REGISTERED:
        raise UnknownEngine(f"unknown engine '{name}' (known: {', '.join(_REGISTERED)})")
    return _REGISTERED[name]


def engines(runs: str | None = None, fmi_version: str = "2.0", **where) -> list[Engine]:
    """The registered engines in the order they were registered; with ``runs`` ("fmu" or
    "ssp") only those that run it with FMUs of ``fmi_version``, with keywords only those whose
    attributes have the given values (``engines("ssp", independent=True)``)."""
    return [e for e in _REGISTERED.values()
            if (runs is None or e.runs(runs, fmi_version)) and all(getattr(e, k) == v for k, v in where.items())]


def result(times, columns: dict[str, list[float]]) -> np.ndarray:
    """The structured array of an engine's run: ``time`` and the ``columns``, all float64."""
    dtype = [("time", np.float64)] + [(n, np.float64) for n in columns]
    rows = list(zip(times, *columns.values()))
    return np.array(rows, dtype=dtype)


def steps(stop_time: float, step: float) -> int:
    """How many steps ``step`` [s] make ``stop_time`` [s]; SimulationError unless a whole number."""
    n = int(round(stop_time / step))
    if n <= 0 or abs(n * step - stop_time) > 1e-9 * max(1.0, stop_time):
        raise SimulationError(f"stop time {stop_time} is not a whole number of steps {step}")
    return n
