"""The tape of the local variables (cosim/compiler/tape.py, interpreted by cosim/runtime/cosim_tape.c)
computes the same bits as CasADi's generated C that it replaces, for every operation it knows,
on ordinary and special values (signed zeros, infinities, NaN, tiny and huge numbers)."""
from __future__ import annotations

import ctypes
import itertools
import shutil
import subprocess

import casadi as ca
import numpy as np
import pytest

from cosim.compiler import tape
from cosim.compiler.codegen import RUNTIME_DIR
from cosim.errors import BuildError

# the quick run (-m 'not slow') leaves this module out: its tests build, compile or run FMUs
pytestmark = [pytest.mark.slow, pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")]

SPECIAL = [0.0, -0.0, 1.0, -1.0, 0.5, -2.5, 3.0, 1e-300, -1e300, np.inf, -np.inf, np.nan]


def _all_operations():
    """An SX function of (a, b, c) whose instructions use every operation a tape knows, and the
    indices of its fmin and fmax entries."""
    x = ca.SX.sym("x", 3)
    a, b, c = x[0], x[1], x[2]
    exprs = [a + b, a - b, a * b, a / b, -a, ca.exp(a), ca.log(a), a ** b, ca.constpow(a, 2.5), ca.sqrt(a), a ** 2,
             ca.sin(a), ca.cos(a), ca.tan(a), ca.asin(a), ca.acos(a), ca.atan(a), ca.atan2(a, b),
             ca.sinh(a), ca.cosh(a), ca.tanh(a), ca.asinh(a), ca.acosh(a), ca.atanh(a),
             a < b, a <= b, a == b, a != b, ca.logic_not(a), ca.logic_and(a, b), ca.logic_or(a, b),
             ca.if_else(a > 0, b, c), ca.floor(a), ca.ceil(a), ca.fmod(a, b), ca.remainder(a, b), ca.fabs(a),
             ca.sign(a), ca.copysign(a, b), ca.erf(a), ca.log1p(a), ca.expm1(a),
             ca.hypot(a, b), 1 / a, a * 0.1 + 1e-310, ca.inf * a, np.nan + c, ca.fmin(a, b), ca.fmax(a, b)]
    f = ca.Function("f", [x], [ca.vertcat(*exprs)])
    # the derivatives add TWICE, SQ, INV and ASSIGN-style instructions
    g = ca.Function("g", [x], [ca.densify(ca.vertcat(f(x), ca.jacobian(f(x), x)[:, 0]))])
    return g, [len(exprs) - 2, len(exprs) - 1]


def _compile(tmp_path, name: str, sources: list) -> ctypes.CDLL:
    """The C files ``sources`` as the shared library ``name``, without optimization (as eval_locals was)."""
    lib = tmp_path / f"{name}.so"
    subprocess.run(["gcc", "-std=c99", "-fPIC", "-shared", "-w", "-O0", f"-I{RUNTIME_DIR}", *map(str, sources),
                    "-o", str(lib), "-lm"], check=True)
    return ctypes.CDLL(str(lib))


def _inputs() -> np.ndarray:
    rng = np.random.default_rng(3)
    grid = [(a, b, c) for a, b in itertools.product(SPECIAL, SPECIAL) for c in (SPECIAL[4],)]
    return np.vstack([np.array(grid), rng.normal(0.0, 2.0, (200, 3)), rng.uniform(-1.0, 1.0, (200, 3))])


def test_every_operation_gives_the_bits_of_casadis_generated_c(tmp_path):
    f, fmin_fmax = _all_operations()
    known = set(tape.OPERATIONS) | {ca.OP_INPUT, ca.OP_OUTPUT, ca.OP_CONST}
    used = {f.instruction_id(k) for k in range(f.n_instructions())}
    assert used <= known
    assert len(used) >= 45, "the test function exercises (nearly) every operation of the tape"
    # the reference: CasADi's own C
    generator = ca.CodeGenerator("reference.c", {"casadi_real": "double", "casadi_int": "long long"})
    generator.add(f)
    generator.generate(str(tmp_path) + "/")
    reference = _compile(tmp_path, "reference", [tmp_path / "reference.c"])
    taped_c = tmp_path / "taped.c"
    taped_c.write_text('#include "cosim_tape.h"\n' + tape.tape_tables(f, "t") +
                       "int run(const double *x, double *z) { const double *arg[1] = {x}; "
                       "return cosim_tape_run(&t, arg, z); }\n")
    taped = _compile(tmp_path, "taped", [taped_c, RUNTIME_DIR / "cosim_tape.c"])
    n = f.nnz_out(0)
    D = ctypes.POINTER(ctypes.c_double)
    for x in _inputs():
        xin = np.ascontiguousarray(x, dtype=float)
        expected, got = np.full(n, 7.0), np.full(n, 7.0)
        arg = (D * 1)(xin.ctypes.data_as(D))
        res = (D * 1)(expected.ctypes.data_as(D))
        iw = (ctypes.c_longlong * max(1, f.sz_iw()))()
        w = (ctypes.c_double * max(1, f.sz_w()))()
        assert reference.g(arg, res, iw, w, 0) == 0
        assert taped.run(xin.ctypes.data_as(D), got.ctypes.data_as(D)) == 0
        differ = got.view(np.uint64) != expected.view(np.uint64)
        # C leaves open which zero fmin(0, -0) and fmax(0, -0) return, and gcc, to which fmin and fmax
        # are commutative, passes the operands of a call in either order: the bits of those ties
        # differ between two compilations of CasADi's own C too
        tie = (got == 0) & (expected == 0) & np.isin(np.arange(n), fmin_fmax)
        assert not (differ & ~tie).any(), f"inputs {x}: entries {np.flatnonzero(differ & ~tie)} differ"


def test_constants_read_back_as_the_same_double():
    for value in (0.1, -0.0, 1e-310, 5e-324, 1.7976931348623157e308, np.pi, 1 / 3):
        text, special = tape._constant(value)
        assert special == 0 and float(text) == value and np.signbit(float(text)) == np.signbit(value)
    # what a static table of every C compiler cannot hold is made by the interpreter
    assert [tape._constant(v)[1] for v in (np.inf, -np.inf, np.nan)] == [1, 2, 3]


def test_a_sparse_output_is_refused():
    x = ca.SX.sym("x", 2)
    f = ca.Function("f", [x], [ca.vertcat(x[0], ca.SX(1, 1))])  # a structural zero: res[nz] != res[row]
    with pytest.raises(ValueError, match="dense"):
        tape.tape_tables(f, "t")


def test_an_operation_no_tape_has_is_named():
    x = ca.SX.sym("x")
    f = ca.Function("f", [x], [ca.erfinv(x) + 1])
    with pytest.raises(BuildError, match="ERFINV"):
        tape.tape_tables(f, "t", "Pkg.Model")
