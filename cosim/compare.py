"""`cosim compare`: an FMU's linearization against the analytic twin of its model.

For every input -> output pair both transfer functions are reduced to minimal realizations and
their poles, zeros and gain (the ``k`` of the zero-pole-gain form) compared; the eigenvalues of
the full A matrices are compared as sets too. Roots are matched by minimum total distance.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np
from scipy.optimize import linear_sum_assignment
from scipy.signal import ss2zpk

MINREAL_TOL = 1e-7  # pole-zero cancellation tolerance of the minimal realizations


def root_set_error(found, expected) -> float:
    """Largest relative distance between two root sets matched one to one (inf if sizes differ).

    Each distance is relative to the magnitude of the expected root, floored at 1e-6 times the
    largest expected magnitude (roots at the origin are compared absolutely on that scale)."""
    found, expected = np.asarray(found, complex), np.asarray(expected, complex)
    if found.size != expected.size:
        return float("inf")
    if found.size == 0:
        return 0.0
    cost = np.abs(found[:, None] - expected[None, :])
    rows, cols = linear_sum_assignment(cost)
    floor = max(1e-6 * np.max(np.abs(expected)), 1e-12)
    return float(np.max(cost[rows, cols] / np.maximum(np.abs(expected[cols]), floor)))


def _zpk(sys):
    """Zeros, poles and gain of a SISO StateSpace after removing cancelling pole-zero pairs."""
    import control

    reduced = control.minreal(sys, tol=MINREAL_TOL, verbose=False)
    if reduced.nstates == 0:
        return np.zeros(0), np.zeros(0), float(np.squeeze(reduced.D))
    z, p, k = ss2zpk(reduced.A, reduced.B, reduced.C, reduced.D)
    z = z[np.isfinite(z)]
    return z, p, float(k)


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
            z, p, k = _zpk(found[o, i])
            ez, ep, ek = _zpk(expected[eo, ei])
            scale = max(abs(ek), 1e-300)
            result.pairs.append(PairComparison(
                u, y, list(p), list(z), k, list(ep), list(ez), ek,
                root_set_error(p, ep), root_set_error(z, ez),
                0.0 if k == ek else abs(k - ek) / scale))
    return result


def parse_speeds(text: str) -> list[float]:
    """``A:B:STEP`` (inclusive) or a comma-separated list of speeds in m/s."""
    if ":" in text:
        try:
            start, stop, step = (float(v) for v in text.split(":"))
        except ValueError:
            raise ValueError(f"--speeds expects A:B:STEP, got '{text}'") from None
        if step <= 0 or stop < start:
            raise ValueError(f"--speeds {text}: need STEP > 0 and B >= A")
        n = int(np.floor((stop - start) / step + 1e-9)) + 1
        return [round(start + k * step, 12) for k in range(n)]
    try:
        return [float(v) for v in text.split(",")]
    except ValueError:
        raise ValueError(f"--speeds expects A:B:STEP or a list, got '{text}'") from None


def format_table(comparisons: list[Comparison], speed_name: str) -> str:
    """One line per operating point and transfer function."""
    lines = [f"{speed_name + ' [m/s]':>10}  {'transfer function':<22} {'poles':>9} {'zeros':>9} {'gain':>9}"]
    for c in comparisons:
        v = c.parameters.get(speed_name, float("nan"))
        lines.append(f"{v:10.4g}  {'eigenvalues of A':<22} {c.eigenvalue_error:9.1e}")
        for p in c.pairs:
            lines.append(f"{'':10}  {p.input + ' -> ' + p.output:<22} {p.pole_error:9.1e} {p.zero_error:9.1e} "
                         f"{p.gain_error:9.1e}")
    worst = max((c.error for c in comparisons), default=0.0)
    lines.append(f"largest relative error: {worst:.2e}")
    return "\n".join(lines)
