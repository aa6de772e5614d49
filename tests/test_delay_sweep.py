"""Rider delay: the physical loop (exact delay equation) against the co-simulated loop (rider delay
plus the master's coupling lag); the stability boundary found two independent ways; the root
finder of the delay equation checked on x' = -a x(t - tau), whose roots are Lambert W values; the
p*tau limits of the paper."""
from __future__ import annotations

import math

import control
import numpy as np
import pytest
from scipy.special import lambertw

from cosim.analytic.delay import (
    characteristic_function,
    characteristic_roots,
    critical_delay,
    crossing_delays,
    feedback_matrices,
    first_crossing_delay,
    spectral_abscissa,
)
from cosim.studies.delay_sweep import (
    MODEL,
    coupling_delay,
    format_cases,
    largest_stabilizable_p_tau,
    loop,
    main,
    physical_max_real,
    stability_boundary,
    sweep,
)

# s; the physical loop loses stability near 0.096 s for k2 = 1, the co-simulated one (7.5 ms of
# coupling lag at the 5 ms step) near 0.088 s: 0.09 lies between the two.
TAUS = [0.0, 0.04, 0.06, 0.08, 0.09, 0.1, 0.12, 0.3, 0.8]
STEP = 0.005
# Co-simulated growth rate vs largest real part of its own prediction: 0.01 1/s plus 2 % (the
# per-window peak estimate of a fast-decaying oscillation is biased by up to about 1 %).
GROWTH_ABS, GROWTH_REL = 0.01, 0.02


@pytest.fixture(scope="module")
def cases(fmus):
    return sweep(fmus[MODEL], TAUS, k2=1.0, V=5.0, step=STEP)


@pytest.fixture(scope="module")
def boundary():
    return stability_boundary(k2=1.0, V=5.0)


# --- the co-simulated loop -------------------------------------------------------------------------

def test_every_delay_agrees(cases):
    assert all(c.agrees for c in cases), [(c.tau, c.predicted, c.observed) for c in cases]
    assert {c.predicted for c in cases} >= {"stable", "unstable"}  # the sweep crosses the boundary


def test_growth_rates_match(cases):
    for c in cases:
        if c.observed != "fell":
            tolerance = GROWTH_ABS + GROWTH_REL * abs(c.predicted_max_real)
            assert c.growth == pytest.approx(c.predicted_max_real, abs=tolerance), c


# --- the physical loop and its boundary ------------------------------------------------------------

def test_boundary_two_ways(boundary):
    """The first delay with a root on the imaginary axis (root finding on the delay equation) equals
    phase margin / crossover frequency (frequency response), and python-control's margins agree."""
    assert boundary.by_roots == pytest.approx(boundary.by_crossing, rel=1e-8)
    A, B, C, K = loop({"V": 5.0}, 1.0)
    _, pm, _, wc = control.margin(control.ss(A, B, C, 0) * -K)
    assert math.radians(pm) / wc == pytest.approx(boundary.by_crossing, rel=1e-6)
    assert boundary.frequency == pytest.approx(wc, rel=1e-6)
    # the delay margin for k2 = 1 at 5 m/s, against the known value to 3 digits
    assert round(boundary.by_roots, 3) == 0.096


def test_boundary_is_a_crossing(boundary):
    """Just below the boundary every root is in the left half plane, just above a pair is in the
    right one, and at the boundary i w_c is a root of the exact characteristic function."""
    A, E = feedback_matrices(*loop({"V": 5.0}, 1.0))
    assert spectral_abscissa(A, E, boundary.by_roots - 1e-4) < 0 < spectral_abscissa(A, E, boundary.by_roots + 1e-4)
    f = characteristic_function(A, E, boundary.by_roots, 1j * boundary.frequency)
    scale = abs(characteristic_function(A, E, boundary.by_roots, 2j * boundary.frequency))
    assert abs(f) < 1e-9 * scale


def test_physical_verdicts(cases, boundary):
    """The physical column: stable exactly below the boundary; its co-simulated twin is the physical
    loop with the delay tau + lag; at tau = 0.09 s the physical loop is stable, the co-simulated one
    (and the co-simulation) not."""
    for c in cases:
        assert c.physical == ("stable" if c.tau < boundary.by_roots else "unstable"), c
        assert c.predicted_max_real == pytest.approx(physical_max_real({"V": 5.0}, 1.0, c.tau + c.lag), abs=1e-9)
        assert c.lag == pytest.approx(coupling_delay(c.tau, STEP))
    at_009 = next(c for c in cases if c.tau == 0.09)
    assert at_009.physical == "stable" and at_009.physical_max_real < -0.05
    assert at_009.predicted == "unstable" and at_009.observed == "unstable"
    table = format_cases(cases, boundary)
    row = next(line for line in table.splitlines() if line.split()[:1] == ["0.090"])
    assert row.split()[3:5] == ["stable", f"{at_009.lag:.4f}"] and "unstable" in row.split()[5:8]


def test_physical_roots_match_pade():
    """The exact rightmost root and the closed loop with a [10/10] Padé delay agree (a check of the
    state-space form of G_phi_delta, independent of the delay-equation solver)."""
    A, B, C, K = loop({"V": 5.0}, 1.0)
    plant = control.ss(A, B, C, 0)
    for tau in (0.03, 0.09, 0.12):
        pade = control.tf(*control.pade(tau, 10))
        poles = control.feedback(plant * pade * -K, 1).poles()
        assert np.max(poles.real) == pytest.approx(physical_max_real({"V": 5.0}, 1.0, tau), abs=1e-6), tau


