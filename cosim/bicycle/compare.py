"""`cosim compare`: an FMU's linearization against the analytic twin of its model
(:mod:`cosim.bicycle.twins`), compared by :func:`cosim.analytic.compare.compare_systems`."""
from __future__ import annotations

from cosim.analytic.compare import compare_systems
from cosim.analytic.twins import TWINS
from cosim.bicycle.linearize import MAX_SPEEDS, parse_speeds  # noqa: F401 (the grammar of --speeds, one place)
from cosim.bicycle.parameters import forward_speed, from_command_line
from cosim.bicycle.twins import STEADY_MOTION_TWINS, twin
from cosim.errors import CosimError, ParameterError
from cosim.fmu.access import read_fmu
from cosim.fmu.linearize import linearize
from cosim.fmu.parameters import check, declarations
from cosim.fmu.target import is_fmu_path, resolve_fmu


def _parameter_defaults(fmu) -> dict:
    """Start values of the FMU's top-level Real parameters."""
    md = read_fmu(fmu)
    return {v.name: float(v.start) for v in md.modelVariables
            if v.causality == "parameter" and "." not in v.name and v.type == "Real" and v.start is not None}


def _analytic(model: str, parameters: dict):
    """The analytic twin's system; its refusals (ValueError, KeyError) as ParameterError."""
    try:
        return twin(model).system(parameters)
    except CosimError:
        raise
    except (KeyError, ValueError) as exc:
        raise ParameterError(f"{model}: the analytic model refuses these parameters: "
                             f"{exc.args[0] if exc.args else exc}") from None


def compare_model(model: str, speeds=None, parameters: dict | None = None, parameter_set: str | None = None,
                  output=None) -> list:
    """Linearize the FMU of ``model`` and compare it with the model's analytic twin.

    For every input -> output pair the transfer functions of the FMU's linearization and of the
    analytic model are reduced to minimal realizations and their poles, zeros and gains are
    compared, and so are the eigenvalues of both A matrices (:func:`cosim.analytic.compare.compare_systems`).

    Parameters
    ----------
    model : str
        Full Modelica name of a model with an analytic twin, e.g.
        ``"Bicycle.Bicycles.SelfStabilizing"`` (:data:`cosim.analytic.twins.TWINS` lists them).
    speeds : sequence of float, optional
        Forward speeds [m/s] to compare at, set as the model's speed parameter (``V`` or ``v``);
        default: the model's own speed.
    parameters : dict, optional
        Parameter values by Modelica name (SI units), checked against the model's declarations.
    parameter_set : str, optional
        A Meijaard parameter set (bundled name or TOML file) for models with Meijaard names,
        such as ``Bicycle.Bicycles.WhippleLinear``.
    output : path, optional
        Folder the model is built into (default: ``$COSIM_FMU_DIR``, else ``./fmus``).

    Returns
    -------
    list of Comparison
        One per speed; ``Comparison.error`` is the largest relative error (dimensionless) of
        its eigenvalues, poles, zeros and gains.

    Raises
    ------
    ParameterError
        The model has no analytic twin or no speed parameter, a speed or parameter is refused
        (naming it), or the analytic model refuses the values.
    UnknownModelError, ModelicaError, BuildError
        The model cannot be built.

    Examples
    --------
    >>> worst = max(c.error for c in compare_model("Bicycle.Bicycles.SelfStabilizing", [2.0, 5.0]))
    >>> worst < 1e-9
    True
    """
    if is_fmu_path(model):
        raise ParameterError("compare needs a model name (the analytic twin is chosen by model)")
    if model not in TWINS and model not in STEADY_MOTION_TWINS:
        raise ParameterError(f"no analytic twin for '{model}'; twins exist for: "
                             f"{', '.join([*TWINS, *STEADY_MOTION_TWINS])}")
    declared = declarations(model)
    speed = forward_speed(model, declared)
    speeds = [None] if speeds is None else [float(v) for v in speeds]
    base = from_command_line(model, [], parameters, parameter_set=parameter_set,
                             input_hint="compare linearizes at the inputs' start values", declared=declared)
    for v in speeds:  # refused before anything is built
        if v is not None:
            speed.check(v)
            if speed.wheel_radius is None:
                check({speed.parameter: v}, declared)
    fmu = resolve_fmu(model, output)
    defaults = _parameter_defaults(fmu)
    comparisons = []
    for v in speeds:
        params = {**base, **(speed.values(v, {**defaults, **base}) if v is not None else {})}
        expected = _analytic(model, {**defaults, **params})  # refusals before the linearization
        try:
            found = twin(model).reduce(linearize(fmu, params))
        except ValueError as exc:  # not the operating point the twin describes
            if isinstance(exc, CosimError):
                raise
            raise ParameterError(str(exc)) from None
        result = compare_systems(model, {**defaults, **params}, found, expected)
        result.speed = speed.speed({**defaults, **params})
        comparisons.append(result)
    return comparisons
