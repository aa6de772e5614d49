"""The model-exchange coupling of the master (``algorithm = "model-exchange"``,
cosim/cosimulation/model_exchange.py): all components integrated together as one ODE by
classic Runge-Kutta 4 at the communication step.

A loop of Python blocks only (no FMU to build): a Step into the derivative input of an
integral-only PID whose torque drives a Pade delay that feeds the PID's roll input back. The
PID has no proportional part, so its output does not depend on the fed-back input without a
state (no algebraic loop); the closed loop is linear with a constant input, so its exact
solution at the communication points is a matrix exponential (scipy's expm), against which
the integrator's order is measured. The tests with FMUs (the composed examples against their
parts) are in tests/test_connected_examples.py; here FMUs only show what is refused.
"""
from __future__ import annotations

import os
import re
import zipfile
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import expm

from conftest import run_cli
from cosim.cosimulation.factory import run_system
from cosim.cosimulation.master import RunFailed
from cosim.cosimulation.registry import lookup
from cosim.cosimulation.system import SystemError_, system_from_dict

# the quick run (-m 'not slow') leaves this module out: its tests build, compile or run FMUs
pytestmark = pytest.mark.slow

KI, KD, TAU, AMPLITUDE, STOP = 1.0, 1.0, 0.5, 1.0, 4.0  # 1/s, N.m.s/rad, s, rad/s, s
SIGNALS = ["pid.T", "delay.y"]
LOOP = ["step.y -> pid.phi_dot", "pid.T -> delay.u", "delay.y -> pid.phi"]


def loop_system(step: float, kp: float = 0.0, algorithm: str = "model-exchange") -> dict:
    """The loop as the dict of a system file (``kp`` != 0 makes it an algebraic loop)."""
    return {"system": {"stop": STOP, "step": step, "algorithm": algorithm, "record": SIGNALS},
            "components": {"step": {"python": "Step", "parameters": {"amplitude": AMPLITUDE, "start": 0.0}},
                           "pid": {"python": "PID", "parameters": {"kp": kp, "ki": KI, "kd": KD}},
                           "delay": {"python": "PadeDelay", "parameters": {"tau": TAU}}},
            "connections": LOOP}


def exact(times: np.ndarray) -> dict[str, np.ndarray]:
    """The closed loop solved exactly at ``times``: states (delay's two, the PID's integral),
    u = pid.T = -KI xi - KD s, x_d' = A x_d + B u, y = C x_d + D u, xi' = y."""
    m = lookup("PadeDelay").create("delay", {"tau": TAU}).linear({})
    A, B, C, D = m.A, m.B[:, 0], m.C[0], m.D[0, 0]
    F = np.zeros((3, 3))
    F[:2, :2], F[:2, 2] = A, -KI * B
    F[2, :2], F[2, 2] = C, -KI * D
    G = np.concatenate([-KD * AMPLITUDE * B, [-KD * AMPLITUDE * D]])
    E = np.zeros((4, 4))
    E[:3, :3], E[:3, 3] = F, G
    x = np.array([expm(E * t)[:3, 3] for t in times])  # from x(0) = 0, the input constant from t = 0
    u = -KI * x[:, 2] - KD * AMPLITUDE
    return {"pid.T": u, "delay.y": x[:, :2] @ C + D * u}


def error(result: np.ndarray) -> float:
    """Largest deviation from the exact solution over the signals, relative to each one's largest magnitude."""
    reference = exact(result["time"])
    return max(float(np.max(np.abs(result[s] - reference[s])) / np.max(np.abs(reference[s]))) for s in SIGNALS)


def test_rk4_is_fourth_order_on_a_loop_of_python_blocks():
    """Halving the step divides the error by ~16 (RK4), and the loop moves (no trivial zero)."""
    errors = {}
    for h in (0.01, 0.005, 0.0025):
        run = run_system(system_from_dict(loop_system(h)))
        assert run.outcome.status == "completed" and run.steps == round(STOP / h)
        assert np.ptp(run.data["delay.y"]) > 0.5
        errors[h] = error(run.data)
    ratios = [errors[0.01] / errors[0.005], errors[0.005] / errors[0.0025]]
    assert 1e-10 < errors[0.0025] < 1e-6, errors  # above rounding: the ratios measure the scheme
    assert all(14 < r < 18 for r in ratios), (errors, ratios)


def test_jacobi_on_the_same_loop_is_first_order():
    """The same loop under the zero-order-hold master converges at first order only: what the
    model-exchange coupling changes."""
    errors = [error(run_system(system_from_dict(loop_system(h, algorithm="jacobi"))).data) for h in (0.01, 0.005)]
    assert errors[0] > 1e-3 and 1.7 < errors[0] / errors[1] < 2.3, errors


def _read_csv(path) -> dict[str, np.ndarray]:
    names = path.read_text().splitlines()[0].split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {name: data[:, j] for j, name in enumerate(names)}


def _toml(system: dict) -> str:
    from conftest import toml_value

    lines = [f"connections = {toml_value(system['connections'])}", "[system]"]
    lines += [f"{k} = {toml_value(v)}" for k, v in system["system"].items()]
    for name, entry in system["components"].items():
        lines += [f"[components.{name}]"] + [f"{k} = {toml_value(v)}" for k, v in entry.items()]
    return "\n".join(lines) + "\n"