def test_cli_prints_both_loops(fmus, capsys, boundary):
    assert main(["--taus", "0.09", "--fmu", str(fmus[MODEL])]) == 0
    out = capsys.readouterr().out
    assert "physical loop (tau)" in out and "co-simulated loop (tau + coupling lag)" in out
    assert f"tau < {boundary.by_roots:.5f} s" in out and f"= {boundary.by_crossing:.5f} s" in out


@pytest.mark.parametrize("argv, message", [
    (["--step", "0"], "--step must be a positive time"),
    (["--taus", "-0.1"], "--taus must be delays >= 0 s"),
    (["--k2", "0.2"], "k2 = 0.2 does not stabilize the bicycle at V = 5 m/s"),
], ids=["step", "negative-tau", "unstabilizing-gain"])
def test_cli_bad_input(argv, message, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    assert exit_.value.code == 2 and message in capsys.readouterr().err


# --- the root finder on a known case: x' = -a x(t - tau) ---------------------------------------------

@pytest.mark.parametrize("a, tau", [(1.0, 0.2), (1.0, 1.0), (1.0, 1.5), (2.0, 1.0), (1.0, 3.0)],
                         ids=["real-root", "damped", "near-boundary", "unstable", "many-roots"])
def test_roots_are_lambert_w(a, tau):
    """The roots of s + a exp(-s tau) = 0 are W_k(-a tau) / tau; with sigma 1.5 1/s to the left of
    the rightmost root every such root is found (no more, no fewer) to 1e-10."""
    exact = np.array([lambertw(-a * tau, k) / tau for k in range(-200, 201)])
    sigma = np.max(exact.real) - 1.5
    expected = exact[exact.real >= sigma]
    found = characteristic_roots([[0.0]], [[-a]], tau, sigma=sigma)
    assert len(found) == len(expected)
    assert max(np.min(np.abs(expected - z)) for z in found) < 1e-10
    assert found[0].real == pytest.approx(np.max(exact.real), abs=1e-12)


def test_lambert_w_boundary_two_ways():
    """x' = -a x(t - tau) loses stability at a tau = pi / 2, by both methods."""
    a = 2.0
    assert critical_delay([[0.0]], [[-a]], tau_max=3.0) == pytest.approx(math.pi / (2 * a), rel=1e-9)
    assert first_crossing_delay([[0.0]], [[1.0]], [[1.0]], -a) == pytest.approx(math.pi / (2 * a), rel=1e-12)
    (crossing,) = crossing_delays([[0.0]], [[1.0]], [[1.0]], -a)
    assert crossing.frequency == pytest.approx(a) and crossing.phase_margin == pytest.approx(math.pi / 2)


def test_bad_delay_is_refused():
    with pytest.raises(ValueError, match="tau must be a finite delay >= 0 s"):
        characteristic_roots([[0.0]], [[-1.0]], -0.1)


# --- the paper's p tau ---------------------------------------------------------------------------

def test_p_tau_limits(cases):
    """Comfortable (p tau < 0.2) delays are stable; beyond p tau = 2 nothing is; no gain of
    steer-angle feedback stabilizes the pendulum at p tau >= 2 (it fails far earlier); the limit
    over the gains is the same from the frequency-crossing formula."""
    assert all(c.observed == "stable" for c in cases if c.p_tau < 0.2)
    assert all(c.observed != "stable" for c in cases if c.p_tau > 2)
    gains = np.geomspace(0.4, 20, 25)
    limit = largest_stabilizable_p_tau(gains)
    assert 0.2 < limit < 2.0
    p = stability_boundary(1.0, 5.0).p
    by_crossing = max(p * first_crossing_delay(*loop({"V": 5.0}, k2)) for k2 in gains)
    assert limit == pytest.approx(by_crossing, rel=1e-8)


@pytest.mark.parametrize("case", ["lambert", "bicycle-pd"])
def test_stable_delay_intervals(case):
    """The exact stable delays of a single loop. x' = -a x(t - tau): stable exactly for
    a tau < pi/2 (relative 1e-12). The benchmark bicycle at 4 m/s with the steer-torque PD rider
    T = -2 phi - phi_dot is unstable without delay and stable in one window of delays: inside it
    the certified rightmost root is in the left half plane, at 0 an eigenvalue is in the right."""
    from cosim.analytic import whipple as W
    from cosim.analytic.delay import stable_delay_intervals
    from cosim.analytic.parameters import load_parameters

    if case == "lambert":
        a = 2.0
        (start, end), = stable_delay_intervals([[0.0]], [[1.0]], [[1.0]], -a, 10.0)
        assert start == 0.0 and end == pytest.approx(math.pi / (2 * a), rel=1e-12)
        return
    A, B = W.state_matrices(load_parameters("benchmark"), 4.0)
    C = np.array([[2.0, 0.0, 1.0, 0.0]])
    (start, end), = stable_delay_intervals(A, B[:, [1]], C, -1.0, 2.0)
    Ae, E = feedback_matrices(A, B[:, [1]], C, -1.0)
    assert 0.0 < start < 0.2 < end < 1.0, (start, end)
    assert np.linalg.eigvals(Ae + E).real.max() > 0 and spectral_abscissa(Ae, E, 0.5 * (start + end)) < 0
