"""Python blocks and their Modelica twins: a system with Python blocks becomes an all-FMU system
(for SSP export and for other FMI tools) by swapping each block for the FMU of its twin."""
from __future__ import annotations

import dataclasses

from .controllers import lqr_gains
from .system import ComponentSpec, SystemError_, SystemSpec


def _same(parameters: dict) -> dict:
    return dict(parameters)


def _lqr(parameters: dict) -> dict:
    return lqr_gains(**{k: parameters[k] for k in parameters})


def _delay(parameters: dict) -> dict:
    # The exact transport delay has no Modelica form the compiler accepts (no delay()); its twin is
    # the Pade approximation whose order is fixed when the FMU is built (n = 2).
    return {"tau": parameters.get("tau", 0.1)}


def _pade(parameters: dict) -> dict:
    if parameters.get("n", 2) != 2:
        raise SystemError_("the Modelica twin Bicycle.Rider.PadeDelay is built with n = 2")
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
        components[name] = ComponentSpec(name, "model", model, convert(entry.parameters), entry.step_multiple)
        exact = " (exact delay -> Pade approximation, n = 2)" if entry.source == "TransportDelay" else ""
        notes.append(f"{name}: Python {entry.source} -> {model}{exact}")
    return dataclasses.replace(spec, components=components), notes
