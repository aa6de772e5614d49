"""`cosim build --wasm`: an FMI 2.0 FMU -> a WebAssembly module for the browser.

The module is compiled from the FMU's own C sources (those its modelDescription.xml lists for
Co-Simulation: the generated model code, cosim_runtime.c, fmi2_api.c and the tape interpreter
cosim_tape.c) and ``wasm_api.c``, a
small API for JavaScript on top of the FMI 2 functions, by the C compiler of the ``ziglang``
wheel (Zig's clang with wasi-libc) for ``wasm32-wasi`` as a reactor (a library with no ``main``:
``_initialize``, then any export). It imports nothing: the page needs no WASI implementation.
``cosim/wasm/fmu.js`` loads it.

For the FMU ``OUTPUT/NAME.fmu`` two files are written:

``OUTPUT/wasm/NAME.wasm``
    the module;
``OUTPUT/wasm/NAME.json``
    what the page needs to use it, taken from the FMU's modelDescription.xml: model name, GUID,
    default experiment, every variable with its value reference, type, causality, variability,
    start value, unit and description; plus the module's size and SHA-256 and the build key.

Incremental: the module is rebuilt only when its key changes, the digest of everything it is made
from: the FMU's build manifest (fingerprint and source hashes; the FMU file itself if it has no
manifest), the Zig version, ``wasm_api.c``, this file and the compiler flags. Atomic: each file
is written under a temporary name and renamed, the module first, so a NAME.json always describes
a complete NAME.wasm of its key (a build killed between the two renames leaves the old NAME.json,
whose key no longer matches: the next build compiles again). One build of a module at a time: a
second one waits for the lock, then finds it up to date.

Floating point: the model code runs the same IEEE double operations in WebAssembly as on x86-64
(no fused multiply-add: ``-ffp-contract=off``, and WebAssembly has none without relaxed SIMD);
what may differ in the last bit are the libm functions (wasi-libc's musl against glibc) of the
nonlinear models and the square root of the runtime's error norm (the processor's instruction on
x86-64, Newton's method elsewhere, see ``rt_root`` in cosim_runtime.c).
"""
from __future__ import annotations

import functools
import hashlib
import importlib.util
import json
import os
import re
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
import zipfile
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

from cosim.errors import BuildError, FMUError, MissingExtraError
from cosim.outputs import atomic_output, check_output_folder, write_text
from cosim.compiler.catalog import cache_folder
from cosim.compiler.fmu import MANIFEST

HERE = Path(__file__).resolve().parent
SHIM = HERE / "wasm_api.c"
LOADER = HERE / "fmu.js"
WASM_FOLDER = "wasm"  # OUTPUT/wasm/NAME.wasm beside OUTPUT/NAME.fmu (and OUTPUT/fmi3/)
JSON_FORMAT = 1  # of NAME.json; fmu.js refuses another

TARGET = ("-target", "wasm32-wasi")
# C99 as for the native FMU; no contraction into fused multiply-adds (the native build has none on
# x86-64 without -march); no sanitizer (zig cc adds UBSan traps in debug builds).
CFLAGS = (*TARGET, "-std=c99", "-ffp-contract=off", "-fno-sanitize=undefined")
OPTIMIZATION = "-O2"
# Code that no co-simulation step runs and no page calls (adjoint derivatives; the local variables
# that an importer reads are a tape in model.c, no code): -O0 changes no result. The directional
# derivatives are optimized: the app's eigenvalue view calls them four times per speed, 290 speeds
# per redraw of the nonlinear bicycle (at -O0 they took four fifths of a redraw), and Zig's clang
# compiles them at -O2 as fast as at -O0 (the nonlinear bicycles: 2.1 s against 2.9 s, with a rider
# 7.8 s against 7.3 s).
UNOPTIMIZED = re.compile(r"model_vjp\.c")
# A reactor (no main); no debug information or names (-s: without it the linear bicycle's module
# is ten times larger, 1.1 MB instead of 120 kB); a stack
# of 1 MiB (the work arrays of the generated functions are on the stack, and WebAssembly has no
# guard page: an overflow would silently overwrite data).
LDFLAGS = (*TARGET, "-mexec-model=reactor", "-s", "-Wl,-z,stack-size=1048576")


@dataclass
class WasmResult:
    """What :func:`build_wasm` did for one FMU."""

    model: str
    wasm: Path         # OUTPUT/wasm/NAME.wasm
    description: Path  # OUTPUT/wasm/NAME.json
    rebuilt: bool
    seconds: float = 0.0  # [s]
    size: int = 0         # bytes of the module


