"""Commands take a model name or an FMU file: this turns either into an FMU path."""
from __future__ import annotations

from pathlib import Path

from cosim.compiler.build import DEFAULT_OUTPUT, build_model
from cosim.compiler.library import load_library


def is_fmu_path(target: str) -> bool:
    """A target is an FMU file if it ends in ``.fmu`` or names an existing file (else a model)."""
    return target.endswith(".fmu") or Path(target).is_file()


def resolve_fmu(target: str, output: str | Path | None = None) -> Path:
    """The FMU of ``target``: the file itself, or the model built (if needed) into ``output``.

    Model names are resolved in the Modelica library named by ``COSIM_MODELICA_PATH`` (which the
    command line's ``--library DIR`` sets), else in the library shipped with the package.

    Parameters
    ----------
    target : str
        An FMU file (a path ending in ``.fmu`` or naming an existing file) or a full Modelica
        model name such as ``"Bicycle.Bicycles.SelfStabilizing"``.
    output : path, optional
        Folder a model is built into (default: ``$COSIM_FMU_DIR``, else ``./fmus`` of the
        working directory); the build is incremental (nothing is done if the FMU is up to date).

    Returns
    -------
    Path
        The FMU file (FMI 2.0, Model Exchange and Co-Simulation for models built here; times in
        s, SI units as declared in the Modelica source).

    Raises
    ------
    FMUError
        ``target`` is a file that is not a usable FMU (the message names the file and problem).
    UnknownModelError, ModelicaError, ModelStructureError, BuildError, OutputError
        The model cannot be found or built (see :func:`cosim.compiler.build.build_model`).
    """
    if is_fmu_path(target):
        from cosim.fmu.access import read_fmu

        path = Path(target)
        read_fmu(path)  # FMUError naming the file and the problem if it is not a usable FMU
        return path
    return build_model(target, output or DEFAULT_OUTPUT, load_library()).fmu
