"""Parameters of the bicycle models over their FMUs: Meijaard parameter sets (``--params``), the
rider's upper body split off a set's rear frame, and the forward speed (``--speed``).

The generic part -- the declarations of a model or FMU and the check of values against them --
is :mod:`cosim.fmu.parameters`; the sets themselves are loaded by
:func:`cosim.analytic.parameters.load_set_for_models`.
"""
from __future__ import annotations

import math
import sys
from collections.abc import Callable
from dataclasses import dataclass

from cosim.analytic.parameters import (load_set_for_models, load_upper_body, split_upper_body, upper_body_for,
                                       validate_parameters)
from cosim.errors import ParameterError
from cosim.fmu.parameters import (SIMULATE_INPUT_HINT, Declared, check, declarations, split_assignment,
                                  starts)


def from_command_line(target: str, assignments: list[str], extra: dict | None = None,
                      parameter_set: str | None = None, input_hint: str | None = SIMULATE_INPUT_HINT,
                      speed: float | None = None, declared: dict[str, Declared] | None = None,
                      report: Callable[[str], None] | None = None) -> dict:
    """``--params`` set, then ``--param`` strings, then ``extra`` values, then the forward speed
    ``speed`` [m/s] (``--speed``, see :func:`forward_speed`), checked for ``target``.

    ``parameter_set`` is a Meijaard parameter set (bundled name or TOML file) for models whose
    parameters carry the Meijaard names, such as ``Bicycle.Bicycles.WhippleLinear``. A set whose
    file waives checks (``allow_nonphysical``, see
    :func:`cosim.analytic.parameters.load_set_for_models`) is reported by one line to ``report``
    (default: stderr), since the nonlinear models use such values as they are.
    ``declared`` (from :func:`cosim.fmu.parameters.declarations`) saves reading the model again."""
    values = {}
    if parameter_set:
        try:
            loaded = load_set_for_models(parameter_set)
        except FileNotFoundError:
            raise ParameterError(f"--params {parameter_set}: no such bundled set or file") from None
        values.update(loaded.values)
        waiver = loaded.waiver
        declared = declarations(target) if declared is None else declared
        if "mU" in declared:
            values = _split_rider(values, parameter_set, waiver.checks if waiver else ())
        if waiver is not None:
            (report or _note_on_stderr)(f"--params {parameter_set}: {waiver.describe()}")
    values.update(dict(split_assignment(a) for a in assignments))  # a repeated name: the last wins
    values.update(extra or {})
    if not values and speed is None:
        return {}
    declared = declarations(target) if declared is None else declared
    if speed is not None:
        fs = forward_speed(target, declared)
        values.update(fs.values(speed, {**starts(declared), **values}))
    return check(values, declared, input_hint)


def _note_on_stderr(message: str) -> None:
    print(f"cosim: note: {message}", file=sys.stderr)


def _split_rider(values: dict[str, float], parameter_set: str, waived=()) -> dict[str, float]:
    """A Meijaard set's rear frame B holds the whole (rigid) rider. For a model with the rider's upper
    body on a hip hinge (parameters mU, xU, ...), the set's bundled upper body
    (:func:`cosim.analytic.parameters.upper_body_for`) is split off B, so that with the hinge locked
    the bicycle is the set's bicycle (not one carrying a second upper body). The checks the set's
    file waives (``waived``) stay waived for the split rear frame."""
    try:
        split = split_upper_body(values, load_upper_body(upper_body_for(parameter_set)))
        validate_parameters({k: split[k] for k in values}, waive=waived)
    except ValueError as exc:
        raise ParameterError(f"--params {parameter_set}: the rear frame of the set cannot carry the rider's "
                             f"upper body of this model: {exc}") from None
    return split


SPEED_NAMES = ("V", "v")


#: Rolling bicycles: the initial rear wheel rate [rad/s] and the rear wheel radius [m].
WHEEL_RATE, WHEEL_RADIUS = "u_R0", "rR"


