"""Commands take a model name or an FMU file: this turns either into an FMU path."""
from __future__ import annotations

import contextlib
import os
import sys
from pathlib import Path
from cosim.compiler.library import fmu_up_to_date, load_library


def is_fmu_path(target: str) -> bool:
    """A target is an FMU file if it ends in ``.fmu`` or names an existing file (else a model).
    A text that cannot name a file (longer than the system allows, a NUL character) is a model
    name: the library then says whether there is such a model."""
    if target.endswith(".fmu"):
        return True
    try:
        return Path(target).is_file()
    except (OSError, ValueError):
        return False


def resolve_fmu(target: str, output: str | Path | None = None, versions: tuple[str, ...] | None = None) -> Path:
    """The FMU of ``target``: the file itself, or the model built (if needed) into ``output``.

    Model names are resolved in the folders named by ``COSIM_MODELICA_PATH`` (which the command
    line's ``--library DIR`` sets) and in the library shipped with the package, searched last.

    Parameters
    ----------
    target : str
        An FMU file (a path ending in ``.fmu`` or naming an existing file) or a full Modelica
        model name such as ``"Bicycle.Bicycles.SelfStabilizing"``.
    output : path, optional
        Folder a model is built into (default: ``$COSIM_FMU_DIR``, else ``./fmus`` of the
        working directory); the build is incremental (nothing is done if the FMU is up to date).
    versions : tuple of str, optional
        The FMI versions the caller runs (default: :data:`cosim.fmu.access.SUPPORTED_FMI_VERSIONS`);
        an FMU file of another version is refused in one line. A verb that handles FMI 3 passes
        :data:`cosim.fmu.access.ALL_FMI_VERSIONS`.

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
        # deferred: loads numpy, which importing this module does not
        from cosim.fmu.access import SUPPORTED_FMI_VERSIONS, read_fmu

        path = Path(target)
        # FMUError naming the file and the problem if it is not a usable FMU
        read_fmu(path, SUPPORTED_FMI_VERSIONS if versions is None else versions)
        return path
    folder = Path(output) if output is not None else default_output()
    fmu = built_fmu(target, folder)
    if fmu is not None:
        return fmu
    # deferred: loads casadi, numpy, which importing this module does not
    from cosim.compiler.build import build_model

    return build_model(target, folder, load_library()).fmu


def built_fmu(model: str, output: str | Path | None = None, fmi_version: str = "2") -> Path | None:
    """The FMU of the model ``model`` in ``output`` (default: :func:`default_output`) if it is
    there and up to date (:func:`cosim.compiler.library.fmu_up_to_date`), else None.

    The check needs neither cosim.compiler.build nor a parse of the library: importing it
    (pymoca, CasADi) and parsing would cost seconds before a simulation of an FMU that is
    already built."""
    folder = (Path(output) if output is not None else default_output()).absolute()
    if str(fmi_version) == "3":
        folder = folder / "fmi3"  # as cosim.compiler.build.fmu_path
    fmu = folder / f"{model.replace('.', '_')}.fmu"
    with contextlib.suppress(OSError, ValueError):  # a name too long for a file: the build says so
        if fmu.is_file() and fmu_up_to_date(model, fmu, fmi_version=str(fmi_version)):
            return fmu
    return None


def default_output() -> Path:
    """The folder model names are built into: :data:`cosim.compiler.build.DEFAULT_OUTPUT` if
    that module is loaded (it is fixed when it is imported), else the same rule applied now
    (``$COSIM_FMU_DIR``, else ``./fmus`` of the working directory)."""
    build = sys.modules.get("cosim.compiler.build")
    if build is not None:
        return build.DEFAULT_OUTPUT
    return Path(os.environ.get("COSIM_FMU_DIR") or Path.cwd() / "fmus").absolute()
