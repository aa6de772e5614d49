"""Compile the C sources with gcc and pack the FMU (a zip) atomically."""
from __future__ import annotations

import contextlib
import functools
import hashlib
import json
import os
import shutil
import subprocess
import tempfile
import time
import zipfile
from pathlib import Path

from cosim.errors import BuildError
from cosim.outputs import atomic_output

CFLAGS = ["-std=c99", "-fPIC", "-shared", "-fvisibility=hidden", "-Wall"]
# gcc -O2 on the straight-line code CasADi generates for large models (the nonlinear Whipple
# bicycle: 700 kB) takes minutes; -O1 is about 3x faster to compile at little run-time cost.
LARGE_SOURCE = 300_000  # bytes of C above which LARGE_OPTIMIZATION is used
# Of -O1, the dominator optimizations (jump threading, redundancy elimination over the dominator
# tree) grow much faster than the size of one function: on the 500 kB eval function of a
# 2000-state chain gcc took more than 140 s with them and 1.9 s without. They do not change
# floating-point results (no reassociation at any -O level without -ffast-math).
LARGE_OPTIMIZATION = ("-O1", "-fno-tree-dominator-opts")
# One generated file above this size (a 3000-state model's directional derivatives: 1.4 MB of
# straight-line code, 6 s of gcc at -O1, 3 s at -O0) is compiled without optimization: its build
# time, not its run time, is what a user of such a model waits for. -O0 changes no result either
# (the same IEEE operations on x86-64's SSE2; no fused multiply-add without -march).
HUGE_FILE = 1_000_000  # bytes
# Model code (the runtime not counted) up to which all files are compiled as one translation unit.
UNITY_SOURCE = 100_000  # bytes
UNITY_FILE = "model_unity.c"
# -O1 compiles a small model in two thirds of -O2's time; the co-simulation steps of the linear
# bicycle with its controllers and delay are as fast (0.82 us per step of 4 FMUs either way).
UNITY_OPTIMIZATION = "-O1"
MANIFEST = "documentation/build.json"
PACK_LEVEL = 1  # deflate level of the files in an FMU (see pack)
# Partial FMUs this process is writing (an abandoned build worker removes them, see build.py).
PARTIALS: set[Path] = set()


def platform_folder(fmi_version: str = "2") -> str:
    """The folder under ``binaries/`` of this machine: FMI 2.0's platform (linux64, darwin64, win64)
    or, for ``fmi_version`` "3", FMI 3.0's platform tuple (x86_64-linux, aarch64-darwin, x86_64-windows)."""
    import fmpy

    return fmpy.platform_tuple if str(fmi_version) == "3" else fmpy.platform


