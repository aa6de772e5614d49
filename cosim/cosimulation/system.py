"""System files (TOML): components, parameters, connections and settings of a co-simulation.

Example (``connections`` stands before the first table, as TOML requires of top-level keys)::

    connections = ["bike.phi -> rider.phi", "rider.T -> bike.T_delta"]

    [system]
    name = "rider-p-control"
    start = 0.0
    stop = 10.0
    step = 0.01                 # base communication step [s]
    algorithm = "jacobi"        # or "gauss-seidel", or "model-exchange" (one ODE, RK4 at step)
    initialize = true           # propagate outputs to inputs before the first step
    sampling = "after-step"     # or "after-transfer": when outputs are recorded
    fall = { signal = "bike.phi", limit = 1.0 }   # stop with "fell at t = ..." beyond |limit|

    [components.bike]
    model = "Bicycle.Bicycles.WhippleLinear"      # or fmu = "path.fmu", or python = "TransportDelay"
    fmi_version = 2                               # a model is built as FMI 2.0 (default) or 3.0
    params = "benchmark"                          # a Meijaard parameter set (name or TOML file)
    step_multiple = 1
    parameters = { v = 4.0 }

    [components.rider]
    python = "Proportional"
    parameters = { k = 20.0 }
"""
from __future__ import annotations

import math
import os
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from cosim.errors import ParameterError
from cosim.cosimulation import algorithms
from cosim.outputs import check_input_file, read_text_file

# When outputs are recorded: right after the step (libcosim's observers) or after the connected
# inputs were updated, so direct-feedthrough outputs already see the new inputs (Ecos).
SAMPLINGS = ("after-step", "after-transfer")


class SystemError_(ParameterError):
    """A system file that cannot be run; the message names the file and the offending entry."""


@dataclass
class ComponentSpec:
    name: str
    kind: str  # model, fmu or python
    source: str  # model name, FMU path or Python block name
    parameters: dict = field(default_factory=dict)
    step_multiple: int = 1
    parameter_set: str | None = None  # Meijaard parameter set (name or TOML) applied before `parameters`
    fmi_version: str = "2"  # a model component: the FMI version it is built as ("2" or "3")


@dataclass
class Connection:
    source: str  # component name
    output: str
    target: str
    input: str

    def __str__(self):
        return f"{self.source}.{self.output} -> {self.target}.{self.input}"


@dataclass
class SystemSpec:
    name: str
    path: Path | None
    components: dict[str, ComponentSpec]
    connections: list[Connection]
    start: float = 0.0
    stop: float = 10.0
    step: float = 0.01
    algorithm: str = "jacobi"
    initialize: bool = True
    fall_signal: str | None = None
    fall_limit: float | None = None
    record: list[str] | None = None
    description: str = ""
    sampling: str = "after-step"


def _split_signal(text: str, where: str) -> tuple[str, str]:
    component, sep, variable = text.strip().partition(".")
    if not sep or not component or not variable:
        raise SystemError_(f"{where}: '{text}' is not COMPONENT.VARIABLE")
    return component, variable


def parse_connection(text: str, where: str) -> Connection:
    """``"a.y -> b.u"`` as a Connection."""
    left, arrow, right = text.partition("->")
    if not arrow:
        raise SystemError_(f"{where}: connection '{text}' must read 'COMPONENT.OUTPUT -> COMPONENT.INPUT'")
    source, output = _split_signal(left, where)
    target, input_ = _split_signal(right, where)
    return Connection(source, output, target, input_)


def load_system(path: str | Path) -> SystemSpec:
    """Read a system file and check it against the schema (:func:`system_from_dict`); names are
    checked against the components when the system is assembled (see
    :func:`cosim.cosimulation.master.assemble`).

    Parameters
    ----------
    path : str or Path
        The system file (TOML): ``[system]`` settings (``start``, ``stop``, ``step`` in s),
        ``[components.NAME]`` (a model, an FMU or a registered Python block, with parameters in
        SI units) and ``connections``.

    Returns
    -------
    SystemSpec
        The checked system.

    Raises
    ------
    SystemError_
        Naming the file and every problem found.
    """
    path = check_input_file(path, SystemError_, what="system file")
    try:
        data = tomllib.loads(read_text_file(path, SystemError_, str(path)))
    except tomllib.TOMLDecodeError as exc:
        raise SystemError_(f"{path}: {exc}") from None
    except RecursionError:  # tomllib parses nested arrays and tables recursively
        raise SystemError_(f"{path}: not valid TOML: nested too deeply") from None
    return system_from_dict(data, path)


