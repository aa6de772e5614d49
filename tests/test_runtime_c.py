"""The shared C runtime (the core cosim_runtime.c with the FMI 2.0 API fmi2_api.c and the FMI 3.0
API fmi3_api.c): its own test harnesses (hand-written test models, sanitizers, exports) and its
behaviour in real FMUs of both versions."""
from __future__ import annotations

import ctypes
import math
import os
import shutil
import subprocess

import numpy as np
import pytest
from fmpy import extract, instantiate_fmu, read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import fmi2Discard, fmi2Error, fmi2LastSuccessfulTime, fmi2Terminated
from fmpy.fmi3 import FMU3Slave, fmi3Boolean, fmi3Discard, fmi3Error, fmi3Float64, fmi3OK

from conftest import ROOT
from cosim.compiler.build import build_model

# the quick run (-m 'not slow') leaves this module out: its tests build, compile or run FMUs
pytestmark = pytest.mark.slow

WHIPPLE = "Bicycle.Bicycles.Whipple"
LINEAR = "Bicycle.Bicycles.WhippleLinear"
PADE = "Bicycle.Rider.PadeDelay"
# Slow (1.5 m/s, u_R0 = -v / rR) with a push in roll: the bicycle falls, and near t = 1 s the
# steer angle passes pi/2, where the rolling constraints are singular: the integrator's step size
# underflows inside a communication step.
FALLING = {"u_R0": -5.0, "u_phi0": 0.3}
STEP = 0.01  # communication step [s]
STOP = 3.0   # [s]


@pytest.mark.skipif(shutil.which("gcc") is None, reason="needs gcc")
def test_runtime_harness():
    result = subprocess.run(["sh", str(ROOT / "cosim/runtime/tests/run.sh")], capture_output=True, text=True,
                            timeout=600)
    assert result.returncode == 0, result.stdout[-4000:] + result.stderr[-4000:]
    assert "all runtime tests passed" in result.stdout
    # both harnesses and the tape interpreter's ran, each twice (-O2, sanitizers), without a failed check
    assert result.stdout.count("FMI 2.0 runtime tests") == 1 and result.stdout.count("FMI 3.0 runtime tests") == 1
    assert result.stdout.count("tape: 17 checks, 0 failed") == 2
    assert result.stdout.count(" checks, 0 failed") == 6 and "FAILED" not in result.stdout
    assert "FMI 3 and FMI 2 bit-identical: NO" not in result.stdout
    # the step size factor decided without the fifth root where it is clamped: the same bits
    assert "step_factor: 1200018 checks, 0 differ from the full formula" in result.stdout
    assert "exports: 44 fmi2 functions, nothing else" in result.stdout
    assert "exports: 75 fmi3 functions, nothing else" in result.stdout


def _falling_slave(fmu, tmp_path, messages: list):
    """A Co-Simulation instance of the falling Whipple bicycle, initialized, with a logger that
    collects (status, message)."""
    md = read_model_description(fmu)
    vr = {v.name: v.valueReference for v in md.modelVariables}

    def logger(environment, instance, status, category, message):
        messages.append((status, message.decode("utf-8", "replace")))

    slave = instantiate_fmu(extract(fmu, unzipdir=tmp_path / "unzipped"), md, fmi_type="CoSimulation", logger=logger)
    slave.setupExperiment(startTime=0.0, stopTime=STOP)
    slave.enterInitializationMode()
    slave.setReal([vr[name] for name in FALLING], list(FALLING.values()))
    slave.exitInitializationMode()
    return slave, vr


