"""Create the components of a system file: FMUs (built from models when needed) and Python blocks."""
from __future__ import annotations

import os
from pathlib import Path

from cosim.errors import FMUError, ParameterError
from cosim.cosimulation import registry
from cosim.cosimulation.component import Component, FMUComponent
from cosim.cosimulation.system import SystemError_, SystemSpec, load_system
from cosim.fmu.isolation import DEFAULT_TIMEOUT, built_here, can_isolate
from cosim.outputs import check_input_file
from cosim.compiler.library import load_library
from cosim.cosimulation.isolated import run_isolated_system
from cosim.cosimulation.master import run_components
from cosim.fmu.access import ALL_FMI_VERSIONS, read_fmu
from cosim.fmu.parameters import check, declarations
from cosim.fmu.simulate import variable_units
from cosim.fmu.target import built_fmu


def python_block(name: str, block: str, parameters: dict, where: str = "system") -> Component:
    """Instantiate a registered Python block (:mod:`cosim.cosimulation.registry`); unknown blocks
    and parameters, and values of the wrong type (checked against the block's signature), are
    named in the error."""
    try:
        cls = registry.lookup(block)
    except ParameterError as exc:
        raise SystemError_(f"{where}: component '{name}': {exc}") from None
    try:
        return cls.create(name, parameters)
    except ParameterError as exc:
        raise SystemError_(f"{where}: component '{name}' ({block}): {exc}") from None


def check_parameters(spec: SystemSpec) -> dict[str, dict]:
    """The parameter values of every FMU and model component of ``spec``, checked against what
    its FMU declares (:func:`cosim.fmu.parameters.declarations`: for a model, the FMU it is
    built as, read without building it) and converted to the declared types: component name ->
    values. Nothing is built.

    Raises
    ------
    SystemError_
        Naming the system file, the component and the parameter (unknown, calculated, an input,
        of the wrong type or out of range), or an FMU file that does not exist.
    FMUError
        An FMU file that cannot be read, with the component named.
    UnknownModelError, ModelicaError, ModelStructureError
        A model that is not in the library or cannot be built.
    """
    where = str(spec.path or spec.name)
    checked = {}
    for name, entry in spec.components.items():
        if entry.kind == "python":
            continue
        if entry.kind == "fmu":  # a regular file (not a FIFO, a device, a loop of links) before it is read
            if not os.path.lexists(entry.source):  # (also a name with a NUL character)
                raise SystemError_(f"{where}: component '{name}': FMU '{entry.source}' not found")
            check_input_file(entry.source, SystemError_, f"{where}: component '{name}': FMU '{entry.source}'",
                             "FMU file", "an")
        try:
            declared = declarations(entry.source, entry.fmi_version) if entry.kind == "model" \
                else declarations(str(entry.source))
            checked[name] = check(entry.parameters, declared, input_hint="connect it, e.g. to a Step or Pulse block")
        except ParameterError as exc:
            raise SystemError_(f"{where}: component '{name}': {exc}") from None
        except FMUError as exc:
            raise FMUError(f"{where}: component '{name}': {exc}") from None
    return checked


