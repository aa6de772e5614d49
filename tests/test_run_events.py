"""`cosim run` follows the FMI state machines for events and for an FMU's own end.

- A component FMU that asks to terminate (``terminateSimulation``: FMI 2 ``fmi2DoStep`` returning
  fmi2Discard with fmi2Terminated, FMI 3 ``fmi3DoStep``'s out-argument, or a Model Exchange event
  update) ends the run normally there: exit 0, the result under its final name up to that time,
  one note naming the component and the time. The Reference FMU ``Stair`` counts the seconds and
  asks to terminate when its counter reaches 10 (t = 9 s); the FMI 3 variant ``StairEnds`` passes
  the flag out of fmi3DoStep (tests/test_fmu_terminate.py). An early return stays a failure.
- The model-exchange coupling handles the FMUs' events (:mod:`cosim.fmu.access`): time events
  (Stair), state events located by bisection (``BouncingBall``), step events. The bouncing ball
  falls freely between bounces, a parabola that RK4 integrates exactly, so the coupling's result
  is compared with the closed-form solution; FMPy's CVode (`cosim simulate --fmi-type me`) locates
  the bounces to its own tolerance only.
"""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT, cli_in_process
from reference_fmus import reference_fmu, reference_fmu2

from cosim.cosimulation.master import System
from cosim.fmu.access import indicators_crossed, locate_state_event

STOP = 20.0  # s, after Stair's end
STEP = 0.2  # s
END = 9.0  # s, where Stair's counter reaches 10
PASS_TERMINATE = {"fmi3Functions.c": [("*terminateSimulation = fmi3False;",
                                       "*terminateSimulation = S->terminateSimulation;")]}
ALWAYS_EARLY = {"fmi3Functions.c": [("*earlyReturn = !nextCommunicationPointReached;", "*earlyReturn = fmi3True;")]}
EXACT = 1e-9  # [m, m/s] the coupling's bouncing ball against the closed form: bisection to 1e-10 of a step
CVODE_H, CVODE_V = 5e-4, 2e-2  # [m, m/s] FMPy's CVode (rtol 1e-4): its bounce times are off by ~1e-4 s by t = 2.5 s
GRAVITY, RESTITUTION, V_MIN = 9.81, 0.7, 0.1  # BouncingBall's g [m/s^2], e, v_min [m/s]


@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    folder = tmp_path_factory.mktemp("events")
    return {"Stair2": reference_fmu2("Stair", folder / "fmi2"),
            "Stair3": reference_fmu("Stair", folder / "fmi3", edits=PASS_TERMINATE, fmu_name="StairEnds"),
            "BouncingBall2": reference_fmu2("BouncingBall", folder / "fmi2"),
            "BouncingBall3": reference_fmu("BouncingBall", folder / "fmi3"),
            "Early3": reference_fmu("Stair", folder / "early", edits=ALWAYS_EARLY, fmu_name="StairEarly")}


def _system(folder, components: dict, algorithm: str = "jacobi", stop: float = STOP, step: float = STEP):
    lines = ["[system]", 'name = "events"', f"stop = {stop}", f"step = {step}", f'algorithm = "{algorithm}"']
    for name, fmu in components.items():
        lines += [f"[components.{name}]", f'fmu = "{fmu}"']
    path = folder / "events.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def _run(folder, system, fast: bool = True):
    saved = System.use_fast_loop
    System.use_fast_loop = fast
    try:
        return cli_in_process(["run", str(system), "-o", str(folder / "events.csv")], folder)
    finally:
        System.use_fast_loop = saved


def _rows(path):
    return np.genfromtxt(path, delimiter=",", names=True, deletechars="", ndmin=1)


def _simulated(fmu, fmi_type: str, stop: float, step: float):
    from fmpy import simulate_fmu

    return simulate_fmu(str(fmu), stop_time=stop, output_interval=step,
                        fmi_type="CoSimulation" if fmi_type == "cs" else "ModelExchange")


@pytest.mark.parametrize("algorithm, fast", [("jacobi", True), ("jacobi", False), ("gauss-seidel", False),
                                             ("model-exchange", False)],
                         ids=["c-loop", "python-loop", "gauss-seidel", "model-exchange"])
