"""A thin layer over FMPy for one FMI 2.0 FMU: extract once, instantiate as ME or CS, address
variables by name. Linearization, validation and the co-simulation master build on it."""
from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import numpy as np

from .errors import SimulationError


class FMU:
    """An extracted FMU with its model description.

    Parameters
    ----------
    path : path-like
        The ``.fmu`` file.
    """

    def __init__(self, path: str | Path):
        from fmpy import extract, read_model_description

        self.path = Path(path)
        if not self.path.is_file():
            raise FileNotFoundError(f"{self.path}: no such FMU file")
        self.description = read_model_description(str(self.path))
        self._tmp = tempfile.mkdtemp(prefix="cosim-fmu-")
        self.unzipdir = extract(str(self.path), self._tmp)
        self.variables = {v.name: v for v in self.description.modelVariables}
        self.vr = {name: v.valueReference for name, v in self.variables.items()}

    def close(self):
        shutil.rmtree(self._tmp, ignore_errors=True)

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
