"""Model Exchange start-up follows the FMI state machines: after ``ExitInitializationMode`` the
FMU is in Event Mode, and ``fmi2NewDiscreteStates`` (FMI 2) or ``fmi3UpdateDiscreteStates``
(FMI 3) is called until no discrete state needs another update before ``EnterContinuousTimeMode``.

The FMUs are the vendored Reference FMUs (tests/reference_fmus.py) and FMI 2 and FMI 3 variants of
them whose ``EnterContinuousTimeMode`` refuses unless the initial event iteration ran, and whose
first ``fmi2NewDiscreteStates``/``fmi3UpdateDiscreteStates`` after initialization asks for one more
(as FMUs exported by Dymola do).
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from conftest import cli_in_process
from cosim.errors import FMUError
from cosim.fmu.access import ALL_FMI_VERSIONS, FMU
from cosim.fmu.simulate import default_step
from reference_fmus import reference_fmu, reference_fmu2

# the quick run (-m 'not slow') leaves this module out: it builds FMUs from Modelica per test
pytestmark = pytest.mark.slow

#: Directional derivatives against the analytic Jacobian (exact in the models' C code).
JACOBIAN_TOLERANCE = 1e-12
#: Central finite differences (relative step 1e-6) of a model linear in its states: rounding only.
FINITE_DIFFERENCE_TOLERANCE = 1e-8
#: cosim simulate against FMPy's simulate_fmu on the same FMU.
SIMULATE_TOLERANCE = 1e-6

_ITERATION_STATE = "static int pendingEventIteration = 0;  /* NewDiscreteStates calls still owed */\n\n"
#: fmi2Functions.c edits: ExitInitializationMode (ME) owes two NewDiscreteStates calls, the first
#: reports newDiscreteStatesNeeded, EnterContinuousTimeMode refuses while any is owed.
NEEDS_ITERATION = {"fmi2Functions.c": [
    ("fmi2Status fmi2ExitInitializationMode(fmi2Component c) {",
     _ITERATION_STATE + "fmi2Status fmi2ExitInitializationMode(fmi2Component c) {"),
    ("        S->state = EventMode;\n    } else {",
     "        S->state = EventMode;\n        pendingEventIteration = 2;\n    } else {"),
    ("    eventInfo->newDiscreteStatesNeeded           = S->newDiscreteStatesNeeded;",
     "    eventInfo->newDiscreteStatesNeeded = S->newDiscreteStatesNeeded || pendingEventIteration == 2;\n"
     "    if (pendingEventIteration > 0) pendingEventIteration--;"),
    ("    ASSERT_STATE(EnterContinuousTimeMode);\n",
     "    ASSERT_STATE(EnterContinuousTimeMode);\n    if (pendingEventIteration > 0) {\n"
     '        logError(S, "fmi2EnterContinuousTimeMode: may only be called when exited event mode");\n'
     "        return fmi2Error;\n    }\n"),
]}
#: The same for fmi3Functions.c (UpdateDiscreteStates, discreteStatesNeedUpdate).
NEEDS_ITERATION_FMI3 = {"fmi3Functions.c": [
    ("fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {",
     _ITERATION_STATE + "fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {"),
    ("        case ModelExchange:\n            S->state = EventMode;\n",
     "        case ModelExchange:\n            S->state = EventMode;\n            pendingEventIteration = 2;\n"),
    ("    if (discreteStatesNeedUpdate)          *discreteStatesNeedUpdate          = S->newDiscreteStatesNeeded;",
     "    if (discreteStatesNeedUpdate) *discreteStatesNeedUpdate = S->newDiscreteStatesNeeded"
     " || pendingEventIteration == 2;\n    if (pendingEventIteration > 0) pendingEventIteration--;"),
    ("    ASSERT_STATE(EnterContinuousTimeMode);\n",
     "    ASSERT_STATE(EnterContinuousTimeMode);\n    if (pendingEventIteration > 0) {\n"
     '        logError(S, "fmi3EnterContinuousTimeMode: may only be called when exited event mode");\n'
     "        return fmi3Error;\n    }\n"),
]}
#: The first NewDiscreteStates after initialization asks to terminate.
TERMINATES = {"fmi2Functions.c": NEEDS_ITERATION["fmi2Functions.c"] + [
    ("    eventInfo->terminateSimulation               = S->terminateSimulation;",
     "    eventInfo->terminateSimulation = S->terminateSimulation || pendingEventIteration == 1;")]}
#: NewDiscreteStates always asks for another call.
NEVER_SETTLES = {"fmi2Functions.c": [
    ("    eventInfo->newDiscreteStatesNeeded           = S->newDiscreteStatesNeeded;",
     "    eventInfo->newDiscreteStatesNeeded = fmi2True;")]}

BUILDERS = {"fmi2": reference_fmu2, "fmi3": reference_fmu}


@pytest.fixture(scope="module")
def fmus(tmp_path_factory) -> dict[str, Path]:
    """The Reference FMUs as FMI 2 and FMI 3 (``fmi2-VanDerPol``, ...) and the FMI 2 variants
    (``iterate-VanDerPol``, ...) and FMI 3 variants (``iterate3-VanDerPol``, ...), compiled once for this module."""
    folder = tmp_path_factory.mktemp("me-event-iteration")
    built = {f"{v}-{name}": BUILDERS[v](name, folder, fmu_name=f"{v}-{name}")
             for v in BUILDERS for name in ("BouncingBall", "VanDerPol", "Dahlquist", "Stair")}
    for name in ("BouncingBall", "VanDerPol", "Dahlquist", "Stair"):
        built[f"iterate-{name}"] = reference_fmu2(name, folder, edits=NEEDS_ITERATION, fmu_name=f"iterate-{name}")
    for name in ("BouncingBall", "VanDerPol"):
        built[f"iterate3-{name}"] = reference_fmu(name, folder, edits=NEEDS_ITERATION_FMI3,
                                                  fmu_name=f"iterate3-{name}")
    built["iterate3-SpeedVanDerPol"] = reference_fmu(
        "VanDerPol", folder, fmu_name="iterate3-SpeedVanDerPol",
        edits={**NEEDS_ITERATION_FMI3, "modelDescription.xml": [('name="mu"', 'name="V"')]})
    built["iterate-SpeedVanDerPol"] = reference_fmu2(
        "VanDerPol", folder, fmu_name="iterate-SpeedVanDerPol",
        edits={**NEEDS_ITERATION, "modelDescription.xml": [('name="mu"', 'name="V"')]})
    built["terminates-VanDerPol"] = reference_fmu2("VanDerPol", folder, edits=TERMINATES,
                                                   fmu_name="terminates-VanDerPol")
    built["never-settles-VanDerPol"] = reference_fmu2("VanDerPol", folder, edits=NEVER_SETTLES,
                                                      fmu_name="never-settles-VanDerPol")
    return built


def cosim(*argv: str, cwd: Path) -> tuple[int, str, str]:
    return cli_in_process(list(argv), cwd)


def vanderpol_jacobian(mu: float, x0: float, x1: float) -> np.ndarray:
    """d(der(x0), der(x1))/d(x0, x1) of model.c: x0' = x1, x1' = mu (1 - x0^2) x1 - x0."""
    return np.array([[0.0, 1.0], [-1.0 - 2.0 * mu * x0 * x1, mu * (1.0 - x0 ** 2)]])


#: (FMU key, --param options, expected A, tolerance): BouncingBall h' = v, v' = g (constant);
#: Dahlquist x' = -k x; VanDerPol at its start x = (2, 0).
LINEARIZED = [
    *[(f"{v}-VanDerPol", ("mu=1",), vanderpol_jacobian(1.0, 2.0, 0.0), JACOBIAN_TOLERANCE)
      for v in ("fmi2", "fmi3", "iterate", "iterate3")],
    *[(f"{v}-VanDerPol", ("mu=2.5",), vanderpol_jacobian(2.5, 2.0, 0.0), JACOBIAN_TOLERANCE)
      for v in ("fmi2", "iterate")],
    *[(f"{v}-BouncingBall", (), np.array([[0.0, 1.0], [0.0, 0.0]]), FINITE_DIFFERENCE_TOLERANCE)
      for v in ("fmi2", "fmi3", "iterate", "iterate3")],
    *[(f"{v}-Dahlquist", ("k=3",), np.array([[-3.0]]), FINITE_DIFFERENCE_TOLERANCE)
      for v in ("fmi2", "fmi3", "iterate")],
]


@pytest.mark.parametrize("key, params, A, tol", LINEARIZED,
                         ids=[f"{k}-{'-'.join(p) or 'default'}" for k, p, _, _ in LINEARIZED])
def test_linearize_after_the_initial_event_iteration(fmus, tmp_path, key, params, A, tol):
    argv = ["linearize", str(fmus[key]), "--json", *[a for p in params for a in ("--param", p)]]
    status, out, err = cosim(*argv, cwd=tmp_path)
    assert status == 0, err
    np.testing.assert_allclose(json.loads(out)["A"], A, rtol=0, atol=tol)


@pytest.mark.parametrize("key", ["iterate-SpeedVanDerPol", "iterate3-SpeedVanDerPol"], ids=["fmi2", "fmi3"])
def test_linearize_speeds_after_the_initial_event_iteration(fmus, tmp_path, key):
    """The sweep's fast path (raw fmi2/fmi3 calls, reset and re-initialized per speed) iterates too."""
    status, out, err = cosim("linearize", str(fmus[key]), "--speeds", "0:2:0.5", "--json",
                             "--matrices", cwd=tmp_path)
    assert status == 0, err
    report = json.loads(out)
    assert report["speeds"] == [0.0, 0.5, 1.0, 1.5, 2.0]
    for speed, point in zip(report["speeds"], report["points"]):
        np.testing.assert_allclose(point["A"], vanderpol_jacobian(speed, 2.0, 0.0), rtol=0, atol=JACOBIAN_TOLERANCE)


