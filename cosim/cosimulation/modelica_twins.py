"""Python blocks and their Modelica twins: a system with Python blocks becomes an all-FMU system
(for SSP export and for other FMI tools) by swapping each block for the FMU of its twin."""
from __future__ import annotations

import dataclasses

from ..errors import ParameterError
from .controllers import lqr_gains
from .system import ComponentSpec, SystemError_, SystemSpec


def _same(parameters: dict) -> dict:
    return dict(parameters)


def _lqr(parameters: dict) -> dict:
    """The gains the Python LQR block would design (its defaults for what is not given)."""
    import inspect

    from .controllers import lqr

    defaults = {k: p.default for k, p in inspect.signature(lqr).parameters.items() if k != "name"}
    unknown = sorted(set(parameters) - set(defaults))
    if unknown:
        raise ParameterError(f"unknown parameter(s) {', '.join(unknown)}; accepted: {', '.join(sorted(defaults))}")
    return lqr_gains(**{**defaults, **parameters})


def _delay(parameters: dict) -> dict:
    # The exact transport delay has no Modelica form the compiler accepts (no delay()); its twin is
    # the Pade approximation whose order is fixed when the FMU is built (n = 2).
    return {"tau": parameters.get("tau", 0.1)}


def _pade(parameters: dict) -> dict:
    if parameters.get("n", 2) != 2:
        raise ParameterError("the Modelica twin Bicycle.Rider.PadeDelay is built with n = 2")
    return {"tau": parameters.get("tau", 0.1)}


TWINS = {
    "Proportional": ("Bicycle.Control.Proportional", _same),
    "PD": ("Bicycle.Control.PD", _same),
    "SteerAngleFeedback": ("Bicycle.Control.SteerAngleFeedback", _same),
    "StateFeedback": ("Bicycle.Control.StateFeedback", _same),
    "LQR": ("Bicycle.Control.StateFeedback", _lqr),
    "LaneChange": ("Bicycle.Control.LaneChange", _same),
    "LeanSteer": ("Bicycle.Control.LeanSteer", _same),
    "Pulse": ("Bicycle.Sources.TorquePulse", _same),
    "TransportDelay": ("Bicycle.Rider.PadeDelay", _delay),
    "PadeDelay": ("Bicycle.Rider.PadeDelay", _pade),
}


def with_twins(spec: SystemSpec) -> tuple[SystemSpec, list[str]]:
    """The system with every Python block replaced by its Modelica twin, and a note per swap."""
    components, notes = {}, []
    for name, entry in spec.components.items():
        if entry.kind != "python":
            components[name] = entry
            continue
        if entry.source not in TWINS:
            raise SystemError_(f"{spec.path or spec.name}: component '{name}': the Python block "
                               f"'{entry.source}' has no Modelica twin")
        model, convert = TWINS[entry.source]
        try:
            parameters = convert(entry.parameters)
        except ParameterError as exc:
            raise SystemError_(f"{spec.path or spec.name}: component '{name}' ({entry.source}): {exc}") from None
        components[name] = ComponentSpec(name, "model", model, parameters, entry.step_multiple)
        exact = " (exact delay -> Pade approximation, n = 2)" if entry.source == "TransportDelay" else ""
        notes.append(f"{name}: Python {entry.source} -> {model}{exact}")
    return dataclasses.replace(spec, components=components), notes