# --------------------------------------------------------------------------- the schema
#
# One description of every key a system file may have, checked in one pass that collects all
# problems (as FMPy's validation does) before one SystemError_ lists them.

SYSTEM_KEYS = ("name", "description", "start", "stop", "step", "algorithm", "initialize", "fall", "record",
               "sampling")
COMPONENT_KEYS = ("model", "fmu", "python", "parameters", "step_multiple", "params", "fmi_version")
KINDS = ("model", "fmu", "python")
#: The FMI versions a model component is built as (``fmi_version``; an FMU file has its own).
FMI_VERSIONS = ("2", "3")
DEFAULTS = {"start": 0.0, "stop": 10.0, "step": 0.01}
#: Most communication steps one run takes (a guard against ``stop = 1e9, step = 1e-9``).
MAX_STEPS = 10_000_000


def type_name(value) -> str:
    """A TOML value's type for a message, with the value where it is short: "a string ('x')"."""
    if isinstance(value, bool):
        return f"a boolean ({str(value).lower()})"
    if isinstance(value, int):
        return f"an integer ({value})" if abs(value) < 10 ** 12 else "an integer"
    if isinstance(value, float):
        return f"a number ({value!r})"
    if isinstance(value, str):
        return f"a string ({value!r})" if len(value) <= 40 else "a string"
    if isinstance(value, list):
        return "an array"
    if isinstance(value, dict):
        return "a table"
    return type(value).__name__


class _Problems:
    """Collects schema problems; ``raise_if_any`` raises one SystemError_ listing them all."""

    def __init__(self, where: str):
        self.where, self.items = where, []

    def add(self, key: str, text: str) -> None:
        self.items.append(f"{key}: {text}" if key else text)

    def expected(self, key: str, what: str, value) -> None:
        self.add(key, f"expected {what}, got {type_name(value)}")

    def raise_if_any(self) -> None:
        if len(self.items) == 1:
            raise SystemError_(f"{self.where}: {self.items[0]}")
        if self.items:
            raise SystemError_(f"{self.where}: {len(self.items)} problems: " + "; ".join(self.items))


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _number(problems: _Problems, key: str, value, positive: bool = False):
    """A finite number (TOML int or float, not a boolean); None after recording a problem."""
    if not _is_number(value):
        problems.expected(key, "a number", value)
        return None
    value = float(value)
    if not math.isfinite(value):
        problems.add(key, f"must be finite, got {value!r}")
        return None
    if positive and not value > 0:
        problems.add(key, f"must be > 0, got {value:g}")
        return None
    return value


def _string(problems: _Problems, key: str, value, choices: tuple[str, ...] | None = None):
    if not isinstance(value, str):
        what = f"a string ({' or '.join(repr(c) for c in choices)})" if choices else "a string"
        problems.expected(key, what, value)
        return None
    if choices is not None and value.lower() not in choices:
        problems.add(key, f"must be one of {', '.join(choices)}, got '{value}'")
        return None
    return value.lower() if choices is not None else value


def _string_list(problems: _Problems, key: str, value) -> list[str] | None:
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        problems.expected(key, "an array of strings", value)
        return None
    return list(value)