def wasm_paths(fmu: str | Path, output: str | Path | None = None) -> tuple[Path, Path]:
    """``(OUTPUT/wasm/NAME.wasm, OUTPUT/wasm/NAME.json)`` of the FMU ``NAME.fmu``; ``output``
    defaults to the FMU's folder."""
    fmu = Path(fmu)
    folder = Path(output if output is not None else fmu.parent) / WASM_FOLDER
    return folder / f"{fmu.stem}.wasm", folder / f"{fmu.stem}.json"


def zig_command() -> list[str]:
    """The command of Zig's C compiler driver: ``[python, -m, ziglang]``.

    Raises
    ------
    MissingExtraError
        If the ``ziglang`` wheel (the optional extra ``wasm``) is not installed.
    """
    if importlib.util.find_spec("ziglang") is None:
        raise MissingExtraError("cosim build --wasm", "the Zig toolchain of the 'ziglang' wheel", "wasm")
    return [sys.executable, "-m", "ziglang"]


@functools.lru_cache(maxsize=1)
def zig_version() -> str:
    """The version of the installed Zig (``zig version``), part of the build key."""
    try:
        done = subprocess.run([*zig_command(), "version"], capture_output=True, text=True, timeout=120)
    except (OSError, subprocess.SubprocessError) as exc:
        raise BuildError(f"cannot run the Zig compiler: {exc}") from None
    if done.returncode != 0 or not done.stdout.strip():
        raise BuildError(f"cannot run the Zig compiler (zig version exited {done.returncode}): "
                         f"{done.stderr.strip()[-500:]}")
    return done.stdout.strip()


def _zig_environment(scratch: Path) -> dict:
    """The compiler's environment: Zig's global cache (wasi-libc compiled once for these flags,
    half a minute) in cosim's cache folder; its local cache (an object per source) in the build's
    temporary folder, removed with it, so that builds of new sources do not pile up objects."""
    return {**os.environ, "ZIG_GLOBAL_CACHE_DIR": str(cache_folder() / "zig"),
            "ZIG_LOCAL_CACHE_DIR": str(scratch / "zig-local")}


# --- what the FMU holds -------------------------------------------------------------------------

def _read_fmu(fmu: Path) -> tuple[bytes, dict | None, dict[str, bytes]]:
    """The FMU's modelDescription.xml, build manifest (None if it has none) and C sources and
    headers (file name -> bytes, the files of ``sources/``)."""
    try:
        with zipfile.ZipFile(fmu) as archive:
            names = archive.namelist()
            if "modelDescription.xml" not in names:
                raise FMUError(f"{fmu}: not an FMU (no modelDescription.xml)")
            description = archive.read("modelDescription.xml")
            manifest = json.loads(archive.read(MANIFEST)) if MANIFEST in names else None
            sources = {name.removeprefix("sources/"): archive.read(name) for name in names
                       if name.startswith("sources/") and not name.endswith("/")
                       and "/" not in name.removeprefix("sources/")}
    except (OSError, zipfile.BadZipFile) as exc:
        raise FMUError(f"{fmu}: cannot read the FMU: {getattr(exc, 'strerror', None) or exc}") from None
    except ValueError as exc:
        raise FMUError(f"{fmu}: its build manifest is not valid JSON: {exc}") from None
    return description, manifest, sources


def model_table(description_xml: bytes, fmu: Path) -> dict:
    """What the page needs of modelDescription.xml (FMI 2.0): model name, identifier, GUID,
    default experiment, the Co-Simulation source files and every variable.

    Raises
    ------
    FMUError
        If it is not an FMI 2.0 description with Co-Simulation and source files.
    """
    try:
        root = ET.fromstring(description_xml)
    except ET.ParseError as exc:
        raise FMUError(f"{fmu}: modelDescription.xml is not well-formed XML: {exc}") from None
    if root.tag != "fmiModelDescription" or root.get("fmiVersion") != "2.0":
        raise FMUError(f"{fmu}: --wasm compiles FMI 2.0 FMUs; this one is FMI {root.get('fmiVersion')!r}")
    cs = root.find("CoSimulation")
    if cs is None:
        raise FMUError(f"{fmu}: the FMU has no Co-Simulation interface, which the WebAssembly module runs")
    files = [f.get("name") for f in cs.iterfind("SourceFiles/File")]
    if not files:
        raise FMUError(f"{fmu}: the FMU lists no C source files (a binary-only FMU cannot be compiled to "
                       "WebAssembly)")
    experiment = root.find("DefaultExperiment")
    default = {key: float(experiment.get(key)) for key in ("startTime", "stopTime", "tolerance", "stepSize")
               if experiment is not None and experiment.get(key) is not None}
    variables = []
    for v in root.iterfind("ModelVariables/ScalarVariable"):
        typed = next((child for child in v if child.tag in ("Real", "Integer", "Boolean", "String",
                                                              "Enumeration")), None)
        entry = {"name": v.get("name"), "valueReference": int(v.get("valueReference")),
                 "type": typed.tag if typed is not None else None,
                 "causality": v.get("causality", "local"), "variability": v.get("variability", "continuous")}
        for key in ("initial", "description"):
            if v.get(key) is not None:
                entry[key] = v.get(key)
        if typed is not None:
            start = typed.get("start")
            if start is not None:
                entry["start"] = (float(start) if typed.tag == "Real" else
                                  int(start) if typed.tag in ("Integer", "Enumeration") else
                                  start == "true" if typed.tag == "Boolean" else start)
            for key in ("unit", "displayUnit", "min", "max", "derivative"):
                if typed.get(key) is not None:
                    value = typed.get(key)
                    entry[key] = int(value) if key == "derivative" else float(value) if key in ("min", "max") \
                        else value
        variables.append(entry)
    return {"modelName": root.get("modelName"), "modelIdentifier": cs.get("modelIdentifier"),
            "guid": root.get("guid"), "description": root.get("description", ""),
            "generationTool": root.get("generationTool", ""), "defaultExperiment": default,
            "sourceFiles": files, "variables": variables}


