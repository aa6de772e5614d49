"""A solver failure part-way keeps what was computed: the nonlinear Whipple bicycle started at
3 m/s (below its weave speed) with a small roll falls over; its steer angle swings to -pi/2,
where the rolling constraints are singular, and the integrator gives up at t = 1.906 s.

`simulate` and `run` write the rows up to the failure to NAME.incomplete.csv (never NAME.csv),
say so on stderr naming the steer angle, and exit 4 -- with the runtime's fmi2Error and with its
fmi2Discard + fmi2LastSuccessfulTime alike (the clean-up never calls fmi2Terminate after an
error)."""
from __future__ import annotations

import re
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT, failing_do_step, run_cli

# the quick run (-m 'not slow') leaves this module out: its tests build, compile or run FMUs
pytestmark = pytest.mark.slow

WHIPPLE = "Bicycle.Bicycles.Whipple"
FALLING = ["--param", "u_R0=-10", "--param", "phi0=0.05"]  # v = -u_R0 * rR = 3 m/s, 0.05 rad of roll
FAILURE_TIME = 1.9056  # s, where the steer angle passes -pi/2 (both integrators agree to 1e-3 s)


def _check_incomplete(result, folder, name, suffix=".csv"):
    assert result.returncode == 4, result.stdout + result.stderr
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr, result.stderr
    assert not (folder / f"{name}{suffix}").exists(), "an incomplete result under the final name"
    partial = folder / f"{name}.incomplete{suffix}"
    assert partial.is_file()
    assert not [p for p in folder.iterdir() if ".partial" in p.name]
    # Co-Simulation stops at the steer singularity; CVode (ME) runs on past it to the wheels lying flat
    assert re.search(r"(steer angle \S*delta|roll angle \S*phi) = \S+ rad \(\S+ deg\) reached \+-pi/2", result.stderr)
    assert f"to {partial}" in result.stderr
    return partial


@pytest.mark.parametrize("fmi_type", ["cs", "me"])
def test_simulate_solver_failure_writes_rows_up_to_failure(fmus, tmp_path, fmi_type):
    out = tmp_path / "w.csv"
    result = run_cli("simulate", str(fmus[WHIPPLE]), "--stop-time", "5", "--step", "0.01", "--fmi-type", fmi_type,
                     *FALLING, "-o", str(out), "--plot", str(tmp_path / "w.png"))
    partial = _check_incomplete(result, tmp_path, "w")
    assert (tmp_path / "w.incomplete.png").is_file() and not (tmp_path / "w.png").exists()
    data = np.genfromtxt(partial, delimiter=",", names=True)  # an ordinary CSV a reader takes as is
    assert data["time"][0] == 0.0 and data["phi"][0] == pytest.approx(0.05, abs=1e-12)
    if fmi_type == "cs":  # CVode (me) gets past the singularity for a while before it gives up
        assert data["time"][-1] == pytest.approx(FAILURE_TIME, abs=0.02)
        assert abs(data["delta"][-1]) > 1.4
    assert np.all(np.diff(data["time"]) > 0) and len(data) > 150


def test_simulate_npy_incomplete_result_is_npy(fmus, tmp_path):
    result = run_cli("simulate", str(fmus[WHIPPLE]), "--stop-time", "5", *FALLING, "-o", str(tmp_path / "w.npy"))
    partial = _check_incomplete(result, tmp_path, "w", ".npy")
    data = np.load(partial)
    assert data["time"][-1] == pytest.approx(FAILURE_TIME, abs=0.02)


# `python -m cosim` with the master's C stepping loop switched off (System.use_fast_loop)
PYTHON_LOOP_CLI = ("import sys; from cosim.cosimulation.master import System; System.use_fast_loop = False; "
                   "from cosim.cli import main; sys.exit(main(sys.argv[1:]))")


