"""The time grid of `cosim simulate` and :func:`cosim.simulate`: the default communication step
(the FMU's DefaultExperiment stepSize, else DEFAULT_STEP, whatever the stop time), a run too long
for it refused with one message, a long step on a model at rest; and inputs that change at the
start time acting from the start (Co-Simulation and Model Exchange)."""
from __future__ import annotations

import re
import zipfile

import numpy as np
import pytest

import cosim
from conftest import cli_in_process, run_cli
from cosim.fmu.simulate import DEFAULT_STEP, MAX_ROWS, input_signals, simulate

# the quick run (-m 'not slow') leaves this module out: its tests build, compile or run FMUs
pytestmark = pytest.mark.slow

MODEL = "Bicycle.Bicycles.SelfStabilizing"  # input T; DefaultExperiment stepSize 0.01 s
RIDER = "Bicycle.Bicycles.WhippleRider"  # input T_beta, the rider's lean torque


def _with_experiment(fmu, folder, experiment: str | None):
    """A copy of ``fmu`` whose modelDescription.xml has ``experiment`` (an XML element) as its
    DefaultExperiment, or none."""
    copy = folder / f"{fmu.stem}-{'none' if experiment is None else 'edited'}.fmu"
    with zipfile.ZipFile(fmu) as src, zipfile.ZipFile(copy, "w", zipfile.ZIP_DEFLATED) as dst:
        for item in src.infolist():
            data = src.read(item)
            if item.filename == "modelDescription.xml":
                text, count = re.subn(r"<DefaultExperiment[^>]*/>", experiment or "", data.decode("utf-8"))
                assert count == 1
                data = text.encode("utf-8")
            dst.writestr(item, data)
    return copy


def _result(folder, name="out.csv"):
    return np.genfromtxt(folder / name, delimiter=",", names=True)


# --------------------------------------------------------------------------- the default step

DEFAULT_STEP_CASES = {  # FMU -> (DefaultExperiment element or "as built", stop time [s], expected spacing [s])
    "experiment-interval-stop-100": ("as built", "100", 0.01),
    "experiment-interval-1000-stop-1e6": ('<DefaultExperiment startTime="0.0" stepSize="1000" />', "1e6", 1000.0),
    "no-experiment-stop-100": (None, "100", 0.01),
}


@pytest.mark.parametrize("case", list(DEFAULT_STEP_CASES))
def test_default_step_is_the_experiment_interval_whatever_the_stop_time(fmus, tmp_path, case):
    """Rows are the FMU's DefaultExperiment stepSize apart (else DEFAULT_STEP = 0.01 s), to
    1e-9 of the step, from the start to the stop time; the Python API takes the same step."""
    experiment, stop, spacing = DEFAULT_STEP_CASES[case]
    assert experiment is not None or spacing == DEFAULT_STEP
    fmu = fmus[MODEL] if experiment == "as built" else _with_experiment(fmus[MODEL], tmp_path, experiment)
    status, out, err = cli_in_process(["simulate", str(fmu), "--stop-time", stop, "-o", "out.csv"], tmp_path)
    assert status == 0, err
    t = _result(tmp_path)["time"]
    rows = round(float(stop) / spacing) + 1
    assert len(t) == rows and f"({rows} rows" in out
    np.testing.assert_allclose(np.diff(t), spacing, rtol=1e-9, atol=0)
    assert t[-1] == float(stop)
    api = cosim.simulate(fmu, stop_time=float(stop), outputs=["phi"])["time"]
    np.testing.assert_array_equal(api, t)