def compile_binary(sources: Path, identifier: str, target: Path, cc: str | None = None,
                   generated: tuple[str, ...] = (), objects: Path | None = None,
                   cache: Path | None = None, unoptimized: tuple[str, ...] = ()) -> None:
    """gcc every C file of ``sources`` into the shared library ``target``.

    The files are compiled in parallel (as many gcc at once as there are CPUs, the next one
    starting as soon as one ends), then linked. ``generated`` names the files that CasADi wrote:
    they are compiled without warnings (-Wall on 600 kB of generated straight-line code costs
    10 % of the build and says nothing a user could act on). ``unoptimized`` names files compiled
    with -O0 (code that no integration step runs; -O0 changes no result, see HUGE_FILE), also
    inside the one translation unit of a small model (:func:`unity_source`). Object files go to
    ``objects`` (default: a temporary folder). gcc runs in ``sources`` on relative file names, so
    that no temporary path ends up in the binary (the same sources give the same bytes).

    The runtime (:data:`RUNTIME_SOURCES` that ``sources`` has: the core ``cosim_runtime.c``, the
    API of the FMU's FMI version and the tape interpreter ``cosim_tape.c``, the same for every
    FMU, 70 % of the gcc time of a small model) is taken from the object cache ``cache`` (a
    folder, see :func:`load_runtime_object`), one object per runtime source, when one is given,
    and stored there when compiled; the FMU ships its sources all the same.
    """
    compiler = cc or os.environ.get("CC") or "gcc"
    if shutil.which(compiler) is None:
        raise BuildError(f"C compiler '{compiler}' not found (set CC or install gcc)")
    c_files = sorted(sources.glob("*.c"))
    size = sum(f.stat().st_size for f in c_files)
    optimization = LARGE_OPTIMIZATION if size > LARGE_SOURCE else ("-O2",)
    with contextlib.ExitStack() as stack:
        if objects is None:
            objects = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="cosim-objects-")))
        objects.mkdir(parents=True, exist_ok=True)
        runtime = [f for f in c_files if f.name in RUNTIME_SOURCES]
        keys: dict[str, str] = {}   # runtime source -> its cache key
        cached: set[str] = set()    # runtime sources whose object came from the cache
        if cache is not None:
            for f in runtime:
                keys[f.name] = runtime_key(sources, compiler, f.name)
                if load_runtime_object(cache, keys[f.name], objects / f"{f.stem}.o", f.name):
                    cached.add(f.name)
        model_files = [f for f in c_files if f.name not in RUNTIME_SOURCES]
        if sum(f.stat().st_size for f in model_files) <= UNITY_SOURCE:
            # A small model in one translation unit: one compiler run instead of one per file
            # (a third of the CPU time of a small model's build). Written beside the sources, so
            # that gcc sees a relative name (no temporary path in the binary), and removed.
            unity = sources / UNITY_FILE
            unity.write_text(unity_source(model_files, unoptimized))
            stack.callback(unity.unlink, missing_ok=True)
            units = [unity] + runtime
        else:
            units = c_files
        jobs = [[compiler, *CFLAGS, *_flags(f, optimization, unoptimized, generated), "-I.", "-c", f.name,
                 "-o", str(objects / f"{f.stem}.o")]
                for f in sorted(units, key=lambda f: -f.stat().st_size)  # the longest first
                if f.name not in cached]
        link = [compiler, *CFLAGS, "-o", str(target), *(str(objects / f"{f.stem}.o") for f in units), "-lm"]
        _run_compiler(jobs, identifier, compiler, sources, os.cpu_count() or 1)
        for f in runtime:
            if f.name in keys and f.name not in cached:
                store_runtime_object(cache, keys[f.name], objects / f"{f.stem}.o", f.name)
        _run_compiler([link], identifier, compiler, sources, 1)


# In the one translation unit of a small model, the functions of the files no integration step
# runs (``unoptimized``: the directional derivatives) come after this pragma and are
# compiled without optimization, as they are in a large model: a third less gcc time for a
# component-assembled bicycle (0.15 s instead of 0.23 s), the same results (see HUGE_FILE). A
# compiler that does not know the pragma (clang) ignores it (-w) and optimizes them all.
UNOPTIMIZED_PRAGMA = '#pragma GCC optimize ("O0")'


def unity_source(model_files: list[Path], unoptimized: tuple[str, ...] = ()) -> str:
    """The translation unit of a small model: ``#include`` of each of its C files, those named in
    ``unoptimized`` last, after :data:`UNOPTIMIZED_PRAGMA`."""
    optimized = [f.name for f in model_files if f.name not in unoptimized]
    rest = [f.name for f in model_files if f.name in unoptimized]
    lines = [f'#include "{name}"' for name in optimized]
    if rest:
        lines += [UNOPTIMIZED_PRAGMA, *(f'#include "{name}"' for name in rest)]
    return "\n".join(lines) + "\n"


