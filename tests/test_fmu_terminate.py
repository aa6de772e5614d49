"""An FMU that ends the run itself without an error is a normal end.

The Reference FMU ``Stair`` (tests/reference_fmus.py) counts the seconds and sets
``terminateSimulation`` when its counter reaches 10 (at t = 9 s): through fmi2NewDiscreteStates /
fmi3UpdateDiscreteStates in Model Exchange, fmi2DoStep returning fmi2Discard with fmi2Terminated in
FMI 2 Co-Simulation. The vendored FMI 3 fmi3DoStep always reports ``terminateSimulation = false``;
the variant ``StairEnds`` passes the model's flag out, as the FMI 3 standard describes.

`cosim simulate` writes the rows under the final name, says so in one note line and exits 0; the
rows are those of FMPy's own ``simulate_fmu`` with the same settings. An end with an error message
stays an incomplete result (tests/test_simulate_incomplete.py, tests/test_singular_configuration.py).
"""
from __future__ import annotations

import warnings

import numpy as np
import pytest

from conftest import cli_in_process
from reference_fmus import reference_fmu, reference_fmu2

# the quick run (-m 'not slow') leaves this module out: it compiles and runs defective or foreign FMUs
pytestmark = pytest.mark.slow

STOP = 20.0  # s, after the end at t = 9 s
STEP = 0.2  # s
END = 9.0  # s, where the counter reaches 10
# fmi3DoStep of the vendored sources: pass the model's own terminateSimulation out
PASS_TERMINATE = {"fmi3Functions.c": [("*terminateSimulation = fmi3False;",
                                       "*terminateSimulation = S->terminateSimulation;")]}


@pytest.fixture(scope="module")
def stair(tmp_path_factory):
    """Stair as FMI 2 and FMI 3 (the latter with fmi3DoStep passing terminateSimulation out)."""
    folder = tmp_path_factory.mktemp("stair")
    return {"2": reference_fmu2("Stair", folder / "fmi2"),
            "3": reference_fmu("Stair", folder / "fmi3", edits=PASS_TERMINATE, fmu_name="StairEnds")}


def _fmpy_rows(fmu, fmi_type):
    from fmpy import simulate_fmu

    return simulate_fmu(str(fmu), stop_time=STOP, output_interval=STEP, output=["counter"],
                        fmi_type="CoSimulation" if fmi_type == "cs" else "ModelExchange")


@pytest.mark.parametrize("fmi_type", ["cs", "me"])
@pytest.mark.parametrize("version", ["2", "3"], ids=["fmi2", "fmi3"])
def test_terminate_simulation_is_a_normal_end(stair, tmp_path, version, fmi_type):
    out = tmp_path / "stair.csv"
    code, stdout, stderr = cli_in_process(["simulate", str(stair[version]), "--stop-time", str(STOP), "--step",
                                           str(STEP), "--fmi-type", fmi_type, "-o", str(out)], tmp_path)
    assert code == 0, stdout + stderr
    assert stderr.strip().splitlines() == [
        f"cosim simulate: note: the FMU ended the simulation at t = {END:g} s (terminateSimulation)"]
    assert out.is_file() and not (tmp_path / "stair.incomplete.csv").exists()
    rows = np.genfromtxt(out, delimiter=",", names=True, ndmin=1)
    expected = _fmpy_rows(stair[version], fmi_type)
    assert rows["time"][-1] == pytest.approx(END, abs=1e-9)
    assert len(rows) == len(expected)
    np.testing.assert_allclose(rows["time"], expected["time"], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(rows["counter"], expected["counter"])


def test_api_returns_rows_and_warns(stair):
    from cosim.fmu.simulate import SimulationTerminated, simulate

    with pytest.warns(SimulationTerminated, match=r"at t = 9 s") as caught:
        result = simulate(stair["3"], STOP, STEP, "me", isolate=False)
    assert [w.message.time for w in caught if isinstance(w.message, SimulationTerminated)] == [END]
    expected = _fmpy_rows(stair["3"], "me")
    np.testing.assert_array_equal(result["counter"], expected["counter"])


def test_run_to_the_stop_time_does_not_warn(stair):
    from cosim.fmu.simulate import simulate

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        result = simulate(stair["2"], 5.0, STEP, "cs", isolate=False)
    assert result["time"][-1] == pytest.approx(5.0, abs=1e-9)
