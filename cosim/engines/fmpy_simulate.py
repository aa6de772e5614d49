"""FMPy, through ``cosim simulate`` (:func:`cosim.fmu.simulate.simulate`): single FMUs."""
from __future__ import annotations

import numpy as np

from cosim.engines.base import Engine, EngineUnavailable, register
from cosim.fmu.simulate import simulate


@register
class FMPy(Engine):
    """FMPy's Co-Simulation of one FMI 2.0 or 3.0 FMU (its own fixed communication step), as
    ``cosim simulate --fmi-type cs`` runs it; the row FMPy records at the start is left out, as
    the other engines record only after each step."""

    name = "fmpy"
    module = "fmpy"
    fmi_versions = ("2.0", "3.0")
    independent = True
    reference = True

    def load(self):
        try:
            import fmpy as module
        except ImportError as exc:
            raise EngineUnavailable(f"FMPy cannot be loaded: {exc}") from None
        return module

    def run_fmu(self, fmu, stop_time, step, start_values=None, outputs=None) -> np.ndarray:
        return simulate(fmu, stop_time, step, "cs", start_values, outputs=outputs)[1:]
