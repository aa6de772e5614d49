"""The app's WebAssembly modules and diagrams as the package ships them (``cosim/app/modules/``).

`cosim app` and `cosim app --export` need, for the models of :data:`cosim.app.export.MODULES`,
the WebAssembly module and NAME.json that `cosim build --wasm` makes from each FMU, and the
diagrams of the page's bicycles that :mod:`cosim.app.diagrams` draws from the parsed library.
Building them takes half a minute to minutes (four FMUs, Zig's wasi-libc, the compilations) and
parsing the library seconds; the package therefore carries them, made by
``python -m cosim.app.ship`` (:mod:`cosim.app.ship`, which tests/test_app_shipped.py runs and
compares byte for byte with these files):

``modules/NAME.wasm``, ``modules/NAME.json``
    the files `cosim build --wasm` wrote for ``NAME.fmu`` (``NAME`` as the FMU's name), unchanged;
``modules/diagrams.json``
    ``COSIM_DATA.diagrams`` (:func:`cosim.app.diagrams.page_diagrams`);
``modules/manifest.json``
    model name -> ``NAME``, the diagrams' models, the Zig and tool versions they were made with,
    and the key of the sources (:func:`sources_key`).

The files are used only while they are current (:func:`load`): while the key recomputed from
the installed sources equals the recorded one. The key is computed from files alone, nothing is
compiled or parsed: the digest of the Modelica library that would be built
(:func:`cosim.compiler.library.library_digest`, the one the FMUs' up-to-date check uses, which
changes when a developer edits the library or a user's folder of ``COSIM_MODELICA_PATH`` hides or
adds to it) and of the code that makes the modules and diagrams from it (:data:`MADE_BY`: the
compiler and the FMU runtime, as :func:`cosim.compiler.library.compiler_digest` hashes them, the
WebAssembly build and its API, the diagram layer). Unlike the FMUs' own key it leaves out the
versions of Python, pymoca and CasADi: a wheel installed under another Python must use the
modules it carries (the Zig, pymoca and CasADi versions are pinned by pyproject.toml, and the
byte-for-byte test shows what the pinned tools make). When they are not current, the app builds
as it always did (FMUs, then Zig).
"""
from __future__ import annotations

import base64
import hashlib
import json
from dataclasses import dataclass
from pathlib import Path

from cosim.compiler.library import library_digest
from cosim.errors import ModelicaError

PACKAGE = Path(__file__).resolve().parents[1]  # cosim/
SHIPPED = Path(__file__).resolve().parent / "modules"
MANIFEST = "manifest.json"
DIAGRAMS = "diagrams.json"
FORMAT = 1  # of manifest.json; another is not read
#: The code that makes the shipped files from the library (globs relative to the package).
MADE_BY = ("compiler/*.py", "runtime/*.[ch]", "wasm/build.py", "wasm/wasm_api.c", "diagram/*.py",
           "app/diagrams.py")


@dataclass
class Shipped:
    """The shipped files, read: what ``COSIM_DATA.modules`` and ``COSIM_DATA.diagrams`` hold."""

    modules: dict   # model name -> {"description": NAME.json as a dict, "wasm": base64 of NAME.wasm}
    diagrams: dict  # model name -> cosim.app.diagrams.diagram_data


def sources_key(path=None) -> str:
    """The digest of what the shipped files are made from: the library at ``path`` (as for
    :func:`cosim.compiler.library.library_paths`; default ``COSIM_MODELICA_PATH`` and the
    shipped library) and the files of :data:`MADE_BY`, by name and content.

    Raises
    ------
    ModelicaError
        If a library folder does not exist or is a file.
    """
    h = hashlib.sha256(f"cosim app modules {FORMAT}\0{library_digest(path)}\0".encode())
    for file in sorted({f for pattern in MADE_BY for f in PACKAGE.glob(pattern)}):
        h.update(file.relative_to(PACKAGE).as_posix().encode() + b"\0")
        h.update(hashlib.sha256(file.read_bytes()).digest())
    return h.hexdigest()


def module_name(model: str) -> str:
    """``Bicycle.Control.PD`` -> ``Bicycle_Control_PD``: the FMU's name, that of its module."""
    return model.replace(".", "_")


def load(models, folder: Path = SHIPPED, path=None) -> Shipped | None:
    """The shipped modules of ``models`` and the shipped diagrams, if the files in ``folder``
    hold exactly these modules, are complete and are current for the library at ``path``
    (:func:`sources_key`); None otherwise (the caller builds them). The caller checks that the
    diagrams are those of the models it needs."""
    try:
        manifest = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
        if (manifest.get("format") != FORMAT or list(manifest["modules"]) != list(models)
                or manifest["key"] != sources_key(path)):
            return None
        modules = {}
        for model, name in manifest["modules"].items():
            description = json.loads((folder / f"{name}.json").read_text(encoding="utf-8"))
            wasm = (folder / f"{name}.wasm").read_bytes()
            if hashlib.sha256(wasm).hexdigest() != description["wasm"]["sha256"]:
                return None
            modules[model] = {"description": description, "wasm": base64.b64encode(wasm).decode("ascii")}
        diagrams = json.loads((folder / DIAGRAMS).read_text(encoding="utf-8"))
    except (OSError, ValueError, KeyError, TypeError, AttributeError, ModelicaError):
        return None  # (a library folder that does not exist: the build says so)
    if not isinstance(diagrams, dict) or list(diagrams) != manifest.get("diagrams"):
        return None
    return Shipped(modules, diagrams)