def build_key(fmu: Path, manifest: dict | None) -> str:
    """Digest of everything the module is made from (see the module docstring)."""
    h = hashlib.sha256(f"cosim-wasm {JSON_FORMAT}\0{zig_version()}\0".encode())
    h.update(" ".join([*CFLAGS, OPTIMIZATION, UNOPTIMIZED.pattern, *LDFLAGS]).encode())
    for path in (SHIM, Path(__file__)):
        h.update(b"\0" + path.read_bytes())
    if manifest and manifest.get("fingerprint") and manifest.get("sources"):
        h.update(json.dumps({"fingerprint": manifest["fingerprint"], "sources": manifest["sources"]},
                            sort_keys=True).encode())
    else:  # not built by cosim: the FMU as it is
        h.update(hashlib.sha256(fmu.read_bytes()).digest())
    return h.hexdigest()


def module_interface(data: bytes) -> tuple[list[tuple[str, str, str]], list[tuple[str, str]]]:
    """The imports ``(module, name, kind)`` and exports ``(name, kind)`` of the WebAssembly binary
    ``data`` (kind: function, table, memory, global, tag), read from its import and export
    sections (WebAssembly core specification 5.5.10 and 5.5.11).

    Raises
    ------
    BuildError
        If ``data`` is not a WebAssembly binary module.
    """
    kinds = ("function", "table", "memory", "global", "tag")
    if data[:8] != b"\0asm\x01\0\0\0":
        raise BuildError("not a WebAssembly binary module (version 1)")

    def uint(at):  # unsigned LEB128
        value = shift = 0
        while True:
            byte = data[at]
            at += 1
            value |= (byte & 0x7F) << shift
            shift += 7
            if byte < 0x80:
                return value, at

    def name(at):
        length, at = uint(at)
        return data[at:at + length].decode("utf-8"), at + length

    def limits(at):
        flags, at = uint(at)
        _, at = uint(at)
        if flags & 1:
            _, at = uint(at)
        return at

    imports, exports, at = [], [], 8
    try:
        while at < len(data):
            section, size_at = data[at], at + 1
            size, at = uint(size_at)
            end = at + size
            if section == 2:  # imports: module, name, description
                count, p = uint(at)
                for _ in range(count):
                    module, p = name(p)
                    field, p = name(p)
                    kind = data[p]
                    p += 1
                    if kind == 0:    # function: type index
                        _, p = uint(p)
                    elif kind == 1:  # table: reference type, limits
                        p = limits(p + 1)
                    elif kind == 2:  # memory: limits
                        p = limits(p)
                    elif kind == 3:  # global: value type, mutability
                        p += 2
                    else:            # tag: attribute, type index
                        _, p = uint(p + 1)
                    imports.append((module, field, kinds[kind] if kind < len(kinds) else str(kind)))
            elif section == 7:  # exports: name, kind, index
                count, p = uint(at)
                for _ in range(count):
                    field, p = name(p)
                    kind = data[p]
                    _, p = uint(p + 1)
                    exports.append((field, kinds[kind] if kind < len(kinds) else str(kind)))
            at = end
    except (IndexError, UnicodeDecodeError):
        raise BuildError("truncated or malformed WebAssembly module") from None
    return imports, exports


def _up_to_date(wasm: Path, description: Path, key: str) -> bool:
    try:
        table = json.loads(description.read_text(encoding="utf-8"))
        return table["build"]["key"] == key and wasm.stat().st_size == table["wasm"]["bytes"]
    except (OSError, ValueError, KeyError, TypeError):
        return False


# --- compiling ----------------------------------------------------------------------------------