def test_integration_failure_is_discard_with_last_successful_time(fmus, tmp_path):
    messages: list[tuple[int, str]] = []
    slave, vr = _falling_slave(fmus[WHIPPLE], tmp_path, messages)
    watch = ["phi", "delta", "u_phi", "u_delta", "residual"]
    t, last = 0.0, None
    try:
        with pytest.raises(FMICallException) as failure:
            for k in range(round(STOP / STEP)):
                slave.doStep(currentCommunicationPoint=t, communicationStepSize=STEP)
                t = (k + 1) * STEP
                last = slave.getReal([vr[n] for n in watch])
        # fmi2Discard (the slave computed only a part of the step), not fmi2Error
        assert failure.value.status == fmi2Discard
        lst = slave.getRealStatus(fmi2LastSuccessfulTime)
        assert t <= lst < t + STEP  # inside the failed communication step
        assert 0.5 < lst < 1.5      # where the bicycle falls (about 0.98 s)
        assert slave.getBooleanStatus(fmi2Terminated)
        status, message = messages[-1]
        assert status == fmi2Discard
        assert "too small" in message and "last successful time" in message and f"{lst:.16g}" in message

        # the state and outputs are those at the last successful time: finite, steer past pi/2
        values = dict(zip(watch, slave.getReal([vr[n] for n in watch])))
        assert all(math.isfinite(v) for v in values.values())
        assert abs(values["delta"]) > math.pi / 2
        assert abs(last[1]) < math.pi / 2  # still below at the last communication point
        assert abs(values["residual"]) < 1e-8  # the holonomic constraint held up to there

        # no further step (stepFailed), but terminating works, as a master's clean-up does it
        with pytest.raises(FMICallException) as again:
            slave.doStep(currentCommunicationPoint=lst, communicationStepSize=STEP)
        assert again.value.status == fmi2Error
        slave.terminate()
        assert slave.getReal([vr["delta"]])[0] == values["delta"]
    finally:
        slave.freeInstance()

    # FMPy's master keeps the rows up to the failure and ends with a sample at the last successful
    # time (its default tolerance is the model's, so the time differs from the one above slightly)
    result = simulate_fmu(fmus[WHIPPLE], fmi_type="CoSimulation", stop_time=STOP, output_interval=STEP,
                          start_values=FALLING, output=["delta"], logger=lambda *args: None)
    assert result["time"][-1] == pytest.approx(lst, rel=1e-6)
    assert t < result["time"][-1] < t + STEP
    assert len(result) == round(t / STEP) + 2  # t = 0, every communication point before, the failure
    assert np.all(np.isfinite(result["delta"])) and abs(result["delta"][-1]) > math.pi / 2


# ---------------------------------------------------------------------------------------------
# FMI 3.0 FMUs of the same models


@pytest.fixture(scope="module")
def fmi3_fmus() -> dict[str, object]:
    """FMI 3.0 FMUs of a few models, built into the session's FMU folder."""
    return {m: build_model(m, os.environ["COSIM_FMU_DIR"], fmi_version="3").fmu for m in (WHIPPLE, LINEAR, PADE)}


def _slave3(fmu, folder, messages: list, start_values: dict | None = None) -> tuple[FMU3Slave, dict]:
    """An initialized FMI 3 Co-Simulation instance (tolerance and stop time as FMPy's default
    run: none, stop STOP) with a logger that collects (status, message)."""
    md = read_model_description(fmu)
    vr = {v.name: v.valueReference for v in md.modelVariables}

    def log(environment, status, category, message):
        messages.append((status, message.decode("utf-8", "replace")))

    slave = FMU3Slave(guid=md.guid, unzipDirectory=extract(fmu, unzipdir=folder),
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="fmi3")
    slave.instantiate(logMessage=log)
    slave.enterInitializationMode(startTime=0.0, stopTime=STOP)
    for name, value in (start_values or {}).items():
        slave.setFloat64([vr[name]], [value])
    slave.exitInitializationMode()
    return slave, vr


def _do_step(slave: FMU3Slave, t: float, h: float) -> tuple[int, bool, bool, bool, float]:
    """fmi3DoStep without FMPy's exception: (status, eventHandlingNeeded, terminateSimulation,
    earlyReturn, lastSuccessfulTime)."""
    event, terminate, early, last = fmi3Boolean(True), fmi3Boolean(False), fmi3Boolean(True), fmi3Float64(-1.0)
    status = slave._functions["fmi3DoStep"](slave.component, t, h, True, ctypes.byref(event),
                                            ctypes.byref(terminate), ctypes.byref(early), ctypes.byref(last))
    return status, event.value, terminate.value, early.value, last.value