# The runtime, the same C for every FMU, by FMI version: its own files (cosim/runtime: the
# version-independent core, the API of the FMI version and the interpreter of tapes, the C sources
# in the order the FMU lists them, then their headers) and the FMI standard's headers (FMPy's
# c-code). The one table of what an FMU ships (codegen.runtime_files) and of what the build
# compiles once per machine (RUNTIME_SOURCES, RUNTIME_HEADERS).
RUNTIME_FILES = {
    "2": (("cosim_runtime.c", "fmi2_api.c", "cosim_tape.c", "cosim_runtime.h", "cosim_model.h", "cosim_tape.h"),
          ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h")),
    "3": (("cosim_runtime.c", "fmi3_api.c", "cosim_tape.c", "cosim_runtime.h", "cosim_model.h", "cosim_tape.h"),
          ("fmi3Functions.h", "fmi3FunctionTypes.h", "fmi3PlatformTypes.h")),
}
# The runtime's C sources of every FMI version. Always compiled with -O2 (also in an FMU whose
# generated code is large enough for -O1): one object per source serves every model, and the flags
# change no result (x86-64 without -march has no fused multiply-add for gcc to contract into).
RUNTIME_SOURCES = tuple(dict.fromkeys(name for own, _ in RUNTIME_FILES.values() for name in own if name.endswith(".c")))
RUNTIME_OPTIMIZATION = "-O2"
# Headers the runtime includes, of every FMI version (an FMU has those of its version, the others
# count as absent).
RUNTIME_HEADERS = tuple(dict.fromkeys(name for own, standard in RUNTIME_FILES.values()
                                      for name in (*own, *standard) if name.endswith(".h")))


def _flags(file: Path, default: tuple[str, ...], unoptimized: tuple[str, ...], generated: tuple[str, ...]):
    """Optimization (and warning) flags of one C file of an FMU (see :func:`compile_binary`)."""
    if file.name in RUNTIME_SOURCES:
        return (RUNTIME_OPTIMIZATION,)
    if file.name == UNITY_FILE:
        return (UNITY_OPTIMIZATION, "-w")
    level = ("-O0",) if file.name in unoptimized or file.stat().st_size > HUGE_FILE else default
    return (*level, *(("-w",) if file.name in generated else ()))


@functools.lru_cache(maxsize=8)
def _compiler_identity(compiler: str) -> str:
    """Path and ``--version`` of the C compiler (part of the runtime object's key)."""
    path = shutil.which(compiler) or compiler
    try:
        version = subprocess.run([compiler, "--version"], capture_output=True, text=True, errors="replace",
                                 timeout=60).stdout
    except (OSError, subprocess.SubprocessError) as exc:
        raise BuildError(f"cannot run the C compiler '{compiler}': {exc}") from None
    return f"{os.path.realpath(path)}\n{version}"


def runtime_key(sources: Path, compiler: str, source: str) -> str:
    """Digest of everything the object of the runtime source ``source`` (one of
    :data:`RUNTIME_SOURCES`) is made from: that source and the headers the runtime includes (as
    they are in ``sources``), the compiler (path and version) and the flags."""
    h = hashlib.sha256(_compiler_identity(compiler).encode())
    h.update(" ".join([*CFLAGS, RUNTIME_OPTIMIZATION]).encode())
    for name in (source, *RUNTIME_HEADERS):
        h.update(b"\0" + name.encode() + b"\0")
        path = sources / name
        h.update(path.read_bytes() if path.is_file() else b"(absent)")
    return h.hexdigest()


_CACHE_MAGIC = b"cosim-runtime-object 1\n"


def runtime_entry(source: str) -> str:
    """File name of the cache entry of the runtime source ``source``: ``cosim_runtime.o.entry``."""
    return f"{Path(source).stem}.o.entry"


def load_runtime_object(cache: Path, key: str, destination: Path, source: str) -> bool:
    """Copy the cached object of the runtime source ``source`` under ``key`` to ``destination``;
    False if there is none.

    A cache entry is one file, ``cache/<key>/<stem>.o.entry`` (:func:`runtime_entry`): a header
    line, the SHA-256 of the object, the object. An entry that does not match its digest
    (truncated, edited) is ignored (and replaced by the build that compiles the source then).
    """
    try:
        data = (cache / key / runtime_entry(source)).read_bytes()
    except OSError:
        return False
    if not data.startswith(_CACHE_MAGIC):
        return False
    digest, _, obj = data[len(_CACHE_MAGIC):].partition(b"\n")
    if not obj or hashlib.sha256(obj).hexdigest().encode() != digest:
        return False
    destination.write_bytes(obj)
    return True


def store_runtime_object(cache: Path, key: str, obj_file: Path, source: str) -> None:
    """Store the compiled object of the runtime source ``source`` under ``key``: written to a
    temporary name and renamed, so concurrent builds see a complete entry or none. A cache that
    cannot be written costs only the time of compiling the runtime again."""
    obj = obj_file.read_bytes()
    folder = cache / key
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd, partial = tempfile.mkstemp(prefix=f".{Path(source).stem}.", suffix=".partial", dir=folder)
        try:
            with os.fdopen(fd, "wb") as file:
                file.write(_CACHE_MAGIC + hashlib.sha256(obj).hexdigest().encode() + b"\n" + obj)
            os.chmod(partial, 0o644)
            os.replace(partial, folder / runtime_entry(source))
        except BaseException:
            with contextlib.suppress(OSError):
                os.unlink(partial)
            raise
    except OSError:
        pass  # a read-only or full output folder: this build has its object all the same


def _run_compiler(commands: list[list[str]], identifier: str, compiler: str, cwd: Path, width: int) -> None:
    """Run the compiler commands in ``cwd``, at most ``width`` at a time, the next one starting
    as soon as one ends; the first failure stops the others and raises a BuildError with the
    compiler's last lines. (stderr goes to a file: a pipe that fills up would block gcc.)"""
    pending = list(commands)
    running: list[tuple[subprocess.Popen, object]] = []
    try:
        while pending or running:
            while pending and len(running) < width:
                command = pending.pop(0)
                log = tempfile.TemporaryFile()
                try:
                    running.append((subprocess.Popen(command, cwd=cwd, stdout=subprocess.DEVNULL, stderr=log), log))
                except OSError as exc:
                    log.close()
                    raise BuildError(f"{identifier}: cannot run the C compiler '{compiler}': "
                                     f"{exc.strerror or exc}") from None
            done = [(p, log) for p, log in running if p.poll() is not None]
            if not done:
                time.sleep(0.002)
                continue
            for process, log in done:
                running.remove((process, log))
                log.seek(0)
                stderr = log.read().decode("utf-8", errors="replace")
                log.close()
                if process.returncode != 0:
                    tail = "\n".join(stderr.strip().splitlines()[-30:])
                    raise BuildError(f"{identifier}: C compilation failed:\n{tail}")
    finally:
        for process, log in running:
            if process.poll() is None:
                process.kill()
                process.wait()
            log.close()


def pack(staging: Path, destination: Path) -> None:
    """Zip ``staging`` into ``destination``; the file appears only when complete
    (:func:`cosim.outputs.atomic_output`: a partial FMU a killed build left in the folder is
    removed by the next build into it).

    Raises
    ------
    OutputError
        If the FMU cannot be written (folder not writable, disk full, a folder in the way).
    """
    with atomic_output(destination, "the FMU") as partial:
        PARTIALS.add(partial)  # removed by a pool worker whose parent died (cosim.compiler.build)
        try:
            # Level 1: much faster than the default level for a few more bytes (docs/benchmarks.md).
            # Given to writestr: for an entry given as a ZipInfo, zipfile ignores the archive's
            # compresslevel and deflates at level 6.
            with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as archive:
                for path in sorted(staging.rglob("*")):
                    if path.is_file():
                        info = zipfile.ZipInfo(str(path.relative_to(staging)), date_time=(2000, 1, 1, 0, 0, 0))
                        info.compress_type = zipfile.ZIP_DEFLATED
                        info.external_attr = 0o644 << 16
                        archive.writestr(info, path.read_bytes(), compresslevel=PACK_LEVEL)
        finally:
            PARTIALS.discard(partial)


def read_manifest(fmu: Path) -> dict | None:
    """The build manifest of an FMU built by cosim (None if absent or unreadable)."""
    try:
        with zipfile.ZipFile(fmu) as archive:
            return json.loads(archive.read(MANIFEST))
    except (OSError, KeyError, zipfile.BadZipFile, ValueError):
        return None