def _run(commands: list[list[str]], cwd: Path, env: dict, what: str) -> None:
    """Run the compiler commands, as many at once as there are CPUs; BuildError with the
    compiler's last lines if one fails."""
    def run(command):
        return subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True, errors="replace",
                              timeout=1800)

    try:
        with ThreadPoolExecutor(max_workers=max(1, min(len(commands), os.cpu_count() or 1))) as pool:
            done = list(pool.map(run, commands))
    except (OSError, subprocess.SubprocessError) as exc:
        raise BuildError(f"{what}: cannot run the Zig compiler: {exc}") from None
    for process in done:
        if process.returncode != 0:
            tail = "\n".join((process.stderr or process.stdout).strip().splitlines()[-30:])
            raise BuildError(f"{what}: WebAssembly compilation failed:\n{tail}")


def _compile(sources: dict[str, bytes], files: list[str], target: Path, scratch: Path, what: str) -> None:
    """Compile ``files`` (of ``sources``) and the API into the module ``target``."""
    folder = scratch / "sources"
    objects = scratch / "objects"
    folder.mkdir()
    objects.mkdir()
    for name, data in sources.items():
        (folder / name).write_bytes(data)
    missing = [name for name in files if name not in sources]
    if missing:
        raise FMUError(f"{what}: modelDescription.xml lists source files that are not in sources/: "
                       f"{', '.join(missing)}")
    units = [(name, name) for name in files] + [(str(SHIM), "wasm_api_shim.c")]
    zig = zig_command()
    env = _zig_environment(scratch)
    # Relative names in the FMU's source folder (its headers are found with -I.); the longest first.
    compile_jobs = [[*zig, "cc", *CFLAGS, "-O0" if UNOPTIMIZED.fullmatch(name) else OPTIMIZATION, "-w", "-I.",
                     "-c", source, "-o", str(objects / f"{Path(name).stem}.o")]
                    for source, name in sorted(units, key=lambda u: -len(sources.get(u[0], b"")))]
    _run(compile_jobs, folder, env, what)
    link = [*zig, "cc", *LDFLAGS, "-o", str(target), *(str(objects / f"{Path(name).stem}.o") for _, name in units)]
    _run([link], folder, env, what)


def build_wasm(fmu: str | Path, output: str | Path | None = None, force: bool = False) -> WasmResult:
    """Compile the FMI 2.0 FMU ``fmu`` into ``OUTPUT/wasm/NAME.wasm`` and ``NAME.json``, unless
    they are up to date.

    Parameters
    ----------
    fmu : path
        An FMI 2.0 FMU with C sources and Co-Simulation (every FMI 2.0 FMU of `cosim build`).
    output : path, optional
        The folder whose ``wasm/`` receives the module (default: the FMU's folder).
    force : bool
        Rebuild even if up to date.

    Returns
    -------
    WasmResult
        Paths, ``rebuilt`` (False if up to date), ``seconds`` [s] spent, ``size`` [bytes].

    Raises
    ------
    BuildError
        If the compilation failed.
    MissingExtraError
        If the ``ziglang`` wheel (the optional extra ``wasm``) is not installed.
    FMUError
        If ``fmu`` is not an FMI 2.0 FMU with sources and Co-Simulation.
    OutputError
        If the module cannot be written.
    """
    # deferred: loads casadi, numpy, which importing this module does not
    from cosim.compiler.build import _build_lock

    started = time.perf_counter()
    fmu = Path(fmu)
    if not fmu.is_file():
        raise FMUError(f"{fmu}: no such FMU file")
    wasm, description = wasm_paths(fmu, output)
    check_output_folder(wasm.parent)
    xml, manifest, sources = _read_fmu(fmu)
    table = model_table(xml, fmu)
    key = build_key(fmu, manifest)
    name = table["modelName"] or fmu.stem
    with _build_lock(wasm):
        if not force and _up_to_date(wasm, description, key):
            return WasmResult(name, wasm, description, False, time.perf_counter() - started, wasm.stat().st_size)
        with tempfile.TemporaryDirectory(prefix="cosim-wasm-") as tmp:
            with atomic_output(wasm, "WebAssembly module") as partial:
                _compile(sources, table["sourceFiles"], partial, Path(tmp), name)
                data = partial.read_bytes()
        table.pop("sourceFiles")
        imports, _ = module_interface(data)
        table = {"format": JSON_FORMAT, **table,
                 "wasm": {"file": wasm.name, "bytes": len(data), "sha256": hashlib.sha256(data).hexdigest(),
                          "imports": [f"{module}.{field}" for module, field, _ in imports]},
                 "build": {"key": key, "zig": zig_version(), "fmu": fmu.name,
                           "fingerprint": (manifest or {}).get("fingerprint")}}
        write_text(description, json.dumps(table, separators=(",", ":")) + "\n", "WebAssembly model description")
    return WasmResult(name, wasm, description, True, time.perf_counter() - started, len(data))

