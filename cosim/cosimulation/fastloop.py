"""Load (compiling on first use) the C stepping loop for systems made only of FMUs."""
from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import tempfile
from ctypes import CDLL, POINTER, Structure, c_double, c_int, c_uint, c_void_p, cast
from functools import lru_cache
from pathlib import Path


SOURCE = Path(__file__).with_name("fastloop.c")


class FastComponent(Structure):
    _fields_ = [
        ("instance", c_void_p), ("set_real", c_void_p), ("get_real", c_void_p), ("do_step", c_void_p),
        ("n_in", c_int), ("in_vr", POINTER(c_uint)), ("in_src", POINTER(c_int)), ("in_buf", POINTER(c_double)),
        ("n_out", c_int), ("out_vr", POINTER(c_uint)), ("out_offset", c_int), ("multiple", c_int),
    ]


def _cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "cosim"


@lru_cache(maxsize=1)
def library():
    """The compiled loop, or None where it cannot be had (no C compiler, no writable cache
    folder, a library that does not load): the master then steps in Python, with the same results."""
    digest = hashlib.sha256(SOURCE.read_bytes()).hexdigest()[:16]
    target = _cache_dir() / f"fastloop-{digest}.so"
    try:
        if not target.exists() and not _compile(target):
            return None
        lib = CDLL(str(target))
    except OSError:  # an unwritable cache folder or a library that does not load
        return None
    lib.cosim_fast_run.restype = c_int
    return lib


def _compile(target: Path) -> bool:
    """Compile fastloop.c into ``target`` (atomically: concurrent processes may do the same)."""
    compiler = os.environ.get("CC") or "gcc"
    if shutil.which(compiler) is None:
        return False
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, partial = tempfile.mkstemp(prefix=".fastloop-", suffix=".so", dir=target.parent)
    os.close(fd)
    try:
        result = subprocess.run([compiler, "-O2", "-shared", "-fPIC", "-std=c99", str(SOURCE), "-o", partial, "-lm"],
                                capture_output=True, text=True)
        if result.returncode != 0:
            return False
        os.replace(partial, target)
        return True
    finally:
        Path(partial).unlink(missing_ok=True)


def address(function) -> int:
    return cast(function, c_void_p).value
