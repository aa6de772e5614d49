"""Compile the C sources with gcc and pack the FMU (a zip) atomically."""
from __future__ import annotations

import contextlib
import json
import os
import shutil
import subprocess
import tempfile
import zipfile
from pathlib import Path

from cosim.errors import BuildError, OutputError

CFLAGS = ["-std=c99", "-fPIC", "-shared", "-fvisibility=hidden", "-Wall"]
# gcc -O2 on the straight-line code CasADi generates for large models (the nonlinear Whipple
# bicycle: 700 kB) takes minutes; -O1 is about 3x faster to compile at little run-time cost.
LARGE_SOURCE = 300_000  # bytes of C above which -O1 is used
MANIFEST = "documentation/build.json"
# Partial FMUs this process is writing (an abandoned build worker removes them, see build.py).
PARTIALS: set[Path] = set()


def platform_folder() -> str:
    """FMI 2.0 platform folder of this machine (linux64, darwin64, win64)."""
    import fmpy

    return fmpy.platform


def compile_binary(sources: Path, identifier: str, target: Path, cc: str | None = None,
                   generated: tuple[str, ...] = (), objects: Path | None = None) -> None:
    """gcc every C file of ``sources`` into the shared library ``target``.

    The files are compiled in parallel (one gcc per file, as many at once as there are CPUs), then
    linked. ``generated`` names the files that CasADi wrote: they are compiled without warnings
    (-Wall on 600 kB of generated straight-line code costs 10 % of the build and says nothing a
    user could act on). Object files go to ``objects`` (default: a temporary folder).
    """
    compiler = cc or os.environ.get("CC") or "gcc"
    if shutil.which(compiler) is None:
        raise BuildError(f"C compiler '{compiler}' not found (set CC or install gcc)")
    c_files = sorted(sources.glob("*.c"))
    size = sum(f.stat().st_size for f in c_files)
    optimization = "-O1" if size > LARGE_SOURCE else "-O2"
    with contextlib.ExitStack() as stack:
        if objects is None:
            objects = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="cosim-objects-")))
        objects.mkdir(parents=True, exist_ok=True)
        jobs = [[compiler, *CFLAGS, optimization, *(["-w"] if f.name in generated else []), f"-I{sources}",
                 "-c", str(f), "-o", str(objects / f"{f.stem}.o")] for f in c_files]
        link = [compiler, *CFLAGS, "-o", str(target), *(str(objects / f"{f.stem}.o") for f in c_files), "-lm"]
        _run_compiler([*_batches(jobs, os.cpu_count() or 1), [link]], identifier, compiler)


def _batches(commands: list, width: int) -> list[list]:
    """The commands in groups of at most ``width`` that run at the same time."""
    return [commands[k:k + width] for k in range(0, len(commands), width)]


def _run_compiler(batches: list[list[list[str]]], identifier: str, compiler: str) -> None:
    """Run each batch of compiler commands in parallel, the batches one after the other; the first
    failure stops the others and raises a BuildError with the compiler's last lines."""
    for batch in batches:
        running = []
        try:
            for command in batch:
                try:
                    running.append(subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                                    text=True, errors="replace"))
                except OSError as exc:
                    raise BuildError(f"{identifier}: cannot run the C compiler '{compiler}': "
                                     f"{exc.strerror or exc}") from None
            for process in running:
                _, stderr = process.communicate()
                if process.returncode != 0:
                    tail = "\n".join(stderr.strip().splitlines()[-30:])
                    raise BuildError(f"{identifier}: C compilation failed:\n{tail}")
        finally:
            for process in running:
                if process.poll() is None:
                    process.kill()
                    process.wait()

def pack(staging: Path, destination: Path) -> None:
    """Zip ``staging`` into ``destination``; the file appears only when complete.

    Raises
    ------
    OutputError
        If the FMU cannot be written (folder not writable, disk full, a folder in the way).
    """
    try:
        destination.parent.mkdir(parents=True, exist_ok=True)
        fd, partial = tempfile.mkstemp(prefix=f".{destination.name}.", suffix=".partial", dir=destination.parent)
    except OSError as exc:
        raise OutputError(f"cannot write the FMU '{destination}': {exc.strerror or exc}") from None
    os.close(fd)
    PARTIALS.add(Path(partial))
    try:
        with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as archive:
            for path in sorted(staging.rglob("*")):
                if path.is_file():
                    info = zipfile.ZipInfo(str(path.relative_to(staging)), date_time=(2000, 1, 1, 0, 0, 0))
                    info.compress_type = zipfile.ZIP_DEFLATED
                    info.external_attr = 0o644 << 16
                    archive.writestr(info, path.read_bytes())
        os.chmod(partial, 0o644)
        os.replace(partial, destination)
    except OSError as exc:
        Path(partial).unlink(missing_ok=True)
        raise OutputError(f"cannot write the FMU '{destination}': {exc.strerror or exc}") from None
    except BaseException:
        Path(partial).unlink(missing_ok=True)
        raise
    finally:
        PARTIALS.discard(Path(partial))


def read_manifest(fmu: Path) -> dict | None:
    """The build manifest of an FMU built by cosim (None if absent or unreadable)."""
    try:
        with zipfile.ZipFile(fmu) as archive:
            return json.loads(archive.read(MANIFEST))
    except (OSError, KeyError, zipfile.BadZipFile, ValueError):
        return None