def _settings(problems: _Problems, settings) -> dict:
    """The checked [system] table (missing keys take :data:`DEFAULTS`)."""
    if not isinstance(settings, dict):
        problems.expected("[system]", "a table", settings)
        return {}
    if "connections" in settings:
        problems.add("", "'connections' ended up inside [system]: write it at the top of the file, "
                         "before the first [table]")
    unknown = sorted(set(settings) - set(SYSTEM_KEYS) - {"connections"})
    if unknown:
        problems.add("", f"unknown [system] keys: {', '.join(unknown)} (known: {', '.join(SYSTEM_KEYS)})")
    out: dict = {}
    for key in ("name", "description"):
        if key in settings:
            out[key] = _string(problems, f"[system] {key}", settings[key])
    for key in ("start", "stop"):
        out[key] = _number(problems, f"[system] {key}", settings.get(key, DEFAULTS[key]))
    out["step"] = _number(problems, "[system] step", settings.get("step", DEFAULTS["step"]), positive=True)
    start, stop, step = out["start"], out["stop"], out["step"]
    if start is not None and stop is not None and not stop > start:
        problems.add("[system] stop", f"must be after start ({stop:g} s <= {start:g} s)")
    elif None not in (start, stop, step) and step > stop - start:
        problems.add("[system] step", f"{step:g} s is longer than the run from {start:g} s to {stop:g} s")
    elif None not in (start, stop, step) and not (stop - start) / step <= MAX_STEPS:
        problems.add("[system] step", f"{step:g} s from {start:g} s to {stop:g} s would take "
                                      f"{(stop - start) / step:.3g} steps (at most {MAX_STEPS:,}); use a larger step")
    out["algorithm"] = _string(problems, "[system] algorithm", settings.get("algorithm", "jacobi"),
                               algorithms.names())
    out["sampling"] = _string(problems, "[system] sampling", settings.get("sampling", "after-step"), SAMPLINGS)
    initialize = settings.get("initialize", True)
    if not isinstance(initialize, bool):
        problems.expected("[system] initialize", "a boolean (true or false)", initialize)
    out["initialize"] = bool(initialize) if isinstance(initialize, bool) else True
    out["fall_signal"] = out["fall_limit"] = None
    if "fall" in settings:
        out["fall_signal"], out["fall_limit"] = _fall(problems, settings["fall"])
    out["record"] = _string_list(problems, "[system] record", settings["record"]) if "record" in settings else None
    return out


def _fall(problems: _Problems, fall) -> tuple[str | None, float | None]:
    key = "[system] fall"
    if not isinstance(fall, dict):
        problems.expected(key, "a table { signal = \"COMPONENT.OUTPUT\", limit = NUMBER }", fall)
        return None, None
    unknown = sorted(set(fall) - {"signal", "limit"})
    if unknown:
        problems.add(key, f"unknown keys {', '.join(unknown)} (known: signal, limit)")
    if "signal" not in fall or "limit" not in fall:
        problems.add(key, "needs both signal and limit")
        return None, None
    signal = _string(problems, f"{key}.signal", fall["signal"])
    if signal is not None:
        try:
            _split_signal(signal, f"{key}.signal")
        except SystemError_ as exc:
            problems.add("", str(exc))
            signal = None
    limit = _number(problems, f"{key}.limit", fall["limit"], positive=True)
    return signal, limit


def _parameters(problems: _Problems, key: str, value) -> dict:
    """A table of parameter values: numbers, booleans or strings (types are checked against the
    model or block when the component is created)."""
    if not isinstance(value, dict):
        problems.expected(key, "a table { NAME = VALUE, ... }", value)
        return {}
    good = {}
    for name, v in value.items():
        if isinstance(v, (list, dict)):
            problems.expected(f"{key} {name}", "a number, boolean or string", v)
        else:
            good[name] = v
    return good


def _component(problems: _Problems, name: str, entry, path: Path | None) -> ComponentSpec | None:
    key = f"[components.{name}]"
    if not name.strip() or "." in name or name != name.strip():
        problems.add(key, "a component name must be non-empty, without dots or surrounding spaces "
                          "(signals are named COMPONENT.VARIABLE)")
        return None
    if not isinstance(entry, dict):
        problems.expected(key, "a table", entry)
        return None
    if "connections" in entry:
        problems.add("", f"'connections' ended up inside {key}: write it at the top of the file, "
                         "before the first [table]")
    extra = sorted(set(entry) - set(COMPONENT_KEYS) - {"connections"})
    if extra:
        problems.add(key, f"unknown keys {', '.join(extra)} (known: {', '.join(COMPONENT_KEYS)})")
    kinds = [k for k in KINDS if k in entry]
    if len(kinds) != 1:
        problems.add(key, f"needs exactly one of model, fmu, python (got {', '.join(kinds) or 'none'})")
        return None
    kind = kinds[0]
    source = _string(problems, f"{key} {kind}", entry[kind])
    multiple = entry.get("step_multiple", 1)
    if isinstance(multiple, bool) or not isinstance(multiple, int) or multiple < 1:
        problems.add(f"{key} step_multiple", f"must be a positive integer, got {type_name(multiple)}")
        multiple = None
    parameters = _parameters(problems, f"{key} parameters", entry.get("parameters", {}))
    fmi_version = _fmi_version(problems, key, kind, entry)
    parameter_set = entry.get("params")
    if parameter_set is not None:
        parameter_set = _string(problems, f"{key} params", parameter_set)
    if source is None or multiple is None or fmi_version is None or ("params" in entry and parameter_set is None):
        return None
    if kind == "fmu" and path is not None and not Path(source).is_absolute():
        source = os.path.abspath(path.parent / source)  # (not resolve(): a loop of links is named later)
    if parameter_set is not None:
        # deferred: `cosim --help` loads this module, and parameter sets rarely
        from cosim.analytic.parameters import parameters_for_model

        if path is not None and (parameter_set.endswith(".toml") or "/" in parameter_set):
            parameter_set = os.path.abspath(path.parent / parameter_set)
        try:
            parameters = {**parameters_for_model(parameter_set), **parameters}
        except ParameterError as exc:
            problems.add(f"{key} params", str(exc))
            return None
        except FileNotFoundError:
            problems.add(f"{key} params", f"no such bundled parameter set or file '{entry['params']}'")
            return None
    return ComponentSpec(name, kind, source, parameters, multiple, parameter_set, fmi_version)