@pytest.mark.parametrize("version", ["2", "3"], ids=["fmi2", "fmi3"])
def test_an_fmu_ending_the_run_is_a_normal_end(fmus, tmp_path, version, algorithm, fast):
    # The ball beside the stair: its rows up to the end are those of the ball alone.
    system = _system(tmp_path, {"ball": fmus[f"BouncingBall{version}"], "stair": fmus[f"Stair{version}"]}, algorithm)
    code, stdout, stderr = _run(tmp_path, system, fast)
    assert code == 0, stdout + stderr
    assert stderr.strip().splitlines() == [
        f"cosim run: note: component 'stair' ended the run at t = {END:g} s (terminateSimulation)"]
    assert not (tmp_path / "events.incomplete.csv").exists()
    rows = _rows(tmp_path / "events.csv")
    kind = "me" if algorithm == "model-exchange" else "cs"
    stair = _simulated(fmus[f"Stair{version}"], kind, STOP, STEP)
    # FMPy's Model Exchange rows repeat an event's time (before and after it); run records each point
    # once, after its events
    stair = stair[np.append(np.diff(stair["time"]) > 0, True)]
    np.testing.assert_allclose(rows["time"], stair["time"], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(rows["stair.counter"], stair["counter"])  # an Integer (FMI 3: Int32) output
    if kind == "cs":  # the same FMU stepped alone over the same grid: the same values
        ball = _simulated(fmus[f"BouncingBall{version}"], kind, END, STEP)
        np.testing.assert_array_equal(rows["ball.h"], ball["h"])
        np.testing.assert_array_equal(rows["ball.v"], ball["v"])


@pytest.mark.parametrize("version", ["2", "3"], ids=["fmi2", "fmi3"])
def test_time_events_between_communication_points(fmus, tmp_path, version):
    """Stair's time events (every second) inside the steps of 0.35 s under model-exchange: the
    counter at every communication point as FMPy's, and the end at t = 9 s a last row of its own."""
    step = 0.35  # s
    system = _system(tmp_path, {"stair": fmus[f"Stair{version}"]}, "model-exchange", STOP, step)
    code, stdout, stderr = _run(tmp_path, system)
    assert code == 0 and "ended the run at t = 9 s" in stderr, stdout + stderr
    rows = _rows(tmp_path / "events.csv")
    np.testing.assert_allclose(rows["time"], np.append(step * np.arange(int(END / step) + 1), END), rtol=0, atol=1e-12)
    fmpy = _simulated(fmus[f"Stair{version}"], "me", STOP, step)
    last = fmpy[np.append(np.diff(fmpy["time"]) > 0, True)]  # after the events at a time
    at = [int(np.flatnonzero(np.abs(last["time"] - t) <= 1e-9)[0]) for t in rows["time"]]
    np.testing.assert_array_equal(rows["stair.counter"], last["counter"][at])


def test_an_early_return_stays_a_failure(fmus, tmp_path):
    code, stdout, stderr = _run(tmp_path, _system(tmp_path, {"stair": fmus["Early3"]}))
    assert code == 4, stdout + stderr
    assert "earlyReturn" in stderr and "note:" not in stderr
    assert (tmp_path / "events.incomplete.csv").is_file() and not (tmp_path / "events.csv").exists()


def _ball(t: float) -> tuple[float, float]:
    """Height [m] and velocity [m/s] of BouncingBall at ``t`` [s] (from h = 1 m at rest), closed form."""
    fall = np.sqrt(2.0 / GRAVITY)
    if t < fall:
        return 1.0 - GRAVITY * t * t / 2, -GRAVITY * t
    start, v = fall, GRAVITY * fall * RESTITUTION
    while v >= V_MIN:
        flight = 2 * v / GRAVITY
        if t < start + flight:
            s = t - start
            return v * s - GRAVITY * s * s / 2, v - GRAVITY * s
        start, v = start + flight, v * RESTITUTION
    return 0.0, 0.0


@pytest.mark.parametrize("version", ["2", "3"], ids=["fmi2", "fmi3"])
def test_state_events_under_model_exchange(fmus, tmp_path, version):
    stop, step = 3.0, 0.01
    system = _system(tmp_path, {"ball": fmus[f"BouncingBall{version}"]}, "model-exchange", stop, step)
    code, stdout, stderr = _run(tmp_path, system)
    assert code == 0 and not stderr, stdout + stderr
    rows = _rows(tmp_path / "events.csv")
    exact = np.array([_ball(t) for t in rows["time"]])
    np.testing.assert_allclose(rows["ball.h"], exact[:, 0], rtol=0, atol=EXACT)
    np.testing.assert_allclose(rows["ball.v"], exact[:, 1], rtol=0, atol=EXACT)
    # cosim simulate of the FMU alone (CVode), at the communication points
    out = tmp_path / "alone.csv"
    code, stdout, stderr = cli_in_process(["simulate", str(fmus[f"BouncingBall{version}"]), "--fmi-type", "me",
                                           "--stop-time", str(stop), "--step", str(step), "-o", str(out)], tmp_path)
    assert code == 0, stdout + stderr
    alone = np.genfromtxt(out, delimiter=",", names=True)
    at = [np.flatnonzero(np.abs(alone["time"] - t) < 1e-9)[-1] for t in rows["time"]]  # after an event row
    np.testing.assert_allclose(rows["ball.h"], alone["h"][at], rtol=0, atol=CVODE_H)
    np.testing.assert_allclose(rows["ball.v"], alone["v"][at], rtol=0, atol=CVODE_V)


@pytest.mark.parametrize("indicators, expected", [
    (lambda t: [0.3 - t], 0.3),
    (lambda t: [-1.0, t - 0.7], 0.7),  # z <= 0 to z > 0 is a crossing too
    (lambda t: [0.5 - t, 0.25 - t], 0.25),  # the first of two
], ids=["positive-to-negative", "negative-to-positive", "first-of-two"])
def test_locate_state_event(indicators, expected):
    resolution = 1e-12  # s
    z0 = np.array(indicators(0.0))
    found = locate_state_event(lambda t: np.array(indicators(t)), 0.0, 1.0, z0, resolution)
    assert expected <= found <= expected + 2 * resolution
    assert np.any(indicators_crossed(z0, indicators(found)))


def test_outcome_types_have_their_own_module():
    code = ("import sys, cosim.cosimulation.model_exchange; "
            "assert 'cosim.cosimulation.master' not in sys.modules, 'model_exchange imports master'; "
            "from cosim.cosimulation.master import Outcome, RunFailed, RunResult; "
            "from cosim.cosimulation import outcome; "
            "assert (Outcome, RunFailed, RunResult) == (outcome.Outcome, outcome.RunFailed, outcome.RunResult)")
    subprocess.run([sys.executable, "-c", code], check=True, cwd=ROOT)
