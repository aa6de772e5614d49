"""A misbehaving FMU from elsewhere cannot take `cosim` down.

The FMUs of ``tests/hostile_fmus.py`` segfault, call ``exit`` or ``abort``, loop forever, kill their
parent process, return NaN or fail to instantiate. Through ``simulate`` (Co-Simulation and Model
Exchange), ``run``, ``linearize``, ``info`` and ``validate`` every command ends (a hang within its
``--timeout``), exits non-zero with one line naming the fault (``info`` reads only the model
description and succeeds), and keeps the rows computed before the fault.

Commands whose FMU hangs or kills its parent run as separate processes (a regression there must
fail the test, not stop the test session); the others run in this process.
"""
from __future__ import annotations

import csv
import os

import numpy as np
import pytest

from conftest import cli_in_process, run_cli
from hostile_fmus import hostile_fmu

# the quick run (-m 'not slow') leaves this module out: it compiles and runs defective or foreign FMUs
pytestmark = pytest.mark.slow

TIMEOUT = "1"  # --timeout [s] for the FMUs that hang
# exit() runs the exit handlers of every library in the process: in one that has loaded C++
# libraries whose static destructors end threads (here: the test session's engines), that ends in
# abort(). Either way the message names how the FMU's process ended.
#: What the one error line says for each fault.
SAYS = {
    "segfault": "crashed (SIGSEGV)", "exit": ("exit status 0", "aborted (SIGABRT"), "abort": "aborted (SIGABRT",
    "hang": f"no answer within {TIMEOUT} s", "kill-parent": "parent process was killed (SIGKILL",
}
SEPARATE = {"hang", "kill-parent"}  # run in a child process of the test
FAULTS = tuple(SAYS)


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("hostile")


@pytest.fixture(scope="module")
def good_rows(folder):
    """The rows of the well-behaved variant, to compare the kept rows with."""
    fmu = hostile_fmu(folder, "none")
    status, _, stderr = cli_in_process(["simulate", str(fmu), "--stop-time", "1", "--step", "0.1", "-o",
                                        str(folder / "good.csv")], folder)
    assert status == 0, stderr
    return read_rows(folder / "good.csv")


def read_rows(path) -> np.ndarray:
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    return np.array(rows[1:], dtype=float)


def cosim(argv, cwd, separate: bool):
    """(status, stdout, stderr) of ``cosim ARGV``; ``separate``: in its own process."""
    argv = [str(a) for a in argv]
    if not separate:
        return cli_in_process(argv, cwd)
    done = run_cli(*argv, cwd=cwd)
    return done.returncode, done.stdout, done.stderr


def one_error_line(stderr: str, status: int, says: str) -> str:
    """The single message line of a failed command (no traceback), containing ``says``."""
    assert "Traceback" not in stderr and "internal error" not in stderr, stderr
    lines = [line for line in stderr.splitlines() if line.strip()]
    assert len(lines) == 1, stderr
    assert any(text in lines[0] for text in ((says,) if isinstance(says, str) else says)), stderr
    return lines[0]


@pytest.mark.parametrize("kind", ["cs", "me"])
@pytest.mark.parametrize("fault", FAULTS)
def test_simulate_keeps_the_rows_before_the_fault(folder, good_rows, fault, kind):
    fmu = hostile_fmu(folder, fault, "step")
    out = folder / f"sim-{fault}-{kind}.csv"
    status, stdout, stderr = cosim(["simulate", fmu, "--stop-time", "1", "--step", "0.1", "--fmi-type", kind,
                                    "--timeout", TIMEOUT, "-o", out], folder, fault in SEPARATE)
    assert status == 4, stderr
    line = one_error_line(stderr, status, SAYS[fault])
    assert str(fmu.name) in line and ("fmi2DoStep" if kind == "cs" else "fmi2GetDerivatives") in line
    assert not out.exists()
    kept = read_rows(out.with_name(out.stem + ".incomplete.csv"))
    # the fault strikes at t = 0.5 s; CVode's own steps run ahead of the output points
    assert kept[-1, 0] <= 0.5 + 1e-12 and len(kept) >= (6 if kind == "cs" else 3)
    if kind == "cs":  # the same steps as the well-behaved FMU, bit for bit
        np.testing.assert_array_equal(kept, good_rows[:len(kept)])