@pytest.mark.parametrize("loop", ["fast-c-loop", "python-loop"])
def test_run_solver_failure_writes_rows_up_to_failure_without_second_crash(fmus, tmp_path, loop):
    """The C loop runs systems of FMUs and the built-in blocks (here a Step source); the Python
    loop, which a block without a native form needs, reports the same."""
    system = tmp_path / "falls.toml"
    system.write_text('connections = ["push.y -> bike.T_phi"]\n[system]\nstop = 5.0\nstep = 0.01\n'
                      f'[components.bike]\nfmu = "{fmus[WHIPPLE]}"\nparameters = {{ u_R0 = -10.0, phi0 = 0.05 }}\n'
                      '[components.push]\npython = "Step"\nparameters = { amplitude = 0.0 }\n')
    arguments = ("run", str(system), "-o", str(tmp_path / "falls.csv"))
    if loop == "fast-c-loop":
        result = run_cli(*arguments)
    else:
        result = subprocess.run([sys.executable, "-c", PYTHON_LOOP_CLI, *arguments], capture_output=True, text=True,
                                cwd=ROOT, timeout=600)
    partial = _check_incomplete(result, tmp_path, "falls")
    assert "fmi2DoStep failed at t = 1.9 s" in result.stderr
    assert "fmi2Terminate" not in result.stderr  # the clean-up made no call FMI forbids
    data = np.genfromtxt(partial, delimiter=",", names=True)
    assert data["time"][-1] == pytest.approx(1.9, abs=1e-9) and len(data) == 191


class _FakeInstance:
    """Records the FMI calls the clean-up makes."""

    def __init__(self):
        self.calls = []

    def terminate(self):
        self.calls.append("terminate")

    def freeInstance(self):
        self.calls.append("freeInstance")


@pytest.mark.parametrize("status,calls", [(0, ["terminate", "freeInstance"]), (2, ["terminate", "freeInstance"]),
                                          (3, ["freeInstance"]), (4, [])],
                         ids=["ok", "discard", "error", "fatal"])
def test_component_cleanup_after_failed_step_follows_fmi_state_machine(fmus, status, calls):
    """FMI 2.0: fmi2Terminate is allowed after fmi2Discard, not after fmi2Error; after fmi2Fatal nothing."""
    from cosim.cosimulation.component import FMUComponent

    comp = FMUComponent("bike", fmus[WHIPPLE])
    comp.instance = fake = _FakeInstance()
    comp.status = status
    comp.close()
    assert fake.calls == calls and comp.instance is None


def test_physical_cause_names_roll_steer_and_residual():
    from cosim.compiler.catalog import singular_configurations
    from cosim.fmu.simulate import physical_cause

    whipple = singular_configurations("Bicycle.Bicycles.Whipple")
    assert physical_cause({"phi": 0.1, "delta": 0.2}, whipple) is None
    text = physical_cause({"bike.phi": 1.55, "bike.delta": 0.3}, whipple)
    assert text.startswith("roll angle bike.phi = 1.55 rad (88.8 deg) reached +-pi/2") and "lie flat" in text
    text = physical_cause({"delta": -1.6, "phi": 1.0, "residual": 3e-5}, whipple)
    assert text.index("residual") < text.index("steer angle delta = -1.6 rad (-91.7 deg) reached")


@pytest.mark.parametrize("loop", ["fast-c-loop", "python-loop"])
@pytest.mark.parametrize("status", [2, 3], ids=["discard", "error"])
def test_run_keeps_rows_when_fmu_step_returns_discard_or_error(fmus, monkeypatch, status, loop):
    """Both runtime behaviours (fmi2Error, and fmi2Discard with fmi2LastSuccessfulTime): the rows
    up to the failed step are kept, the outcome says which component failed, and fmi2Terminate
    is called after a Discard only."""
    from cosim.cosimulation.factory import run_system
    from cosim.cosimulation.master import RunFailed, System
    from cosim.cosimulation.system import system_from_dict

    fail_at = 1.0  # s
    terminated = []
    failing_do_step(monkeypatch, status, fail_at, terminated)
    monkeypatch.setattr(System, "use_fast_loop", loop == "fast-c-loop")
    components = {"bike": {"fmu": str(fmus["Bicycle.Bicycles.SelfStabilizing"]), "parameters": {"V": 6.0}}}
    connections = []
    if loop == "python-loop":  # with a block as well (natively stepped in the C loop)
        components["push"] = {"python": "Step", "parameters": {"amplitude": 0.1}}
        connections = ["push.y -> bike.T"]
    spec = system_from_dict({"system": {"stop": 2.0, "step": 0.1}, "components": components,
                             "connections": connections})
    with pytest.raises(RunFailed) as info:
        run_system(spec)
    result = info.value.result
    assert result.outcome.status == "failed" and not result.outcome.complete
    assert f"fmi2DoStep failed at t = 1 s (status {'Discard' if status == 2 else 'Error'})" in result.outcome.message
    assert result.data["time"][-1] == pytest.approx(fail_at, abs=1e-12) and result.steps == 10
    assert terminated == (["bike"] if status == 2 else [])
