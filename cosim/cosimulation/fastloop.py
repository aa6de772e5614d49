"""Load (compiling on first use) the C stepping loop for systems of FMUs and native blocks, and
describe a block's native form (:class:`~cosim.cosimulation.registry.Native`) to it."""
from __future__ import annotations

from ctypes import POINTER, Structure, c_double, c_int, c_longlong, c_size_t, c_uint, c_void_p, cast
from functools import lru_cache
from pathlib import Path

import numpy as np
from cosim.native import load


SOURCE = Path(__file__).with_name("fastloop.c")
#: -ffp-contract=off: no fused multiply-adds, so the native blocks round as numpy does.
FLAGS = ["-O2", "-ffp-contract=off", "-shared", "-fPIC", "-std=c99"]


#: Block kinds of fastloop.c by Native.kind.
KINDS = {"affine": 1, "linear": 2, "delay": 3}


class FastBlock(Structure):
    _fields_ = [
        ("kind", c_int), ("n_in", c_int), ("n_out", c_int), ("n_x", c_int),
        ("u", POINTER(c_double)), ("y", POINTER(c_double)), ("t", POINTER(c_double)), ("u_set", POINTER(c_double)),
        ("D", POINTER(c_double)),
        ("has_window", c_int), ("lo", c_double), ("hi", c_double), ("shift", c_double),
        ("on", POINTER(c_double)), ("off", POINTER(c_double)),
        ("x", POINTER(c_double)), ("x_next", POINTER(c_double)), ("C", POINTER(c_double)),
        ("Ad", POINTER(c_double)), ("Bd", POINTER(c_double)), ("which", POINTER(c_int)),
        ("tau", c_double), ("ring_t", POINTER(c_double)), ("ring_v", POINTER(c_double)),
        ("ring", POINTER(c_longlong)), ("capacity", c_longlong),
    ]


class FastComponent(Structure):
    _fields_ = [
        ("instance", c_void_p), ("set_real", c_void_p), ("get_real", c_void_p), ("do_step", c_void_p),
        ("n_in", c_int), ("in_vr", POINTER(c_uint)), ("in_src", POINTER(c_int)), ("in_buf", POINTER(c_double)),
        ("n_out", c_int), ("out_vr", POINTER(c_uint)), ("out_offset", c_int), ("multiple", c_int),
        ("block", POINTER(FastBlock)), ("in_target", POINTER(c_int)), ("now", c_double),
    ]


class Fmi3Adapter(Structure):
    """fastloop.c's ``fmi3_adapter``: an FMI 3 Co-Simulation instance with its raw fmi3SetFloat64,
    fmi3GetFloat64 and fmi3DoStep, and what the last fmi3DoStep reported (``status``, its flags,
    ``last_successful_time`` [s])."""

    _fields_ = [
        ("instance", c_void_p), ("set_float64", c_void_p), ("get_float64", c_void_p), ("do_step", c_void_p),
        ("status", c_int), ("event_handling_needed", c_int), ("terminate_simulation", c_int),
        ("early_return", c_int), ("last_successful_time", c_double),
    ]


def fmi3_adapters(lib):
    """The adapters of fastloop.c (``cosim_fmi3_set_real``, ``cosim_fmi3_get_real``,
    ``cosim_fmi3_do_step``): FMI 3 calls with the FMI 2 signatures the loop calls, their first
    argument a pointer to an :class:`Fmi3Adapter`."""
    set_real, get_real, do_step = lib.cosim_fmi3_set_real, lib.cosim_fmi3_get_real, lib.cosim_fmi3_do_step
    set_real.argtypes = [c_void_p, POINTER(c_uint), c_size_t, POINTER(c_double)]
    get_real.argtypes = [c_void_p, POINTER(c_uint), c_size_t, POINTER(c_double)]
    do_step.argtypes = [c_void_p, c_double, c_double, c_int]
    for function in (set_real, get_real, do_step):
        function.restype = c_int
    return set_real, get_real, do_step


