"""System files (TOML): components, parameters, connections and settings of a co-simulation.

Example (``connections`` stands before the first table, as TOML requires of top-level keys)::

    connections = ["bike.phi -> rider.phi", "rider.T -> bike.T_delta"]

    [system]
    name = "rider-p-control"
    start = 0.0
    stop = 10.0
    step = 0.01                 # base communication step [s]
    algorithm = "jacobi"        # or "gauss-seidel"
    initialize = true           # propagate outputs to inputs before the first step
    sampling = "after-step"     # or "after-transfer": when outputs are recorded
    fall = { signal = "bike.phi", limit = 1.0 }   # stop with "fell at t = ..." beyond |limit|

    [components.bike]
    model = "Bicycle.Bicycles.WhippleLinear"      # or fmu = "path.fmu", or python = "TransportDelay"
    params = "benchmark"                          # a Meijaard parameter set (name or TOML file)
    step_multiple = 1
    parameters = { v = 4.0 }

    [components.rider]
    python = "Proportional"
    parameters = { k = 20.0 }
"""
from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import ParameterError

ALGORITHMS = ("jacobi", "gauss-seidel")
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
    """Read and check the structure of a system file (names are checked against the components
    when the system is assembled, see :func:`cosim.cosimulation.master.assemble`)."""
    path = Path(path)
    if not path.is_file():
        raise SystemError_(f"{path}: system file not found")
    try:
        data = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as exc:
        raise SystemError_(f"{path}: {exc}") from None
    return system_from_dict(data, path)


def system_from_dict(data: dict, path: Path | None = None) -> SystemSpec:
    where = str(path) if path else "system"
    settings = data.get("system", {})
    if "connections" in settings:
        raise SystemError_(f"{where}: 'connections' ended up inside [system]: "
                           "write it at the top of the file, before the first [table]")
    unknown = set(settings) - {"name", "description", "start", "stop", "step", "algorithm", "initialize",
                               "fall", "record", "sampling"}
    if unknown:
        raise SystemError_(f"{where}: unknown [system] keys: {', '.join(sorted(unknown))}")
    components = {}
    for name, entry in data.get("components", {}).items():
        kinds = [k for k in ("model", "fmu", "python") if k in entry]
        if len(kinds) != 1:
            raise SystemError_(f"{where}: component '{name}' needs exactly one of model, fmu, python")
        extra = set(entry) - {"model", "fmu", "python", "parameters", "step_multiple", "params"}
        if "connections" in extra:
            raise SystemError_(f"{where}: 'connections' ended up inside [components.{name}]: "
                               "write it at the top of the file, before the first [table]")
        if extra:
            raise SystemError_(f"{where}: component '{name}': unknown keys {', '.join(sorted(extra))}")
        source = entry[kinds[0]]
        if kinds[0] == "fmu" and path is not None and not Path(source).is_absolute():
            source = str((path.parent / source).resolve())
        multiple = entry.get("step_multiple", 1)
        if not isinstance(multiple, int) or multiple < 1:
            raise SystemError_(f"{where}: component '{name}': step_multiple must be a positive integer")
        parameters = dict(entry.get("parameters", {}))
        parameter_set = entry.get("params")
        if parameter_set is not None:
            from ..errors import ParameterError
            from ..whipple_params import parameters_for_model

            if path is not None and (parameter_set.endswith(".toml") or "/" in parameter_set):
                parameter_set = str((path.parent / parameter_set).resolve())
            try:
                parameters = {**parameters_for_model(parameter_set), **parameters}
            except ParameterError as exc:
                raise SystemError_(f"{where}: component '{name}': {exc}") from None
        components[name] = ComponentSpec(name, kinds[0], source, parameters, multiple, parameter_set)
    if not components:
        raise SystemError_(f"{where}: no [components]")
    connections = [parse_connection(text, where) for text in data.get("connections", [])]
    algorithm = settings.get("algorithm", "jacobi").lower()
    if algorithm not in ALGORITHMS:
        raise SystemError_(f"{where}: algorithm must be one of {', '.join(ALGORITHMS)}, got '{algorithm}'")
    step = float(settings.get("step", 0.01))
    start, stop = float(settings.get("start", 0.0)), float(settings.get("stop", 10.0))
    if not step > 0:
        raise SystemError_(f"{where}: step must be positive")
    if not stop > start:
        raise SystemError_(f"{where}: stop must be after start")
    sampling = settings.get("sampling", "after-step")
    if sampling not in SAMPLINGS:
        raise SystemError_(f"{where}: sampling must be one of {', '.join(SAMPLINGS)}, got '{sampling}'")
    fall = settings.get("fall", {})
    return SystemSpec(
        name=settings.get("name", path.stem if path else "system"), path=path, components=components,
        connections=connections, start=start, stop=stop, step=step, algorithm=algorithm,
        initialize=bool(settings.get("initialize", True)), fall_signal=fall.get("signal"),
        fall_limit=float(fall["limit"]) if "limit" in fall else None, record=settings.get("record"),
        description=settings.get("description", ""), sampling=sampling,
    )