@dataclass(frozen=True)
class ForwardSpeed:
    """How the forward speed ``V`` [m/s] of a model is set.

    * ``V`` (simple models) or ``v`` (``WhippleLinear``): the speed parameter itself (any finite
      value its declaration allows);
    * ``u_R0`` with ``rR`` (the nonlinear bicycles ``Whipple``, ``WhippleRider``): upright straight
      running at forward speed ``V >= 0``, i.e. the initial rear wheel rate ``u_R0 = -V/rR``
      (pitch 0 when upright with zero steer, so the rear contact moves at ``-u_R rR``).
    """

    parameter: str
    wheel_radius: str | None = None

    @property
    def label(self) -> str:
        """The speed's symbol in tables (``V``, ``v``)."""
        return "v" if self.wheel_radius else self.parameter

    def check(self, V) -> float:
        """``V`` as a float [m/s]; ParameterError if it is not a finite number or, for a rolling
        bicycle, negative (the declared ``min``/``max`` of ``V``/``v`` are checked with the other
        parameters, see :func:`cosim.fmu.parameters.check`)."""
        try:
            V = float(V)
        except (TypeError, ValueError):
            raise ParameterError(f"the speed must be a number [m/s], got {V!r}") from None
        if not math.isfinite(V):
            raise ParameterError(f"the speed must be finite, got {V}")
        if self.wheel_radius is not None and V < 0:
            raise ParameterError(f"the forward speed must be >= 0 m/s (upright straight running forwards), got {V:g}")
        return V

    def values(self, V: float, known: dict) -> dict[str, float]:
        """Parameter values for speed ``V`` [m/s] (refused as by :meth:`check`); ``known`` holds
        the other parameter values (``rR`` [m] for a rolling bicycle)."""
        V = self.check(V)
        if self.wheel_radius is None:
            return {self.parameter: V}
        radius = known.get(self.wheel_radius)
        try:  # a --param value is still text here
            r = float(radius)
        except (TypeError, ValueError):
            r = math.nan
        if not (math.isfinite(r) and r > 0):
            raise ParameterError(f"the speed needs a positive rear wheel radius {self.wheel_radius} [m], "
                                 f"got {radius!r}")
        return {self.parameter: -V / r}

    def speed(self, values: dict) -> float:
        """The forward speed [m/s] that parameter ``values`` set (inverse of :meth:`values`)."""
        if self.wheel_radius is None:
            return float(values[self.parameter])
        return -float(values[self.parameter]) * float(values[self.wheel_radius])


def forward_speed(target: str, declared: dict[str, Declared] | None = None) -> ForwardSpeed:
    """How the forward speed of a model or FMU is set (:class:`ForwardSpeed`).

    Parameters
    ----------
    target : str
        Model name or FMU file.
    declared : dict, optional
        Its :func:`cosim.fmu.parameters.declarations` (read if not given).

    Raises
    ------
    ParameterError
        The model has no forward speed (no ``V``, ``v`` or ``u_R0`` with ``rR``).
    """
    declared = declarations(target) if declared is None else declared

    def parameter(name):
        return name in declared and declared[name].causality == "parameter"

    for name in SPEED_NAMES:
        if parameter(name):
            return ForwardSpeed(name)
    if parameter(WHEEL_RATE) and parameter(WHEEL_RADIUS):
        return ForwardSpeed(WHEEL_RATE, WHEEL_RADIUS)
    raise ParameterError(f"{target} has no forward speed (no parameter {', '.join(SPEED_NAMES)}, "
                         f"or {WHEEL_RATE} with {WHEEL_RADIUS}); --speed does not apply")


def speed_parameter(target: str) -> str:
    """The parameter that sets the forward speed of a model or FMU (``V`` in the simple models,
    ``v`` in ``WhippleLinear``, ``u_R0`` in the nonlinear bicycles, see :func:`forward_speed`);
    :class:`ParameterError` if it has none."""
    return forward_speed(target).parameter
