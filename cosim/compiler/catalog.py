"""What the library offers: models with their interface (for `cosim list` and `cosim info MODEL`)."""
from __future__ import annotations

import sys
from collections.abc import Callable
from dataclasses import asdict, dataclass, field

from cosim.compiler.flatten import flatten
from cosim.compiler.library import Library, load_library
from cosim.errors import CosimError


#: Longest parameter value `cosim list` prints in full; longer ones (expressions) are shortened.
SHORT_VALUE = 40


def shorten(value, limit: int = SHORT_VALUE) -> str:
    """``value`` as text of at most ``limit`` characters: a longer one (typically a parameter
    defined by a long expression) is cut to its first ``limit - 3`` characters and ``...``.
    ``None`` (a value that is not known before the model is built) prints as ``?``."""
    text = "?" if value is None else str(value)
    return text if len(text) <= limit else text[:limit - 3] + "..."


@dataclass
class Signal:
    """A top-level input, output or parameter of a model."""

    name: str
    unit: str | None = None
    description: str = ""
    value: float | str | None = None
    min: float | None = None
    max: float | None = None
    type: str = "Real"  # the declared type: Real, Integer or Boolean


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
        """JSON-ready: full values, ``None`` (JSON ``null``) where a value is unknown."""
        return asdict(self)


def summarize(name: str, library: Library | None = None) -> ModelSummary:
    """Flatten ``name`` and list its top-level inputs, outputs and parameters, each with its
    declared type (Real, Integer or Boolean, also behind a derived type such as
    ``Bicycle.Units.Angle``), unit, description, ``min``/``max`` and, for parameters, value.

    Raises
    ------
    UnknownModelError, ModelicaError
    """
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
            # a number, an expression of other parameters (its text), or unknown (None: JSON null)
            signal.value = value if value is None or isinstance(value, (int, float)) else str(value)
            summary.parameters.append(signal)
        elif "input" in decl.prefixes:
            summary.inputs.append(signal)
        elif "output" in decl.prefixes:
            summary.outputs.append(signal)
    return summary


def _warn_on_stderr(message: str) -> None:
    print(f"cosim: warning: {message}", file=sys.stderr)


def catalog(library: Library | None = None, exported_only: bool = False,
            warn: Callable[[str], None] | None = None) -> list[ModelSummary]:
    """Summaries of all (or only exported) models of the library that can be summarized.

    The others are left out with a warning of one line each: one per Modelica file that did
    not parse (naming the file, the position and the models left out because they are defined
    in it or use its classes), one per other model that cannot be flattened.

    Parameters
    ----------
    warn : callable, optional
        Called with each warning (default: printed as one line on stderr).
    """
    library = library or load_library()
    warn = warn or _warn_on_stderr
    left_out: dict = {file: [] for file in library.errors}
    summaries = []
    for entry in library.models(exported_only=exported_only):
        try:
            summaries.append(summarize(entry.name, library))
        except CosimError as exc:
            text = str(exc)
            file = next((f for f, error in library.errors.items() if text.startswith(str(error))), None)
            if file is not None:
                left_out[file].append(entry.name)
            else:
                warn(f"{entry.name} is not listed: {text.splitlines()[0]}")
    for file, error in library.errors.items():
        models = f"; not listed: {', '.join(left_out[file])}" if left_out[file] else ""
        warn(f"{str(error).splitlines()[0]}{models}")
    return summaries