@pytest.mark.parametrize("fault", ["segfault", "hang"])
def test_simulate_fault_before_the_first_step(folder, fault):
    fmu = hostile_fmu(folder, fault, "instantiate")
    status, _, stderr = cosim(["simulate", fmu, "--stop-time", "1", "--timeout", TIMEOUT, "-o",
                               folder / "first.csv"], folder, fault in SEPARATE)
    assert status == 2
    line = one_error_line(stderr, status, SAYS[fault])
    assert "before the first step" in line and "fmi2Instantiate" in line


@pytest.mark.parametrize("kind", ["cs"])  # (ME: CVode fails on the NaN derivative, after 500 tries, 8 s)
def test_simulate_nan_output_is_a_failure(folder, good_rows, kind):
    fmu = hostile_fmu(folder, "nan", "step")
    out = folder / f"nan-{kind}.csv"
    status, _, stderr = cosim(["simulate", fmu, "--stop-time", "1", "--step", "0.1", "--fmi-type", kind, "-o", out],
                              folder, False)
    assert status == 4
    one_error_line(stderr, status, "output y is nan at t = 0.5 s" if kind == "cs" else "t = 0.5")
    kept = read_rows(out.with_name(out.stem + ".incomplete.csv"))
    assert np.all(np.isfinite(kept)) and kept[-1, 0] < 0.5


def test_simulate_null_instance(folder):
    status, _, stderr = cosim(["simulate", hostile_fmu(folder, "null-instance"), "--stop-time", "1"], folder, False)
    assert status == 2
    one_error_line(stderr, status, "cannot instantiate")


def system_file(folder, fmu, name: str):
    path = folder / f"{name}.toml"
    path.write_text(f'connections = ["push.y -> h.u"]\n[system]\nname = "{name}"\nstop = 1.0\nstep = 0.1\n'
                    f'[components.h]\nfmu = "{fmu.name}"\n[components.push]\npython = "Pulse"\n'
                    'parameters = { amplitude = 1.0, start = 0.2, duration = 0.2 }\n')
    return path


@pytest.mark.parametrize("fault", FAULTS + ("nan",))
def test_run_keeps_the_rows_before_the_fault(folder, fault):
    fmu = hostile_fmu(folder, fault, "step")
    system = system_file(folder, fmu, f"run-{fault}")
    out = folder / f"run-{fault}.csv"
    status, _, stderr = cosim(["run", system, "--timeout", TIMEOUT, "-o", out], folder, fault in SEPARATE)
    assert status == 4, stderr
    one_error_line(stderr, status, SAYS.get(fault, "signal h.y is not finite at t = 0.5 s"))
    kept = read_rows(out.with_name(out.stem + ".incomplete.csv"))
    assert len(kept) == 6 and kept[-1, 0] == 0.5
    assert not out.exists()


def test_run_null_instance(folder):
    system = system_file(folder, hostile_fmu(folder, "null-instance"), "run-null")
    status, _, stderr = cosim(["run", system], folder, False)
    assert status == 2
    one_error_line(stderr, status, "instantiate")


@pytest.mark.parametrize("fault", FAULTS + ("nan",))
def test_linearize_names_the_fault(folder, fault):
    fmu = hostile_fmu(folder, fault, "step", fault_time=0.0)  # strikes in fmi2GetDerivatives at t = 0
    status, stdout, stderr = cosim(["linearize", fmu, "--timeout", TIMEOUT], folder, fault in SEPARATE)
    assert status == 2 and stdout == ""
    one_error_line(stderr, status, SAYS.get(fault, "is nan at the operating point"))


