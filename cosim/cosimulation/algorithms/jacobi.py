"""Jacobi coupling: every component steps from the outputs of the previous communication point."""
from __future__ import annotations

from cosim.cosimulation.algorithms.base import CouplingAlgorithm, register


@register
class Jacobi(CouplingAlgorithm):
    """Fixed-step Jacobi: the inputs of every due component are set from the outputs of the
    previous communication point, then all step, then all outputs are read. A component without
    states answers one of its steps late; a component with states sees its inputs held over its
    step (zero-order hold, half a step late on average). This is OSP's FixedStepAlgorithm
    (libcosim, Ecos) and OMSimulator's fixed-step master."""

    name = "jacobi"
    sequential = False
    fast_code = 0
    osp_algorithm = "FixedStepAlgorithm"
    omsimulator_master = "oms-ma"

    def output_lag(self, step: float) -> float:
        return step

    def hold_lag(self, step: float) -> float:
        return step / 2
