"""Parameter values given on the command line (``--param NAME=VALUE``) or in system files,
checked against the model's declarations (names, types, ``min``/``max``) before anything is
built or run.

Every FMU built here also has the parameter ``solver.fixedStepSize`` [s]: 0 (the default) lets
the FMU's Co-Simulation solver choose its steps (error-controlled Dormand-Prince 5(4)); a value
> 0 makes it take fixed steps of that size (the last step of a communication interval is
shortened to end on it). It is accepted by model name and by FMU, must be finite and >= 0, and
has no effect in Model Exchange (FMPy's CVode integrates there; ``cosim simulate`` refuses it).
"""
from __future__ import annotations

import math
import numbers
from dataclasses import asdict, dataclass

from cosim.compiler.catalog import CALCULATED, START_GUESS, START_VALUE, indexed_declarations, settable_role
from cosim.compiler.catalog import fmu_declarations as described_by_compiler
from cosim.errors import ParameterError
from cosim.fmu.access import READABLE_FMI_VERSIONS, read_fmu
from cosim.fmu.target import built_fmu, is_fmu_path

#: The roles (:attr:`Declared.causality`) of start values of states.
START_ROLES = (START_VALUE, START_GUESS)
#: The solver parameter every FMU built by this package has (see the module docstring).
FIXED_STEP_PARAMETER = "solver.fixedStepSize"
_BOOLEAN_WORDS = {"true": True, "false": False, "1": True, "0": False}


@dataclass
class Declared:
    """What a model says about one parameter or input."""

    name: str
    # parameter, input, "calculated parameter", "start value" or "start value (guess of the initial
    # equations)": see cosim.compiler.catalog.settable_role
    causality: str
    type: str = "Real"  # Real, Integer, Boolean, String or Enumeration
    unit: str | None = None
    min: float | None = None
    max: float | None = None
    start: float | None = None  # the default (start) value where it is a number
    range: tuple[int, int] | None = None  # the values an Integer can hold (None: 32 bit signed)


#: FMI 3 variable types by the FMI 2 type whose values they take here (a value is checked as
#: that type; the FMU is set with the setter of its own type, see cosim.fmu.access.FMU.set).
FMI3_TYPES = {"Float64": "Real", "Float32": "Real", **{f"{s}Int{b}": "Integer" for s in ("", "U") for b in (8, 16, 32, 64)}}
#: The values each FMI 3 integer type holds.
INTEGER_RANGES = {**{f"Int{b}": (-2 ** (b - 1), 2 ** (b - 1) - 1) for b in (8, 16, 32, 64)},
                  **{f"UInt{b}": (0, 2 ** b - 1) for b in (8, 16, 32, 64)}}


def split_assignment(text: str, option: str = "--param") -> tuple[str, str]:
    """Split ``NAME=VALUE``; ParameterError names the option if malformed."""
    name, sep, value = text.partition("=")
    if not sep or not name.strip() or not value.strip():
        raise ParameterError(f"{option} expects NAME=VALUE, got '{text}'")
    return name.strip(), value.strip()


def declarations(target: str, fmi_version: str = "2") -> dict[str, Declared]:
    """What a user may set of an FMU file or a model: its parameters, inputs (named, to be refused
    as constants), start values of states, and calculated parameters (named, to be refused).

    The same for a model name as for its built FMU: an FMU file's come from its
    modelDescription.xml (:func:`fmu_declarations`), a model's from the modelDescription.xml
    `cosim build` makes of it (:func:`model_declarations`, nothing is built), both by
    :func:`described`.

    Parameters
    ----------
    target : str
        FMU file or model name.
    fmi_version : {"2", "3"}
        For a model name: the FMI version of the FMU it is built as (an FMU file has its own).

    Raises
    ------
    FMUError
        If ``target`` is an FMU file that cannot be read (see :func:`cosim.fmu.access.read_fmu`).
    UnknownModelError, ModelicaError, ModelStructureError
        If ``target`` is a model name that is not in the library or cannot be built.
    """
    if is_fmu_path(target):
        return fmu_declarations(target)
    return model_declarations(target, fmi_version)