@pytest.mark.parametrize("key", ["iterate-VanDerPol", "iterate3-VanDerPol", "fmi3-VanDerPol", "fmi2-Stair", "fmi3-Stair"])
def test_initialize_me_reaches_continuous_time_mode(fmus, key):
    """FMU.initialize_me leaves the FMU in Continuous-Time Mode (states readable, a second
    EnterContinuousTimeMode refused by the FMU's state machine)."""
    fmu = FMU(fmus[key], versions=ALL_FMI_VERSIONS)
    instance = fmu.instantiate("me")
    try:
        fmu.initialize_me(instance)
        if fmu.n_states:
            np.testing.assert_array_equal(fmu.get_real(instance, ["x0", "x1"]), [2.0, 0.0])
        with pytest.raises(Exception, match="EnterContinuousTimeMode"):
            instance.enterContinuousTimeMode()
    finally:
        instance.freeInstance()


@pytest.mark.parametrize("key, message", [("terminates-VanDerPol", "asks to terminate"),
                                          ("never-settles-VanDerPol", "did not end after 1000 fmi2NewDiscreteStates")],
                         ids=["terminates", "never-settles"])
def test_initial_event_iteration_refusals(fmus, key, message):
    fmu = FMU(fmus[key], versions=ALL_FMI_VERSIONS)
    instance = fmu.instantiate("me")
    try:
        with pytest.raises(FMUError, match=message):
            fmu.initialize_me(instance)
    finally:
        instance.freeInstance()


