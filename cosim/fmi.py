"""A thin layer over FMPy for one FMI 2.0 FMU: extract once, instantiate as ME or CS, address
variables by name. Linearization, validation and the co-simulation master build on it."""
from __future__ import annotations

import shutil
import tempfile
from ctypes import c_double
from pathlib import Path

import numpy as np

from .errors import SimulationError

_EXTRACTED: dict[tuple, tuple] = {}  # (path, size, mtime) -> (unzip folder, model description)


def _extract(path: Path):
    """Unzip an FMU once per process (and file version); the folders are removed at exit."""
    import atexit

    from fmpy import extract, read_model_description

    stat = path.stat()
    key = (str(path.resolve()), stat.st_size, stat.st_mtime_ns)
    if key not in _EXTRACTED:
        if not _EXTRACTED:
            atexit.register(_remove_extracted)
        folder = tempfile.mkdtemp(prefix="cosim-fmu-")
        extract(str(path), folder)
        _EXTRACTED[key] = (folder, read_model_description(str(path)))
    return _EXTRACTED[key]


def _remove_extracted() -> None:
    for folder, _ in _EXTRACTED.values():
        if Path(folder).name.startswith("cosim-fmu-"):  # only the folders made by _extract
            shutil.rmtree(folder, ignore_errors=True)
    _EXTRACTED.clear()


def get_continuous_states(instance, nx: int) -> np.ndarray:
    """The continuous states of an FMPy Model Exchange instance."""
    x = (c_double * nx)()
    if nx:
        instance.getContinuousStates(x, nx)
    return np.array(x[:])


def set_continuous_states(instance, x) -> None:
    """Set the continuous states of an FMPy Model Exchange instance."""
    x = np.asarray(x, float)
    if x.size:
        instance.setContinuousStates((c_double * x.size)(*x), x.size)


class FMU:
    """An extracted FMU with its model description (unzipped once per process and file version).

    Parameters
    ----------
    path : path-like
        The ``.fmu`` file.
    """

    def __init__(self, path: str | Path):
        self.path = Path(path)
        if not self.path.is_file():
            raise FileNotFoundError(f"{self.path}: no such FMU file")
        self.unzipdir, self.description = _extract(self.path)
        self.variables = {v.name: v for v in self.description.modelVariables}
        self.vr = {name: v.valueReference for name, v in self.variables.items()}

    def close(self):
        """Nothing to release: the unzipped FMU is shared within the process (see ``_extract``)."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def names(self, causality: str) -> list[str]:
        """Variable names of one causality (input, output, parameter, calculatedParameter, local)."""
        return [v.name for v in self.description.modelVariables if v.causality == causality]

    @property
    def states(self) -> list[str]:
        """Names of the continuous states, in the order of ModelStructure/Derivatives."""
        return [d.variable.derivative.name for d in self.description.derivatives]

    @property
    def derivatives(self) -> list[str]:
        return [d.variable.name for d in self.description.derivatives]

    def instantiate(self, kind: str = "cs", name: str = "instance", logger=None):
        """An FMPy FMU2Slave (``cs``) or FMU2Model (``me``), instantiated but not initialized."""
        from fmpy.fmi2 import FMU2Model, FMU2Slave

        cls = FMU2Slave if kind == "cs" else FMU2Model
        section = self.description.coSimulation if kind == "cs" else self.description.modelExchange
        if section is None:
            raise SimulationError(f"{self.path}: the FMU does not support {kind.upper()}")
        instance = cls(guid=self.description.guid, unzipDirectory=self.unzipdir,
                       modelIdentifier=section.modelIdentifier, instanceName=name)
        instance.instantiate(loggingOn=False)
        return instance

    def set(self, instance, values: dict) -> None:
        """Set values by name, each with the setter of its type."""
        for name, value in values.items():
            v = self.variables[name]
            if v.type == "Real":
                instance.setReal([v.valueReference], [float(value)])
            elif v.type in ("Integer", "Enumeration"):
                instance.setInteger([v.valueReference], [int(value)])
            elif v.type == "Boolean":
                instance.setBoolean([v.valueReference], [bool(value)])
            else:
                instance.setString([v.valueReference], [str(value)])

    def get_real(self, instance, names: list[str]) -> np.ndarray:
        return np.array(instance.getReal([self.vr[n] for n in names])) if names else np.zeros(0)
