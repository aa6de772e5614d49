"""Compile the C sources with gcc and pack the FMU (a zip) atomically."""
from __future__ import annotations

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


def compile_binary(sources: Path, identifier: str, target: Path, cc: str | None = None) -> None:
    """gcc every C file of ``sources`` into the shared library ``target``."""
    compiler = cc or os.environ.get("CC") or "gcc"
    if shutil.which(compiler) is None:
        raise BuildError(f"C compiler '{compiler}' not found (set CC or install gcc)")
    c_files = sorted(str(p) for p in sources.glob("*.c"))
    size = sum(Path(f).stat().st_size for f in c_files)
    optimization = "-O1" if size > LARGE_SOURCE else "-O2"
    command = [compiler, *CFLAGS, optimization, f"-I{sources}", "-o", str(target), *c_files, "-lm"]
    try:
        result = subprocess.run(command, capture_output=True, text=True, errors="replace")
    except OSError as exc:
        raise BuildError(f"{identifier}: cannot run the C compiler '{compiler}': {exc.strerror or exc}") from None
    if result.returncode != 0:
        tail = "\n".join(result.stderr.strip().splitlines()[-30:])
        raise BuildError(f"{identifier}: C compilation failed:\n{tail}")


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
