"""The matrix pencil fit in C (cosim/matrix/pencil.c) against classify.py's numpy version: the
same decision (fitted or not, the window, the number of modes) and the same modes to rounding."""
from __future__ import annotations

import math

import numpy as np
import pytest

from cosim.matrix import classify, pencil

T = np.round(np.arange(1001) * 0.01, 10)


def _modes(rng, count, t):
    return sum(rng.normal() * np.exp(0.4 * rng.normal() * t) * np.cos(rng.uniform(0, 8) * t + rng.uniform(0, 3))
               for _ in range(count))


SIGNALS = {
    "weave-and-capsize": lambda: (T, 0.01 * np.exp(-0.5 * T) * np.sin(5 * T) + 1e-4 * np.exp(0.03 * T)),
    "slow-oscillation": lambda: (T, 0.01 * np.exp(0.308 * T) * np.cos(0.29 * T + 0.3)),
    "growing-and-decaying": lambda: (T, np.exp(0.3 * T) * np.cos(T) + 0.5 * np.exp(-T)),
    "12-modes": lambda: (T, sum(np.exp((-0.1 - 0.15 * k) * T) * np.cos((1 + 0.9 * k) * T + 0.3 * k)
                                for k in range(6))),
    "18-modes": lambda: (T, sum(np.exp((-0.1 - 0.15 * k) * T) * np.cos((1 + 0.9 * k) * T + 0.3 * k)
                                for k in range(9))),
    "fell-after-3s": lambda: (T[:301], 0.01 * np.exp(1.5 * T[:301]) * np.cos(4 * T[:301])
                              + 0.002 * np.exp(-3 * T[:301])),
    "30-samples": lambda: (np.arange(30) * 0.03, np.exp(-0.2 * np.arange(30) * 0.03)),
    "2001-samples-decimated": lambda: (np.round(np.arange(2001) * 0.01, 10),
                                       np.exp(-0.2 * np.arange(2001) * 0.01) * np.cos(2 * np.arange(2001) * 0.01)),
    "last-short-step": lambda: (np.append(T, 10.004), np.append(np.exp(-0.3 * T) * np.sin(3 * T), 0.0)),
    "noisy": lambda: (T, 0.01 * np.exp(-0.3 * T) * np.sin(5 * T)
                      + 1e-4 * np.random.default_rng(1).standard_normal(T.size)),
    "clipped": lambda: (T, np.clip(0.01 * np.exp(0.2 * T) * np.sin(5 * T), -0.02, 0.02)),
    "switched-on": lambda: (T, np.where(T < 7.0, 0.0, 0.01 * np.exp(0.2 * (T - 7.0)) * np.sin(5 * (T - 7.0)))),
    "rectified": lambda: (T, np.abs(0.01 * np.exp(-0.2 * T) * np.sin(5 * T))),
    "sawtooth": lambda: (T, (T % 1.0) - 0.5),
    "constant": lambda: (T, np.full(T.size, 0.01)),
    "zero": lambda: (T, np.zeros(T.size)),
    "non-finite": lambda: (T, np.where(T > 5, np.inf, np.sin(T))),
    "too-short": lambda: (T[:20], np.sin(T[:20])),
    "irregular-grid": lambda: (np.cumsum(np.random.default_rng(2).uniform(0.005, 0.015, 1001)), np.sin(T)),
}


@pytest.fixture(scope="module")
def native():
    fitter = pencil.native()
    if fitter is None:
        pytest.fail("the C matrix pencil cannot be had here (no C compiler or no LAPACK of numpy found)")
    return fitter


def _compare(t, x, small, native) -> classify.ModalFit | None:
    reference = classify.modal_fit(t, x, small=small, native=False)
    fit = native.modal_fit(t, x, classify.MODAL_SAMPLES, classify.MODAL_MAX_ORDER, classify.MODAL_RESIDUAL, small)
    assert (fit is None) == (reference is None)
    if fit is None:
        return None
    assert fit.order == reference.order and fit.start == reference.start
    assert fit.rate == pytest.approx(reference.rate, abs=1e-8 * max(1.0, abs(reference.rate)))
    # the same set of modes (conjugates with equal real parts may come in either order)
    for mode in reference.modes:
        assert min(abs(mode - m) for m in fit.modes) <= 1e-6 * max(1.0, abs(mode))
    assert fit.residual == pytest.approx(reference.residual, rel=1e-3, abs=1e-8)  # at the rounding floor
    for a, b in zip(sorted(fit.contributions), sorted(reference.contributions)):
        assert a == pytest.approx(b, rel=1e-6, abs=1e-12)
    return fit


@pytest.mark.parametrize("small", [True, False], ids=["small-pencil-first", "n/3-pencil"])
@pytest.mark.parametrize("name", list(SIGNALS))
def test_c_fit_equals_numpy_fit(name, small, native):
    t, x = SIGNALS[name]()
    fit = _compare(t, x, small, native)
    refused = {"clipped", "noisy", "switched-on", "rectified", "zero", "non-finite", "too-short", "irregular-grid"}
    if name != "sawtooth":  # a finite sum of undamped modes, which may be fitted or refused (test_matrix_robustness)
        assert (fit is None) == (name in refused)


@pytest.mark.slow
def test_c_fit_equals_numpy_fit_on_random_sums_of_modes(native):
    """300 random sums of one to five damped oscillations, both pencils."""
    rng = np.random.default_rng(0)
    found = 0
    for _ in range(300):
        x = _modes(rng, int(rng.integers(1, 6)), T)
        for small in (True, False):
            found += _compare(T, x, small, native) is not None
    assert found > 500  # nearly all are sums of modes the fit accepts


def test_modal_fit_uses_the_c_fit(native):
    t, x = SIGNALS["weave-and-capsize"]()
    assert classify.modal_fit(t, x) == native.modal_fit(t, x, classify.MODAL_SAMPLES, classify.MODAL_MAX_ORDER,
                                                          classify.MODAL_RESIDUAL, True)


def test_numpy_lapack_is_found():
    """numpy's wheels bundle an ILP64 OpenBLAS (symbols scipy_dgesdd_64_ ...): pencil.c calls it."""
    found = pencil.numpy_lapack()
    assert found is not None
    lib, pattern, ilp64 = found
    if "scipy-openblas" in str(np.__config__.CONFIG["Build Dependencies"]["lapack"].get("name")):
        assert pattern == "scipy_{}_64_" and ilp64
    assert all(hasattr(lib, pattern.format(r)) for r in pencil.ROUTINES)


def test_exact_growth_rate_with_either_fit(native):
    """An exact sum of modes: both fits return its largest real part to 1e-9 1/s."""
    x = 0.01 * np.exp(-0.7 * T) * np.cos(4.2 * T) + 0.003 * np.exp(-0.05 * T)
    for fit in (classify.modal_fit(T, x, native=False), classify.modal_fit(T, x)):
        assert fit.rate == pytest.approx(-0.05, abs=1e-9)
        assert any(math.isclose(m.imag, 4.2, abs_tol=1e-7) for m in fit.modes)
