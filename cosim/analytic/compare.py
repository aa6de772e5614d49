"""Two linear systems compared: the arithmetic of `cosim compare` (an FMU's linearization against
the analytic twin of its model, :func:`cosim.bicycle.compare.compare_model`).

For every input -> output pair both transfer functions are reduced to minimal realizations and
their poles, zeros and gain (the ``k`` of the zero-pole-gain form) compared; the eigenvalues of
the full A matrices are compared as sets too. Roots are matched by minimum total relative distance; roots at the origin by number.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np
from scipy.optimize import linear_sum_assignment


ORIGIN = 1e-6  # roots with |r| <= ORIGIN * max(1, max |roots|) are roots at the origin (integrators)
REDUCTION_TOL = 1e-10  # relative tolerance of the Krylov reduction to a minimal realization


def _krylov_basis(A: np.ndarray, v: np.ndarray, tol: float) -> np.ndarray:
    """Orthonormal basis of the Krylov space of (A, v) (Arnoldi with re-orthogonalization)."""
    n = A.shape[0]
    scale = max(np.linalg.norm(A, 2), 1e-300)
    norm = np.linalg.norm(v)
    if norm == 0:
        return np.zeros((n, 0))
    Q = [v / norm]
    while len(Q) < n:
        w = A @ Q[-1]
        for _ in range(2):
            for q in Q:
                w = w - (q @ w) * q
        if np.linalg.norm(w) <= tol * scale:
            break
        Q.append(w / np.linalg.norm(w))
    return np.column_stack(Q)


def _reachable(A: np.ndarray, start: np.ndarray) -> np.ndarray:
    """States reachable in the graph of the non-zero entries of A (edge j -> i if A[i, j] != 0)."""
    seen = start != 0
    while True:
        more = seen | np.any((A != 0) & seen[None, :], axis=1)
        if np.array_equal(more, seen):
            return seen
        seen = more


def _reduce(A, b, c, tol):
    """Remove the unreachable states of (A, b) (basis change only if the dimension drops)."""
    Q = _krylov_basis(A, b, tol)
    if Q.shape[1] == A.shape[0]:
        return A, b, c
    return Q.T @ A @ Q, Q.T @ b, c @ Q


def minimal_zpk(sys, tol: float = REDUCTION_TOL):
    """Zeros, poles and gain of a SISO system after removal of uncontrollable and unobservable
    states (no slycot needed): first structurally (states not reachable from the input or not
    reaching the output through exact non-zeros, a principal submatrix, no rounding), then by
    orthogonal Krylov reduction if the rest is still not minimal. The gain is the first non-zero
    Markov parameter ``c A^(r-1) b`` (``d`` if r = 0), r = number of poles - number of zeros."""
    A, b, c, d = np.asarray(sys.A, float), np.asarray(sys.B, float)[:, 0], np.asarray(sys.C, float)[0], \
        float(np.asarray(sys.D)[0, 0])
    keep = _reachable(A, b) & _reachable(A.T, c)
    A, b, c = A[np.ix_(keep, keep)], b[keep], c[keep]
    A1, b1, c1 = _reduce(A, b, c, tol)
    At, ct, bt = _reduce(A1.T, c1, b1, tol)
    Am, bm, cm = At.T, bt, ct
    n = Am.shape[0]
    poles = np.linalg.eigvals(Am) if n else np.zeros(0, complex)
    if n:
        from scipy.linalg import eigvals

        M = np.block([[Am, bm[:, None]], [cm[None, :], np.array([[d]])]])
        N = np.block([[np.eye(n), np.zeros((n, 1))], [np.zeros((1, n + 1))]])
        alpha, beta = eigvals(M, N, homogeneous_eigvals=True)
        finite = np.abs(beta) > 1e-12 * np.abs(alpha)  # the pencil's infinite eigenvalues are no zeros
        zeros = alpha[finite] / beta[finite]
    else:
        zeros = np.zeros(0, complex)
    r = n - len(zeros)
    gain = d if r == 0 else float(cm @ np.linalg.matrix_power(Am, r - 1) @ bm)
    return zeros, poles, gain


def root_set_error(found, expected) -> float:
    """Largest relative distance of two root sets matched one to one; roots at the origin
    (integrators) are compared by number. inf if the sets do not correspond."""
    found, expected = np.asarray(found, complex), np.asarray(expected, complex)
    if found.size != expected.size:
        return math.inf
    if found.size == 0:
        return 0.0
    threshold = ORIGIN * max(1.0, np.max(np.abs(expected)))
    f0, e0 = np.abs(found) <= threshold, np.abs(expected) <= threshold
    if f0.sum() != e0.sum():
        return math.inf
    f, e = found[~f0], expected[~e0]
    if f.size == 0:
        return 0.0
    cost = np.abs(f[:, None] - e[None, :]) / np.abs(e[None, :])
    rows, cols = linear_sum_assignment(cost)
    return float(np.max(cost[rows, cols]))


@dataclass
class PairComparison:
    """One input -> output transfer function at one operating point."""

    input: str
    output: str
    poles: list
    zeros: list
    gain: float
    expected_poles: list
    expected_zeros: list
    expected_gain: float
    pole_error: float
    zero_error: float
    gain_error: float

    @property
    def error(self) -> float:
        return max(self.pole_error, self.zero_error, self.gain_error)


@dataclass
class Comparison:
    """FMU versus analytic model at one parameter set."""

    model: str
    parameters: dict
    eigenvalues: list
    expected_eigenvalues: list
    eigenvalue_error: float
    pairs: list[PairComparison] = field(default_factory=list)
    speed: float | None = None  # forward speed [m/s] of the operating point

    @property
    def error(self) -> float:
        return max([self.eigenvalue_error] + [p.error for p in self.pairs])

    def to_dict(self) -> dict:
        def complex_list(values):
            return [[float(np.real(v)), float(np.imag(v))] for v in values]

        d = asdict(self)
        d["eigenvalues"] = complex_list(self.eigenvalues)
        d["expected_eigenvalues"] = complex_list(self.expected_eigenvalues)
        for pair, src in zip(d["pairs"], self.pairs):
            for key in ("poles", "zeros", "expected_poles", "expected_zeros"):
                pair[key] = complex_list(getattr(src, key))
        d["error"] = self.error
        return d


def compare_systems(model: str, parameters: dict, found, expected) -> Comparison:
    """Compare two python-control StateSpace systems with the same named inputs and outputs."""
    missing = [n for n in expected.input_labels if n not in found.input_labels] + \
              [n for n in expected.output_labels if n not in found.output_labels]
    if missing:
        raise ValueError(f"{model}: the FMU lacks the analytic model's signals: {', '.join(missing)}")
    eig, expected_eig = np.linalg.eigvals(found.A), np.linalg.eigvals(expected.A)
    result = Comparison(model, parameters, list(eig), list(expected_eig), root_set_error(eig, expected_eig))
    for u in expected.input_labels:
        for y in expected.output_labels:
            i, o = found.input_labels.index(u), found.output_labels.index(y)
            ei, eo = expected.input_labels.index(u), expected.output_labels.index(y)
            z, p, k = minimal_zpk(found[o, i])
            ez, ep, ek = minimal_zpk(expected[eo, ei])
            scale = max(abs(ek), 1e-300)
            result.pairs.append(PairComparison(
                u, y, list(p), list(z), k, list(ep), list(ez), ek,
                root_set_error(p, ep), root_set_error(z, ez),
                0.0 if k == ek else abs(k - ek) / scale))
    return result


def format_table(comparisons: list[Comparison], speed_name: str) -> str:
    """One line per operating point and transfer function."""
    lines = [f"{speed_name + ' [m/s]':>10}  {'transfer function':<22} {'poles':>9} {'zeros':>9} {'gain':>9}"]
    for c in comparisons:
        v = c.speed if c.speed is not None else c.parameters.get(speed_name, float("nan"))
        lines.append(f"{v:10.4g}  {'eigenvalues of A':<22} {c.eigenvalue_error:9.1e}")
        for p in c.pairs:
            lines.append(f"{'':10}  {p.input + ' -> ' + p.output:<22} {p.pole_error:9.1e} {p.zero_error:9.1e} "
                         f"{p.gain_error:9.1e}")
    worst = max((c.error for c in comparisons), default=0.0)
    lines.append(f"largest relative error: {worst:.2e}")
    return "\n".join(lines)
