"""C helpers of the Python package, compiled on first use and cached (not the FMUs: those are
built by :mod:`cosim.compiler`).

Each is one C file beside the module that uses it (the master's stepping loop,
``cosimulation/fastloop.c``; the classification's matrix pencil, ``matrix/pencil.c``). It is
compiled with the system's C compiler (``$CC``, else ``gcc``) into the user's cache folder
(``$XDG_CACHE_HOME/cosim``, else ``~/.cache/cosim``) under a name made from the digest of its
source and flags, so that an edited source or other flags never load a stale library, and
processes that compile it at the same time do not see each other's half-written files. Where no
compiler or no writable cache folder is to be had, :func:`load` returns None and the caller
computes in Python, with the same results.
"""
from __future__ import annotations

import hashlib
import os
import re
import shutil
import subprocess
import tempfile
from ctypes import CDLL
from pathlib import Path


def cache_dir() -> Path:
    """The folder of the compiled helpers: ``$XDG_CACHE_HOME/cosim``, else ``~/.cache/cosim``."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "cosim"


def loaded_libraries(pattern: str) -> list[str]:
    """Paths of the shared libraries loaded in this process whose path matches the regular
    expression ``pattern`` (e.g. ``openblas|blas``), from ``/proc/self/maps`` (Linux; elsewhere
    none): how the BLAS and LAPACK that numpy loaded are found."""
    try:
        with open("/proc/self/maps") as f:
            maps = f.read()
    except OSError:
        return []
    return sorted(set(re.findall(rf"(/\S*(?:{pattern})\S*\.so[^\s]*)", maps)))


def load(source: Path, flags: list[str], libraries: tuple[str, ...] = ("-lm",)) -> CDLL | None:
    """The shared library of the C file ``source`` compiled with ``flags`` and linked with
    ``libraries`` (compiled now if not cached yet), or None where it cannot be had (no C
    compiler, a compile error, no writable cache folder, a library that does not load)."""
    digest = hashlib.sha256(source.read_bytes() + " ".join([*flags, *libraries]).encode()).hexdigest()[:16]
    target = cache_dir() / f"{source.stem}-{digest}.so"
    try:
        if not target.exists() and not _compile(source, flags, libraries, target):
            return None
        return CDLL(str(target))
    except OSError:  # an unwritable cache folder or a library that does not load
        return None


def _compile(source: Path, flags: list[str], libraries: tuple[str, ...], target: Path) -> bool:
    """Compile ``source`` into ``target`` (atomically: concurrent processes may do the same)."""
    compiler = os.environ.get("CC") or "gcc"
    if shutil.which(compiler) is None:
        return False
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, partial = tempfile.mkstemp(prefix=f".{source.stem}-", suffix=".so", dir=target.parent)
    os.close(fd)
    try:
        result = subprocess.run([compiler, *flags, str(source), "-o", partial, *libraries],
                                capture_output=True, text=True)
        if result.returncode != 0:
            return False
        os.replace(partial, target)
        return True
    finally:
        Path(partial).unlink(missing_ok=True)
