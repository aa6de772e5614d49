"""The Reference FMUs 0.0.41 (Modelica Association, BSD-2-Clause) as FMI 3.0 and FMI 2.0 FMUs built from
their vendored sources.

Foreign FMUs for the import and validation tests, made offline: the sources are in
``tests/data/reference-fmus/`` (an unmodified copy of the upstream tag, see its README.md and
LICENSE.txt), their own FMI headers in ``include/``; gcc compiles them with the flags of upstream's CMake
build. Nothing is downloaded.

Usage (build once per test session; the compilation takes well under a second per model)::

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

SOURCES = Path(__file__).resolve().parent / "data" / "reference-fmus"
"""The vendored sources: ``include/`` and ``src/`` (shared by every model) and one folder per model."""

ARRAY_MODELS = ("StateSpace",)
"""Reference FMUs with array variables (FMI 3 ``<Dimension>``, structural parameters), built by
:func:`reference_fmu` like the others but kept out of :data:`REFERENCE_MODELS`, whose tests compare one
CSV column per variable."""

SCHEDULED_MODELS = ("Clocks",)
"""Reference FMUs of FMI 3 Scheduled Execution only (no Model Exchange, no Co-Simulation interface)."""

CORPUS_MODELS = ("Resource", "Roberts")
"""Scalar FMI 3 Reference FMUs that only the corpus test (tests/test_reference_corpus.py) runs:
``Resource`` reads ``resources/y.txt``, ``Roberts`` is a stiff ODE with the fmi-ls-dae layered standard."""

ALL_MODELS_FMI3 = tuple(sorted(p.name for p in SOURCES.iterdir() if (p / "FMI3.xml").is_file()))
"""Every FMI 3 Reference FMU of the vendored tag."""

REFERENCE_MODELS = tuple(m for m in ALL_MODELS_FMI3
                         if m not in ARRAY_MODELS + SCHEDULED_MODELS + CORPUS_MODELS)
"""Names (= model identifiers) of the FMI 3 Reference FMUs with scalar variables that the import tests
compare one by one: BouncingBall, Dahlquist, Feedthrough, Stair, VanDerPol."""

ALL_MODELS_FMI2 = tuple(sorted(p.name for p in SOURCES.iterdir() if (p / "FMI2.xml").is_file()))
"""Every FMI 2 Reference FMU of the vendored tag (also ``Resource``)."""

REFERENCE_MODELS_FMI2 = tuple(m for m in ALL_MODELS_FMI2 if m not in CORPUS_MODELS)
"""The FMI 2.0 Reference FMUs of :data:`REFERENCE_MODELS`."""

COMMON_HEADERS = ("cosimulation.h", "model.h")
MODEL_FILES = ("model.c", "config.h")
PLATFORMS = {2: "linux64", 3: "x86_64-linux"}
# Upstream's CMake flags for gcc (-Wall -Wextra -Wpedantic -Werror, hidden visibility; FMI_VERSION selects
# the API in model.h/cosimulation.c, DISABLE_PREFIX exports the plain fmiN* names). gcc 12 reports a
# strncpy bound equal to the buffer size in Resource/model.c (-Wstringop-truncation, which the compilers
# of upstream's CI do not enable by -Wall); the call is followed by an explicit terminator there.
# Unoptimized: gcc takes half the time, and the tests' models are small (x86-64's SSE2 arithmetic
# without FMA gives the same numbers at every optimization level).
CFLAGS = ("-shared", "-fPIC", "-O0", "-fvisibility=hidden", "-Wall", "-Wextra", "-Wpedantic", "-Werror",
          "-Wno-stringop-truncation", "-Werror=implicit-function-declaration", "-DDISABLE_PREFIX")


class ReferenceBuildError(RuntimeError):
    """gcc failed on a vendored Reference FMU (the message carries gcc's output)."""


def model_description(name: str, version: int = 3) -> Path:
    """The vendored model description ``NAME/FMI{version}.xml`` (``modelDescription.xml`` in the FMU)."""
    return SOURCES / name / f"FMI{version}.xml"


def reference_output(name: str) -> Path:
    """The reference result ``NAME/NAME_out.csv`` of the model's default experiment (fmi-ls-ref)."""
    return SOURCES / name / f"{name}_out.csv"


def reference_fmu(name: str, folder: Path | str, edits: dict[str, list[tuple[str, str]]] | None = None,
                  fmu_name: str | None = None) -> Path:
    """Compile the Reference FMU ``name`` as an FMI 3.0 FMU (all its interfaces in one binary) into ``folder``.

    Parameters
    ----------
    name : str
        One of :data:`ALL_MODELS_FMI3` (the model identifier, e.g. ``"VanDerPol"``).
    folder : Path or str
        Where the FMU and its build tree go (``folder/NAME/`` unzipped, ``folder/NAME.fmu``). Callers
        pass a session-scoped temporary folder and keep the returned path: there is no cache here.
    edits : dict, optional
        For variants (broken FMUs, renamed variables): file name (``modelDescription.xml``,
        ``fmi3Functions.c``, ``cosimulation.c``, ``model.c``, ...) -> ``(old, new)`` text replacements
        applied to the copy before compiling; each ``old`` must occur (else ValueError: a test cannot
        silently test the unmodified FMU).
    fmu_name : str, optional
        The file and folder name of the result (default ``name``), so that variants of one model
        can live in one folder; the model identifier (binary name) stays ``name``.

    Returns
    -------
    Path
        ``folder/NAME.fmu`` as upstream's CMake build assembles it: ``modelDescription.xml``,
        ``binaries/x86_64-linux/NAME.so``, ``sources/`` (the C files and ``buildDescription.xml``),
        ``resources/`` (Resource), ``extra/`` (the fmi-ls-ref manifest and ``NAME_out.csv``; the
        fmi-ls-dae manifest of Roberts).

    Raises
    ------
    KeyError
        ``name`` is not a vendored FMI 3 Reference FMU.
    ValueError
        An ``old`` text of ``edits`` does not occur.
    ReferenceBuildError
        gcc failed.
    """
    if name not in ALL_MODELS_FMI3:
        raise KeyError(f"no Reference FMU {name!r} in {SOURCES} (there are {', '.join(ALL_MODELS_FMI3)})")
    return _build(name, 3, Path(folder), edits, fmu_name)


def reference_fmu2(name: str, folder: Path | str, edits: dict[str, list[tuple[str, str]]] | None = None,
                   fmu_name: str | None = None) -> Path:
    """Compile the Reference FMU ``name`` as an FMI 2.0 FMU (ME and CS in one binary) into ``folder``.

    The same model code as :func:`reference_fmu` with the FMI 2 API (``-DFMI_VERSION=2``) and the model's
    ``FMI2.xml``; parameters and result as there, the binary in ``binaries/linux64/``, the sources with
    the file ``all.c`` that the model description lists (as upstream's FMI 2 FMUs).

    Raises
    ------
    KeyError
        ``name`` has no FMI 2 model description (:data:`ALL_MODELS_FMI2`).
    ValueError
        An ``old`` text of ``edits`` does not occur.
    ReferenceBuildError
        gcc failed.
    """
    if name not in ALL_MODELS_FMI2:
        raise KeyError(f"no FMI 2 Reference FMU {name!r} in {SOURCES} (there are {', '.join(ALL_MODELS_FMI2)})")
    return _build(name, 2, Path(folder), edits, fmu_name)


def _build(name: str, version: int, folder: Path, edits: dict[str, list[tuple[str, str]]] | None,
           fmu_name: str | None) -> Path:
    """Assemble and compile the FMI ``version`` FMU of ``name`` in ``folder`` (see :func:`reference_fmu`)."""
    tree = folder / (fmu_name or name)
    if tree.exists():
        shutil.rmtree(tree)
    sources, binaries = tree / "sources", tree / "binaries" / PLATFORMS[version]
    sources.mkdir(parents=True)
    binaries.mkdir(parents=True)
    api = f"fmi{version}Functions.c"
    for file in (api, "cosimulation.c"):
        shutil.copy2(SOURCES / "src" / file, sources / file)
    for file in COMMON_HEADERS:
        shutil.copy2(SOURCES / "include" / file, sources / file)
    for file in MODEL_FILES:
        shutil.copy2(SOURCES / name / file, sources / file)
    if version == 3:
        shutil.copy2(SOURCES / name / "buildDescription.xml", sources / "buildDescription.xml")
    else:
        (sources / "all.c").write_text(f'#define FMI_VERSION {version}\n\n#include "{api}"\n'
                                       '#include "model.c"\n#include "cosimulation.c"\n')
    shutil.copy2(model_description(name, version), tree / "modelDescription.xml")
    if (SOURCES / name / "y.txt").is_file():
        (tree / "resources").mkdir()
        shutil.copy2(SOURCES / name / "y.txt", tree / "resources" / "y.txt")
    if (SOURCES / name / "fmi-ls-ref.xml").is_file():
        ref = tree / "extra" / "org.fmi-standard.fmi-ls-ref"
        ref.mkdir(parents=True)
        shutil.copy2(SOURCES / name / "fmi-ls-ref.xml", ref / "fmi-ls-manifest.xml")
        shutil.copy2(reference_output(name), ref / reference_output(name).name)
    if (SOURCES / name / "fmi-ls-dae.xml").is_file():
        dae = tree / "extra" / "org.fmi-standard.fmi-ls-dae"
        dae.mkdir(parents=True)
        shutil.copy2(SOURCES / name / "fmi-ls-dae.xml", dae / "fmi-ls-manifest.xml")
    _apply(edits, tree, sources, name)
    command = ["gcc", *CFLAGS, f"-DFMI_VERSION={version}", f"-I{sources}", f"-I{SOURCES / 'include'}",
               *(str(sources / f) for f in (api, "cosimulation.c", "model.c")),
               "-lm", "-o", str(binaries / f"{name}.so")]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        raise ReferenceBuildError(f"gcc failed on the FMI {version} Reference FMU {name}:\n{result.stderr}")
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