def _fmi_version(problems: _Problems, key: str, kind: str, entry: dict) -> str | None:
    """The checked ``fmi_version`` of a component ("2" where not given); None after a problem."""
    if "fmi_version" not in entry:
        return "2"
    value = entry["fmi_version"]
    if kind != "model":
        what = "an FMU file has its own FMI version" if kind == "fmu" else "a Python block is no FMU"
        problems.add(f"{key} fmi_version", f"applies to model components only ({what})")
        return None
    text = str(value) if isinstance(value, (int, float, str)) and not isinstance(value, bool) else None
    version = {"2": "2", "2.0": "2", "3": "3", "3.0": "3"}.get(text.strip() if text else "")
    if version is None:
        problems.add(f"{key} fmi_version", f"must be 2 or 3, got {type_name(value)}")
    return version


def system_from_dict(data: dict, path: Path | None = None) -> SystemSpec:
    """Check a parsed system file against the schema and build the SystemSpec.

    Every key is checked for its type and range (numbers finite, ``step`` > 0 and not longer
    than the run, ``stop`` after ``start``, strings from their lists of choices, ...); all
    problems are collected and reported together in one :class:`SystemError_` that names the
    file, each key and the expected type.
    """
    where = str(path) if path else "system"
    problems = _Problems(where)
    if not isinstance(data, dict):
        problems.expected("", "a TOML document (tables and keys)", data)
        problems.raise_if_any()
    unknown = sorted(set(data) - {"system", "components", "connections"})
    if unknown:
        problems.add("", f"unknown top-level keys: {', '.join(unknown)} "
                         "(a system file has connections, [system] and [components.NAME])")
    settings = _settings(problems, data.get("system", {}))
    components = {}
    raw_components = data.get("components", {})
    if not isinstance(raw_components, dict):
        problems.expected("[components]", "tables [components.NAME]", raw_components)
    else:
        for name, entry in raw_components.items():
            component = _component(problems, name, entry, path)
            if component is not None:
                components[name] = component
        if not raw_components:
            problems.add("", "no [components]")
    connections = []
    raw_connections = data.get("connections", [])
    texts = _string_list(problems, "connections", raw_connections)
    for text in texts or []:
        try:
            connections.append(parse_connection(text, where))
        except SystemError_ as exc:
            problems.add("", str(exc).removeprefix(f"{where}: "))
    if settings.get("algorithm") and algorithms.algorithm(settings["algorithm"]).one_ode:
        for component in components.values():  # one ODE: every part moves with the same step
            if component.step_multiple != 1:
                problems.add(f"[components.{component.name}] step_multiple",
                             f"must be 1 under algorithm = \"{settings['algorithm']}\", got {component.step_multiple}")
    problems.raise_if_any()
    return SystemSpec(
        name=settings.get("name") or (path.stem if path else "system"), path=path, components=components,
        connections=connections, start=settings["start"], stop=settings["stop"], step=settings["step"],
        algorithm=settings["algorithm"], initialize=settings["initialize"], fall_signal=settings["fall_signal"],
        fall_limit=settings["fall_limit"], record=settings["record"],
        description=settings.get("description") or "", sampling=settings["sampling"],
    )