@pytest.mark.parametrize("fault", FAULTS + ("nan", "null-instance"))
def test_info_does_not_load_the_binary(folder, fault):
    status, stdout, stderr = cosim(["info", hostile_fmu(folder, fault, "instantiate")], folder, False)
    assert status == 0, stderr
    assert "hostile" in stdout


@pytest.mark.parametrize("fault", FAULTS)
def test_validate_reports_the_fault_as_a_problem(folder, fault):
    fmu = hostile_fmu(folder, fault, "instantiate")
    status, stdout, stderr = cosim(["validate", fmu, "--timeout", TIMEOUT], folder, fault in SEPARATE)
    assert status == 1, stderr
    assert "Traceback" not in stderr
    says = (SAYS[fault],) if isinstance(SAYS[fault], str) else SAYS[fault]
    problems = [line for line in stdout.splitlines() if line.startswith("  - ")]
    assert problems and all(any(text in p for text in says) for p in problems), stdout
    assert any(any(text in p for text in says) and "instantiate" in p for p in problems), stdout


def test_python_api_raises_with_the_rows(folder, good_rows):
    import cosim
    from cosim.fmu.simulate import IncompleteResult

    with pytest.raises(IncompleteResult, match="crashed") as caught:
        cosim.simulate(hostile_fmu(folder, "segfault", "step"), stop_time=1.0, step=0.1)
    rows = caught.value.result
    np.testing.assert_array_equal(rows["y"], good_rows[:len(rows), 1])


def test_own_fmus_run_in_process(fmus, tmp_path, monkeypatch):
    """An FMU built here takes the in-process path (its runtime checks every call)."""
    from cosim.fmu import isolation, simulate as simulate_module

    fmu = fmus["Bicycle.Bicycles.SelfStabilizing"]
    assert isolation.built_here(fmu)
    assert not isolation.built_here(hostile_fmu(tmp_path, "none"))

    def refuse(*args, **kwargs):
        raise AssertionError("an FMU built here was isolated")

    monkeypatch.setattr(simulate_module, "run_isolated", refuse)
    status, _, stderr = cli_in_process(["simulate", str(fmu), "--stop-time", "0.2", "-o", str(tmp_path / "own.csv")],
                                       tmp_path)
    assert status == 0, stderr


def test_no_worker_outlives_the_command(folder):
    """After a hang was stopped, neither the guard nor the worker process is left."""
    fmu = hostile_fmu(folder, "hang", "step")
    mark = str(folder / "gone.csv")  # in the command line of the command and of its forks only
    done = run_cli("simulate", str(fmu), "--stop-time", "1", "--timeout", "1", "-o", mark, cwd=folder)
    assert done.returncode == 4
    left = []
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as handle:
                if mark.encode() in handle.read():
                    left.append(pid)
        except OSError:
            pass
    assert left == [], left



def test_fmi3_crash_in_do_step_keeps_the_rows(folder):
    """The same for an FMI 3.0 FMU: the Reference FMU VanDerPol with a segfault in fmi3DoStep."""
    from reference_fmus import reference_fmu

    crash = ("    ASSERT_STATE(DoStep);\n",
             "    ASSERT_STATE(DoStep);\n"
             "    if (currentCommunicationPoint >= 0.5) { volatile int *volatile p = 0; *p = 1; }\n")
    fmu = reference_fmu("VanDerPol", folder / "fmi3", edits={"fmi3Functions.c": [crash]}, fmu_name="crashing")
    out = folder / "vdp.csv"
    status, _, stderr = cosim(["simulate", fmu, "--stop-time", "1", "--step", "0.1", "-o", out], folder, False)
    assert status == 4
    one_error_line(stderr, status, "crashed (SIGSEGV) during fmi3DoStep from t = 0.5 s")
    kept = read_rows(out.with_name(out.stem + ".incomplete.csv"))
    assert len(kept) == 6 and kept[-1, 0] == 0.5
