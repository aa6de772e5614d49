"""Parameter values given on the command line (``--param NAME=VALUE``), checked against the
model's declarations (names, numbers, ``min``/``max``) before anything is built or run."""
from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import ParameterError
from .target import is_fmu_path


@dataclass
class Declared:
    """What a model says about one parameter or input."""

    name: str
    causality: str  # parameter or input
    type: str = "Real"
    unit: str | None = None
    min: float | None = None
    max: float | None = None


def split_assignment(text: str, option: str = "--param") -> tuple[str, str]:
    """Split ``NAME=VALUE``; ParameterError names the option if malformed."""
    name, sep, value = text.partition("=")
    if not sep or not name.strip() or not value.strip():
        raise ParameterError(f"{option} expects NAME=VALUE, got '{text}'")
    return name.strip(), value.strip()


def declarations(target: str) -> dict[str, Declared]:
    """Settable variables of an FMU file (from modelDescription.xml) or a model (from its source)."""
    if is_fmu_path(target):
        from fmpy import read_model_description

        md = read_model_description(target)

        def number(value):
            return None if value in (None, "") else float(value)

        # Parameters, inputs, and states with an exact start value (settable before initialization).
        return {v.name: Declared(v.name, v.causality if v.causality != "local" else "start value", v.type,
                                 getattr(v, "unit", None), number(getattr(v, "min", None)),
                                 number(getattr(v, "max", None)))
                for v in md.modelVariables
                if v.causality in ("parameter", "input")
                or (v.causality == "local" and v.initial == "exact" and v.variability == "continuous")}
    from .catalog import summarize

    summary = summarize(target)
    found = {s.name: Declared(s.name, "parameter", "Real", s.unit, s.min, s.max) for s in summary.parameters}
    found.update({s.name: Declared(s.name, "input", "Real", s.unit, s.min, s.max) for s in summary.inputs})
    return found


def check(values: dict, declared: dict[str, Declared]) -> dict:
    """Validate values by name against declarations; returns them converted to the declared types."""
    checked = {}
    for name, raw in values.items():
        d = declared.get(name)
        if d is None:
            known = ", ".join(n for n, v in declared.items() if v.causality == "parameter" and "." not in n)
            raise ParameterError(f"unknown parameter '{name}'; top-level parameters are: {known}")
        try:
            value = float(raw)
        except (TypeError, ValueError):
            raise ParameterError(f"parameter '{name}': '{raw}' is not a number") from None
        if not math.isfinite(value):
            raise ParameterError(f"parameter '{name}': value must be finite, got {raw}")
        unit = f" {d.unit}" if d.unit else ""
        if d.min is not None and value < d.min:
            raise ParameterError(f"parameter '{name}' = {value:g}{unit} is below its minimum {d.min:g}{unit}")
        if d.max is not None and value > d.max:
            raise ParameterError(f"parameter '{name}' = {value:g}{unit} is above its maximum {d.max:g}{unit}")
        checked[name] = int(value) if d.type == "Integer" else (value != 0 if d.type == "Boolean" else value)
    return checked


def from_command_line(target: str, assignments: list[str], extra: dict | None = None,
                      parameter_set: str | None = None) -> dict:
    """``--params`` set, then ``--param`` strings, then ``extra`` values (e.g. ``--speed``),
    checked for ``target``.

    ``parameter_set`` is a Meijaard parameter set (bundled name or TOML file) for models whose
    parameters carry the Meijaard names, such as ``Bicycle.Bicycles.WhippleLinear``."""
    values = {}
    if parameter_set:
        from .whipple_params import parameters_for_model

        values.update(parameters_for_model(parameter_set))
    values.update(dict(split_assignment(a) for a in assignments))
    values.update(extra or {})
    return check(values, declarations(target)) if values else {}