def test_linearize_of_an_fmu_that_terminates_at_the_start_is_refused(fmus, tmp_path):
    status, out, err = cosim("linearize", str(fmus["terminates-VanDerPol"]), "--json", cwd=tmp_path)
    assert status not in (0, 70)
    assert "asks to terminate" in err and "Traceback" not in err


SIMULATED = [("fmi2-BouncingBall", 3.0), ("iterate-BouncingBall", 3.0), ("fmi2-Stair", 6.0), ("iterate-Stair", 6.0),
             ("fmi3-BouncingBall", 3.0), ("iterate3-BouncingBall", 3.0)]


@pytest.mark.parametrize("key, stop", SIMULATED, ids=[k for k, _ in SIMULATED])
def test_simulate_me_equals_fmpy(fmus, tmp_path, key, stop):
    from fmpy import read_model_description, simulate_fmu

    fmu = fmus[key]
    status, out, err = cosim("simulate", str(fmu), "--stop-time", str(stop), "--fmi-type", "me", "-o", "out.csv",
                             cwd=tmp_path)
    assert status == 0, err
    ours = np.genfromtxt(tmp_path / "out.csv", delimiter=",", names=True, deletechars="", ndmin=1)
    theirs = simulate_fmu(str(fmu), fmi_type="ModelExchange", stop_time=stop,
                          output_interval=default_step(read_model_description(str(fmu)))[0])
    assert len(ours) == len(theirs) > 10
    np.testing.assert_allclose(ours["time"], theirs["time"], rtol=0, atol=SIMULATE_TOLERANCE)
    for column in set(ours.dtype.names) - {"time"}:
        np.testing.assert_allclose(ours[column], theirs[column].astype(float), rtol=0, atol=SIMULATE_TOLERANCE,
                                   err_msg=f"{key}: {column}")
