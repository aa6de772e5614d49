"""Create the components of a system file: FMUs (built from models when needed) and Python blocks."""
from __future__ import annotations

import inspect
from pathlib import Path

from ..errors import FMUError, ParameterError
from . import blocks, controllers
from .component import Component, FMUComponent
from .system import SystemError_, SystemSpec, load_system

PYTHON_BLOCKS = {
    "Proportional": controllers.Proportional,
    "PD": controllers.PD,
    "SteerAngleFeedback": controllers.SteerAngleFeedback,
    "StateFeedback": controllers.StateFeedback,
    "LQR": controllers.lqr,
    "LaneChange": controllers.LaneChange,
    "LeanSteer": controllers.LeanSteer,
    "TransportDelay": blocks.TransportDelay,
    "PadeDelay": blocks.pade_delay,
    "Pulse": blocks.Pulse,
    "Step": blocks.Step,
}


def _block_argument(block: str, key: str, value, annotation: str):
    """A system-file value for a block argument, checked against the argument's annotation."""
    import math

    kind = str(annotation).split("|")[0].strip()
    if kind == "float":
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ParameterError(f"parameter '{key}': expected a number, got {value!r}")
        if not math.isfinite(value):
            raise ParameterError(f"parameter '{key}': must be finite, got {value!r}")
        return float(value)
    if kind == "int":
        if isinstance(value, bool) or not isinstance(value, (int, float)) or value != int(value):
            raise ParameterError(f"parameter '{key}': expected a whole number, got {value!r}")
        return int(value)
    if kind == "str" and not isinstance(value, str):
        raise ParameterError(f"parameter '{key}': expected a string, got {value!r}")
    return value


def python_block(name: str, block: str, parameters: dict, where: str = "system") -> Component:
    """Instantiate a built-in Python block; unknown blocks and parameters, and values of the
    wrong type (checked against the block's signature), are named in the error."""
    factory = PYTHON_BLOCKS.get(block)
    if factory is None:
        raise SystemError_(f"{where}: component '{name}': unknown Python block '{block}' "
                           f"(available: {', '.join(PYTHON_BLOCKS)})")
    signature = inspect.signature(factory).parameters
    accepted = set(signature) - {"name"}
    unknown = set(parameters) - accepted
    if unknown:
        raise SystemError_(f"{where}: component '{name}' ({block}): unknown parameter(s) "
                           f"{', '.join(sorted(unknown))}; accepted: {', '.join(sorted(accepted))}")
    try:
        arguments = {k: _block_argument(block, k, v, signature[k].annotation) for k, v in parameters.items()}
        return factory(name, **arguments)
    except ParameterError as exc:
        raise SystemError_(f"{where}: component '{name}' ({block}): {exc}") from None


def create_components(spec: SystemSpec, fmu_dir: str | Path | None = None) -> dict[str, Component]:
    """Component objects for every entry of the system (models are built into ``fmu_dir``)."""
    from ..compiler.build import DEFAULT_OUTPUT, build_model
    from ..compiler.library import load_library
    from ..parameters import check, declarations

    where = str(spec.path or spec.name)
    created: dict[str, Component] = {}
    try:
        for name, entry in spec.components.items():
            if entry.kind == "python":
                created[name] = python_block(name, entry.source, entry.parameters, where)
                continue
            if entry.kind == "model":
                fmu = build_model(entry.source, fmu_dir or DEFAULT_OUTPUT, load_library()).fmu
            else:
                fmu = Path(entry.source)
                if not fmu.is_file():
                    raise SystemError_(f"{where}: component '{name}': FMU '{fmu}' not found")
            try:
                values = check(entry.parameters, declarations(str(fmu)),
                               input_hint="connect it, e.g. to a Step or Pulse block")
                created[name] = FMUComponent(name, fmu, values)
            except ParameterError as exc:
                raise SystemError_(f"{where}: component '{name}': {exc}") from None
            except FMUError as exc:
                raise FMUError(f"{where}: component '{name}': {exc}") from None
    except BaseException:
        for comp in created.values():
            comp.close()
        raise
    return created


def run_system(path_or_spec, fmu_dir: str | Path | None = None):
    """Load a system file, create its components and run it; returns a RunResult."""
    from .master import run_components

    spec = path_or_spec if isinstance(path_or_spec, SystemSpec) else load_system(path_or_spec)
    return run_components(spec, create_components(spec, fmu_dir))
