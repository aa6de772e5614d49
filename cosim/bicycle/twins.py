"""The analytic twins of the exported bicycle models, with those of the nonlinear bicycles.

:data:`cosim.analytic.twins.TWINS` (the simple models and ``WhippleLinear``) compare with an FMU's
linearization as it is; the nonlinear bicycles' twins (:data:`STEADY_MOTION_TWINS`) reduce it
first to the lateral dynamics about upright straight running
(:func:`cosim.bicycle.linearize.steady_motion`) and read their defaults from the model's Modelica
declarations. :func:`twin` and :func:`analytic_system` take any of them by model name.
"""
from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache

import control

from cosim.analytic.twins import LATERAL_OUTPUTS, TWINS, Twin, steady_lateral
from cosim.bicycle.linearize import steady_motion
from cosim.fmu.parameters import declarations, starts

__all__ = ["SteadyMotionTwin", "STEADY_MOTION_TWINS", "twin", "analytic_system"]


@dataclass(frozen=True)
class SteadyMotionTwin(Twin):
    """The analytic twin of a nonlinear bicycle's linearization about upright straight running.

    The FMU's linearization is first reduced exactly to its lateral dynamics and path
    (:func:`cosim.bicycle.linearize.steady_motion`, with the rider's hinge locked if ``lock_hinge``);
    the defaults are read from the model's Modelica declarations (no copies of the values).
    """

    lock_hinge: bool = False

    def default_values(self) -> dict[str, float]:
        return dict(_modelica_defaults(self.model, os.environ.get("COSIM_MODELICA_PATH")))

    def reduce(self, linearization) -> control.StateSpace:
        return steady_motion(linearization, lock_hinge=self.lock_hinge).to_statespace()


@lru_cache(maxsize=8)
def _modelica_defaults(model: str, library: str | None) -> dict[str, float]:
    """Numeric defaults of the top-level parameters declared by ``model`` (``library``: the cache key)."""
    return {k: v for k, v in starts(declarations(model)).items() if "." not in k}


#: Twins of the nonlinear bicycles' linearization about upright straight running.
STEADY_MOTION_TWINS: dict[str, SteadyMotionTwin] = {t.model: t for t in (
    SteadyMotionTwin("Bicycle.Bicycles.Whipple", lambda p, u: steady_lateral(p, u, rider=False), {},
                     ("T_delta", "T_phi"), LATERAL_OUTPUTS, speed="u_R0",
                     equations="Meijaard et al. (2007) M, C1, K0, K2 plus the path (A 9), about upright "
                               "straight running"),
    SteadyMotionTwin("Bicycle.Bicycles.WhippleRider", lambda p, u: steady_lateral(p, u, rider=True), {},
                     ("T_delta", "T_phi"), LATERAL_OUTPUTS, speed="u_R0",
                     equations="Meijaard et al. (2007) with the upper body merged into the rear frame "
                               "(hip hinge locked)", lock_hinge=True),
)}


def twin(model_name: str) -> Twin:
    """The twin of ``model_name`` (:data:`TWINS`, else :data:`STEADY_MOTION_TWINS`); ``KeyError``
    lists the models that have one."""
    found = TWINS.get(model_name) or STEADY_MOTION_TWINS.get(model_name)
    if found is None:
        raise KeyError(f"no analytic twin for '{model_name}'; twins exist for: "
                       f"{', '.join([*TWINS, *STEADY_MOTION_TWINS])}")
    return found


def analytic_system(model_name: str, parameters: Mapping[str, float] | None = None) -> control.StateSpace:
    """The analytic state-space model of an exported model at the given parameter values.

    Parameters
    ----------
    model_name : str
        Full Modelica name, a key of :data:`cosim.analytic.twins.TWINS` or of
        :data:`STEADY_MOTION_TWINS`.
    parameters : dict, optional
        Top-level parameter values by Modelica name (SI units); missing ones take the model's
        defaults, names containing a dot are ignored.

    Returns
    -------
    control.StateSpace
        Inputs and outputs named and ordered as the FMU's top-level inputs and outputs.

    Raises
    ------
    KeyError
        No twin for the model.
    ValueError
        Unknown parameter name, or a value the analytic model rejects (e.g. V at the
        self-alignment speed, a non-positive mass), naming the parameter.
    """
    return twin(model_name).system(parameters)