@pytest.mark.parametrize("fmi_type", ["CoSimulation", "ModelExchange"])
def test_fmi3_results_equal_fmi2_bit_for_bit(fmus, fmi3_fmus, fmi_type):
    """The same model through both APIs on the one core: FMPy's runs (inputs included) agree exactly."""
    md = read_model_description(fmus[LINEAR])
    outputs = [v.name for v in md.modelVariables if v.causality == "output"]
    inputs = [v.name for v in md.modelVariables if v.causality == "input"]
    t = np.linspace(0.0, 2.0, 21)
    signal = np.zeros(len(t), dtype=[("time", np.float64)] + [(name, np.float64) for name in inputs])
    signal["time"] = t
    for k, name in enumerate(inputs):
        signal[name] = 0.5 * np.sin(3.0 * t + k)
    runs = [simulate_fmu(fmu, fmi_type=fmi_type, stop_time=2.0, output_interval=STEP, input=signal, output=outputs,
                         logger=lambda *args: None) for fmu in (fmus[LINEAR], fmi3_fmus[LINEAR])]
    assert inputs and outputs and len(runs[0]) == len(runs[1]) == 201
    for name in ["time", *outputs]:
        np.testing.assert_array_equal(runs[1][name], runs[0][name], err_msg=name)
    assert np.ptp(runs[0][outputs[0]]) > 0.0  # the inputs moved the bicycle


@pytest.mark.parametrize("options", [{"use_event_mode": True}, {"early_return_allowed": True}],
                         ids=["event-mode-used", "early-return-allowed"])
def test_fmi3_cs_event_mode_and_early_return_change_nothing(fmi3_fmus, options):
    """FMPy's Co-Simulation with eventModeUsed (Event Mode after initialization and at every input
    change: UpdateDiscreteStates, EnterStepMode) or earlyReturnAllowed gives the plain run's result."""
    fmu = fmi3_fmus[LINEAR]
    md = read_model_description(fmu)
    inputs = [v.name for v in md.modelVariables if v.causality == "input"]
    signal = np.zeros(3, dtype=[("time", np.float64)] + [(name, np.float64) for name in inputs])
    signal["time"] = [0.0, 0.5, 0.5]  # a step of the inputs at t = 0.5: an input event
    signal[inputs[0]] = [0.0, 0.0, 1.0]
    runs = [simulate_fmu(fmu, fmi_type="CoSimulation", stop_time=1.0, output_interval=STEP, input=signal,
                         logger=lambda *args: None, **extra) for extra in ({}, options)]
    # with event mode FMPy records the event instant twice (before and after the event update)
    time = runs[1]["time"]
    after = len(time) - 1 - np.unique(time[::-1], return_index=True)[1]  # the last row of each time
    assert len(time) - len(after) == (1 if options.get("use_event_mode") else 0)
    assert len(runs[0]) == len(after) >= 101 and runs[1].dtype == runs[0].dtype
    for name in runs[0].dtype.names:
        np.testing.assert_array_equal(runs[1][name][after], runs[0][name], err_msg=name)
    assert np.ptp(runs[0][runs[0].dtype.names[1]]) > 0.0  # the input step moved the bicycle


@pytest.mark.parametrize("model", [WHIPPLE, LINEAR], ids=["nonlinear", "linear"])
def test_fmi3_adjoint_is_transpose_of_directional(fmi3_fmus, tmp_path, model):
    """v^T (J u) = (J^T v)^T u for the derivatives and outputs (states among them) with respect to
    the states and inputs, and the adjoint rows equal the directional columns (the whole Jacobian)."""
    messages: list = []
    slave, vr = _slave3(fmi3_fmus[model], tmp_path / "unzipped", messages)
    md = read_model_description(fmi3_fmus[model])
    try:
        for k in range(20):
            slave.doStep(k * STEP, STEP)
        states = [d.variable.derivative.valueReference for d in md.derivatives]
        # every ModelStructure unknown: the derivatives and the outputs, states among them (identity rows)
        unknowns = [d.variable.valueReference for d in md.derivatives] + [o.variable.valueReference
                                                                           for o in md.outputs]
        assert set(states) & set(unknowns)
        knowns = states + [v.valueReference for v in md.modelVariables if v.causality == "input"]
        rng = np.random.default_rng(15)
        u, v = rng.standard_normal(len(knowns)), rng.standard_normal(len(unknowns))
        ju = np.array(slave.getDirectionalDerivative(unknowns, knowns, list(u)))
        jtv = np.array(slave.getAdjointDerivative(unknowns, knowns, list(v), nSensitivity=len(knowns)))
        scale = np.abs(v) @ np.abs(ju) + np.abs(jtv) @ np.abs(u)
        assert scale > 0.0
        assert abs(v @ ju - jtv @ u) <= 1e-12 * scale
        jacobian = np.column_stack([slave.getDirectionalDerivative(unknowns, knowns, list(e))
                                    for e in np.eye(len(knowns))])
        # each entry to 1e-12 of the sum of the magnitudes of its terms (rounding, not a tolerance of the method)
        deviation = np.abs(jtv - jacobian.T @ v) / (np.abs(jacobian.T) @ np.abs(v) + 1e-300)
        assert deviation.max() <= 1e-12, deviation
        assert not [m for s, m in messages if s != fmi3OK]
    finally:
        slave.freeInstance()