def test_cli_runs_a_system_file_with_model_exchange(tmp_path):
    """`cosim run FILE.toml` with algorithm = "model-exchange": the usual CSV (time and the
    recorded signals), the same rows as the run in this process, close to the exact solution."""
    path, out = tmp_path / "loop.toml", tmp_path / "loop.csv"
    path.write_text(_toml(loop_system(0.01)))
    result = run_cli("run", str(path), "-o", str(out))
    assert result.returncode == 0, result.stderr
    assert "completed at t = 4 s after 400 steps" in result.stdout
    data = _read_csv(out)
    assert list(data) == ["time", *SIGNALS]
    here = run_system(system_from_dict(loop_system(0.01)))
    for name in data:
        np.testing.assert_allclose(data[name], here.data[name], rtol=1e-15, atol=0, err_msg=name)
    assert error(data) < 1e-5


def test_cli_refuses_an_algebraic_loop(tmp_path):
    """With a proportional part the PID's torque depends on the delay's output, whose Pade
    model passes its input straight through: one message naming the loop, exit 2, no output."""
    path, out = tmp_path / "loop.toml", tmp_path / "loop.csv"
    path.write_text(_toml(loop_system(0.01, kp=1.0)))
    result = run_cli("run", str(path), "-o", str(out))
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert "Traceback" not in result.stderr and len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert 'algebraic loop under algorithm = "model-exchange" through pid, delay' in result.stderr
    assert "'pid.T -> delay.u'" in result.stderr and "'delay.y -> pid.phi'" in result.stderr
    assert "step.y" not in result.stderr  # the source is not part of the loop
    assert not out.exists()


@pytest.mark.parametrize("change,message", [
    ({"components": {"delay": {"python": "TransportDelay", "parameters": {"tau": TAU}}}},
     "component 'delay' (TransportDelay) reads its input history (an exact delay is no ODE)"),
    ({"components": {"step": {"python": "Step", "step_multiple": 2}}},
     '[components.step] step_multiple: must be 1 under algorithm = "model-exchange", got 2'),
    ({"system": {"algorithm": "model_exchange"}},
     "[system] algorithm: must be one of jacobi, gauss-seidel, model-exchange, got 'model_exchange'"),
], ids=["exact-delay", "step-multiple", "misspelt"])
def test_systems_model_exchange_cannot_run_are_refused(change, message):
    """One SystemError_ naming the entry, before anything runs."""
    system = loop_system(0.01)
    for key, entries in change.items():
        for name, value in entries.items():
            system[key][name] = value
    with pytest.raises(SystemError_) as info:
        run_system(system_from_dict(system))
    assert message in str(info.value)


@pytest.fixture(scope="module")
def whipple() -> Path:
    """The linear Whipple bicycle's FMU (Model Exchange and Co-Simulation), built once."""
    from cosim.compiler.build import build

    (result,) = build(["Bicycle.Bicycles.WhippleLinear"], output=os.environ["COSIM_FMU_DIR"])
    return result.fmu


def _edited_copy(fmu: Path, folder: Path, pattern: str, new: str) -> Path:
    """A copy of ``fmu`` whose modelDescription.xml has the one match of the regular expression
    ``pattern`` replaced by ``new``."""
    copy = folder / fmu.name
    with zipfile.ZipFile(fmu) as original, zipfile.ZipFile(copy, "w") as edited:
        for item in original.infolist():
            data = original.read(item)
            if item.filename == "modelDescription.xml":
                data, count = re.subn(pattern.encode(), new.encode(), data, flags=re.S)
                assert count == 1, f"{pattern!r} not once in the model description: update this test"
            edited.writestr(item, data)
    return copy


@pytest.mark.parametrize("old,new,message", [
    ("<ModelExchange .*?</ModelExchange>", "", "has no Model Exchange interface"),
], ids=["co-simulation-only"])
def test_fmus_model_exchange_cannot_integrate_are_refused(whipple, tmp_path, old, new, message):
    """An FMU without a Model Exchange interface: one SystemError_ naming the component, before
    anything runs (FMUs with events take part: tests/test_run_events.py)."""
    fmu = _edited_copy(whipple, tmp_path, old, new)
    system = {"system": {"stop": 1.0, "step": 0.01, "algorithm": "model-exchange"},
              "components": {"bike": {"fmu": str(fmu)}, "rider": {"python": "Proportional"}},
              "connections": ["bike.phi -> rider.phi", "rider.T -> bike.T_delta"]}
    with pytest.raises(SystemError_) as info:
        run_system(system_from_dict(system))
    assert "component 'bike': " in str(info.value) and message in str(info.value)


def test_event_indicators_the_binary_does_not_have_fail_the_run(whipple, tmp_path):
    """A model description declaring event indicators its binary refuses to report: the run
    fails at the start naming the call, with the row it has (no silently missed events)."""
    fmu = _edited_copy(whipple, tmp_path, 'numberOfEventIndicators="0"', 'numberOfEventIndicators="2"')
    system = {"system": {"stop": 1.0, "step": 0.01, "algorithm": "model-exchange"},
              "components": {"bike": {"fmu": str(fmu)}}, "connections": []}
    with pytest.raises(RunFailed) as info:
        run_system(system_from_dict(system))
    assert "bike: fmi2GetEventIndicators failed at t = 0 s (status Error)" in str(info.value)
    assert len(info.value.result.data) == 1
