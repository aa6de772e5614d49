"""Model-exchange coupling: every component integrated together as one ODE by RK4 at the step."""
from __future__ import annotations

from cosim.cosimulation.algorithms.base import CouplingAlgorithm, register


@register
class ModelExchangeCoupling(CouplingAlgorithm):
    """All components integrated as one ODE by classic Runge-Kutta 4 at the communication step
    (:mod:`cosim.cosimulation.model_exchange`): no input is held, so the coupling adds no lag of
    a sampled-data system. Neither the analytic prediction of the case matrix nor SSP annotations
    describe it."""

    name = "model-exchange"
    one_ode = True
