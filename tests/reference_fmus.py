"""The Reference FMUs (Modelica Association, BSD-2-Clause) as FMI 3.0 and FMI 2.0 FMUs built from their
vendored sources.

Foreign FMUs for the import and validation tests, made offline: the sources are in
``tests/data/reference-fmus/`` (FMI 3 and the model code) and ``tests/data/reference-fmus-fmi2/`` (the FMI 2
API and model descriptions; see their READMEs and LICENSE.txt), the FMI headers come from the installed
FMPy (``fmpy/c-code``), gcc compiles them. Nothing is downloaded.

Usage (build once per test session; the compilation takes about a second per model)::

    from reference_fmus import REFERENCE_MODELS, reference_fmu

    @pytest.fixture(scope="session")
    def vanderpol(tmp_path_factory):
        return reference_fmu("VanDerPol", tmp_path_factory.mktemp("reference-fmus"))
"""
from __future__ import annotations

import shutil
import subprocess
import zipfile
from pathlib import Path

import fmpy

SOURCES = Path(__file__).resolve().parent / "data" / "reference-fmus"
"""The vendored sources: ``common/`` (shared by every model) and one folder per model."""
FMI2_SOURCES = Path(__file__).resolve().parent / "data" / "reference-fmus-fmi2"
"""The FMI 2.0 API (``fmi2Functions.c``) and one folder per model with its FMI 2.0 ``modelDescription.xml``."""

ARRAY_MODELS = ("StateSpace",)
"""Vendored Reference FMUs with array variables (FMI 3 ``<Dimension>``, structural parameters), built by
:func:`reference_fmu` like the others but kept out of :data:`REFERENCE_MODELS`, whose tests compare one
CSV column per variable."""

REFERENCE_MODELS = tuple(sorted(p.name for p in SOURCES.iterdir()
                                if (p / "modelDescription.xml").is_file() and p.name not in ARRAY_MODELS))
"""Names (= model identifiers) of the vendored Reference FMUs with scalar variables: BouncingBall,
Dahlquist, Feedthrough, Stair, VanDerPol."""

REFERENCE_MODELS_FMI2 = tuple(sorted(p.name for p in FMI2_SOURCES.iterdir()
                                     if (p / "modelDescription.xml").is_file()))
"""The Reference FMUs that have an FMI 2.0 model description (all of :data:`REFERENCE_MODELS`)."""

COMMON_SOURCES = ("fmi3Functions.c", "cosimulation.c")
COMMON_HEADERS = ("cosimulation.h", "model.h")
MODEL_FILES = ("model.c", "config.h")
FMI3_HEADERS = Path(fmpy.__file__).resolve().parent / "c-code"
PLATFORM = "x86_64-linux"


class ReferenceBuildError(RuntimeError):
    """gcc failed on a vendored Reference FMU (the message carries gcc's output)."""


def reference_fmu(name: str, folder: Path | str, edits: dict[str, list[tuple[str, str]]] | None = None,
                  fmu_name: str | None = None) -> Path:
    """Compile the Reference FMU ``name`` as an FMI 3.0 FMU (ME and CS in one binary) into ``folder``.

    Parameters
    ----------
    name : str
        One of :data:`REFERENCE_MODELS` or :data:`ARRAY_MODELS` (the model identifier, e.g. ``"VanDerPol"``).
    folder : Path or str
        Where the FMU and its build tree go (``folder/NAME/`` unzipped, ``folder/NAME.fmu``). Callers
        pass a session-scoped temporary folder and keep the returned path: there is no cache here.
    edits : dict, optional
        For variants (broken FMUs, renamed variables): file name (``modelDescription.xml``,
        ``fmi3Functions.c``, ``model.c``, ...) -> ``(old, new)`` text replacements applied to the
        copy before compiling; each ``old`` must occur (else ValueError: a test cannot silently
        test the unmodified FMU).
    fmu_name : str, optional
        The file and folder name of the result (default ``name``), so that variants of one model
        can live in one folder; the model identifier (binary name) stays ``name``.

    Returns
    -------
    Path
        ``folder/NAME.fmu`` with ``modelDescription.xml``, ``binaries/x86_64-linux/NAME.so`` and
        ``sources/`` (the C files and ``buildDescription.xml``, so that the FMU rebuilds elsewhere).

    Raises
    ------
    KeyError
        ``name`` is not a vendored Reference FMU.
    ReferenceBuildError
        gcc failed.
    """
    if name not in REFERENCE_MODELS + ARRAY_MODELS:
        raise KeyError(f"no Reference FMU {name!r} in {SOURCES} "
                       f"(there are {', '.join(REFERENCE_MODELS + ARRAY_MODELS)})")
    folder = Path(folder)
    tree = folder / (fmu_name or name)
    if tree.exists():
        shutil.rmtree(tree)
    sources = tree / "sources"
    binaries = tree / "binaries" / PLATFORM
    sources.mkdir(parents=True)
    binaries.mkdir(parents=True)
    for file in COMMON_SOURCES + COMMON_HEADERS:
        shutil.copy2(SOURCES / "common" / file, sources / file)
    for file in MODEL_FILES + ("buildDescription.xml",):
        shutil.copy2(SOURCES / name / file, sources / file)
    shutil.copy2(SOURCES / name / "modelDescription.xml", tree / "modelDescription.xml")
    _apply(edits, tree, sources, name)
    # The flags of the Reference FMUs' own CMake build for a binary FMU: FMI_VERSION selects the API in
    # model.h/cosimulation.c, DISABLE_PREFIX exports the plain fmi3* names (no MODEL_IDENTIFIER_ prefix).
    # gcc's default dialect (gnu17), not -std=c99: cosimulation.c calls the POSIX strdup, which strict
    # C99 does not declare; implicitly declared, it returns an int and the truncated pointer crashes
    # fmi3FreeInstance. -Werror=implicit-function-declaration keeps such a fault from passing silently.
    command = [
        "gcc", "-shared", "-fPIC", "-O2", "-Werror=implicit-function-declaration",
        "-DFMI_VERSION=3", "-DDISABLE_PREFIX",
        f"-I{sources}", f"-I{FMI3_HEADERS}",
        *(str(sources / f) for f in COMMON_SOURCES + ("model.c",)),
        "-lm", "-o", str(binaries / f"{name}.so"),
    ]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        raise ReferenceBuildError(f"gcc failed on the Reference FMU {name}:\n{result.stderr}")
    return pack(tree, folder / f"{fmu_name or name}.fmu")


