"""What the library offers: models with their interface (for `cosim list` and `cosim info MODEL`)."""
from __future__ import annotations

from dataclasses import asdict, dataclass, field

from .compiler.flatten import flatten
from .compiler.library import Library, load_library


@dataclass
class Signal:
    """A top-level input, output or parameter of a model."""

    name: str
    unit: str | None = None
    description: str = ""
    value: float | str | None = None
    min: float | None = None
    max: float | None = None
    type: str = "Real"


@dataclass
class ModelSummary:
    """The interface of one Modelica model."""

    name: str
    description: str
    exported: bool
    experiment: dict
    inputs: list[Signal] = field(default_factory=list)
    outputs: list[Signal] = field(default_factory=list)
    parameters: list[Signal] = field(default_factory=list)

    def to_dict(self) -> dict:
        return asdict(self)


def summarize(name: str, library: Library | None = None) -> ModelSummary:
    """Flatten ``name`` and list its top-level inputs, outputs and parameters."""
    library = library or load_library()
    entry = library.entry(name)
    flat = flatten(library, name)
    values = {v.symbol.name(): v.value for v in flat.casadi.parameters}
    summary = ModelSummary(name, entry.description, entry.exported, entry.experiment)
    for decl in flat.declarations.values():
        if "." in decl.name:
            continue
        signal = Signal(decl.name, decl.unit, decl.description, None,
                        decl.min if isinstance(decl.min, (int, float)) else None,
                        decl.max if isinstance(decl.max, (int, float)) else None, decl.type)
        if "parameter" in decl.prefixes:
            value = values.get(decl.name)
            signal.value = value if isinstance(value, (int, float)) else str(value)
            summary.parameters.append(signal)
        elif "input" in decl.prefixes:
            summary.inputs.append(signal)
        elif "output" in decl.prefixes:
            summary.outputs.append(signal)
    return summary


def catalog(library: Library | None = None, exported_only: bool = False) -> list[ModelSummary]:
    """Summaries of all (or only exported) models of the library."""
    library = library or load_library()
    return [summarize(e.name, library) for e in library.models(exported_only=exported_only)]
