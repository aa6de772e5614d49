"""Python blocks and their Modelica twins: a system with Python blocks becomes an all-FMU system
(for SSP export and for other FMI tools) by swapping each block for the FMU of its twin. Each
block declares its twin and the twin's parameter values itself (:mod:`cosim.cosimulation.registry`)."""
from __future__ import annotations

import dataclasses

from cosim.errors import ParameterError
from cosim.cosimulation import registry
from cosim.cosimulation.system import ComponentSpec, SystemError_, SystemSpec


def with_twins(spec: SystemSpec) -> tuple[SystemSpec, list[str]]:
    """The system with every Python block replaced by its Modelica twin, and a note per swap.

    Raises
    ------
    SystemError_
        If a block is unknown, has no twin, or its parameters are refused (by the block, or
        because the twin cannot represent them).
    """
    where = spec.path or spec.name
    components, notes = {}, []
    for name, entry in spec.components.items():
        if entry.kind != "python":
            components[name] = entry
            continue
        try:
            cls = registry.lookup(entry.source)
        except ParameterError as exc:
            raise SystemError_(f"{where}: component '{name}': {exc}") from None
        if cls.twin is None:
            raise SystemError_(f"{where}: component '{name}': the Python block '{entry.source}' has no Modelica twin")
        try:
            parameters = cls.create(name, entry.parameters).twin_parameters()
        except ParameterError as exc:
            raise SystemError_(f"{where}: component '{name}' ({entry.source}): {exc}") from None
        components[name] = ComponentSpec(name, "model", cls.twin, parameters, entry.step_multiple)
        approximation = f" ({cls.twin_approximation})" if cls.twin_approximation else ""
        notes.append(f"{name}: Python {entry.source} -> {cls.twin}{approximation}")
    return dataclasses.replace(spec, components=components), notes
