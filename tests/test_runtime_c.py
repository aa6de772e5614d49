"""The shared FMI 2.0 C runtime: its own test harness (hand-written test model, sanitizers, exports)
and its behaviour in a real FMU."""
from __future__ import annotations

import math
import shutil
import subprocess

import numpy as np
import pytest
from fmpy import extract, instantiate_fmu, read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import fmi2Discard, fmi2Error, fmi2LastSuccessfulTime, fmi2Terminated

from conftest import ROOT

WHIPPLE = "Bicycle.Bicycles.Whipple"
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
    assert "0 failed" in result.stdout


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
