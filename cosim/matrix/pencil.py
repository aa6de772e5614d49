"""The matrix pencil fit of :func:`cosim.matrix.classify.modal_fit` in C (``pencil.c``).

The C function runs classify.py's algorithm with the LAPACK routines numpy itself calls, taken
from numpy's own LAPACK library (the OpenBLAS numpy's wheels bundle, ILP64 with the symbol names
``scipy_dgesdd_64_`` ...; an LP64 ``dgesdd_`` elsewhere), so it needs nothing numpy does not
have. :func:`native` is None where that library or a C compiler cannot be had; classify.py then
fits with numpy. Both give the same modes to rounding (tests/test_matrix_pencil.py); the C one
costs a third as much per case. The settings both share (:data:`SMALL_PENCIL`, :data:`SMALL_ORDER`,
:data:`MODAL_SIGNIFICANT`) and the result type :class:`ModalFit` are defined here.
"""
from __future__ import annotations

from ctypes import CDLL, POINTER, Structure, addressof, c_double, c_int, c_size_t, c_void_p, cast
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from cosim.native import load, loaded_libraries

#: The pencil parameter tried first, kept when it finds at most :data:`SMALL_ORDER` modes, else the
#: fit is redone with n/3 columns: a small Hankel matrix makes the SVD, most of a case's CPU time,
#: cheap without changing a class; runs that fell keep n/3 (``observe``), as near a fall the signal
#: is no sum of modes (docs/benchmarks.md).
SMALL_PENCIL = 24
SMALL_ORDER = SMALL_PENCIL // 2 - 2
#: A mode counts when its largest contribution |a| max_k |z|^k is at least this fraction of the peak
#: of |x| (and 100 times the fit's RMS residual): smaller ones are fitting noise.
MODAL_SIGNIFICANT = 1e-6


@dataclass
class ModalFit:
    """Exponents of ``x(t) ~ sum_m a_m exp(lambda_m (t - t_m))`` fitted to uniform samples.

    ``rate`` [1/s] is the largest Re(lambda) of the significant modes, ``modes`` those exponents
    [1/s] (largest real part first), ``contributions`` their largest |a_m exp(lambda_m t)| over
    the window relative to the peak of |x|, ``residual`` the relative 2-norm error of the fit,
    ``start`` [s] the beginning of the fitted window."""

    rate: float
    modes: list
    contributions: list
    residual: float
    order: int
    start: float


SOURCE = Path(__file__).with_name("pencil.c")
#: -ffp-contract=off: no fused multiply-adds (the products round as numpy's do).
FLAGS = ["-O2", "-ffp-contract=off", "-shared", "-fPIC", "-std=c99"]
#: The LAPACK routines pencil.c calls.
ROUTINES = ("dgeqrf", "dgesdd", "dgesvd", "dgeev", "zgelsd")
#: Symbol names of LAPACK routines and their integer types: numpy's ILP64 OpenBLAS first; an
#: LP64 library only where its file name says nothing of 64-bit integers.
SYMBOLS = (("scipy_{}_64_", True), ("{}_64_", True), ("scipy_{}_", False), ("{}_", False))


class _Lapack(Structure):
    _fields_ = [(name, c_void_p) for name in ROUTINES]


class _Settings(Structure):
    _fields_ = [("max_samples", c_int), ("max_order", c_int), ("max_residual", c_double),
                ("small_pencil", c_int), ("small_order", c_int), ("significant", c_double)]


class _Fit(Structure):
    _fields_ = [("order", c_int), ("residual", c_double), ("start", c_double),
                ("modes_re", POINTER(c_double)), ("modes_im", POINTER(c_double)),
                ("contributions", POINTER(c_double))]


def numpy_lapack() -> tuple[CDLL, str, bool] | None:
    """(library, symbol format, 64-bit integers) of the LAPACK numpy's linear algebra calls, found
    among the libraries loaded in this process (``/proc/self/maps``, Linux), or None."""
    import numpy.linalg  # noqa: F401  (loads numpy's LAPACK)

    for path in loaded_libraries("openblas|lapack|blas"):
        try:
            lib = CDLL(path)
        except OSError:
            continue
        for pattern, ilp64 in SYMBOLS:
            if not ilp64 and "64" in Path(path).name:
                continue  # an ILP64 library may export the plain names: never guess the integer size
            if all(hasattr(lib, pattern.format(r)) for r in ROUTINES):
                return lib, pattern, ilp64
    return None


class NativePencil:
    """pencil.c with numpy's LAPACK: :meth:`modal_fit` as classify.modal_fit."""

    def __init__(self, lib: CDLL, lapack: CDLL, pattern: str):
        self._function = lib.cosim_modal_fit
        self._function.restype = c_int
        # addresses as integers: a case calls this once, and ctypes' pointer objects cost more than the fit's set-up
        self._function.argtypes = [c_void_p, c_void_p, c_void_p, c_void_p, c_size_t, c_int, c_void_p]
        self._lapack = _Lapack(*[cast(getattr(lapack, pattern.format(r)), c_void_p).value for r in ROUTINES])
        self._lapack_address = addressof(self._lapack)
        self._small = (SMALL_PENCIL, SMALL_ORDER, MODAL_SIGNIFICANT)
        self._settings = {}
        self._fit_class = ModalFit

    def _prepared(self, max_samples: int, max_order: int, max_residual: float):
        """(settings, result structure, its arrays) for these limits, made once."""
        key = (max_samples, max_order, max_residual)
        found = self._settings.get(key)
        if found is None:
            small_pencil, small_order, significant = self._small
            settings = _Settings(int(max_samples), int(max_order), float(max_residual), int(small_pencil),
                                 int(small_order), float(significant))
            out = np.empty((3, max(1, int(max_order))))
            row = POINTER(c_double)
            fit = _Fit(0, 0.0, 0.0, out[0].ctypes.data_as(row), out[1].ctypes.data_as(row),
                       out[2].ctypes.data_as(row))
            found = self._settings[key] = (settings, addressof(settings), fit, addressof(fit), out)
        return found

    def modal_fit(self, t: np.ndarray, x: np.ndarray, max_samples: int, max_order: int, max_residual: float,
                  small: bool):
        """classify.modal_fit of float arrays ``t`` and ``x`` of one length: a ModalFit or None."""
        _, settings, fit, fit_address, out = self._prepared(max_samples, max_order, max_residual)
        t = np.ascontiguousarray(t, dtype=float)
        x = np.ascontiguousarray(x, dtype=float)
        status = self._function(self._lapack_address, settings, t.ctypes.data, x.ctypes.data, min(t.size, x.size),
                                1 if small else 0, fit_address)
        if status < 0:
            raise MemoryError("the matrix pencil fit ran out of memory")
        if status == 0:
            return None
        k = fit.order
        re, im = out[0, :k].tolist(), out[1, :k].tolist()
        return self._fit_class(rate=re[0], modes=[complex(a, b) for a, b in zip(re, im)],
                               contributions=out[2, :k].tolist(), residual=fit.residual, order=k, start=fit.start)


@lru_cache(maxsize=1)
def native() -> NativePencil | None:
    """pencil.c compiled for numpy's LAPACK, or None where either cannot be had."""
    found = numpy_lapack()
    if found is None:
        return None
    lapack, pattern, ilp64 = found
    lib = load(SOURCE, [*FLAGS, *(["-DLAPACK_ILP64"] if ilp64 else [])])
    if lib is None:
        return None
    return NativePencil(lib, lapack, pattern)