def test_fmi3_discard_with_last_successful_time_as_fmi2(fmus, fmi3_fmus, tmp_path):
    """The falling bicycle's integration failure: fmi3Discard with terminateSimulation and the last
    successful time, which is FMI 2's fmi2LastSuccessfulTime exactly."""
    messages: list = []
    slave, vr = _slave3(fmi3_fmus[WHIPPLE], tmp_path / "unzipped3", messages, FALLING)
    try:
        t, result = 0.0, None
        for k in range(round(STOP / STEP)):
            result = _do_step(slave, t, STEP)
            if result[0] != fmi3OK:
                break
            assert result[1:] == (False, False, False, t + STEP)
            t = (k + 1) * STEP
        status, event, terminate, early, last = result
        assert status == fmi3Discard and terminate and not event and not early
        assert t < last < t + STEP and 0.5 < last < 1.5
        assert slave.getFloat64([vr["time"]])[0] == last
        level, message = messages[-1]
        assert level == fmi3Discard and "fmi3Discard" in message and f"{last:.16g}" in message
        assert abs(slave.getFloat64([vr["delta"]])[0]) > math.pi / 2
        assert _do_step(slave, last, STEP)[0] == fmi3Error  # no further step
        slave.terminate()
    finally:
        slave.freeInstance()

    fmi2_messages: list = []
    slave2, _ = _falling_slave(fmus[WHIPPLE], tmp_path, fmi2_messages)
    try:
        with pytest.raises(FMICallException):
            for k in range(round(STOP / STEP)):
                slave2.doStep(currentCommunicationPoint=k * STEP, communicationStepSize=STEP)
        assert slave2.getRealStatus(fmi2LastSuccessfulTime) == last
    finally:
        slave2.freeInstance()


def test_fmi3_fmu_state_round_trip_and_foreign_state_refused(fmi3_fmus, tmp_path):
    messages: list = []
    slave, vr = _slave3(fmi3_fmus[LINEAR], tmp_path / "linear", messages)
    other, _ = _slave3(fmi3_fmus[PADE], tmp_path / "pade", [])
    watch = [vr[name] for name in ("phi", "delta", "psi")]

    def run(instance, t0):
        return np.array([(instance.doStep(t0 + k * STEP, STEP), instance.getFloat64(watch))[1] for k in range(10)])

    try:
        slave.setFloat64([vr["T_delta"]], [0.5])
        run(slave, 0.0)
        saved = slave.getFloat64([vr["time"]])[0]
        state = slave.getFMUState()
        first = run(slave, 10 * STEP)
        slave.setFMUState(state)
        assert slave.getFloat64([vr["time"]])[0] == saved
        again = run(slave, 10 * STEP)
        np.testing.assert_array_equal(again, first)
        assert np.ptp(first[:, 0]) > 0.0
        # serialized and restored into the same instance after it moved on
        serialized = slave.serializeFMUState(state)
        restored = slave.deserializeFMUState(serialized)
        slave.setFMUState(restored)
        np.testing.assert_array_equal(run(slave, 10 * STEP), first)
        slave.freeFMUState(restored)
        slave.freeFMUState(state)
        # a state of another model is refused and changes nothing
        foreign = other.serializeFMUState(other.getFMUState())
        before = slave.getFloat64(watch)
        with pytest.raises(FMICallException) as refused:
            slave.deserializeFMUState(foreign)
        assert refused.value.status == fmi3Error
        assert "belongs to another FMU" in messages[-1][1]
        assert slave.getFloat64(watch) == before
    finally:
        slave.freeInstance()
        other.freeInstance()