def reference_fmu2(name: str, folder: Path | str, edits: dict[str, list[tuple[str, str]]] | None = None,
                   fmu_name: str | None = None) -> Path:
    """Compile the Reference FMU ``name`` as an FMI 2.0 FMU (ME and CS in one binary) into ``folder``.

    The same model code as :func:`reference_fmu` with the FMI 2 API and model description of
    ``tests/data/reference-fmus-fmi2/`` (``-DFMI_VERSION=2`` selects the FMI 2 parts); parameters and
    result as there, the binary in ``binaries/linux64/``, the sources as the one file ``all.c`` that the
    model description lists (as in the Reference FMUs' own FMI 2 FMUs).

    Raises
    ------
    KeyError
        ``name`` has no FMI 2 model description here (:data:`REFERENCE_MODELS_FMI2`).
    ValueError
        An ``old`` text of ``edits`` does not occur.
    ReferenceBuildError
        gcc failed.
    """
    if name not in REFERENCE_MODELS_FMI2:
        raise KeyError(f"no FMI 2 Reference FMU {name!r} in {FMI2_SOURCES} "
                       f"(there are {', '.join(REFERENCE_MODELS_FMI2)})")
    folder = Path(folder)
    tree = folder / (fmu_name or name)
    if tree.exists():
        shutil.rmtree(tree)
    sources, binaries = tree / "sources", tree / "binaries" / "linux64"
    sources.mkdir(parents=True)
    binaries.mkdir(parents=True)
    shutil.copy2(FMI2_SOURCES / "fmi2Functions.c", sources)
    for file in ("cosimulation.c",) + COMMON_HEADERS:
        shutil.copy2(SOURCES / "common" / file, sources)
    for file in MODEL_FILES:
        shutil.copy2(SOURCES / name / file, sources)
    (sources / "all.c").write_text('#include "fmi2Functions.c"\n#include "model.c"\n#include "cosimulation.c"\n')
    shutil.copy2(FMI2_SOURCES / name / "modelDescription.xml", tree)
    _apply(edits, tree, sources, name)
    command = ["gcc", "-shared", "-fPIC", "-O2", "-Werror=implicit-function-declaration", "-DFMI_VERSION=2",
               "-DDISABLE_PREFIX", f"-I{sources}", f"-I{FMI3_HEADERS}", str(sources / "all.c"), "-lm",
               "-o", str(binaries / f"{name}.so")]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        raise ReferenceBuildError(f"gcc failed on the FMI 2 Reference FMU {name}:\n{result.stderr}")
    return pack(tree, folder / f"{fmu_name or name}.fmu")


def _apply(edits: dict[str, list[tuple[str, str]]] | None, tree: Path, sources: Path, name: str) -> None:
    """Apply ``edits`` (file name -> (old, new) replacements) to the copies in ``tree``."""
    for file, replacements in (edits or {}).items():
        target = tree / file if file == "modelDescription.xml" else sources / file
        text = target.read_text(encoding="utf-8")
        for old, new in replacements:
            if old not in text:
                raise ValueError(f"edit of {file} of the Reference FMU {name}: {old!r} does not occur")
            text = text.replace(old, new)
        target.write_text(text, encoding="utf-8")


def pack(tree: Path, fmu: Path) -> Path:
    """Zip the FMU folder ``tree`` into ``fmu`` (member names relative to ``tree``)."""
    with zipfile.ZipFile(fmu, "w", zipfile.ZIP_DEFLATED) as archive:
        for path in sorted(tree.rglob("*")):
            if path.is_file():
                archive.write(path, path.relative_to(tree).as_posix())
    return fmu