def create_components(spec: SystemSpec, fmu_dir: str | Path | None = None) -> dict[str, Component]:
    """Component objects for every entry of the system (models are built into ``fmu_dir``, as
    FMI 2.0 or 3.0 FMUs by their ``fmi_version``; FMU files may be either). Every component's
    parameters are checked (:func:`check_parameters`) before any model is built."""
    # deferred: loads casadi, which importing this module does not
    from cosim.compiler.build import DEFAULT_OUTPUT, build_model

    where = str(spec.path or spec.name)
    values = check_parameters(spec)
    created: dict[str, Component] = {}
    try:
        # the Python blocks first: their names and parameters are checked before any build too
        blocks = {name: python_block(name, entry.source, entry.parameters, where)
                  for name, entry in spec.components.items() if entry.kind == "python"}
        created.update(blocks)
        for name, entry in spec.components.items():
            if entry.kind == "model":
                # FMI 2 builds go to OUTPUT/NAME.fmu, FMI 3 ones to OUTPUT/fmi3/NAME.fmu
                fmu = build_model(entry.source, fmu_dir or DEFAULT_OUTPUT, load_library(),
                                  fmi_version=entry.fmi_version).fmu
            elif entry.kind == "fmu":
                fmu = Path(entry.source)  # (a regular file: check_parameters made sure)
            else:
                continue
            try:
                created[name] = FMUComponent(name, fmu, values[name])
            except ParameterError as exc:
                raise SystemError_(f"{where}: component '{name}': {exc}") from None
            except FMUError as exc:
                raise FMUError(f"{where}: component '{name}': {exc}") from None
    except BaseException:
        for comp in created.values():
            comp.close()
        raise
    return {name: created[name] for name in spec.components}  # in the order of the system file


def recorded_units(spec: SystemSpec, fmu_dir: str | Path | None = None) -> dict:
    """``component.variable`` -> unit of the system's FMU components, from their model
    descriptions; a model's FMU is read where a run built it (never built here). A Python block
    declares no units: its output has the unit of the FMU input it is connected to, if any.

    Parameters
    ----------
    spec : SystemSpec
        The system.
    fmu_dir : str or Path, optional
        Where its models were built (default as :func:`run_system`).
    """
    units: dict = {}
    for name, entry in spec.components.items():
        fmu = Path(entry.source) if entry.kind == "fmu" else \
            built_fmu(entry.source, fmu_dir, fmi_version=entry.fmi_version) if entry.kind == "model" else None
        if fmu is not None:
            units.update(variable_units(read_fmu(fmu, ALL_FMI_VERSIONS), prefix=f"{name}."))
    for c in spec.connections:  # a Python block's output has the unit of the FMU input it drives
        target = units.get(f"{c.target}.{c.input}")
        if target is not None:
            units.setdefault(f"{c.source}.{c.output}", target)
    return units


def run_system(path_or_spec, fmu_dir: str | Path | None = None, isolate: bool | None = None,
               timeout: float | None = DEFAULT_TIMEOUT):
    """Co-simulate a system: load the file, create its components (models built as needed) and run.

    Parameters
    ----------
    path_or_spec : str, Path or SystemSpec
        A system file (TOML) or a system already loaded (:func:`load_system`).
    fmu_dir : str or Path, optional
        Where models are built to FMUs (default: ``COSIM_FMU_DIR`` or ``./fmus``).
    isolate : bool, optional
        Run in a guarded child process (:mod:`cosim.cosimulation.isolated`), so that a binary that
        crashes, calls ``exit`` or hangs ends the run with the rows so far instead of ending this
        process. Default: when a component is an FMU not built by this project.
    timeout : float or None
        With ``isolate``: longest time [s] without a completed communication step; None: no limit.

    Returns
    -------
    RunResult
        ``data``: the recorded signals, ``time`` [s] first, then each ``component.output`` in
        SI units [rad, m, N m, ...]; ``outcome``: completed, fell or diverged, with the time
        the run ended [s]; ``steps``: communication steps taken.

    Raises
    ------
    SystemError_
        For a bad system file, component, parameter or connection (nothing is run).
    RunFailed
        If an FMU failed a step, or (isolated) an FMU's binary ended the process or stopped
        answering; ``exc.result`` holds the rows up to the failure.
    FMUProcessError
        (isolated) An FMU's binary ended the process or stopped answering before the first row.
    """
    spec = path_or_spec if isinstance(path_or_spec, SystemSpec) else load_system(path_or_spec)
    components = create_components(spec, fmu_dir)
    foreign = [name for name, c in components.items() if isinstance(c, FMUComponent) and not built_here(c.fmu.path)]
    if isolate is None:
        isolate = bool(foreign) and can_isolate()
    if isolate:
        return run_isolated_system(spec, components, foreign, timeout)
    return run_components(spec, components)