def fmu_declarations(path) -> dict[str, Declared]:
    """:func:`described` of the modelDescription.xml of an FMU file (FMI 2 or 3).

    Raises
    ------
    FMUError
        If the file cannot be read (see :func:`cosim.fmu.access.read_fmu`).
    """
    # Only the model description is read here (FMI 2 or 3): the verb that runs the FMU decides
    # which FMI versions it runs, and refuses the others when it opens the FMU.
    return described(read_fmu(path, READABLE_FMI_VERSIONS))


def model_declarations(name: str, fmi_version: str = "2") -> dict[str, Declared]:
    """:func:`described` of the modelDescription.xml that `cosim build` makes of the model
    ``name`` (FMI ``fmi_version``) without building it: the declarations its FMU will have.

    From the library index where it holds them, else from the model's FMU where that is built
    and up to date (:func:`cosim.fmu.target.built_fmu`), else made by the compiler and kept in
    the index (:func:`cosim.compiler.catalog.fmu_declarations`): a parse once, then none.

    Raises
    ------
    UnknownModelError, ModelicaError, ModelStructureError
        If the model is not in the library or cannot be built.
    """
    version = str(fmi_version)
    records = indexed_declarations(name, version)
    if records is not None:
        try:
            return _from_records(records)
        except (TypeError, KeyError):  # written by another version of this module: made anew below
            pass
    else:
        fmu = built_fmu(name, fmi_version=version)
        if fmu is not None:
            return fmu_declarations(fmu)
    return _from_records(described_by_compiler(name, version, _read_description, refresh=records is not None))


def _from_records(records: list[dict]) -> dict[str, Declared]:
    """The declarations of :func:`_read_description`'s records (as stored in the library index)."""
    return {d["name"]: Declared(**{**d, "range": tuple(d["range"]) if d.get("range") else None}) for d in records}


def _read_description(xml: bytes) -> list[dict]:
    """The :func:`described` variables of a modelDescription.xml text, JSON-ready."""
    import io
    import zipfile

    from fmpy.model_description import read_model_description

    archive = io.BytesIO()
    with zipfile.ZipFile(archive, "w") as z:  # FMPy reads a file object as an FMU archive
        z.writestr("modelDescription.xml", xml)
    archive.seek(0)
    md = read_model_description(archive, validate=False)  # written by the compiler, not a user's file
    return [asdict(d) for d in described(md).values()]


def described(md) -> dict[str, Declared]:
    """The variables a user may name before a run, from a model description (FMPy's
    ``ModelDescription``, FMI 2 or 3), by :func:`cosim.compiler.catalog.settable_role`: the
    parameters and inputs, the calculated parameters, and the start values of states that the
    FMU lets be set (``initial = "exact"`` or ``"approx"``)."""

    def number(value):
        try:
            return None if value in (None, "") else float(value)
        except (TypeError, ValueError):
            return None

    # An output that is a continuous state with an exact start value (foreign FMUs, e.g. the
    # Reference FMUs' VanDerPol x0, x1) is a start value too; other outputs are computed.
    state_outputs = {d.variable.derivative.name for d in md.derivatives
                     if d.variable.derivative is not None and d.variable.derivative.causality == "output"}
    found = {}
    for v in md.modelVariables:
        role = settable_role(v.causality, v.variability, v.initial, v.name in state_outputs)
        if role is not None:
            found[v.name] = Declared(v.name, role, FMI3_TYPES.get(v.type, v.type), getattr(v, "unit", None),
                                     number(getattr(v, "min", None)), number(getattr(v, "max", None)),
                                     number(getattr(v, "start", None)), INTEGER_RANGES.get(v.type))
    solver = found.get(FIXED_STEP_PARAMETER)
    if solver is not None and solver.min is None:  # a step size is never negative
        solver.min = 0.0
    return found


