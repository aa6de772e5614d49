"""Gauss-Seidel coupling: components step one after another along their direct feedthrough."""
from __future__ import annotations

from cosim.cosimulation.algorithms.base import CouplingAlgorithm, register


@register
class GaussSeidel(CouplingAlgorithm):
    """Fixed-step Gauss-Seidel: the due components step one after another in an order along the
    connections with direct feedthrough, each after its inputs took the outputs of the components
    before it in the same step; a cycle of such connections without a delay has no such order
    and is refused. A component without states answers in the same step (no lag); a component
    with states sees its inputs held over its step (half a step late on average). SSP
    annotations have no such algorithm."""

    name = "gauss-seidel"
    sequential = True
    fast_code = 1

    def output_lag(self, step: float) -> float:
        return 0.0

    def hold_lag(self, step: float) -> float:
        return step / 2
