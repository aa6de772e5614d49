"""Create the components of a system file: FMUs (built from models when needed) and Python blocks."""
from __future__ import annotations

import os
from pathlib import Path

from cosim.errors import FMUError, ParameterError
from cosim.cosimulation import registry
from cosim.cosimulation.component import Component, FMUComponent
from cosim.cosimulation.system import SystemError_, SystemSpec, load_system
from cosim.outputs import check_input_file


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


def create_components(spec: SystemSpec, fmu_dir: str | Path | None = None) -> dict[str, Component]:
    """Component objects for every entry of the system (models are built into ``fmu_dir``, as
    FMI 2.0 or 3.0 FMUs by their ``fmi_version``; FMU files may be either)."""
    from cosim.compiler.build import DEFAULT_OUTPUT, build_model
    from cosim.compiler.library import load_library
    from cosim.fmu.parameters import check, declarations

    where = str(spec.path or spec.name)
    created: dict[str, Component] = {}
    try:
        for name, entry in spec.components.items():
            if entry.kind == "python":
                created[name] = python_block(name, entry.source, entry.parameters, where)
                continue
            if entry.kind == "model":
                # FMI 2 builds go to OUTPUT/NAME.fmu, FMI 3 ones to OUTPUT/fmi3/NAME.fmu
                fmu = build_model(entry.source, fmu_dir or DEFAULT_OUTPUT, load_library(),
                                  fmi_version=entry.fmi_version).fmu
            else:
                fmu = Path(entry.source)
                if not os.path.exists(fmu):
                    raise SystemError_(f"{where}: component '{name}': FMU '{fmu}' not found")
                check_input_file(fmu, SystemError_, f"{where}: component '{name}': FMU '{fmu}'", "FMU file", "an")
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
    """Co-simulate a system: load the file, create its components (models built as needed) and run.

    Parameters
    ----------
    path_or_spec : str, Path or SystemSpec
        A system file (TOML) or a system already loaded (:func:`load_system`).
    fmu_dir : str or Path, optional
        Where models are built to FMUs (default: ``COSIM_FMU_DIR`` or ``./fmus``).

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
        If an FMU failed a step; ``exc.result`` holds the rows up to the failure.
    """
    from cosim.cosimulation.master import run_components

    spec = path_or_spec if isinstance(path_or_spec, SystemSpec) else load_system(path_or_spec)
    return run_components(spec, create_components(spec, fmu_dir))
