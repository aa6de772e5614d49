"""`cosim build`: Modelica model -> FMU, incremental and in parallel."""
from __future__ import annotations

import hashlib
import json
import os
import platform
import tempfile
import uuid
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from .. import __version__
from ..errors import CosimError
from .codegen import RUNTIME_DIR, casadi_functions, write_sources
from .description import describe
from .flatten import flatten
from .fmu import MANIFEST, compile_binary, pack, platform_folder, read_manifest
from .library import Library, load_library
from .model_description import model_description_xml
from .ode import make_explicit

# Where `cosim build` and every command that builds on demand put FMUs: fmus/ of the working
# directory (never the installed package), or the folder named by COSIM_FMU_DIR (the tests point
# it to a temporary folder).
DEFAULT_OUTPUT = Path(os.environ.get("COSIM_FMU_DIR") or Path.cwd() / "fmus").absolute()


@dataclass
class BuildResult:
    """What `cosim build` did for one model."""

    model: str
    fmu: Path
    rebuilt: bool
    seconds: float = 0.0


def _tool_versions() -> dict:
    import casadi
    import pymoca

    return {"cosim": __version__, "pymoca": pymoca.__version__, "casadi": casadi.__version__,
            "python": platform.python_version()}


@lru_cache(maxsize=1)
def compiler_digest() -> str:
    """Changes whenever the compiler, the runtime or the tools behind them change."""
    h = hashlib.sha256(json.dumps(_tool_versions(), sort_keys=True).encode())
    here = Path(__file__).resolve().parent
    for path in sorted(list(here.glob("*.py")) + list(RUNTIME_DIR.glob("*.[ch]"))):
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def _fingerprint(flat, entry) -> str:
    """Hash of everything the FMU is made from: the flat equations, declarations, parameter
    values, annotations and the compiler itself."""
    m = flat.casadi
    h = hashlib.sha256(compiler_digest().encode())
    parts = [flat.name, entry.description, repr(entry.annotation), repr(sorted(flat.declarations.items()))]
    parts += [str(e) for e in m.equations] + [str(e) for e in m.initial_equations]
    for group in (m.states, m.der_states, m.alg_states, m.inputs, m.outputs, m.parameters, m.constants):
        parts += [f"{getattr(v, 'symbol', v)}={getattr(v, 'value', '')}|{getattr(v, 'start', '')}" for v in group]
    for part in parts:
        h.update(part.encode())
        h.update(b"\0")
    return h.hexdigest()


def fmu_path(model_name: str, output: Path) -> Path:
    return Path(output) / f"{model_name.replace('.', '_')}.fmu"


def build_model(model_name: str, output: str | Path = DEFAULT_OUTPUT, library: Library | None = None,
                force: bool = False) -> BuildResult:
    """Compile one Modelica model to ``OUTPUT/<identifier>.fmu`` (ME + CS), unless up to date.

    Raises
    ------
    UnknownModelError, ModelicaError, ModelStructureError, ParameterError, BuildError
    """
    import time

    started = time.perf_counter()
    library = library or load_library()
    entry = library.entry(model_name)
    target = fmu_path(model_name, Path(output))
    manifest = read_manifest(target) if target.exists() else None
    # Fast path: no source file and no part of the compiler changed since the FMU was built.
    sources_digest = hashlib.sha256((library.digest() + compiler_digest()).encode()).hexdigest()
    if not force and manifest and manifest.get("sources_digest") == sources_digest:
        return BuildResult(model_name, target, False, time.perf_counter() - started)
    flat = flatten(library, model_name)
    fingerprint = _fingerprint(flat, entry)
    if not force and manifest and manifest.get("fingerprint") == fingerprint:
        return BuildResult(model_name, target, False, time.perf_counter() - started)

    model = make_explicit(flat)
    info = describe(entry, flat, model)
    functions = casadi_functions(model)
    guid_source = hashlib.sha256(fingerprint.encode())
    for f in functions:
        guid_source.update(f.serialize().encode())
    info.guid = "{" + str(uuid.UUID(guid_source.hexdigest()[:32])) + "}"
    versions = _tool_versions()
    tool = f"cosim {versions['cosim']} (pymoca {versions['pymoca']}, CasADi {versions['casadi']})"

    with tempfile.TemporaryDirectory(prefix="cosim-build-") as tmp:
        staging = Path(tmp) / "fmu"
        sources = staging / "sources"
        files = write_sources(info, model, sources)
        (staging / "modelDescription.xml").write_bytes(model_description_xml(info, tool))
        binaries = staging / "binaries" / platform_folder()
        binaries.mkdir(parents=True)
        compile_binary(sources, info.identifier, binaries / f"{info.identifier}.so")
        source_hashes = {name: hashlib.sha256((sources / name).read_bytes()).hexdigest() for name in files}
        (staging / MANIFEST).parent.mkdir(parents=True, exist_ok=True)
        (staging / MANIFEST).write_text(json.dumps({
            "model": model_name,
            "fingerprint": fingerprint,
            "sources_digest": sources_digest,
            "guid": info.guid,
            "modelica_files": [str(p.relative_to(library.path)) for p in library.files],
            "tools": versions,
            "sources": source_hashes,
        }, indent=2, sort_keys=True) + "\n")
        pack(staging, target)
    return BuildResult(model_name, target, True, time.perf_counter() - started)


def _build_one(args):
    model_name, output, library_path, force = args
    try:
        return build_model(model_name, output, load_library(library_path), force)
    except CosimError as exc:
        return exc


def build(models: list[str] | None = None, output: str | Path = DEFAULT_OUTPUT, jobs: int = 1,
          library_path: str | None = None, force: bool = False) -> list[BuildResult]:
    """Build several models (default: every exported model), ``jobs`` at a time.

    All models are attempted; if any fails, the first error is raised after the others finished
    (their FMUs are complete, the failed one leaves nothing behind).
    """
    library = load_library(library_path)
    names = models or [e.name for e in library.models(exported_only=True)]
    for name in names:
        library.entry(name)  # unknown names fail before any work starts
    tasks = [(name, str(output), library_path, force) for name in names]
    if jobs > 1 and len(tasks) > 1:
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            results = list(pool.map(_build_one, tasks))
    else:
        results = [_build_one(task) for task in tasks]
    errors = [r for r in results if isinstance(r, Exception)]
    if errors:
        raise errors[0]
    return results