def _convert(name: str, raw, d: Declared):
    """``raw`` (a string from the command line or a TOML value) as a value of type ``d.type``."""
    if d.type == "String":
        if isinstance(raw, (bool, numbers.Number)) or not isinstance(raw, str):
            raise ParameterError(f"parameter '{name}' is a String; got {raw!r}")
        return raw
    if d.type == "Boolean":
        if isinstance(raw, bool):
            return raw
        if isinstance(raw, str) and raw.strip().lower() in _BOOLEAN_WORDS:
            return _BOOLEAN_WORDS[raw.strip().lower()]
        raise ParameterError(f"parameter '{name}' is a Boolean: give true or false, got {raw!r}")
    if isinstance(raw, bool) or not isinstance(raw, (str, numbers.Real)):
        raise ParameterError(f"parameter '{name}': expected a number, got {raw!r}")
    try:
        value = float(raw)
    except (TypeError, ValueError):
        raise ParameterError(f"parameter '{name}': '{raw}' is not a number") from None
    except OverflowError:
        raise ParameterError(f"parameter '{name}': value must be finite, got {raw}") from None
    if not math.isfinite(value):
        raise ParameterError(f"parameter '{name}': value must be finite, got {raw}")
    if d.type in ("Integer", "Enumeration"):
        if value != int(value):
            raise ParameterError(f"parameter '{name}' is an {d.type}; {raw} is not a whole number")
        low, high = d.range or (-(2**31) + 1, 2**31 - 1)
        if not low <= value <= high:
            what = "32 bit" if d.range is None else f"{low} .. {high}"
            raise ParameterError(f"parameter '{name}' is an {d.type}; {raw} is out of range ({what})")
        return int(value)
    return value


SIMULATE_INPUT_HINT = "give it with --input {name}=FILE.csv or --input {name}=step:T0:VALUE"


def settable(name: str, declared: dict[str, Declared], input_hint: str | None = SIMULATE_INPUT_HINT) -> Declared:
    """The declaration of ``name`` if a value may be given for it before a run: a parameter or a
    start value (see :func:`check`, which checks the value too).

    Raises
    ------
    ParameterError
        Naming the parameter: unknown, an input (``input_hint`` says how inputs are given), or a
        calculated parameter.
    """
    d = declared.get(name)
    if d is None:
        known = ", ".join(n for n, v in declared.items() if v.causality == "parameter" and "." not in n)
        raise ParameterError(f"unknown parameter '{name}'; top-level parameters are: {known}")
    if d.causality == "input":
        how = f"; {input_hint.format(name=name)}" if input_hint else ""
        raise ParameterError(f"'{name}' is an input, not a parameter{how}")
    if d.causality == CALCULATED:
        raise ParameterError(f"parameter '{name}' is a calculated parameter (final, or bound to an expression "
                             "of other parameters) and cannot be set")
    return d


def check(values: dict, declared: dict[str, Declared], input_hint: str | None = SIMULATE_INPUT_HINT) -> dict:
    """Validate values by name against declarations; returns them converted to the declared types.

    Parameters
    ----------
    values : dict
        Name -> value (a string from ``--param`` or a TOML value).
    declared : dict
        From :func:`declarations`.
    input_hint : str or None
        How inputs are given where ``values`` come from, added to the refusal of an input
        (``{name}`` is replaced by the input's name).

    Raises
    ------
    ParameterError
        Naming the parameter: unknown, an input (inputs are not constants), a calculated
        parameter, not a number or not a whole number for an Integer, non-finite, or outside
        ``min``/``max``.
    """
    checked = {}
    for name, raw in values.items():
        d = settable(name, declared, input_hint)
        value = _convert(name, raw, d)
        unit = f" {d.unit}" if d.unit else ""
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            if d.min is not None and value < d.min:
                raise ParameterError(f"parameter '{name}' = {value:g}{unit} is below its minimum {d.min:g}{unit}")
            if d.max is not None and value > d.max:
                raise ParameterError(f"parameter '{name}' = {value:g}{unit} is above its maximum {d.max:g}{unit}")
        checked[name] = value
    return checked


def starts(declared: dict[str, Declared]) -> dict[str, float]:
    """The numeric default (start) values of the declared parameters."""
    return {n: d.start for n, d in declared.items() if d.causality == "parameter" and d.start is not None}