def _pointer(array, ctype, keep: list, shared: bool = False, size: int | None = None):
    """A pointer to the data of ``array``; ``shared`` arrays are the block's own state, which the
    loop must update in place (so they are checked, never copied)."""
    dtype = np.int32 if ctype is c_int else np.int64 if ctype is c_longlong else np.float64
    if array is None:
        array = np.zeros(0, dtype)
    if shared:
        if not (isinstance(array, np.ndarray) and array.dtype == dtype and array.flags.c_contiguous
                and array.flags.writeable):
            raise TypeError(f"a native block's state must be a writable contiguous {np.dtype(dtype)} array")
    else:
        array = np.ascontiguousarray(array, dtype=dtype)
    if size is not None and array.size != size:
        raise ValueError(f"a native block's array has {array.size} elements, not {size}")
    if array.size == 0:
        array = np.zeros(1, dtype)  # a valid address the loop never reads
    keep.append(array)
    return array.ctypes.data_as(POINTER(ctype))


def fast_block(native, u_set: np.ndarray, keep: list) -> FastBlock:
    """The C form of a block's :class:`~cosim.cosimulation.registry.Native` description, reading its
    inputs from ``u_set`` (the master's input vector of the block); ``keep`` holds every buffer
    the structure points into for as long as the loop runs."""
    if native.kind not in KINDS:
        raise ValueError(f"unknown native block kind '{native.kind}' (known: {', '.join(KINDS)})")
    n_in, n_out = native.u.size, native.y.size
    n_x = native.x.size if native.x is not None else 0
    b = FastBlock(kind=KINDS[native.kind], n_in=n_in, n_out=n_out, n_x=n_x)
    b.u, b.y = _pointer(native.u, c_double, keep, True), _pointer(native.y, c_double, keep, True)
    b.t = _pointer(native.t, c_double, keep, True, 1)
    b.u_set = _pointer(u_set, c_double, keep, True, n_in)
    if native.kind != "delay":
        b.D = _pointer(native.D, c_double, keep, size=n_out * n_in)
    window = native.window
    if window is not None:
        b.has_window, b.lo, b.hi, b.shift = 1, window.lo, window.hi, window.shift
        b.on = _pointer(window.on, c_double, keep, size=n_out)
        b.off = _pointer(window.off, c_double, keep, size=n_out)
    if native.kind == "linear":
        pairs = len(native.Ad)
        if n_x and native.which.size and not (0 <= native.which.min() and native.which.max() < pairs):
            raise ValueError("a native linear block's step refers to a missing pair of matrices")
        b.x = _pointer(native.x, c_double, keep, True)
        b.x_next = _pointer(np.zeros(n_x), c_double, keep)
        b.C = _pointer(native.C, c_double, keep, size=n_out * n_x)
        b.Ad = _pointer(native.Ad, c_double, keep, size=pairs * n_x * n_x)
        b.Bd = _pointer(native.Bd, c_double, keep, size=pairs * n_x * n_in)
        b.which = _pointer(native.which, c_int, keep)
    if native.kind == "delay":
        if (n_in, n_out) != (1, 1) or native.ring_t.size != native.ring_v.size or native.ring_t.size < 1:
            raise ValueError("a native delay has one input, one output and a ring of at least one sample")
        b.tau, b.capacity = native.tau, native.ring_t.size
        b.ring_t = _pointer(native.ring_t, c_double, keep, True)
        b.ring_v = _pointer(native.ring_v, c_double, keep, True)
        b.ring = _pointer(native.ring, c_longlong, keep, True, 2)
    keep.append(b)
    return b


@lru_cache(maxsize=1)
def library():
    """The compiled loop, or None where it cannot be had (no C compiler, no writable cache
    folder, a library that does not load): the master then steps in Python, with the same results."""
    lib = load(SOURCE, FLAGS)
    if lib is not None:
        lib.cosim_fast_run.restype = c_int
    return lib


#: Addresses of C functions already asked for, by id, with the function object itself (kept alive
#: while cached, so that its id is not reused); an FMU's functions are asked for at every run.
_ADDRESSES: dict[int, tuple[object, int]] = {}


def address(function) -> int:
    """The address of a ctypes function (cached: the cast costs more than a case's stepping set-up)."""
    found = _ADDRESSES.get(id(function))
    if found is not None and found[0] is function:
        return found[1]
    if len(_ADDRESSES) >= 1024:  # FMUs loaded and freed by the thousand: bounded
        _ADDRESSES.clear()
    value = cast(function, c_void_p).value
    _ADDRESSES[id(function)] = (function, value)
    return value