@pytest.mark.parametrize("stop,rows", [("1e6", "1e+08"), ("1e12", "1e+14")], ids=["stop-1e6", "stop-1e12"])
def test_run_too_long_for_the_default_step_is_one_message(fmus, tmp_path, stop, rows):
    """No silently coarser step and no failure at t = 0: one message with the step, where it
    comes from, the rows and the way out; nothing written."""
    status, _, err = cli_in_process(["simulate", str(fmus[MODEL]), "--stop-time", stop, "-o", "out.csv"], tmp_path)
    assert status == 2 and err.count("\n") == 1, err
    assert (f"cosim simulate: error: --stop-time {float(stop):g} s with the default step of 0.01 s (the FMU's "
            f"DefaultExperiment stepSize) would record {rows} rows (at most 10,000,000); give a --step of at "
            "least") in err, err
    assert "t = 0" not in err
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("fmi_type", ["cs", "me"])
def test_long_step_on_a_model_at_rest_runs_to_the_stop_time(fmus, tmp_path, fmi_type):
    """Communication steps of 1e9 s (up to 1e12 s) on the bicycle at rest: every row, all zero
    (the FMU's integrator starts at a step the time can resolve at that scale, not at 1e-6 s)."""
    status, out, err = cli_in_process(["simulate", str(fmus[MODEL]), "--stop-time", "1e12", "--step", "1e9",
                                       "--fmi-type", fmi_type, "-o", "out.csv"], tmp_path)
    assert status == 0, err
    r = _result(tmp_path)
    assert len(r) == 1001 and r["time"][-1] == 1e12
    assert np.all(r["phi"] == 0.0) and np.all(r["delta"] == 0.0)


def test_help_states_the_default_step_and_the_row_limit():
    text = " ".join(run_cli("simulate", "--help").stdout.split())
    for phrase in ("without --step the output (communication) step is the FMU's DefaultExperiment stepSize",
                   f"or {DEFAULT_STEP:g} s (100 rows per second) if it declares none, whatever the stop time",
                   f"A run of more than {MAX_ROWS:,} rows is refused", "--input NAME=FILE.npy"):
        assert phrase in text, phrase


# --------------------------------------------------------------------------- inputs at the start time

STEP = 0.01  # communication step [s]
START_CASES = {  # model, input, value, stop time [s]
    "self-stabilizing-T": (MODEL, "T", 1.0, 1.0),
    "whipple-rider-T_beta": (RIDER, "T_beta", 5.0, 1.0),
}


def _run(fmu, fmi_type, name, source, stop):
    signals = input_signals(fmu, [f"{name}={source}"], 0.0, stop)
    outputs = ["phi", "delta"] + (["beta"] if name == "T_beta" else [])
    return simulate(fmu, stop, STEP, fmi_type, inputs=signals, outputs=outputs, relative_tolerance=1e-10)


@pytest.mark.parametrize("fmi_type", ["cs", "me"])
@pytest.mark.parametrize("case", list(START_CASES))
def test_step_at_the_start_time_acts_from_the_start(fmus, tmp_path, case, fmi_type):
    """``step:0:VALUE``, and a CSV whose value jumps at t = 0, give the result of a CSV that holds
    VALUE from t = 0, to 1e-12 (rad); a step one communication step later does not (its final
    roll angle more than 1e-6 rad apart: what the step at 0 gave when it acted one step late)."""
    model, name, value, stop = START_CASES[case]
    fmu = fmus[model]
    (tmp_path / "hold.csv").write_text(f"time,{name}\n0,{value!r}\n10,{value!r}\n")
    (tmp_path / "jump.csv").write_text(f"time,{name}\n0,0\n0,{value!r}\n10,{value!r}\n")
    hold = _run(fmu, fmi_type, name, tmp_path / "hold.csv", stop)
    for source in (f"step:0:{value!r}", tmp_path / "jump.csv"):
        run = _run(fmu, fmi_type, name, source, stop)
        np.testing.assert_array_equal(run["time"], hold["time"])
        for signal in hold.dtype.names[1:]:
            np.testing.assert_allclose(run[signal], hold[signal], rtol=0, atol=1e-12, err_msg=f"{source}: {signal}")
    late = _run(fmu, fmi_type, name, f"step:{STEP!r}:{value!r}", stop)
    assert abs(late["phi"][-1] - hold["phi"][-1]) > 1e-6
